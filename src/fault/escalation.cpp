#include "fault/escalation.hpp"

#include <algorithm>

namespace keel::fault {
namespace {

/// After a reset that did not do: the alternative while the role has one left, else a stop.
Step replaceOrStop(const RoleFacts& role) {
  return role.has_alternative && !role.replaced ? Step::Replace : Step::Stop;
}

}  // namespace

std::string_view toString(Outcome o) {
  switch (o) {
    case Outcome::Done: return "done";
    case Outcome::Failed: return "failed";
    case Outcome::IntensityExceeded: return "intensity exceeded";
    case Outcome::Unavailable: return "unavailable";
    case Outcome::Hung: return "hung";
    case Outcome::Busy: return "busy";
  }
  return "?";
}

FirstStep firstStep(const Rules& rules, FaultKind kind, bool busy, bool stopped) {
  FirstStep f;
  f.severity = rules.severityOf(kind);
  f.step = rules.firstStep(f.severity);
  if (f.step == Step::Ignore) return f;
  if (stopped) {
    f.step = Step::Done;
    f.why = "the component is stopped";
  } else if (busy) {
    f.step = Step::Done;
    f.why = "a fault of it is being handled";
  }
  return f;
}

Decision decide(Step step, Outcome outcome, const RoleFacts& role) {
  if (outcome == Outcome::Done) {
    // An emergency stop is followed by what `stop` does; every other step that did is the end.
    if (step == Step::Emergency) return {replaceOrStop(role), false, {}};
    return {Step::Done, false, {}};
  }
  // The local steps need the component's own thread. When it is lost (a hung callback that
  // did not come back) or cannot be had (a passive component that stays busy), only what does
  // not run on it is left: an alternative on a new thread, or a stop.
  const bool local = step == Step::Reset || step == Step::Replace;
  if (local && outcome == Outcome::Hung)
    return {role.alternative_ready ? Step::Replace : Step::Stop, true,
            "the hung callback did not return when interrupted"};
  if (local && outcome == Outcome::Busy) return {Step::Stop, true, "the passive component stays busy"};
  switch (step) {
    case Step::Ignore:
    case Step::Done: return {Step::Done, false, {}};
    case Step::Reset:
      return {replaceOrStop(role), true,
              outcome == Outcome::IntensityExceeded ? "restart intensity exceeded" : "the reset failed"};
    case Step::Replace:
      if (outcome == Outcome::Unavailable)
        return {Step::Stop, true, role.has_alternative ? "the alternative is already in place" : "no alternative"};
      return {Step::Stop, true, "the replacement failed"};
    case Step::Stop:
      // A stop that cannot be carried out leaves a thread keel cannot control: make the robot
      // safe — once; after an emergency there is nothing further to escalate to.
      if (role.emergency_done) return {Step::Done, false, {}};
      return {Step::Emergency, true, "the component cannot be stopped"};
    case Step::Emergency: return {replaceOrStop(role), false, {}};
  }
  return {Step::Done, false, {}};
}

RestartWindow::RestartWindow(int intensity, std::int64_t period_ns) : intensity_(intensity), period_ns_(period_ns) {
  times_.reserve(static_cast<std::size_t>(std::max(intensity, 0)));
}

bool RestartWindow::exceededAt(std::int64_t now_ns) const {
  if (intensity_ <= 0) return true;
  if (times_.size() < static_cast<std::size_t>(intensity_)) return false;
  // The oldest of the last `intensity` recoveries is the next slot to be overwritten.
  return now_ns - times_[next_] < period_ns_;
}

void RestartWindow::note(std::int64_t now_ns) {
  if (intensity_ <= 0) return;
  if (times_.size() < static_cast<std::size_t>(intensity_)) {
    times_.push_back(now_ns);
    next_ = times_.size() % static_cast<std::size_t>(intensity_);
    return;
  }
  times_[next_] = now_ns;
  next_ = (next_ + 1) % times_.size();
}

}  // namespace keel::fault
