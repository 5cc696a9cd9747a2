#include "fault/fault_manager.hpp"

#include <fmt/format.h>
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>

#include "fault/fault_manager_component.hpp"
#include "runtime/checkpoint.hpp"
#include "runtime/component_core.hpp"
#include "runtime/executor.hpp"
#include "runtime/injection.hpp"
#include "runtime/invoke.hpp"

namespace keel::fault {
namespace {

using runtime::coreOf;
using namespace std::chrono_literals;

constexpr std::size_t kQueueCapacity = 512;
// How long the emergency stop waits for an executor to run onEmergencyStop before it runs it
// on its own thread (the executor is taken to be hung).
constexpr auto kEmergencyBound = 20ms;
// How long a fault stop waits for a hung callback to come back after it was interrupted.
constexpr auto kInterruptBound = 200ms;

ComponentHandling* handlingOf(Component& c) { return static_cast<ComponentHandling*>(coreOf(c).handling); }

template <class Pred>
bool waitFor(std::chrono::nanoseconds bound, Pred done) {
  const auto until = std::chrono::steady_clock::now() + bound;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= until) return false;
    std::this_thread::sleep_for(50us);
  }
  return true;
}

/// Runs `job` on `c`'s own thread (posted to its executor, or under a passive component's
/// lock), waiting at most `bound`; false if it did not run in time (it may still run later).
bool onItsThread(Component& c, std::chrono::nanoseconds bound, const std::function<void()>& job) {
  auto& core = coreOf(c);
  runtime::Executor* ex = core.executor.load(std::memory_order_acquire);
  if (ex == nullptr) {
    std::unique_lock lock(core.passive_mutex, std::defer_lock);
    if (!waitFor(bound, [&] { return lock.try_lock(); })) return false;
    job();
    return true;
  }
  if (ex->onThisThread()) {
    job();
    return true;
  }
  auto done = std::make_shared<std::atomic<bool>>(false);
  ex->post([job, done] {
    job();
    done->store(true, std::memory_order_release);
  });
  return waitFor(bound, [&] { return done->load(std::memory_order_acquire); });
}

}  // namespace

FaultManager::FaultManager(FaultLog& log, std::function<Component*(std::string_view)> find)
    : log_(log), find_(std::move(find)), ring_(kQueueCapacity) {}

FaultManager::~FaultManager() { stop(); }

void FaultManager::attach(HandlingHost* host, const DependencyGraph* graph) {
  host_ = host;
  graph_ = graph;
}

void FaultManager::start() {
  if (thread_.joinable()) return;
  stop_.store(false, std::memory_order_release);
  thread_ = std::thread([this] { run(); });
  while (thread_id_.load() == std::thread::id{}) std::this_thread::yield();
  std::lock_guard lock(queue_mutex_);
  accepting_ = true;
}

void FaultManager::stop() {
  if (!thread_.joinable()) return;
  {
    // From now on reporters handle their reports themselves; what is queued is the thread's.
    std::lock_guard lock(queue_mutex_);
    accepting_ = false;
  }
  stop_.store(true, std::memory_order_release);
  signal_.notify();
  thread_.join();
  thread_id_.store(std::thread::id{});
}

void FaultManager::drain() {
  if (thread_id_.load() == std::thread::id{}) return;
  const std::uint64_t target = enqueued_.load(std::memory_order_acquire);
  signal_.notify();
  waitFor(10s, [&] { return processed_.load(std::memory_order_acquire) >= target; });
}

// ---- detection: any thread --------------------------------------------------------------

