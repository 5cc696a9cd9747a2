// keel run --monitor and --record (docs/monitor.md): the run's records, read from its fault log
// as they are written, turned into the Foxglove channels `/keel/state` and `/keel/faults` and
// served live (monitor/server.hpp) and recorded (MCAP, monitor/mcap_writer.hpp). Its own threads — the hub following
// the log, the server's io thread, a control thread for the emergency stop and clear — so the run never waits for it:
// the fault path writes its log line as it always does, and that is all. Thread-safety: start/stop from one thread.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "keel/result.hpp"

namespace keel::engine {
class Engine;
}

namespace keel::monitor {

struct MonitorOptions {
  std::string listen;                              // "[ADDR:]PORT" (keel run --monitor); empty: no server
  std::vector<std::string> allowed_origins;        // --monitor-origin
  std::string log_path;                            // the run's fault log, followed
  std::string profile;                             // the root profile's path, for the metadata
  std::string record;                              // FILE.mcap (keel run --record); empty: none
  std::size_t queue_bytes = std::size_t{4} << 20;  // per client (--monitor-queue): beyond, dropped
};

/// `[ADDR:]PORT` → address and port (127.0.0.1 when no address is given; `[::1]:8765` for IPv6).
Result<std::pair<std::string, std::uint16_t>> parseListen(const std::string& text);

class Monitor {
 public:
  /// Starts serving (and the hub) for `engine`'s run; the engine outlives the monitor.
  static Result<std::unique_ptr<Monitor>> start(engine::Engine& engine, MonitorOptions options);
  ~Monitor();
  Monitor(const Monitor&) = delete;
  Monitor& operator=(const Monitor&) = delete;

  /// The page's address with the control token: what keel run prints (empty: no server).
  std::string url() const;
  /// Reads the log to its end, sends and records what is left, then stops serving and closes
  /// the recording (its summary written). The recording's error, if writing it failed.
  Result<void> stop();

  struct Impl;

 private:
  explicit Monitor(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace keel::monitor
