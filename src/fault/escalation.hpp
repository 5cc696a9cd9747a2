// The escalation decision: which handling step comes after the one just tried, from how it
// ended and what the component's role still has (docs/fault-handling.md, "Escalation").
// reset → replace → stop → emergency; an emergency goes on as a stop; the steps only go up, so
// handling never loops. Pure, as Erlang/OTP's supervisor:add_restart/1: no clock, no thread,
// no log — the fault manager acts, this decides. The restart-intensity window is here too.
// Thread-safety: functions of their arguments; a RestartWindow is guarded by its owner.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "fault/rules.hpp"

namespace keel::fault {

/// How the step just tried ended.
enum class Outcome : std::uint8_t {
  Done,               // it did what it should
  Failed,             // tried and failed (a recovery callback faulted, the alternative did not
                      // load or start, a stop could not be carried out)
  IntensityExceeded,  // a reset would be one recovery too many within the period
  Unavailable,        // a replacement with no alternative, or with the alternative already in place
  Hung,               // (reset, replace) the callback did not come back when interrupted
  Busy,               // (reset, replace) a passive component stayed busy: its thread could not be had
};                    // Hung or Busy at a stop or an emergency count as Failed.
std::string_view toString(Outcome o);

/// What the decision needs to know of the component's role and of this fault so far.
struct RoleFacts {
  bool has_alternative = false;    // the rules name an alternative
  bool replaced = false;           // the alternative already took the role (a role is replaced once)
  bool alternative_ready = false;  // (Hung) an alternative was created and can take over
  bool emergency_done = false;     // this fault already ran an emergency stop
};

struct Decision {
  Step next = Step::Done;
  bool escalates = false;  // logged as an `escalate` action: "<step> → <next>: <why>"
  std::string_view why;    // the reason, for the log (empty when not an escalation)
};

/// The step a new fault of a role starts with; Done when the role is already being handled or
/// was stopped (`why` says which), Step::Ignore for the `ignore` severity.
struct FirstStep {
  profile::Severity severity = profile::Severity::Ignore;
  Step step = Step::Done;
  std::string_view why;  // when step is Done: why the fault is only logged
};
FirstStep firstStep(const Rules& rules, FaultKind kind, bool busy, bool stopped);

/// What comes after `step`, which ended with `outcome`.
Decision decide(Step step, Outcome outcome, const RoleFacts& role);

/// The restart intensity (Erlang/OTP's intensity and period): the times of the last
/// `intensity` recoveries of a role. Resets and replacements both count.
class RestartWindow {
 public:
  RestartWindow() = default;
  RestartWindow(int intensity, std::int64_t period_ns);

  /// True when one more recovery at `now_ns` would be more than `intensity` within `period`.
  bool exceededAt(std::int64_t now_ns) const;
  /// Records a recovery at `now_ns`. Allocates nothing after construction.
  void note(std::int64_t now_ns);

 private:
  int intensity_ = 3;
  std::int64_t period_ns_ = 10'000'000'000;
  std::vector<std::int64_t> times_;  // a ring of the last `intensity` recovery times
  std::size_t next_ = 0;             // the oldest, once the ring is full
};

}  // namespace keel::fault
