// Diagnosis of one detected fault (paper §5.2): who is at fault (the component the event
// names, else the reporter), which fault it is — its id is the injection's when keel injected
// it, so that `injected` and `detected` share it — and what the component's compiled rules
// call for (severity, scope, the first handling step). Claims the role for this fault: a role
// already being handled, or stopped, only logs a further fault.
// Thread-safety: any thread, on the thread that detected the fault; no allocation.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string_view>

#include "fault/report.hpp"
#include "keel/component.hpp"
#include "keel/fault_event.hpp"

namespace keel::fault {

/// Fault ids: one per fault, never 0; the injector takes one per injection.
class FaultIds {
 public:
  std::uint64_t next() { return counter_->fetch_add(1, std::memory_order_relaxed); }
  /// Counts in `shared` instead (a word in memory the run's processes share, starting at 1),
  /// so that ids are unique in the one log they write. Before any fault.
  void share(std::atomic<std::uint64_t>* shared) { counter_ = shared ? shared : &next_; }

 private:
  std::atomic<std::uint64_t> next_{1};
  std::atomic<std::uint64_t>* counter_ = &next_;
};

/// Builds the report of `fault`, found by `reporter` (`detector` names who found it in the log;
/// empty: the reporter). `find` resolves the instance the event names. A fault that is not
/// `recoverable` (a failed lifecycle transition) is only logged, whatever the rules say.
FaultReport diagnose(Component& reporter, const FaultEvent& fault, std::string_view detector,
                     const std::function<Component*(std::string_view)>& find, FaultIds& ids, bool recoverable = true);

}  // namespace keel::fault
