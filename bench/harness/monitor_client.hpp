// A client of keel's live monitor for the benchmarks (`keel bench recovery`'s
// reset_monitored): connects over the Foxglove WebSocket protocol, subscribes to every channel
// it is offered, and reads everything, as a page or Foxglove would, on a thread of its own. For
// each `detected` record it is sent, it keeps how long after the detection it got it (its wall
// clock minus the record's: the server's start_unix_ns + t_ns).
// Thread-safety: construct, waitForData(), detectionLatencies() and the destructor from one thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace keel::bench {

class MonitorClient {
 public:
  /// Connects to the monitor at 127.0.0.1:`port`; error() says why when it could not.
  explicit MonitorClient(std::uint16_t port);
  ~MonitorClient();  // closes the connection, joins the thread
  MonitorClient(const MonitorClient&) = delete;
  MonitorClient& operator=(const MonitorClient&) = delete;

  /// Waits up to 2 s for the first message of a subscribed channel; false if none came.
  bool waitForData();
  /// ns from each detection to this client's receiving it, in the order received.
  std::vector<std::int64_t> detectionLatencies() const;
  const std::string& error() const { return error_; }

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  std::thread thread_;
  std::atomic<std::uint64_t> data_{0};
  std::string error_;
  mutable std::mutex latencies_mutex_;
  std::vector<std::int64_t> latencies_ns_;
};

}  // namespace keel::bench