void FaultManager::onFault(Component& reporter, const FaultEvent& fault, std::string_view detector) {
  const std::int64_t detected = fault.t_ns ? fault.t_ns : steadyNowNs();
  Component* accused = &reporter;
  if (fault.component[0] != '\0' && fault.componentName() != reporter.instanceName()) {
    if (Component* c = find_(fault.componentName())) accused = c;
  }
  auto& core = coreOf(*accused);
  core.faults.fetch_add(1, std::memory_order_relaxed);

  FaultReport r;
  r.event = fault;
  r.event.t_ns = detected;
  if (fault.component[0] == '\0') FaultEvent::copyInto(r.event.component, accused->instanceName());
  FaultEvent::copyInto(r.detector, detector.empty() ? std::string_view(reporter.instanceName()) : detector);
  r.accused = accused;

  // The injection this detection answers: one that manifested in the accused component, or a
  // corrupted value being pushed on this very thread (caught on delivery by the receiver).
  detail::ComponentCore* source = &core;
  std::uint64_t id = core.injected_id.exchange(0, std::memory_order_acq_rel);
  if (id == 0 && runtime::injectionInFlight()) {
    source = runtime::injectionInFlight();
    id = source->injected_id.exchange(0, std::memory_order_acq_rel);
  }
  if (id != 0) r.injected_ns = source->injected_t_ns.load(std::memory_order_acquire);
  r.id = id != 0 ? id : nextId();

  ComponentHandling* h = handlingOf(*accused);
  const Rules no_rules;
  const Rules& rules = h ? h->rules : no_rules;
  r.severity = rules.severityOf(fault.kind);
  r.first = r.next = rules.firstStep(r.severity);
  if (h && r.first != Step::Ignore) {
    std::lock_guard lock(h->mutex);
    if (h->busy || h->stopped) {
      r.first = r.next = Step::Done;
      r.add(ActionKind::Ignore, true, detected, "{}", h->stopped ? "the component is stopped" : "a fault of it is being handled");
    } else {
      h->busy = true;
    }
  }
  if (r.first != Step::Ignore && r.first != Step::Done && allowed(accused->state(), Transition::Fault)) {
    runtime::setStateQuiet(*accused, State::Error);  // logged with the detection
    r.entered_error = true;
  }
  if (h == nullptr && r.next != Step::Ignore) {  // not managed (no runtime): contained only
    r.add(ActionKind::Stop, true, detected, "contained: the component stays in Error");
    r.next = Step::Done;
  }
  r.diagnosed_ns = steadyNowNs();
  unsigned where = onManagerThread() || thread_id_.load() == std::thread::id{} ? kManager : 0;
  if (runtime::Executor* ex = core.executor.load(std::memory_order_acquire);
      ex && ex->onThisThread() && runtime::runningComponent() != accused)
    where |= kLocal;
  advance(r, where);
}

// ---- the handling state machine ----------------------------------------------------------

Step FaultManager::afterReset(ComponentHandling& h) {
  std::lock_guard lock(h.mutex);
  return h.rules.alternative && !h.replaced ? Step::Replace : Step::Stop;
}

void FaultManager::advance(FaultReport& r, unsigned where) {
  ComponentHandling* h = handlingOf(*r.accused);
  for (;;) {
    switch (r.next) {
      case Step::Ignore:
        r.add(ActionKind::Ignore, true, steadyNowNs(), "{}",
              h && h->rules.has_policy ? "severity ignore: logged only" : "no fault_policy: logged only");
        r.next = Step::Done;
        break;
      case Step::Done:
        finish(r, where);
        return;
      case Step::Reset: {
        if (!(where & kLocal)) return handOverLocal(r, where);
        const std::int64_t t = steadyNowNs();
        bool exceeded = false;
        {
          std::lock_guard lock(h->mutex);
          exceeded = h->intensityExceeded(t);
        }
        const Step to = afterReset(*h);
        if (exceeded) {
          r.add(ActionKind::Escalate, true, t, "reset → {}: more than {} recoveries within {} ms", toString(to),
                h->rules.intensity, h->rules.period_ns / 1'000'000);
          r.next = to;
        } else if (reset(r, *h)) {
          r.next = Step::Done;
        } else {
          r.add(ActionKind::Escalate, true, steadyNowNs(), "reset → {}: the reset failed", toString(to));
          r.next = to;
        }
        break;
      }
      case Step::Replace: {
        // Not limited by the restart intensity (docs/fault-handling.md): a role is replaced at
        // most once, and a reset escalates here precisely because the intensity was exceeded.
        bool available = false;
        Component* standby = nullptr;
        {
          std::lock_guard lock(h->mutex);
          available = h->rules.alternative && !h->replaced;
          standby = h->standby;
        }
        if (!available) {
          r.add(ActionKind::Escalate, true, steadyNowNs(), "replace → stop: {}",
                !h->rules.alternative ? "no alternative" : "the alternative is already in place");
          r.next = Step::Stop;
          break;
        }
        if (standby == nullptr) {
          // Not preloaded: load it now, on the component's own thread when this is it (no
          // thread hand-off: under load a wake-up costs more than the dlopen; the executor's
          // other members are one cycle late instead), else on the manager's.
          if (!(where & (kLocal | kManager))) return handOverLocal(r, where);
          auto alt = host_ ? host_->createAlternative(*h, *r.accused) : Result<Component*>(fail("no runtime"));
          if (!alt) {
            r.add(ActionKind::Replace, false, steadyNowNs(), "loading the alternative failed: {}", alt.error().message);
            r.add(ActionKind::Escalate, true, steadyNowNs(), "replace → stop: the replacement failed");
            r.next = Step::Stop;
            break;
          }
          std::lock_guard lock(h->mutex);
          h->standby = *alt;
        }
        if (!(where & kLocal)) return handOverLocal(r, where);
        if (replace(r, *h)) {
          r.next = Step::Done;
        } else {
          r.add(ActionKind::Escalate, true, steadyNowNs(), "replace → stop: the alternative did not start");
          r.next = Step::Stop;
        }
        break;
      }
      case Step::Stop:
        if (!(where & kManager)) return handOverManager(r);
        stopScope(r, *h);
        break;
      case Step::Emergency: {
        if (!(where & kManager)) return handOverManager(r);
        logReport(r);  // what happened so far goes first
        const auto ran = emergencyStop(fmt::format("fault {} of {}", r.id, r.event.componentName()));
        r.add(ActionKind::EmergencyStop, true, steadyNowNs(), "onEmergencyStop ran in {} components", ran.size());
        r.logged_actions = r.n_actions;  // emergencyStop wrote its own record
        r.emergency_done = true;
        std::lock_guard lock(h->mutex);
        r.next = h->rules.alternative && !h->replaced ? Step::Replace : Step::Stop;
        break;
      }
    }
  }
}

