// The injector: carries a fault scenario out during a run (docs/faults.md). Checked against the
// running components first (every problem as `file:line: message`); then a thread arms each
// fault at its time after the start. What an armed fault does, and when it manifests, is
// runtime/injection's business; the log gets `injected` at manifestation (fault manager).
// A hardware fault is not armed: at its time this thread hands it to the component that drives
// that hardware (keel::HardwareDriver::onHardwareFault) and logs `injected` with `"hardware": true`.
// Thread-safety: check/start/stop from the engine's thread.
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "fault/fault_manager.hpp"
#include "injection/scenario.hpp"
#include "log/fault_log.hpp"
#include "runtime/wake_signal.hpp"
#include "runtime/warning.hpp"

namespace keel::injection {

class Injector {
 public:
  using Find = std::function<Component*(std::string_view)>;

  /// `warn` reports a hardware fault its component did not take (default: stderr).
  Injector(Scenario scenario, Find find, fault::FaultManager& manager, log::FaultLog& log, runtime::Warn warn = {});
  ~Injector();
  Injector(const Injector&) = delete;
  Injector& operator=(const Injector&) = delete;

  /// Every fault names a running component and can apply to it; warnings for faults no
  /// detector is configured to see (a hang without <heartbeat>) or that cannot fire (a
  /// passive component is never executed). `passive` tells which components are passive.
  Result<void> check(const runtime::Warn& warn, const std::function<bool(std::string_view)>& passive) const;
  /// Starts arming, with times counted from `t0_ns` (steady clock).
  void start(std::int64_t t0_ns);
  void stop();

 private:
  void run(std::int64_t t0_ns);
  /// A hardware fault: the component that drives that hardware gets it (onHardwareFault).
  void injectHardware(Component& c, const ScheduledFault& f, std::uint64_t id);

  Scenario scenario_;
  Find find_;
  fault::FaultManager& manager_;
  log::FaultLog& log_;
  runtime::Warn warn_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  runtime::WakeSignal signal_;
};

}  // namespace keel::injection
