#include "fault/containment.hpp"

#include <chrono>
#include <memory>

#include "fault/on_thread.hpp"
#include "log/schema.hpp"
#include "plan/fault_manager_profile.hpp"
#include "runtime/component_core.hpp"
#include "runtime/executor.hpp"
#include "runtime/injection.hpp"
#include "runtime/invoke.hpp"

namespace keel::fault {
using runtime::coreOf;
using namespace std::chrono_literals;

void Containment::markStopped(const std::set<std::string>& targets, std::vector<std::string>& components,
                              std::vector<std::string>& applications) {
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

bool Containment::interruptHung(Component* faulty) {
  if (faulty == nullptr) return true;
  auto& core = coreOf(*faulty);
  runtime::Executor* ex = core.executor.load(std::memory_order_acquire);
  if (!ex || ex->abandoned() || core.watch.callback_since_ns.load(std::memory_order_acquire) == 0) return true;
  core.fault.interrupt.store(true, std::memory_order_release);
  ex->interrupt();
  return waitFor(kInterruptBound, [&] { return core.watch.callback_since_ns.load(std::memory_order_acquire) == 0; });
}

Outcome Containment::stopScope(FaultReport& r, ComponentHandling& h) {
  log::FaultLog& log = records_.log();
  records_.logReport(r);  // what happened so far goes first
  const std::string name(r.event.componentName());
  const profile::Scope scope = h.rules.scope;  // `component` without a policy
  std::set<std::string> targets = graph_ ? graph_->scopeOf(name, scope) : std::set<std::string>{};
  targets.insert(name);
  std::vector<std::string> components, applications;
  markStopped(targets, components, applications);
  Component* faulty = find_(name);
  for (const auto& n : components) {
    Component* c = find_(n);
    if (c == nullptr) continue;
    if (ComponentHandling* hc = handlingOf(*c)) {
      std::lock_guard lock(hc->mutex);
      hc->stopped = true;
    }
    if (c == faulty) {  // in Error: its executor no longer runs it, but a node of its runs on
      if (auto* process = dynamic_cast<runtime::ProcessTarget*>(c)) process->endProcess();
      continue;
    }
    auto stop = [c] { runtime::transition(*c, Transition::Stop); };
    if (runtime::Executor* ex = coreOf(*c).executor.load(std::memory_order_acquire)) ex->post(stop);
    else onItsThread(*c, 1s, stop);
  }
  // The faulty component's own callback may be the hung one: interrupt it so that its executor
  // comes back for the components it still runs.
  const bool hung = !interruptHung(faulty);
  const std::int64_t t = runtime::steadyNs();
  r.add(ActionKind::Stop, !hung, t, "scope {}: {} components, {} applications", toString(scope), components.size(),
        applications.size());
  r.logged_actions = r.n_actions;  // written here, with the lists
  nlohmann::json rec = log::schema::action(r.id, name, "stop", !hung, log.sinceStart(t));
  rec[log::schema::field::kScope] = toString(scope);
  rec[log::schema::field::kComponents] = components;
  rec[log::schema::field::kApplications] = applications;
  if (hung) rec[log::schema::field::kDetail] = "the hung callback did not return when interrupted";
  log.write(std::move(rec));
  for (const auto& a : applications)
    log.write(log::schema::applicationState(a, "running", "stopped", r.id, log.sinceStart(t)));
  if (!hung || actions_ == nullptr) return Outcome::Done;
  // Its executor cannot come back: the others move to a new thread.
  auto moved = actions_->abandonExecutor(*faulty, nullptr);
  r.add(ActionKind::Stop, static_cast<bool>(moved), runtime::steadyNs(), "executor abandoned{}{}",
        moved ? "; its other components now run on " : ": ", moved ? *moved : moved.error().message);
  return moved ? Outcome::Done : Outcome::Failed;
}

std::vector<std::string> Containment::emergencyStop(std::string_view by, std::uint64_t fault_id,
                                                    std::string_view component) {
  log::FaultLog& log = records_.log();
  std::lock_guard guard(emergency_mutex_);
  emergency_.store(true, std::memory_order_release);
  std::vector<Component*> all = actions_ ? actions_->components() : std::vector<Component*>{};
  for (Component* c : all) coreOf(*c).fault.emergency.store(true, std::memory_order_release);
  const std::int64_t t0 = runtime::steadyNs();
  nlohmann::json latched = log::schema::emergency("latched", by);
  latched[log::schema::field::kTime] = log.sinceStart(t0);
  log.write(std::move(latched));
  std::vector<std::string> ran, direct, late;
  for (Component* c : all) {
    if (c->instanceName() == plan::kFaultManagerInstance) continue;
    // Whoever claims it first runs it: the executor, or this thread once the executor is late.
    auto claimed = std::make_shared<std::atomic<bool>>(false);
    auto done = std::make_shared<std::atomic<bool>>(false);
    auto job = [c, claimed, done] {
      if (claimed->exchange(true)) return;
      runtime::invokeRecovery(*c, runtime::Callback::EmergencyStop);
      done->store(true, std::memory_order_release);
    };
    if (!onItsThread(*c, emergency_bound_, job)) {
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
  const std::int64_t t = runtime::steadyNs();
  nlohmann::json rec = log::schema::action(fault_id, component, "emergency_stop", late.empty(), log.sinceStart(t));
  rec[log::schema::field::kBy] = by;
  rec[log::schema::field::kComponents] = ran;
  rec[log::schema::field::kLatencyUs] = (t - t0) / 1e3;
  if (!direct.empty()) rec[log::schema::field::kOnFaultManagerThread] = direct;
  if (!late.empty()) rec[log::schema::field::kNotFinished] = late;
  log.write(std::move(rec));
  return ran;
}

bool Containment::clearEmergency(std::string_view by) {
  std::lock_guard guard(emergency_mutex_);
  if (!emergency_.exchange(false, std::memory_order_acq_rel)) return false;
  if (actions_)
    for (Component* c : actions_->components()) coreOf(*c).fault.emergency.store(false, std::memory_order_release);
  log::FaultLog& log = records_.log();
  log.write(log::schema::emergency("cleared", by));
  // The operator's step, as an emergency stop's is: an `action` a fault timeline shows.
  nlohmann::json rec = log::schema::action(0, {}, "clear", true, log.now());
  rec[log::schema::field::kBy] = by;
  log.write(std::move(rec));
  return true;
}

std::set<std::string> Containment::stoppedComponents() const {
  std::lock_guard lock(mutex_);
  return stopped_components_;
}

std::set<std::string> Containment::stoppedApplications() const {
  std::lock_guard lock(mutex_);
  return stopped_applications_;
}

}  // namespace keel::fault