void FaultManager::handOverLocal(FaultReport& r, unsigned where) {
  auto& core = coreOf(*r.accused);
  runtime::Executor* ex = core.executor.load(std::memory_order_acquire);
  if (ex == nullptr) {  // passive: holding its lock makes this thread its own
    if (!(where & kManager)) return handOverManager(r);
    std::unique_lock lock(core.passive_mutex, std::defer_lock);
    if (!waitFor(1s, [&] { return lock.try_lock(); })) {
      r.add(ActionKind::Escalate, true, steadyNowNs(), "{} → stop: the passive component stays busy", toString(r.next));
      r.next = Step::Stop;
      return advance(r, where);
    }
    return advance(r, where | kLocal);
  }
  ComponentHandling* h = handlingOf(*r.accused);
  {
    std::lock_guard lock(h->mutex);
    h->pending = r;
  }
  core.pending.store(true, std::memory_order_release);
  // Inside its own callback on this thread (a range fault on push, raiseFault): invoke()
  // carries on as soon as the callback returns.
  if (ex->onThisThread()) return;
  Component* c = r.accused;
  ex->post([this, c, ex] {
    runPending(*c);
    // Recovered between cycles (a cold replacement, a fault found by another thread): the
    // step it owes runs now rather than at the next release.
    Component* now = find_(c->instanceName());
    if (now && now->state() == State::Active && coreOf(*now).recovering_id.load(std::memory_order_acquire) != 0 &&
        coreOf(*now).executor.load(std::memory_order_acquire) == ex)
      ex->runStep(*now);
  });
  // A hung callback never returns by itself: interrupt it on its thread, and have the manager
  // check that it came back (else its executor is abandoned: checkInterrupted).
  if (r.event.kind == FaultKind::Heartbeat && core.callback_since_ns.load(std::memory_order_acquire) != 0) {
    core.interrupt.store(true, std::memory_order_release);
    ex->interrupt();
    enqueue(Item::Type::CheckInterrupted, r, true);
  }
}

void FaultManager::handOverManager(FaultReport& r) {
  enqueue(Item::Type::Report, r, true);
}

void FaultManager::runPending(Component& c) {
  auto& core = coreOf(c);
  ComponentHandling* h = handlingOf(c);
  if (h == nullptr) return;
  FaultReport r;
  {
    std::lock_guard lock(h->mutex);
    if (!core.pending.exchange(false, std::memory_order_acq_rel)) return;
    r = h->pending;
  }
  core.interrupt.store(false, std::memory_order_release);
  advance(r, kLocal | (onManagerThread() ? kManager : 0));
}

