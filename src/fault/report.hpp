// One fault on its way through the fault manager: what was detected, how it is diagnosed and
// the actions taken so far. A fixed-size value: it is built and carried on fault paths
// (executor threads, a signal just caught), copied between threads, never allocated.
// ComponentHandling is what the fault manager keeps per component role (shared by a component
// and its replacement): its rules, the restart-intensity window (fault/escalation.hpp), whether
// the alternative is in use.
// Thread-safety: FaultReport is a plain value, one thread works on a copy at a time.
// ComponentHandling's fields after `mutex` are guarded by it.
#pragma once

#include <fmt/compile.h>

#include <array>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "fault/escalation.hpp"
#include "fault/rules.hpp"
#include "keel/component.hpp"
#include "keel/fault_event.hpp"
#include "runtime/component_core.hpp"
#include "runtime/fault_detail.hpp"
#include "runtime/guard.hpp"
#include "runtime/invoke.hpp"

namespace keel::fault {

/// The `action` values of the log (docs/fault-log.md).
enum class ActionKind : std::uint8_t { Ignore, Reset, Restore, Replace, Stop, EmergencyStop, Escalate };
std::string_view toString(ActionKind a);

struct Action {
  ActionKind kind = ActionKind::Ignore;
  bool ok = true;
  std::int64_t t_ns = 0;           // steady clock, when it ended
  std::array<char, 120> detail{};  // outcome detail, e.g. "reset → replace: restart intensity..."
};

struct FaultReport {
  FaultEvent event;  // kind and detail; component = the accused; t_ns = detected
  /// A fault the guard caught in a running callback gets its `event.detail` when its records
  /// are written (describeEvent, on the fault manager's thread): making text is no part of the
  /// recovery's path. Until then, what was caught and where.
  struct Caught {
    runtime::GuardOutcome outcome;
    const char* callback = nullptr;  // a static name (runtime::callbackName)
    const char* (*code_name)(int) = nullptr;
  };
  std::optional<Caught> caught;  // set: `event.detail` is still to be written from it
  std::array<char, 48> detector{};
  std::uint64_t id = 0;
  std::int64_t injected_ns = 0;   // 0: not injected
  std::int64_t diagnosed_ns = 0;  // when the rules had chosen the handling
  Component* accused = nullptr;
  Component* alternative = nullptr;  // set when the alternative took the role over
  profile::Severity severity = profile::Severity::Ignore;
  profile::Scope scope = profile::Scope::Component;  // the rules' containment scope
  bool has_policy = false;                           // the component has a <fault_policy>
  Step first = Step::Done;                           // the handling the rules chose
  Step next = Step::Done;                            // what is left to do
  bool detection_logged = false;
  bool emergency_done = false;  // a stop that fails escalates to emergency only once
  std::uint8_t n_actions = 0;
  std::uint8_t logged_actions = 0;
  std::array<Action, 10> actions{};

  /// A state change this fault's handling made, as runtime::setStateQuiet made it, and where it
  /// goes in the log: with the detection, or after the action added next (the step that made it).
  static constexpr std::uint8_t kWithDetection = 0xff;
  struct Change {
    runtime::StateChange change;
    std::uint8_t action = kWithDetection;  // index of the action it belongs to
  };
  std::uint8_t n_changes = 0;
  std::array<Change, 6> changes{};

  /// Writes `event.detail` from `caught`, once.
  void describeEvent() {
    if (!caught) return;
    caught->outcome.describe(event, caught->callback, caught->code_name);
    caught.reset();
  }

  /// Keeps `change` for the log: with the detection, or with the action about to be added.
  void noteState(const runtime::StateChange& change, bool with_detection = false) {
    if (change.from == change.to || n_changes == changes.size()) return;
    changes[n_changes++] = {change, with_detection ? kWithDetection : n_actions};
  }

  template <class... Args>
  void add(ActionKind kind, bool ok, std::int64_t t_ns, fmt::format_string<Args...> f, Args&&... args) {
    addFormatted(kind, ok, t_ns, f, std::forward<Args>(args)...);
  }
  /// The same with FMT_COMPILE("..."): what a recovery adds before the recovered component's
  /// next step. fmt's general formatting code, cold at a fault (faults are rare), costs a
  /// microsecond or two there; a compiled format string is a few plain copies.
  template <class S, class... Args, std::enable_if_t<fmt::detail::is_compiled_string<S>::value, int> = 0>
  void add(ActionKind kind, bool ok, std::int64_t t_ns, const S& f, Args&&... args) {
    addFormatted(kind, ok, t_ns, f, std::forward<Args>(args)...);
  }

 private:
  template <class S, class... Args>
  void addFormatted(ActionKind kind, bool ok, std::int64_t t_ns, const S& f, Args&&... args) {
    if (n_actions == actions.size()) return;  // never more than a handful: steps only go up
    Action& a = actions[n_actions++];
    a.kind = kind;
    a.ok = ok;
    a.t_ns = t_ns;
    auto r = fmt::format_to_n(a.detail.data(), a.detail.size() - 1, f, std::forward<Args>(args)...);
    *r.out = '\0';
  }
};

/// What the fault manager keeps per component role (shared by a component and its replacement).
struct ComponentHandling : runtime::FaultSlot {
  ComponentHandling() = default;
  ComponentHandling(Rules r, std::string instance)
      : rules(r), name(std::move(instance)), window(rules.intensity, rules.period_ns) {}

  Rules rules;
  std::string name;  // instance name

  std::mutex mutex;
  RestartWindow window;                    // the role's recent recoveries
  bool busy = false;                       // a fault of this component is being handled
  bool replaced = false;                   // the alternative took its place: no further replacement
  bool stopped = false;                    // fault-stopped: further faults are only logged
  Component* ready_alternative = nullptr;  // created and initialized, not started
  FaultReport pending;                     // handed to the component's own thread (core.fault.pending)

  /// The facts the escalation decision needs (call with `mutex` held).
  RoleFacts facts() const { return {rules.alternative != nullptr, replaced, ready_alternative != nullptr, false}; }
};

/// The handling of `c`'s role (null before the engine set the rules up).
inline ComponentHandling* handlingOf(Component& c) {
  return static_cast<ComponentHandling*>(runtime::coreOf(c).fault.handling);
}

}  // namespace keel::fault
