// The heartbeat monitor (paper Table 1: "heart beat monitor thread"). For every component with
// a <heartbeat timeout>, it declares a `heartbeat` fault when a callback of the component has
// not returned within the timeout (the component is hung — found although its thread never
// comes back), or when a periodic component has not been executed for its period plus the
// timeout (its executor stopped cycling, or it was stalled). It sleeps until the earliest
// deadline (absolute time), so a hang is declared at timeout + wake-up latency; it asks for
// SCHED_FIFO at the highest priority and says in the log when the OS refuses.
// Thread-safety: start/stop from the engine; reads the components' atomics.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "fault/fault_manager.hpp"
#include "keel/component.hpp"
#include "runtime/wake_signal.hpp"
#include "runtime/warning.hpp"

namespace keel::fault {

struct WatchedComponent {
  const std::atomic<Component*>* component = nullptr;  // the serving component (an alternative too)
  std::int64_t timeout_ns = 0;
  std::int64_t period_ns = 0;  // 0: aperiodic or passive (only callbacks are timed)
};

class Watchdog {
 public:
  /// `realtime`: ask for SCHED_FIFO (the default; benchmarks compare without).
  Watchdog(std::vector<WatchedComponent> watched, FaultManager& manager, runtime::Warn warn, bool realtime = true);
  ~Watchdog();
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

  void start();
  void stop();
  bool empty() const { return watched_.empty(); }

 private:
  struct Episode {
    std::int64_t reported_since = 0;  // callback start already reported as hung
    std::int64_t reported_beat = 0;   // heartbeat already reported as missing
  };
  void run();
  /// Checks one component at `now`; returns the time it must be looked at again.
  std::int64_t check(const WatchedComponent& w, Episode& e, std::int64_t now);
  void report(Component& c, const WatchedComponent& w, std::int64_t now, const char* what, double late_ms);

  std::vector<WatchedComponent> watched_;
  std::vector<Episode> episodes_;
  FaultManager& manager_;
  runtime::Warn warn_;
  std::int64_t poll_ns_ = 50'000'000;
  bool realtime_ = true;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  runtime::WakeSignal signal_;
};

}  // namespace keel::fault