void FaultManager::finish(FaultReport& r, unsigned where) {
  if (ComponentHandling* h = handlingOf(*r.accused)) {
    std::lock_guard lock(h->mutex);
    if (r.first != Step::Ignore && r.first != Step::Done) h->busy = false;
  }
  Component* recovering = r.replacement ? r.replacement : r.accused;
  const bool awaits_recovery = coreOf(*recovering).recovering_id.load(std::memory_order_relaxed) == r.id;
  if ((where & kManager) && onManagerThread()) {
    logReport(r);
  } else {
    // A recovery wakes the manager with its `recovered` record; nothing else is on the path.
    enqueue(Item::Type::Report, r, !awaits_recovery);
  }
  // A passive component has no next step of its own: it is back as soon as it is Active.
  if (awaits_recovery && coreOf(*recovering).executor.load() == nullptr) recovered(*recovering, steadyNowNs());
}

// ---- local recoveries: on the component's own thread -------------------------------------

bool FaultManager::reset(FaultReport& r, ComponentHandling& h) {
  Component& c = *r.accused;
  auto& core = coreOf(c);
  if (c.state() != State::Error) runtime::setStateQuiet(c, State::Error);
  runtime::GuardOutcome failed;
  for (runtime::Callback cb : {runtime::Callback::Error, runtime::Callback::Reset}) {
    runtime::GuardOutcome out = runtime::invokeRecovery(c, cb);
    if (!out.ok() && failed.ok()) failed = out;
  }
  const std::int64_t checkpoint_t = runtime::restoreCheckpoint(core);
  core.stalled_until_ns.store(0, std::memory_order_relaxed);
  if (failed.ok()) failed = runtime::invokeRecovery(c, runtime::Callback::Recover);
  const std::int64_t t = steadyNowNs();
  if (!failed.ok()) {
    FaultEvent why;
    failed.describe(why, "recovery");
    r.add(ActionKind::Reset, false, t, "{}", why.detailText());
    return false;
  }
  runtime::setStateQuiet(c, State::Active);
  r.add(ActionKind::Reset, true, t, "onError → onReset → onRecover");
  if (!core.critical.empty()) {
    if (checkpoint_t != 0)
      r.add(ActionKind::Restore, true, t, "critical memory restored from the checkpoint of {:.3f} ms before",
            (r.event.t_ns - checkpoint_t) / 1e6);
    else
      r.add(ActionKind::Restore, false, t, "no checkpoint yet: critical memory left as it was");
  }
  {
    std::lock_guard lock(h.mutex);
    h.noteRecovery(t);
  }
  markRecovering(r, c);
  return true;
}

bool FaultManager::replace(FaultReport& r, ComponentHandling& h) {
  Component* alt = nullptr;
  bool preloaded = false;
  {
    std::lock_guard lock(h.mutex);
    alt = h.standby;
    h.standby = nullptr;
    h.replaced = true;
    preloaded = h.rules.preload;
  }
  Component& failed = *r.accused;
  const std::size_t copied = runtime::copyCheckpoint(coreOf(failed), coreOf(*alt));
  host_->switchTo(failed, *alt);
  r.replacement = alt;
  runtime::GuardOutcome out = runtime::invokeRecovery(*alt, runtime::Callback::Start);
  const std::int64_t t = steadyNowNs();
  if (!out.ok()) {
    runtime::setStateQuiet(*alt, State::Error);
    FaultEvent why;
    out.describe(why, "onStart");
    r.add(ActionKind::Replace, false, t, "alternative {}: {}", coreOf(*alt).class_name, why.detailText());
    return false;
  }
  runtime::setStateQuiet(*alt, State::Active);
  // Its own first checkpoint: what a later reset of the alternative returns to (the buffers
  // exist since its creation, so nothing is allocated here).
  if (!coreOf(*alt).critical.empty()) runtime::takeCheckpoint(coreOf(*alt), t);
  r.add(ActionKind::Replace, true, t, "alternative {} ({}) took over{}", coreOf(*alt).class_name,
        preloaded ? "preloaded" : "loaded at fault time", copied ? " with the checkpointed state" : "");
  {
    std::lock_guard lock(h.mutex);
    h.noteRecovery(t);
  }
  markRecovering(r, *alt);
  return true;
}

void FaultManager::markRecovering(FaultReport& r, Component& c) {
  coreOf(c).recovering_id.store(r.id, std::memory_order_release);
}

void FaultManager::recovered(Component& c, std::int64_t t_ns) {
  const std::uint64_t id = coreOf(c).recovering_id.exchange(0, std::memory_order_acq_rel);
  if (id == 0) return;
  FaultReport r;  // only the id, the component and the time are read
  r.id = id;
  r.accused = &c;
  r.event.t_ns = t_ns;
  FaultEvent::copyInto(r.event.component, c.instanceName());
  enqueue(Item::Type::Recovered, r, true);
}

