#include "runtime/invoke.hpp"

#include <mutex>

#include "runtime/checkpoint.hpp"
#include "runtime/clock.hpp"
#include "runtime/component_core.hpp"
#include "runtime/injection.hpp"
#include "runtime/port_access.hpp"

namespace keel::runtime {

const char* callbackName(Callback cb) {
  switch (cb) {
    case Callback::Initialize: return "onInitialize";
    case Callback::Start: return "onStart";
    case Callback::Stop: return "onStop";
    case Callback::Destroy: return "onDestroy";
    case Callback::Execute: return "onExecute";
    case Callback::Updated: return "onUpdated";
    case Callback::Event: return "onEvent";
    case Callback::Service: return "a service call";
    case Callback::Error: return "onError";
    case Callback::Reset: return "onReset";
    case Callback::Recover: return "onRecover";
    case Callback::EmergencyStop: return "onEmergencyStop";
  }
  return "?";
}

namespace {

ReturnCode call(Component& c, Callback cb) {
  switch (cb) {
    case Callback::Initialize: return c.onInitialize();
    case Callback::Start: return c.onStart();
    case Callback::Stop: return c.onStop();
    case Callback::Destroy: return c.onDestroy();
    case Callback::Execute: return c.onExecute();
    case Callback::Updated: return c.onUpdated();
    case Callback::Event:    // see dispatchEvents
    case Callback::Service:  // see service.cpp
      return ReturnCode::Ok;
    case Callback::Error: return c.onError();
    case Callback::Reset: return c.onReset();
    case Callback::Recover: return c.onRecover();
    case Callback::EmergencyStop: return c.onEmergencyStop();
  }
  return ReturnCode::Unsupported;
}

bool isLifecycle(Callback cb) {
  return cb == Callback::Initialize || cb == Callback::Start || cb == Callback::Stop || cb == Callback::Destroy;
}

}  // namespace

bool finishCall(Component& c, const GuardOutcome& out, Callback cb) {
  detail::ComponentCore& core = coreOf(c);
  if (out.kind == GuardOutcome::Kind::Signal && out.signo == interruptSignal()) [[unlikely]] {
    core.fault.interrupt.store(false, std::memory_order_release);
    if (core.fault_sink) core.fault_sink->runPending(c);
    return false;
  }
  if (!out.ok()) reportFailedCall(c, out, cb);
  // A fault noticed inside the call (a range fault on push, raiseFault) is handled now; the
  // call then counts as failed, so that a recovered component's step is run again.
  const bool pending = core.fault.pending.load(std::memory_order_acquire);
  if (pending && core.fault_sink) [[unlikely]]
    core.fault_sink->runPending(c);
  return out.ok() && !pending;
}

Component* runningComponent() {
  const guard_detail::GuardFrame* frame = guard_detail::currentFrame();
  return frame ? frame->owner : nullptr;  // the innermost guarded call's, as calls nest
}

void FaultSink::reportCaught(Component& c, const FaultEvent& fault, const GuardOutcome& caught, const char* callback,
                             const char* (*code_name)(int)) {
  FaultEvent described = fault;
  caught.describe(described, callback, code_name);
  report(c, described);
}

void reportFailedCall(Component& c, const GuardOutcome& out, Callback cb) {
  detail::ComponentCore& core = coreOf(c);
  FaultEvent ev;
  ev.t_ns = out.t_ns ? out.t_ns : steadyNs();
  FaultEvent::copyInto(ev.component, core.instance_name);
  if (!isLifecycle(cb)) {
    // A fault of a running callback is the fault manager's to handle by the component's rules;
    // its text is written where it is needed (the fault's records), not on its recovery's way.
    ev.kind = out.faultKind();
    if (core.fault_sink) core.fault_sink->reportCaught(c, ev, out, callbackName(cb), core.code_name);
    return;
  }
  // A failed lifecycle callback leaves the component in Error (no rule recovers it).
  out.describe(ev, callbackName(cb), core.code_name);
  core.transition_fault = ev.detailText();
  State s = core.state.load(std::memory_order_acquire);
  if (cb != Callback::Destroy && allowed(s, Transition::Fault)) setState(c, State::Error);
  if (core.fault_sink) core.fault_sink->reportFailedTransition(c, ev);
}

StateChange setState(Component& c, State to) {
  detail::ComponentCore& core = coreOf(c);
  const StateChange change{core.state.exchange(to, std::memory_order_acq_rel), to, steadyNs(), &c};
  if (change.from != to && core.hooks) core.hooks->stateChanged(c, change.from, to);
  return change;
}

StateChange setStateQuiet(Component& c, State to) {
  return {coreOf(c).state.exchange(to, std::memory_order_acq_rel), to, steadyNs(), &c};
}

void reportFault(Component& c, const FaultEvent& ev) {
  detail::ComponentCore& core = coreOf(c);
  if (core.fault_sink) core.fault_sink->report(c, ev);
}

bool invoke(Component& c, Callback cb) {
  detail::ComponentCore& core = coreOf(c);
  const bool watched = core.watch.heartbeat_ns != 0;
  if (watched) {
    const std::int64_t t = steadyNs();
    core.watch.callback_since_ns.store(t, std::memory_order_relaxed);
    if (cb == Callback::Execute) core.watch.last_beat_ns.store(t, std::memory_order_relaxed);
  }
  GuardOutcome out = guarded(
      [&c, &core, cb] {
        if (cb == Callback::Execute) {
          // acquire (free on x86): pairs with arm()'s release, so inject_id is the armed one.
          if (auto k = core.injection.kind.load(std::memory_order_acquire)) [[unlikely]] {
            core.injection.kind.store(0, std::memory_order_relaxed);
            return fire(c, static_cast<InjectKind>(k));
          }
        }
        return call(c, cb);
      },
      &c, &core.fault.interrupt);
  if (watched) core.watch.callback_since_ns.store(0, std::memory_order_relaxed);
  if (out.ok() && !core.fault.pending.load(std::memory_order_relaxed)) [[likely]]
    return true;
  return finishCall(c, out, cb);
}

GuardOutcome invokeRecovery(Component& c, Callback cb) {
  return guarded([&c, cb] { return call(c, cb); }, &c);
}

bool transition(Component& c, Transition t) {
  State from = c.state();
  if (!allowed(from, t)) return false;
  Callback cb = Callback::Initialize;
  switch (t) {
    case Transition::Initialize: cb = Callback::Initialize; break;
    case Transition::Start: cb = Callback::Start; break;
    case Transition::Stop: cb = Callback::Stop; break;
    case Transition::Destroy: cb = Callback::Destroy; break;
    case Transition::Recover: cb = Callback::Recover; break;
    case Transition::Fault: setState(c, State::Error); return true;
  }
  if (t == Transition::Destroy && from == State::Created) {  // never initialized: nothing to undo
    setState(c, State::Destroyed);
    return true;
  }
  detail::ComponentCore& core = coreOf(c);
  core.refused_property.clear();  // what an earlier call refused says nothing of this one
  core.refused_text.clear();
  bool ok = invoke(c, cb);
  if (ok || t == Transition::Destroy) setState(c, target(t));
  return ok;
}

void dispatchEvents(Component& c) {
  detail::ComponentCore& core = coreOf(c);
  if (!core.event_pending.exchange(false, std::memory_order_acq_rel)) return;
  for (detail::PortBase* p : core.ports) {
    if (p->kind() != PortKind::Event || p->direction() != PortDirection::Input) continue;
    auto& port = static_cast<InputEventPortBase&>(*p);
    while (c.state() == State::Active && detail::PortAccess::takeNext(port)) {
      GuardOutcome out = guarded([&c, &port] { return c.onEvent(port); }, &c, &core.fault.interrupt);
      if (!out.ok() || core.fault.pending.load(std::memory_order_relaxed)) finishCall(c, out, Callback::Event);
    }
  }
}

void dispatchEventsPassive(Component& c) {
  detail::ComponentCore& core = coreOf(c);
  std::lock_guard lock(core.passive_mutex);
  dispatchEvents(c);
  // A passive component's cycle boundary: its events handled, none of its callbacks running.
  if (c.state() == State::Active && !core.fault.pending.load(std::memory_order_relaxed))
    checkpointIfDue(core, steadyNs());
}

}  // namespace keel::runtime
