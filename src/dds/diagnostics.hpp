// keel's health on ROS 2's /diagnostics (docs/dds.md#diagnostics): one
// diagnostic_msgs/DiagnosticStatus per component in a DiagnosticArray, at 1 Hz and at once after
// each change, so that ROS 2's diagnostic tools (rqt_robot_monitor, the aggregator) show it.
// What a component's health is comes from the engine (a snapshot function); this writes it.
// Thread-safety: poke() from any thread; the rest from the owner's.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <chrono>

#include "keel/msg/diagnostic_msgs/msg/diagnostic_array.hpp"

namespace keel::dds {

/// One component's status as /diagnostics carries it.
struct Health {
  enum Level : std::uint8_t { Ok = 0, Warn = 1, Error = 2, Stale = 3 };  // DiagnosticStatus's
  std::string name;                                                      // keel/<application>/<component>
  Level level = Ok;
  std::string message;  // why the level, in words
  std::string state;    // the lifecycle state's name
  std::uint64_t faults = 0;
  std::string last_fault;  // "remote: no sample on /cmd_vel ...", or ""
};

/// The DiagnosticArray of `health`, stamped `wall_ns` (ns since the epoch: ROS time).
msg::diagnostic_msgs::DiagnosticArray diagnosticArray(const std::vector<Health>& health, std::int64_t wall_ns);

class DiagnosticsWriter {
 public:
  using Snapshot = std::function<std::vector<Health>()>;
  using Publish = std::function<void(const msg::diagnostic_msgs::DiagnosticArray&)>;
  /// Publishes `snapshot()` every `period` and after each poke(), on a thread of its own.
  DiagnosticsWriter(Snapshot snapshot, Publish publish, std::chrono::milliseconds period = std::chrono::seconds(1));
  ~DiagnosticsWriter();  // stop()
  DiagnosticsWriter(const DiagnosticsWriter&) = delete;
  DiagnosticsWriter& operator=(const DiagnosticsWriter&) = delete;

  /// Something changed: write a fresh snapshot now (on the writer's thread).
  void poke();
  /// Ends the thread (after the write under way, if any). Idempotent.
  void stop();

 private:
  void run();
  void write();

  Snapshot snapshot_;
  Publish publish_;
  std::chrono::milliseconds period_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool poked_ = false;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace keel::dds