// ---- the manager's thread: fault stop, emergency stop, the log --------------------------

void FaultManager::stopScope(FaultReport& r, ComponentHandling& h) {
  logReport(r);
  const std::string name(r.event.componentName());
  const profile::Scope scope = h.rules.scope;  // `component` without a policy
  std::set<std::string> targets = graph_ ? graph_->scopeOf(name, scope) : std::set<std::string>{};
  targets.insert(name);
  std::vector<std::string> components, applications;
  {
    std::lock_guard lock(mutex_);
    std::set<std::string> all = stopped_components_;
    all.insert(targets.begin(), targets.end());
    Impact impact;
    if (graph_) impact = graph_->impactOf(all);
    for (const auto& c : targets)
      if (!graph_ || !graph_->contains(c)) impact.stopped_components.push_back(c);
    for (const auto& c : impact.stopped_components)
      if (stopped_components_.insert(c).second) components.push_back(c);
    for (const auto& a : impact.stopped_applications)
      if (stopped_applications_.insert(a).second) applications.push_back(a);
  }
  Component* faulty = find_(name);
  for (const auto& n : components) {
    Component* c = find_(n);
    if (c == nullptr) continue;
    if (ComponentHandling* hc = handlingOf(*c)) {
      std::lock_guard lock(hc->mutex);
      hc->stopped = true;
    }
    if (c == faulty) continue;  // in Error: its executor no longer runs it
    auto stop = [c] { runtime::transition(*c, Transition::Stop); };
    if (runtime::Executor* ex = coreOf(*c).executor.load(std::memory_order_acquire)) ex->post(stop);
    else onItsThread(*c, 1s, stop);
  }
  // The faulty component's own callback may be the hung one: interrupt it so that its executor
  // comes back for the components it still runs.
  bool hung = false;
  if (faulty) {
    auto& core = coreOf(*faulty);
    runtime::Executor* ex = core.executor.load(std::memory_order_acquire);
    if (ex && !ex->abandoned() && core.callback_since_ns.load(std::memory_order_acquire) != 0) {
      core.interrupt.store(true, std::memory_order_release);
      ex->interrupt();
      hung = !waitFor(kInterruptBound, [&] { return core.callback_since_ns.load(std::memory_order_acquire) == 0; });
    }
  }
  const std::int64_t t = steadyNowNs();
  r.add(ActionKind::Stop, !hung, t, "scope {}: {} components, {} applications", toString(scope), components.size(),
        applications.size());
  r.logged_actions = r.n_actions;  // written here, with the lists
  nlohmann::json rec = {{"event", "action"},  {"fault_id", r.id},           {"component", name},
                        {"action", "stop"},   {"outcome", hung ? "failed" : "ok"}, {"scope", toString(scope)},
                        {"components", components}, {"applications", applications}, {"t_ns", log_.sinceStart(t)}};
  if (hung) rec["detail"] = "the hung callback did not return when interrupted";
  log_.write(std::move(rec));
  for (const auto& a : applications)
    log_.write({{"event", "state"}, {"application", a}, {"from", "running"}, {"to", "stopped"},
                {"fault_id", r.id}, {"t_ns", log_.sinceStart(t)}});
  r.next = Step::Done;
  if (hung && host_) {  // its executor cannot come back: the others move to a new thread
    auto moved = host_->abandonExecutor(*faulty, nullptr);
    r.add(ActionKind::Stop, static_cast<bool>(moved), steadyNowNs(), "executor abandoned{}{}", moved ? "; its other components now run on " : ": ",
          moved ? *moved : moved.error().message);
    if (!moved && !r.emergency_done) {  // a thread keel cannot control runs on: make the robot safe
      r.add(ActionKind::Escalate, true, steadyNowNs(), "stop → emergency: {} cannot be stopped", name);
      r.next = Step::Emergency;
    }
  }
}

void FaultManager::checkInterrupted(const FaultReport& handed) {
  auto& core = coreOf(*handed.accused);
  ComponentHandling* h = handlingOf(*handed.accused);
  if (h == nullptr) return;
  if (waitFor(kInterruptBound, [&] { return !core.pending.load(std::memory_order_acquire); })) return;
  FaultReport r;
  {
    std::lock_guard lock(h->mutex);
    if (!core.pending.exchange(false, std::memory_order_acq_rel)) return;  // it came back just now
    r = h->pending;
  }
  core.interrupt.store(false, std::memory_order_release);
  abandonHung(r, *h);
  advance(r, kManager);
}

