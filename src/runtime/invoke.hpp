// Running one component's callbacks: each under the guard (runtime/guard.hpp), a failure
// turned into a FaultEvent and reported to the runtime hooks, whose fault manager handles it by
// the component's rules (a failed lifecycle callback leaves it in Error). Lifecycle
// transitions check the OPRoS table (keel/lifecycle.hpp) first.
// Called by executors (on their thread) and by the engine for passive components and for
// initialize/destroy, which happen while no executor runs the component.
// Thread-safety: the caller guarantees that no other callback of `c` runs at the same time.
#pragma once

#include <cstdint>

#include "keel/component.hpp"
#include "runtime/guard.hpp"

namespace keel::runtime {

enum class Callback : std::uint8_t {
  Initialize,
  Start,
  Stop,
  Destroy,
  Execute,
  Updated,
  Event,
  Service,
  Error,
  Reset,
  Recover,
  EmergencyStop
};

const char* callbackName(Callback cb);

/// Runs `cb` on `c` under the guard. On failure the fault is recorded and reported (and may
/// already be recovered from when this returns). Returns true on success.
bool invoke(Component& c, Callback cb);

/// Performs a lifecycle transition: checks the table, runs the callback, sets the state.
/// Returns false when the transition is not allowed from the current state or its callback
/// failed (then the component is in Error, except for Destroy which always ends Destroyed).
bool transition(Component& c, Transition t);

/// Delivers every queued event of every input event port of `c` to onEvent.
void dispatchEvents(Component& c);

/// Passive components: delivers queued events on the calling thread, under the component's lock.
void dispatchEventsPassive(Component& c);

/// A change of a component's lifecycle state, as its one writer made it.
struct StateChange {
  State from = State::Created;
  State to = State::Created;
  std::int64_t t_ns = 0;                 // steady clock
  const Component* component = nullptr;  // the object that changed
};

// The lifecycle state's one writer: these two functions and transition() are the only code
// that sets it (component_core.hpp), and every change they make is recorded as it was made.

/// Sets the state and tells the hooks, which log it (runtime only: Error is entered here, never
/// by authors).
StateChange setState(Component& c, State to);

/// Sets the state without telling the hooks, for the fault path: the returned change is handed
/// to the fault's records (fault::FaultReport::noteState), which log it with the fault, off the
/// executor's thread.
StateChange setStateQuiet(Component& c, State to);

/// Runs a recovery callback (onError, onReset, onRecover, onEmergencyStop) under the guard and
/// returns the outcome; a failure is not reported as a new fault (the caller escalates).
GuardOutcome invokeRecovery(Component& c, Callback cb);

/// The component whose callback is running on this thread, or null between callbacks.
Component* runningComponent();

/// After a guarded call of `c`'s `cb` (made with `c` as owner and its interrupt flag): an
/// interrupt ends a hung call whose fault is already being handled (no new fault); a failure
/// is recorded; a fault noticed inside the call is handled now that it returned. True when the
/// call succeeded and nothing was pending.
bool finishCall(Component& c, const GuardOutcome& out, Callback cb);

/// Records a failed guarded call of `cb` and reports it; a failed lifecycle callback (not
/// Destroy) moves `c` to Error here, other failures are the fault manager's to handle.
void reportFailedCall(Component& c, const GuardOutcome& out, Callback cb);

/// Reports a fault detected outside a callback (port validity, watchdog, ...).
void reportFault(Component& c, const FaultEvent& ev);

}  // namespace keel::runtime
