#include "fault/fault_manager.hpp"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <array>
#include <chrono>

#include "fault/on_thread.hpp"
#include "runtime/component_core.hpp"
#include "runtime/executor.hpp"
#include "runtime/invoke.hpp"

namespace keel::fault {
using runtime::coreOf;
using namespace std::chrono_literals;

FaultManager::FaultManager(log::FaultLog& log, std::function<Component*(std::string_view)> find)
    : find_(std::move(find)), records_(log), containment_(records_, [this](std::string_view n) { return find_(n); }),
      queue_([this](HandlingItem& item) { process(item); }) {}

FaultManager::~FaultManager() { stop(); }

void FaultManager::attach(RecoveryActions* actions, const DependencyGraph* graph) {
  actions_ = actions;
  recovery_.attach(actions);
  containment_.attach(actions, graph);
}

void FaultManager::start() { queue_.start(); }
void FaultManager::stop() { queue_.stop(); }
void FaultManager::drain() { queue_.drain(); }

// ---- detection: any thread --------------------------------------------------------------

std::uint64_t FaultManager::report(Component& reporter, const FaultEvent& fault, std::string_view detector,
                                   bool recoverable, const FaultReport::Caught* caught) {
  FaultReport r = diagnose(reporter, fault, detector, find_, ids_, recoverable);
  if (caught) r.caught = *caught;
  Component* accused = r.accused;
  if (r.first != Step::Ignore && r.first != Step::Done && allowed(accused->state(), Transition::Fault)) {
    r.noteState(runtime::setStateQuiet(*accused, State::Error), true);  // logged with the detection
  }
  if (handlingOf(*accused) == nullptr && r.next != Step::Ignore) {  // not managed (no runtime): contained only
    r.add(ActionKind::Stop, true, r.event.t_ns, "contained: the component stays in Error");
    r.next = Step::Done;
  }
  r.diagnosed_ns = runtime::steadyNs();
  unsigned where = onManagerThread() || !queue_.running() ? kManager : 0;
  if (runtime::Executor* ex = coreOf(*accused).executor.load(std::memory_order_acquire);
      ex && ex->onThisThread() && runtime::runningComponent() != accused)
    where |= kLocal;
  const std::uint64_t id = r.id;
  advance(r, where);
  return id;
}

// ---- the handling state machine: the parts act, escalation decides -----------------------

void FaultManager::escalate(FaultReport& r, Step step, Outcome outcome, std::string_view detail) {
  ComponentHandling* h = handlingOf(*r.accused);
  RoleFacts facts;
  if (h) {
    std::lock_guard lock(h->mutex);
    facts = h->facts();
  }
  facts.emergency_done = r.emergency_done;
  const Decision d = decide(step, outcome, facts);
  if (d.escalates)
    r.add(ActionKind::Escalate, true, runtime::steadyNs(), FMT_COMPILE("{} → {}: {}"), toString(step), toString(d.next),
          detail.empty() ? d.why : detail);
  r.next = d.next;
}

void FaultManager::advance(FaultReport& r, unsigned where) {
  ComponentHandling* h = handlingOf(*r.accused);
  for (;;) {
    switch (r.next) {
      case Step::Ignore:
        r.add(ActionKind::Ignore, true, runtime::steadyNs(), "{}",
              h && h->rules.has_policy ? "severity ignore: logged only" : "no fault_policy: logged only");
        r.next = Step::Done;
        break;
      case Step::Done: finish(r, where); return;
      case Step::Reset: {
        if (!(where & kLocal)) return handOverLocal(r, where);
        if (recovery_.intensityAt(*h, runtime::steadyNs()) == Outcome::IntensityExceeded) {
          // Formatted in place: this thread goes on to the replacement's first step.
          std::array<char, 80> why{};
          fmt::format_to_n(why.data(), why.size() - 1, FMT_COMPILE("more than {} recoveries within {} ms"),
                           h->rules.intensity, h->rules.period_ns / 1'000'000);
          escalate(r, Step::Reset, Outcome::IntensityExceeded, why.data());
          break;
        }
        escalate(r, Step::Reset, recovery_.reset(r, *h));
        break;
      }
      case Step::Replace: {
        // Not limited by the restart intensity (docs/fault-handling.md): a role is replaced at
        // most once, and a reset escalates here precisely because the intensity was exceeded.
        bool available = false;
        Component* ready = nullptr;
        {
          std::lock_guard lock(h->mutex);
          available = h->rules.alternative && !h->replaced;
          ready = h->ready_alternative;
        }
        if (!available) {
          escalate(r, Step::Replace, Outcome::Unavailable);
          break;
        }
        if (ready == nullptr) {
          // Not preloaded: load it now, on the component's own thread when this is it (no
          // thread hand-off: under load a wake-up costs more than the dlopen; the executor's
          // other members are one cycle late instead), else on the manager's.
          if (!(where & (kLocal | kManager))) return handOverLocal(r, where);
          if (recovery_.load(r, *h) != Outcome::Done) {
            escalate(r, Step::Replace, Outcome::Failed);
            break;
          }
        }
        if (!(where & kLocal)) return handOverLocal(r, where);
        const Outcome replaced = recovery_.replace(r, *h);
        escalate(r, Step::Replace, replaced, replaced == Outcome::Failed ? "the alternative did not start" : "");
        break;
      }
      case Step::Stop: {
        if (!(where & kManager)) return handOverManager(r);
        const Outcome stopped = containment_.stopScope(r, *h);
        escalate(r, Step::Stop, stopped, fmt::format("{} cannot be stopped", r.event.componentName()));
        break;
      }
      case Step::Emergency: {
        if (!(where & kManager)) return handOverManager(r);
        records_.logReport(r);  // what happened so far goes first
        const auto ran = containment_.emergencyStop(fmt::format("fault {} of {}", r.id, r.event.componentName()), r.id,
                                                    r.event.componentName());
        r.add(ActionKind::EmergencyStop, true, runtime::steadyNs(), "onEmergencyStop ran in {} components", ran.size());
        r.logged_actions = r.n_actions;  // emergencyStop wrote its own record
        r.emergency_done = true;
        escalate(r, Step::Emergency, Outcome::Done);
        break;
      }
    }
  }
}

void FaultManager::handOverLocal(FaultReport& r, unsigned where) {
  auto& core = coreOf(*r.accused);
  runtime::Executor* ex = core.executor.load(std::memory_order_acquire);
  ComponentHandling* h = handlingOf(*r.accused);
  if (ex == nullptr && runtime::runningComponent() == r.accused) {
    // A passive component that faulted inside its own callback, on this thread: its lock is
    // recursive, so taking it here would run the recovery nested inside that callback. The
    // guard carries on with runPending as soon as the callback returns.
    std::lock_guard lock(h->mutex);
    h->pending = r;
    core.fault.pending.store(true, std::memory_order_release);
    return;
  }
  if (ex == nullptr) {  // passive: holding its lock makes this thread its own
    if (!(where & kManager)) return handOverManager(r);
    std::unique_lock lock(core.passive_mutex, std::defer_lock);
    if (!waitFor(1s, [&] { return lock.try_lock(); })) {
      escalate(r, r.next, Outcome::Busy);
      return advance(r, where);
    }
    return advance(r, where | kLocal);
  }
  {
    std::lock_guard lock(h->mutex);
    h->pending = r;
  }
  core.fault.pending.store(true, std::memory_order_release);
  // Inside its own callback on this thread (a range fault on push, raiseFault): invoke()
  // carries on as soon as the callback returns.
  if (ex->onThisThread()) return;
  Component* c = r.accused;
  ex->post([this, c, ex] {
    runPending(*c);
    // Recovered between cycles (a cold replacement, a fault found by another thread): the
    // step it owes runs now rather than at the next release.
    Component* now = find_(c->instanceName());
    if (now && now->state() == State::Active && coreOf(*now).fault.recovering_id.load(std::memory_order_acquire) != 0 &&
        coreOf(*now).executor.load(std::memory_order_acquire) == ex)
      ex->runStep(*now);
  });
  // A hung callback never returns by itself: interrupt it on its thread, and have the manager
  // check that it came back (else its executor is abandoned: checkInterrupted).
  if (r.event.kind == FaultKind::Heartbeat && core.watch.callback_since_ns.load(std::memory_order_acquire) != 0) {
    core.fault.interrupt.store(true, std::memory_order_release);
    ex->interrupt();
    queue_.enqueue(HandlingItem::Type::CheckInterrupted, r, true);
  }
}

void FaultManager::handOverManager(FaultReport& r) { queue_.enqueue(HandlingItem::Type::Report, r, true); }

void FaultManager::runPending(Component& c) {
  auto& core = coreOf(c);
  ComponentHandling* h = handlingOf(c);
  if (h == nullptr) return;
  FaultReport r;
  {
    std::lock_guard lock(h->mutex);
    if (!core.fault.pending.exchange(false, std::memory_order_acq_rel)) return;
    r = h->pending;
  }
  core.fault.interrupt.store(false, std::memory_order_release);
  advance(r, kLocal | (onManagerThread() ? kManager : 0));
}

void FaultManager::finish(FaultReport& r, unsigned where) {
  if (ComponentHandling* h = handlingOf(*r.accused)) {
    std::lock_guard lock(h->mutex);
    if (r.first != Step::Ignore && r.first != Step::Done) h->busy = false;
  }
  Component* recovering = r.alternative ? r.alternative : r.accused;
  const bool awaits_recovery = coreOf(*recovering).fault.recovering_id.load(std::memory_order_relaxed) == r.id;
  if ((where & kManager) && onManagerThread()) {
    records_.logReport(r);
  } else {
    // A recovery wakes the manager with its `recovered` record; nothing else is on the path.
    queue_.enqueue(HandlingItem::Type::Report, r, !awaits_recovery);
  }
  // A passive component has no next step of its own: it is back as soon as it is Active, or,
  // when its stand-in says it recovers later, when that says so.
  if (awaits_recovery && coreOf(*recovering).executor.load() == nullptr &&
      !coreOf(*recovering).fault.recovers_later.load(std::memory_order_acquire)) {
    const std::int64_t at = coreOf(*recovering).fault.recovered_at_ns.exchange(0, std::memory_order_acq_rel);
    recovered(*recovering, at != 0 ? at : runtime::steadyNs());
  }
}

void FaultManager::recovered(Component& c, std::int64_t t_ns) {
  const std::uint64_t id = coreOf(c).fault.recovering_id.exchange(0, std::memory_order_acq_rel);
  if (id == 0) return;
  FaultReport r;  // only the id, the component and the time are read
  r.id = id;
  r.accused = &c;
  r.event.t_ns = t_ns;
  FaultEvent::copyInto(r.event.component, c.instanceName());
  queue_.enqueue(HandlingItem::Type::Recovered, r, true);
}

void FaultManager::peerBack(Component& c, std::uint64_t id, std::int64_t t_ns) {
  // Its recovering_id, if a reset set one, is not ours to clear: the component's next cycle
  // would log the same fault's recovery; the manager's thread logs the first of the two.
  FaultReport r;
  r.id = id;
  r.accused = &c;
  r.event.t_ns = t_ns;
  FaultEvent::copyInto(r.event.component, c.instanceName());
  queue_.enqueue(HandlingItem::Type::Recovered, r, true);
}

// ---- the manager's thread ----------------------------------------------------------------

void FaultManager::checkInterrupted(const FaultReport& handed) {
  auto& core = coreOf(*handed.accused);
  ComponentHandling* h = handlingOf(*handed.accused);
  if (h == nullptr) return;
  if (waitFor(kInterruptBound, [&] { return !core.fault.pending.load(std::memory_order_acquire); })) return;
  FaultReport r;
  {
    std::lock_guard lock(h->mutex);
    if (!core.fault.pending.exchange(false, std::memory_order_acq_rel)) return;  // it came back just now
    r = h->pending;
  }
  core.fault.interrupt.store(false, std::memory_order_release);
  recovery_.abandon(r, *h);
  advance(r, kManager);
}

void FaultManager::process(HandlingItem& item) {
  switch (item.type) {
    case HandlingItem::Type::Recovered:
      if (const auto h = records_.handling(item.report.id); h && h->recovered_ns != 0) return;  // logged already
      records_.logRecovered(item.report.id, item.report.event.componentName(), item.report.event.t_ns);
      return;
    case HandlingItem::Type::CheckInterrupted: checkInterrupted(item.report); return;
    case HandlingItem::Type::Report:
      records_.logReport(item.report);
      if (item.report.next != Step::Done) advance(item.report, kManager);
      return;
  }
}

void FaultManager::flushUndetected(const std::vector<Component*>& components) {
  for (Component* c : components) {
    auto& core = coreOf(*c);
    std::uint64_t id = core.injection.injected_id.exchange(0, std::memory_order_acq_rel);
    if (id == 0) continue;
    records_.logUndetected(id, c->instanceName(), core.injection.injected_t_ns.load());
  }
}

}  // namespace keel::fault