void FaultManager::abandonHung(FaultReport& r, ComponentHandling& h) {
  Component& hung = *r.accused;
  const std::string from(toString(r.next));
  Component* alt = nullptr;
  bool available = false;
  {
    std::lock_guard lock(h.mutex);
    available = h.rules.alternative && !h.replaced;
    alt = h.standby;
  }
  if (available && alt == nullptr && host_) {
    auto made = host_->createAlternative(h, hung);
    if (made) alt = *made;
    else r.add(ActionKind::Replace, false, steadyNowNs(), "loading the alternative failed: {}", made.error().message);
  }
  if (alt) runtime::copyCheckpoint(coreOf(hung), coreOf(*alt));
  r.add(ActionKind::Escalate, true, steadyNowNs(), "{} → {}: the hung callback did not return when interrupted",
        from, alt ? "replace" : "stop");
  auto moved = host_ ? host_->abandonExecutor(hung, alt) : Result<std::string>(fail("no runtime"));
  const std::int64_t t = steadyNowNs();
  if (!moved) {
    r.add(ActionKind::Stop, false, t, "executor not abandoned: {}", moved.error().message);
    r.next = Step::Stop;
    return;
  }
  if (alt) {
    {
      std::lock_guard lock(h.mutex);
      h.standby = nullptr;
      h.replaced = true;
      h.noteRecovery(t);
    }
    r.replacement = alt;
    const bool started = alt->state() == State::Active;
    r.add(ActionKind::Replace, started, t, "alternative {} took over on the new executor {}", coreOf(*alt).class_name,
          *moved);
    if (started) markRecovering(r, *alt);
    r.next = started ? Step::Done : Step::Stop;
  } else {
    r.add(ActionKind::Stop, true, t, "executor abandoned; its other components now run on {}", *moved);
    r.next = Step::Stop;
  }
}

std::vector<std::string> FaultManager::emergencyStop(std::string_view by) {
  std::lock_guard guard(emergency_mutex_);
  emergency_.store(true, std::memory_order_release);
  std::vector<Component*> all = host_ ? host_->components() : std::vector<Component*>{};
  for (Component* c : all) coreOf(*c).emergency.store(true, std::memory_order_release);
  const std::int64_t t0 = steadyNowNs();
  log_.write({{"event", "emergency"}, {"phase", "latched"}, {"by", by}, {"t_ns", log_.sinceStart(t0)}});
  std::vector<std::string> ran, direct, late;
  for (Component* c : all) {
    if (c->instanceName() == kFaultManagerInstance) continue;
    // Whoever claims it first runs it: the executor, or this thread once the executor is late.
    auto claimed = std::make_shared<std::atomic<bool>>(false);
    auto done = std::make_shared<std::atomic<bool>>(false);
    auto job = [c, claimed, done] {
      if (claimed->exchange(true)) return;
      runtime::invokeRecovery(*c, runtime::Callback::EmergencyStop);
      done->store(true, std::memory_order_release);
    };
    if (!onItsThread(*c, kEmergencyBound, job)) {
      if (!claimed->exchange(true)) {
        runtime::invokeRecovery(*c, runtime::Callback::EmergencyStop);  // its executor is hung
        direct.push_back(c->instanceName());
      } else if (!waitFor(1s, [&] { return done->load(std::memory_order_acquire); })) {
        late.push_back(c->instanceName());  // its executor started it and has not finished
        continue;
      }
    }
    ran.push_back(c->instanceName());
  }
  const std::int64_t t = steadyNowNs();
  nlohmann::json rec = {{"event", "action"}, {"action", "emergency_stop"}, {"outcome", "ok"}, {"by", by},
                        {"components", ran},  {"t_ns", log_.sinceStart(t)}, {"latency_us", (t - t0) / 1e3}};
  if (!direct.empty()) rec["on_fault_manager_thread"] = direct;
  if (!late.empty()) {
    rec["outcome"] = "failed";
    rec["not_finished"] = late;
  }
  log_.write(std::move(rec));
  return ran;
}

