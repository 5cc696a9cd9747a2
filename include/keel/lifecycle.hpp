// The six OPRoS lifecycle states and the transitions between them.
// The runtime is the only one that changes a component's state; `Error` is entered only by the
// runtime (a callback that faulted), never by a component. Header-only, constexpr.
//
//   Created --initialize--> Ready --start--> Active --stop--> Inactive --start--> Active
//   Ready | Inactive | Error | Created --destroy--> Destroyed
//   Created | Ready | Active | Inactive --(fault, runtime only)--> Error --recover--> Active
#pragma once

#include <string_view>

namespace keel {

enum class State {
  Created,    // instance constructed, onInitialize not yet run
  Ready,      // initialized (properties applied, onInitialize succeeded), not executing
  Active,     // started: its executor calls onExecute/onEvent
  Inactive,   // stopped after running; can be started again
  Error,      // a callback faulted; not executed until recovered (runtime only)
  Destroyed,  // onDestroy ran; the instance is about to be deleted
};

enum class Transition { Initialize, Start, Stop, Destroy, Fault, Recover };

/// The state a transition leads to from `from`, or `from` itself when the transition is not
/// allowed there (callers check with `allowed`).
constexpr bool allowed(State from, Transition t) {
  switch (t) {
    case Transition::Initialize: return from == State::Created;
    case Transition::Start: return from == State::Ready || from == State::Inactive;
    case Transition::Stop: return from == State::Active;
    case Transition::Destroy:
      return from == State::Created || from == State::Ready || from == State::Inactive || from == State::Error;
    case Transition::Fault:
      return from == State::Created || from == State::Active || from == State::Ready || from == State::Inactive;
    case Transition::Recover: return from == State::Error;
  }
  return false;
}

constexpr State target(Transition t) {
  switch (t) {
    case Transition::Initialize: return State::Ready;
    case Transition::Start: return State::Active;
    case Transition::Stop: return State::Inactive;
    case Transition::Destroy: return State::Destroyed;
    case Transition::Fault: return State::Error;
    case Transition::Recover: return State::Active;
  }
  return State::Error;
}

constexpr std::string_view toString(State s) {
  switch (s) {
    case State::Created: return "Created";
    case State::Ready: return "Ready";
    case State::Active: return "Active";
    case State::Inactive: return "Inactive";
    case State::Error: return "Error";
    case State::Destroyed: return "Destroyed";
  }
  return "?";
}

constexpr std::string_view toString(Transition t) {
  switch (t) {
    case Transition::Initialize: return "initialize";
    case Transition::Start: return "start";
    case Transition::Stop: return "stop";
    case Transition::Destroy: return "destroy";
    case Transition::Fault: return "fault";
    case Transition::Recover: return "recover";
  }
  return "?";
}

}  // namespace keel
