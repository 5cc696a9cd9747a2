// Engine: what the fault manager needs to handle faults (fault::RecoveryActions) — the compiled
// rules and the dependency graph set up at load, alternatives created ahead of time
// (preload="true") or at fault time, and the switch that puts an alternative in a failed
// component's place: its input connections re-pointed, its provided services rebound, its
// executor slot taken, lookups by name answering the alternative.
#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <set>

#include "engine/engine.hpp"
#include "fault/fault_manager_component.hpp"
#include "fault/rules.hpp"
#include "runtime/checkpoint.hpp"
#include "runtime/injection.hpp"
#include "runtime/invoke.hpp"

namespace keel::engine {

void Engine::setUpHandling() {
  if (auto g = fault::DependencyGraph::build(planned_.plan, set())) graph_ = std::move(*g);
  else warn("fault stops cover the component alone: " + g.error().message);
  for (auto& inst : instances_) {
    if (inst.plan->name == fault::kFaultManagerInstance) continue;  // the framework's own
    // The restart window is allocated whole here: recording a recovery never allocates on the
    // executor's thread.
    auto h = std::make_unique<fault::ComponentHandling>(
        fault::compileRules(inst.plan->policy ? &*inst.plan->policy : nullptr, set().components), inst.plan->name);
    runtime::coreOf(*inst.component).fault.handling = h.get();
    inst.handling = std::move(h);
  }
  fault_manager_.attach(this, graph());
}

Result<void> Engine::preloadAlternatives() {
  for (auto& inst : instances_) {
    if (!inst.handling || !inst.handling->rules.alternative) continue;
    if (!inst.handling->rules.preload) {
      if (inst.plan->node) continue;  // a node: its profile is read, its command found, at load
      // Loaded at a fault: its file is searched for now, off the fault's path (the loader
      // keeps the answer), and a missing one is said at start rather than at the fault.
      const profile::ComponentProfile& cp = *inst.handling->rules.alternative;
      if (auto lib = findLibrary(cp); !lib) {
        const auto& policy = inst.plan->policy;  // where the rule names it, else its own profile
        const profile::Where& where = policy && policy->alternative ? policy->alternative->where : cp.where;
        warn(fmt::format("{}: alternative '{}' of '{}', loaded at a fault, will not load: {}", where.str(), cp.name,
                         inst.plan->name, lib.error().message));
      }
      continue;
    }
    auto alt = createAlternative(*inst.handling, *inst.component);
    if (!alt) return alt.error();
    std::lock_guard lock(inst.handling->mutex);
    inst.handling->ready_alternative = *alt;
  }
  return {};
}

const profile::NodeProfile* Engine::alternativeNode(const plan::PlannedInstance& pi) const {
  if (pi.node == nullptr || !pi.policy || !pi.policy->alternative) return nullptr;
  const auto found = set().nodes.find(pi.policy->alternative->reference);
  return found == set().nodes.end() ? nullptr : &found->second;
}

Result<Component*> Engine::createAlternative(fault::ComponentHandling& h, Component& failed) {
  std::lock_guard creating(create_mutex_);  // executors may load alternatives concurrently
  auto it = std::find_if(instances_.begin(), instances_.end(),
                         [&](const Instance& i) { return i.plan->name == h.name; });
  if (it == instances_.end() || h.rules.alternative == nullptr) return fail("no alternative for '" + h.name + "'");
  const profile::ComponentProfile& cp = *h.rules.alternative;
  // A node's alternative is another node, started in its place by the stand-in's onStart.
  const profile::NodeProfile* node = alternativeNode(*it->plan);
  if (it->plan->node) {
    if (node == nullptr) return fail(fmt::format("{}: not a ROS 2 node's profile", cp.name));
  } else if (auto lib = findLibrary(cp); !lib) {
    // The fault's record keeps one short line; the warning at start said where keel looked.
    const std::string& why = lib.error().message;
    return fail(fmt::format("{}: {}", cp.name, why.substr(0, why.find(';'))));
  }
  const plan::PlannedInstance* plan = nullptr;
  {
    std::lock_guard lock(alternatives_mutex_);
    plan::PlannedInstance& p = alternative_plans_.emplace_back();
    p.name = it->plan->name;
    p.profile = &cp;
    for (const auto& prop : cp.properties) p.properties[prop.name] = prop.value;
    for (const auto& [k, v] : it->plan->properties)  // the subcomponent's values, where the alternative has them
      if (p.properties.count(k)) p.properties[k] = v;
    p.policy = it->plan->policy;
    p.application = it->plan->application;
    p.where = it->plan->where;
    p.node = node;
    plan = &p;
  }
  std::string refused;
  auto made = node ? Result<Instance>(makeStandIn(*plan, refused)) : makeInstance(*plan);
  if (made && node && !made->component) refused = "keel run runs no ROS 2 node here";
  if (made && !refused.empty()) made = fail(refused);
  if (!made) {
    std::string why = made.error().message;
    if (!why.empty() && why.back() == '\n') why.pop_back();
    return fail(why);
  }
  Component* alt = made->component.get();
  runtime::coreOf(*alt).fault.handling = &h;
  // Its `state` records are logged as the alternative's, out of service until the switch; a
  // failure is returned to the caller, not reported as a fault.
  detail::ComponentCore& alt_core = runtime::coreOf(*alt);
  alt_core.alternative = true;
  alt_core.fault_sink = nullptr;
  if (!runtime::transition(*alt, Transition::Initialize)) {
    // As any component whose onInitialize failed: onDestroy, never onStart or onStop.
    const std::string why = alt_core.transition_fault;
    runtime::transition(*alt, Transition::Destroy);
    return fail(fmt::format("{}: {}", cp.name, why.empty() ? "onInitialize returned an error" : why));
  }
  alt_core.fault_sink = &fault_manager_;
  // Allocates its checkpoint buffers now, off the fault path (the switch copies into them).
  if (!runtime::coreOf(*alt).critical.empty()) runtime::takeCheckpoint(runtime::coreOf(*alt), runtime::steadyNs());
  // Outputs and required services now (it sends nothing before it starts); inputs at the switch.
  for (const runtime::Wire& w : wires_) {
    if (w.source == nullptr || &w.source->owner() != &failed) continue;
    detail::PortBase* port = runtime::coreOf(*alt).findPort(w.source->name());
    if (port == nullptr) continue;  // the loader checked that the ports are the same
    if (w.connection) static_cast<detail::OutputPortBase*>(port)->attach(*w.connection);
    else static_cast<detail::ServicePortBase*>(port)->bind(*static_cast<detail::ServicePortBase*>(w.target));
  }
  // The fields of its messages that connections carry (taps_ grows here: by index, copied).
  for (std::size_t i = 0, n = taps_.size(); i < n; ++i) {
    if (taps_[i].owner != &failed) continue;
    const std::string field = taps_[i].field;
    detail::ConnectionBase& connection = *taps_[i].connection;
    detail::PortBase* port = runtime::coreOf(*alt).findPort(taps_[i].port);
    if (port == nullptr) continue;  // the loader checked that the ports are the same
    if (auto tapped = tapField(*port, field, connection); !tapped)
      warn(fmt::format("{}: field '{}' of port '{}': {}", cp.name, field, port->name(), tapped.error().message));
  }
  std::lock_guard lock(alternatives_mutex_);
  alternatives_.push_back(std::move(made->component));
  return alt;
}

void Engine::redirectInputs(Component& failed, Component& alternative) {
  for (const runtime::Wire& w : wires_) {
    if (w.target == nullptr || &w.target->owner() != &failed) continue;
    detail::PortBase* port = runtime::coreOf(alternative).findPort(w.target->name());
    if (port == nullptr) continue;  // the loader checked that the ports are the same
    if (w.connection) static_cast<detail::InputPortBase*>(port)->retarget(*w.connection);
    else static_cast<detail::ServicePortBase*>(w.source)->bind(*static_cast<detail::ServicePortBase*>(port));
  }
}

void Engine::switchTo(Component& failed, Component& alternative) {
  // The executor first: a value that reaches the alternative through a re-pointed connection
  // wakes the alternative's executor.
  if (runtime::Executor* ex = runtime::coreOf(failed).executor.load(std::memory_order_acquire))
    ex->replaceMember(failed, alternative);
  redirectInputs(failed, alternative);
  for (auto& inst : instances_) {
    if (inst.serving() != &failed) continue;
    inst.serving_slot->store(&alternative, std::memory_order_release);
    // A node's topics go into its alternative's stand-in from now on.
    if (inst.plan->node && dds_)
      dds_->nodeServedBy(inst.plan->name,
                         [&](const std::string& port) { return runtime::coreOf(alternative).findPort(port); });
  }
}

Result<std::string> Engine::abandonExecutor(Component& hung, Component* alternative) {
  runtime::Executor* old = runtime::coreOf(hung).executor.load(std::memory_order_acquire);
  if (old == nullptr) return fail("'" + hung.instanceName() + "' has no executor");
  runtime::ExecutorConfig cfg = old->config();
  cfg.name += "+";
  auto fresh = std::make_unique<runtime::Executor>(cfg, [this](const std::string& m) { warn(m); });
  // The old thread is stuck in `hung`'s callback and does not touch its members meanwhile;
  // abandon() makes sure it never does again should it come back.
  const std::vector<Component*> members = old->members();
  fresh->holdStop(stop_barrier_);  // in the barrier before the old one leaves it
  old->abandon();                  // reads no input from other processes any more either: the fresh one does
  for (runtime::ExternalInput* in : old->inputs()) fresh->addInput(*in);
  for (Component* m : members) {
    if (m != &hung) {
      fresh->add(*m);
    } else if (alternative) {
      fresh->add(*alternative);
      redirectInputs(hung, *alternative);
    }
  }
  for (auto& inst : instances_) {
    if (inst.executor == old && inst.serving() != &hung) inst.executor = fresh.get();
    if (alternative && inst.serving() == &hung) {
      inst.serving_slot->store(alternative, std::memory_order_release);
      inst.executor = fresh.get();
    }
  }
  if (alternative) {  // started here: its new executor does not run yet
    runtime::GuardOutcome out = runtime::invokeRecovery(*alternative, runtime::Callback::Start);
    runtime::setState(*alternative, out.ok() ? State::Active : State::Error);  // the manager's thread: logged now
    if (out.ok() && !runtime::coreOf(*alternative).critical.empty())
      runtime::takeCheckpoint(runtime::coreOf(*alternative), runtime::steadyNs());
  }
  fresh->start(/*adopt=*/true);
  std::string name = cfg.name;
  std::lock_guard lock(executors_mutex_);
  executors_.push_back(std::move(fresh));
  return name;
}

std::uint64_t Engine::peerLost(const std::string& instance, const FaultEvent& fault) {
  if (side_->quiet(instance)) return 0;  // a node not up: its death, start or stop speaks for it
  Component* c = find(instance);
  return c ? fault_manager_.report(*c, fault, "dds") : 0;
}

void Engine::peerBack(const std::string& instance, std::uint64_t id, std::int64_t t_ns) {
  if (Component* c = find(instance)) fault_manager_.peerBack(*c, id, t_ns);
}

// OK: running, no fault within kRecentFault. WARN: running, with a remote fault whose writer
// has not come back, or a fault within kRecentFault. ERROR: in Error, or stopped by fault
// handling. STALE: not running (not started yet, stopped, destroyed).
//
// A fault is diagnosed (counted in the accused's core, the accused set to Error) on the thread
// that detected it, and recorded later on the fault manager's: a fault the records do not have
// yet is taken from the core, so that an Error is never reported without its fault.
std::vector<dds::Health> Engine::health() const {
  struct Last {
    FaultKind kind = FaultKind::User;
    std::uint64_t id = 0;
    std::int64_t detected_ns = 0;
    std::string actions;
    bool recovered = false;
  };
  std::vector<dds::Health> out;
  const std::vector<fault::Handling> handlings = fault_manager_.handlings();
  const std::set<std::string> stopped = fault_manager_.stoppedComponents();
  for (const Instance& inst : instances_) {
    const Component* c = inst.serving();
    if (c == nullptr) continue;
    dds::Health h;
    const plan::PlannedInstance& pi = *inst.plan;
    const std::string app = pi.application.empty() ? planned_.plan.name : pi.application;
    const std::string name = pi.application.empty() ? pi.name : pi.name.substr(pi.application.size() + 1);
    h.name = fmt::format("keel/{}/{}", app, name);
    const State state = c->state();  // first: what made it Error is counted before
    const auto& core = runtime::coreOf(*c);
    const std::uint64_t diagnosed = core.faults.load(std::memory_order_acquire);
    h.state = std::string(toString(state));
    std::optional<Last> last;
    std::uint64_t recorded = 0;  // of these, of `c` itself
    for (const fault::Handling& x : handlings) {
      if (x.component != pi.name) continue;
      ++h.faults;
      recorded += x.accused == c ? 1 : 0;
      last = Last{x.kind, x.fault_id, x.detected_ns, x.actions, x.recovered_ns != 0};
    }
    if (diagnosed > recorded) {  // being handled, not recorded yet
      h.faults += diagnosed - recorded;
      last = Last{static_cast<FaultKind>(core.fault.last_kind.load(std::memory_order_relaxed)),
                  core.fault.last_id.load(std::memory_order_relaxed),
                  core.fault.last_ns.load(std::memory_order_relaxed), "being handled", false};
    }
    if (last)
      h.last_fault = fmt::format("{} (fault {}): {}{}", toString(last->kind), last->id, last->actions,
                                 last->recovered ? ", recovered" : "");
    if (state == State::Error || stopped.count(pi.name)) {
      h.level = dds::Health::Error;
      h.message = state == State::Error ? "in Error after a fault" : "stopped by fault handling";
    } else if (state != State::Active) {
      h.level = dds::Health::Stale;
      h.message = fmt::format("not running ({})", h.state);
    } else if (last && !last->recovered && last->kind == FaultKind::Remote) {
      h.level = dds::Health::Warn;
      h.message = "running; the writer of a topic it subscribes to is lost";
    } else if (last && runtime::steadyNs() - last->detected_ns < kRecentFault.count()) {
      h.level = dds::Health::Warn;
      h.message = fmt::format("running; a {} fault within the last {} s ({})", toString(last->kind),
                              kRecentFault.count() / 1'000'000'000, last->recovered ? "recovered" : "handled");
    } else {
      h.message = last ? "running; its faults recovered" : "running";
    }
    out.push_back(std::move(h));
  }
  return out;
}

}  // namespace keel::engine