bool FaultManager::clearEmergency(std::string_view by) {
  std::lock_guard guard(emergency_mutex_);
  if (!emergency_.exchange(false, std::memory_order_acq_rel)) return false;
  if (host_)
    for (Component* c : host_->components()) coreOf(*c).emergency.store(false, std::memory_order_release);
  log_.write({{"event", "emergency"}, {"phase", "cleared"}, {"by", by}});
  return true;
}

void FaultManager::enqueue(Item::Type type, const FaultReport& report, bool wake) {
  std::unique_lock lock(queue_mutex_);
  if (!accepting_ || onManagerThread()) {  // no thread (not started, or stopping): handle here
    lock.unlock();
    Item item{type, report};
    process(item);
    return;
  }
  while (size_ == ring_.size()) {  // full: let the manager catch up (never drops a fault)
    lock.unlock();
    signal_.notify();
    std::this_thread::yield();
    lock.lock();
  }
  Item& slot = ring_[(head_ + size_) % ring_.size()];  // one copy, straight into its slot
  slot.type = type;
  slot.report = report;
  ++size_;
  enqueued_.fetch_add(1, std::memory_order_release);
  lock.unlock();
  if (wake) signal_.notify();
}

void FaultManager::run() {
  pthread_setname_np(pthread_self(), "keel-faults");
  // Real-time when permitted (as the watchdog, one step below it): a cold replacement or a
  // fault stop must not queue behind the load it protects. Refused: normal priority, silently
  // (the watchdog already warned about the same limit).
  sched_param sp{};
  sp.sched_priority = sched_get_priority_max(SCHED_FIFO) - 1;
  (void)pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
  thread_id_.store(std::this_thread::get_id());
  auto item = std::make_unique<Item>();
  for (;;) {
    bool got = false;
    {
      std::lock_guard lock(queue_mutex_);
      if (size_ != 0) {
        *item = ring_[head_];
        head_ = (head_ + 1) % ring_.size();
        --size_;
        got = true;
      }
    }
    if (got) {
      process(*item);
      processed_.fetch_add(1, std::memory_order_release);
      continue;
    }
    if (stop_.load(std::memory_order_acquire)) break;
    // A recovery queues its report without a wake-up (nothing but the recovery may be on its
    // path); its `recovered` record, or the next step, wakes this thread. The timeout is only a
    // safety net: waking more often would put this real-time thread in the executors' way.
    signal_.waitUntil(runtime::WakeSignal::Clock::now() + 100ms);
  }
}

void FaultManager::process(Item& item) {
  if (item.type == Item::Type::Recovered) {
    logRecovered(item.report);
    return;
  }
  if (item.type == Item::Type::CheckInterrupted) {
    checkInterrupted(item.report);
    return;
  }
  FaultReport& r = item.report;
  logReport(r);
  if (r.next != Step::Done) advance(r, kManager);
}

