// The safe commands of ROS 2 nodes (docs/ros2-nodes.md): a node profile's <emergency> may
// declare `<publish topic type rate>`; while keel's emergency stop holds, keel writes the type's
// zero value (every number 0, every string and sequence empty) to that topic at that rate, as a
// ROS 2 publisher would (ROS 2's default QoS), so that what listens to a stopped node hears
// "stand still" rather than its last command. The writers are made at the start, matched long
// before an emergency; one thread writes every command that is on.
// Thread-safety: open from one thread before start(); start, clear and stop from any thread.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "keel/result.hpp"
#include "profile/model.hpp"

namespace keel::dds {

/// One node's safe command.
struct NodeSafeCommand {
  std::string instance;  // the node's subcomponent
  profile::SafeCommand command;
};

class SafeCommands {
 public:
  SafeCommands() = default;
  ~SafeCommands();  // stop()
  SafeCommands(const SafeCommands&) = delete;
  SafeCommands& operator=(const SafeCommands&) = delete;

  /// A writer for each of `commands` in `participant`; each problem (a type not linked into
  /// keel, a topic or writer CycloneDDS refuses) a line of the error, `file:line: ...`.
  Result<void> open(std::int32_t participant, const std::vector<NodeSafeCommand>& commands);
  /// `instance`'s commands are written from now on, each at its rate, until clear().
  void start(const std::string& instance);
  /// The emergency is over: no command is written any more.
  void clear();
  /// Ends the writing thread; nothing is written once it returns. Idempotent.
  void stop();
  /// The writers open() made.
  std::vector<std::int32_t> writers() const;

 private:
  struct Command {
    std::string instance;
    std::int32_t writer = 0;
    std::vector<std::uint64_t> zero;  // the C sample, all zero (aligned for any member)
    std::int64_t period_ns = 0;
    std::int64_t next_ns = 0;  // its next write (steady); 0: off
  };
  void run();

  std::vector<Command> commands_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool ending_ = false;
  std::thread thread_;
};

}  // namespace keel::dds
