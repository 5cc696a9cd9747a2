// The fault manager (paper §3.2): every detected fault reaches it, whichever detector found
// it — the guard, a port, the watchdog, a monitor or voter component, raiseFault, or a
// FaultEvent sent to its `faults` port. It gives the fault its id (the id of the injection
// that caused it, when keel injected it), logs `injected` and `detected`, and marks a
// component that can no longer run (signal, exception, error code, hang) as Error. Handling by
// rule (reset, replace, stop, emergency) builds on this.
// Thread-safety: onFault may be called from any thread, concurrently.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "fault/fault_log.hpp"
#include "keel/component.hpp"
#include "keel/fault_event.hpp"

namespace keel::fault {

struct FaultCount {
  std::string component;
  std::string kind;
  std::string detail;  // the first one
  std::uint64_t count = 0;
};

/// One detection, as kept for summaries and tests.
struct Detection {
  std::uint64_t fault_id = 0;
  std::string component;
  FaultKind kind = FaultKind::User;
  std::int64_t detected_ns = 0;  // steady clock
  std::int64_t injected_ns = 0;  // 0: not injected
};

class FaultManager {
 public:
  /// `find` maps an instance name to its component (null when unknown).
  FaultManager(FaultLog& log, std::function<Component*(std::string_view)> find);

  /// A new fault id (the injector takes one per injection).
  std::uint64_t nextId() { return next_id_.fetch_add(1, std::memory_order_relaxed); }

  /// `reporter` detected `fault`; `fault.component` names the faulty component (empty: the
  /// reporter itself). `detector` names who found it in the log (default: the reporter).
  void onFault(Component& reporter, const FaultEvent& fault, std::string_view detector = {});

  std::vector<FaultCount> counts() const;
  std::vector<Detection> detections() const;
  /// How many faults were detected so far (cheap: no copy, no lock).
  std::size_t detectionCount() const { return detection_count_.load(std::memory_order_acquire); }
  /// Called at the end of a run: logs injections that manifested but were never detected.
  void flushUndetected(const std::vector<Component*>& components);

 private:
  FaultLog& log_;
  std::function<Component*(std::string_view)> find_;
  std::atomic<std::uint64_t> next_id_{1};
  mutable std::mutex mutex_;
  std::vector<FaultCount> counts_;
  std::vector<Detection> detections_;
  std::atomic<std::size_t> detection_count_{0};
};

}  // namespace keel::fault