void FaultManager::logReport(FaultReport& r) {
  const std::string who(r.event.componentName());
  const std::string kind(toString(r.event.kind));
  std::lock_guard lock(mutex_);
  if (!r.detection_logged) {
    r.detection_logged = true;
    if (r.injected_ns != 0)
      log_.write({{"event", "injected"}, {"fault_id", r.id}, {"component", who},
                  {"t_ns", log_.sinceStart(r.injected_ns)}});
    log_.write({{"event", "detected"},
                {"fault_id", r.id},
                {"component", who},
                {"kind", kind},
                {"detail", r.event.detailText()},
                {"detector", std::string(r.detector.data())},
                {"t_ns", log_.sinceStart(r.event.t_ns)}});
    if (r.entered_error)
      log_.write({{"event", "state"}, {"component", who}, {"from", "Active"}, {"to", "Error"},
                  {"fault_id", r.id}, {"t_ns", log_.sinceStart(r.event.t_ns)}});
    ComponentHandling* h = handlingOf(*r.accused);
    const bool has_policy = h && h->rules.has_policy;
    log_.write({{"event", "diagnosed"},
                {"fault_id", r.id},
                {"component", who},
                {"severity", toString(r.severity)},
                {"rules", has_policy ? "fault_policy" : "none (contained, not recovered)"},
                {"scope", toString(h ? h->rules.scope : profile::Scope::Component)},
                {"handling", toString(r.first)},
                {"t_ns", log_.sinceStart(r.diagnosed_ns)}});
    detections_.push_back({r.id, who, r.event.kind, r.event.t_ns, r.injected_ns});
    detection_count_.store(detections_.size(), std::memory_order_release);
    auto fc = std::find_if(counts_.begin(), counts_.end(),
                           [&](const FaultCount& c) { return c.component == who && c.kind == kind; });
    if (fc != counts_.end()) ++fc->count;
    else counts_.push_back({who, kind, std::string(r.event.detailText()), 1});
    handlings_.push_back({r.id, who, r.event.kind, std::string(toString(r.severity)), {}, false, r.event.t_ns,
                          r.injected_ns, 0});
  }
  auto hd = std::find_if(handlings_.rbegin(), handlings_.rend(), [&](const Handling& x) { return x.fault_id == r.id; });
  for (std::size_t i = r.logged_actions; i < r.n_actions; ++i) {  // what is new since last time
    const Action& a = r.actions[i];
    nlohmann::json rec = {{"event", "action"},         {"fault_id", r.id},
                          {"component", who},          {"action", toString(a.kind)},
                          {"outcome", a.ok ? "ok" : "failed"}, {"detail", std::string(a.detail.data())},
                          {"t_ns", log_.sinceStart(a.t_ns)}};
    if (a.kind == ActionKind::Replace && a.ok && r.replacement)
      rec["replacement"] = coreOf(*r.replacement).class_name;
    log_.write(std::move(rec));
    if (a.ok && (a.kind == ActionKind::Reset || a.kind == ActionKind::Replace))
      log_.write({{"event", "state"}, {"component", who}, {"from", "Error"}, {"to", "Active"},
                  {"fault_id", r.id}, {"t_ns", log_.sinceStart(a.t_ns)}});
  }
  if (hd != handlings_.rend()) {  // the summary's view: every action of this fault so far
    std::string rebuilt;
    bool failed = false;
    for (std::size_t i = 0; i < r.n_actions; ++i) {
      if (!rebuilt.empty()) rebuilt += ", ";
      rebuilt += toString(r.actions[i].kind);
      if (!r.actions[i].ok) rebuilt += " (failed)";
      failed |= !r.actions[i].ok && r.actions[i].kind != ActionKind::Restore;
    }
    hd->actions = std::move(rebuilt);
    hd->failed = failed;
  }
  r.logged_actions = r.n_actions;
}

void FaultManager::logRecovered(const FaultReport& r) {
  const std::int64_t t_ns = r.event.t_ns;
  std::lock_guard lock(mutex_);
  auto hd = std::find_if(handlings_.rbegin(), handlings_.rend(), [&](const Handling& x) { return x.fault_id == r.id; });
  nlohmann::json rec = {{"event", "recovered"}, {"fault_id", r.id}, {"component", std::string(r.event.componentName())},
                        {"t_ns", log_.sinceStart(t_ns)}};
  if (hd != handlings_.rend()) {
    hd->recovered_ns = t_ns;
    rec["latency_us"] = (t_ns - hd->detected_ns) / 1e3;
  }
  log_.write(std::move(rec));
  recovered_count_.fetch_add(1, std::memory_order_release);
}

// ---- readers -------------------------------------------------------------------------------

std::vector<FaultCount> FaultManager::counts() const {
  std::lock_guard lock(mutex_);
  return counts_;
}

std::vector<Detection> FaultManager::detections() const {
  std::lock_guard lock(mutex_);
  return detections_;
}

std::vector<Handling> FaultManager::handlings() const {
  std::lock_guard lock(mutex_);
  return handlings_;
}

std::optional<Handling> FaultManager::handling(std::uint64_t id) const {
  std::lock_guard lock(mutex_);
  for (auto it = handlings_.rbegin(); it != handlings_.rend(); ++it)
    if (it->fault_id == id) return *it;
  return std::nullopt;
}

std::set<std::string> FaultManager::stoppedComponents() const {
  std::lock_guard lock(mutex_);
  return stopped_components_;
}

std::set<std::string> FaultManager::stoppedApplications() const {
  std::lock_guard lock(mutex_);
  return stopped_applications_;
}

void FaultManager::flushUndetected(const std::vector<Component*>& components) {
  for (Component* c : components) {
    auto& core = coreOf(*c);
    std::uint64_t id = core.injected_id.exchange(0, std::memory_order_acq_rel);
    if (id == 0) continue;
    log_.write({{"event", "injected"}, {"fault_id", id}, {"component", c->instanceName()},
                {"t_ns", log_.sinceStart(core.injected_t_ns.load())}, {"detected", false}});
  }
}

}  // namespace keel::fault
