#include "engine/engine.hpp"

#include "engine/host_side.hpp"
#include "engine/run_side.hpp"

#include "log/schema.hpp"
#include "runtime/clock.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <system_error>

#include <pthread.h>
#include <unistd.h>

#include "runtime/checkpoint.hpp"
#include "runtime/guard.hpp"
#include "runtime/invoke.hpp"

namespace keel::engine {

Engine::Engine(EngineOptions options)
    : options_(std::move(options)), loader_(options_.search_path),
      fault_manager_(log_, [this](std::string_view name) { return find(name); }) {}

Engine::~Engine() {
  shutdown();
  if (side_) side_->close();  // the supervisor's threads report to the fault manager: gone before it is
}

Result<std::unique_ptr<Engine>> Engine::create(profile::ProfileSet set, EngineOptions options) {
  auto planned = plan::planProfiles(std::move(set));
  if (!planned) return planned.error();
  if (auto r = plan::applyPropertySettings(planned->plan, options.property_settings); !r) return r.error();
  return create(std::move(*planned), std::move(options));
}

Result<std::unique_ptr<Engine>> Engine::create(plan::PlannedProfiles planned, EngineOptions options) {
  std::unique_ptr<Engine> engine(new Engine(std::move(options)));
  Engine* e = engine.get();
  e->planned_ = std::move(planned);
  if (supervision::ProcessHost* host = e->options_.host) e->side_ = std::make_unique<HostSide>(*e, *host);
  else e->side_ = std::make_unique<RunSide>(*e);
  if (auto r = e->side_->openLog(); !r) return r.error();
  if (!e->options_.check_only) {
    if (auto r = e->side_->setUpProcesses(); !r) return r.error();
  }
  if (auto r = e->instantiate(); !r) return r.error();
  if (e->options_.check_only) {
    if (auto r = e->checkCrossings(); !r) return r.error();
  }
  e->setUpHandling();
  if (e->options_.scenario) {
    // Each process injects into its own components; keel run also kills component processes.
    auto& faults = e->options_.scenario->faults;
    std::erase_if(faults, [e](const injection::ScheduledFault& f) {
      return !e->side_->injects(f, e->planned_.plan.find(f.component));
    });
    e->injector_ = std::make_unique<injection::Injector>(
        *e->options_.scenario, [e](std::string_view n) { return e->find(n); }, e->fault_manager_, e->log_,
        [e](const std::string& m) { e->warn(m); });
    auto passive = [e](std::string_view name) {
      for (const auto& ex : e->planned_.plan.executors)
        if (std::find(ex.members.begin(), ex.members.end(), name) != ex.members.end()) return false;
      return true;
    };
    if (auto r = e->injector_->check([e](const std::string& m) { e->warn(m); }, passive); !r) return r.error();
  }
  return engine;
}

bool Engine::isLocal(const plan::PlannedInstance& pi) const {
  if (pi.node) return false;  // a ROS 2 node: its own process, keel's proxy stands in for it
  return options_.check_only || pi.process == side_->process();
}

Result<void> Engine::checkCrossings() const {
  const plan::Plan& plan = planned_.plan;
  std::string errors;
  for (const std::size_t i : supervision::crossingConnections(plan)) {
    const plan::PlannedConnection& c = plan.connections[i];
    for (const profile::Endpoint* end : {&c.source, &c.target}) {
      Component* comp = find(end->component);
      const detail::PortBase* port = comp ? runtime::coreOf(*comp).findPort(end->port) : nullptr;
      if (port == nullptr) continue;  // a port the code lacks: instantiate() said so
      if (auto problem = supervision::crossingProblem(plan, c, *port)) {
        errors += *problem + "\n";
        break;  // both ends have the type: said once
      }
    }
  }
  if (errors.empty()) return {};
  errors.pop_back();
  return fail(errors);
}

Component* Engine::find(std::string_view instance) const {
  const auto it = by_name_.find(instance);
  return it == by_name_.end() ? nullptr : it->second->serving();
}

bool Engine::serves(const Component& c) const {
  const auto it = by_name_.find(c.instanceName());
  if (it == by_name_.end()) return true;
  const Component* serving = it->second->serving();
  return serving == &c || (serving == nullptr && !runtime::coreOf(c).alternative);  // nullptr: not built yet
}

void Engine::warn(const std::string& message) {
  log_.write(log::schema::warning(message));
  if (options_.warn) options_.warn(message);
  else runtime::warnOnStderr(message);
}

void Engine::buildExecutors() {
  for (const auto& pe : planned_.plan.executors) {
    const plan::PlannedInstance* first = planned_.plan.find(pe.members.front());
    if (first && !isLocal(*first)) continue;  // runs in its component process
    runtime::ExecutorConfig cfg;
    cfg.name = pe.name;
    cfg.kind = pe.periodic ? runtime::ExecutorKind::Periodic : runtime::ExecutorKind::Aperiodic;
    cfg.period = std::chrono::nanoseconds(static_cast<std::int64_t>(pe.period_ms * 1e6));
    cfg.priority = pe.priority;
    cfg.policy = pe.policy;
    auto ex = std::make_unique<runtime::Executor>(cfg, [this](const std::string& m) { warn(m); });
    for (const auto& m : pe.members) {
      for (auto& inst : instances_) {
        if (inst.plan->name != m) continue;
        ex->add(*inst.component);
        inst.executor = ex.get();
      }
    }
    ex->holdStop(stop_barrier_);  // none stops its members while another still cycles
    executors_.push_back(std::move(ex));
  }
}

void Engine::runComponents(runtime::Executor* self) {
  crossings_.resume();
  for (auto& inst : instances_) {
    if (inst.executor) continue;  // passive: started here, under its lock
    auto& core = runtime::coreOf(*inst.component);
    std::lock_guard lock(core.passive_mutex);
    runtime::transition(*inst.component, Transition::Start);
    if (!core.critical.empty()) runtime::takeCheckpoint(core, runtime::steadyNs());
  }
  std::lock_guard lock(executors_mutex_);  // a hang may already abandon one (engine_recovery.cpp)
  for (auto& ex : executors_) {
    if (self) {
      ex->release();  // the takeover's thread does not wait for the others' onStart
    } else {
      ex->holdFirstCycle(&first_cycle_);  // every member started before any cycle runs
      ex->start();
    }
  }
  first_cycle_.store(1, std::memory_order_release);
  first_cycle_.notify_all();
}

void Engine::holdCpuLatency() {
  if (!options_.cpu_dma_latency_us) return;
  auto held = runtime::CpuLatencyRequest::hold(*options_.cpu_dma_latency_us);
  if (held) cpu_latency_ = std::move(*held);
  else warn(held.error().message);
}

Result<void> Engine::start() {
  runtime::installSignalHandlers();
  if (auto r = side_->launch(); !r) return r;
  for (auto& inst : instances_) {
    if (runtime::transition(*inst.component, Transition::Initialize)) continue;
    const detail::ComponentCore& core = runtime::coreOf(*inst.component);
    // A property it refused: said at the line that gave the value, in the component's words.
    if (const auto w = inst.plan->property_where.find(core.refused_property);
        !core.refused_property.empty() && w != inst.plan->property_where.end() && !w->second.file.empty())
      return fail(fmt::format("{}: {}", w->second.str(), core.refused_text));
    const auto& w = inst.plan->where;
    const std::string& why = core.refused_text.empty() ? core.transition_fault : core.refused_text;
    return fail(fmt::format("{}:{}: component '{}' failed to initialize: {}", w.file, w.line, inst.plan->name,
                            why.empty() ? "onInitialize returned an error" : why));
  }
  if (auto r = connect(); !r) return r;
  if (auto r = side_->waitReady(); !r) return r;
  if (auto r = preloadAlternatives(); !r) return r;
  fault_manager_.start();
  return side_->run();
}

void Engine::startDetectors() {
  std::vector<fault::WatchedComponent> watched;
  for (const auto& inst : instances_) {
    const auto& core = runtime::coreOf(*inst.component);
    if (core.watch.heartbeat_ns == 0) continue;
    std::int64_t period = inst.executor && inst.executor->config().kind == runtime::ExecutorKind::Periodic
                              ? inst.executor->config().period.count()
                              : 0;
    watched.push_back({inst.serving_slot.get(), core.watch.heartbeat_ns, period});
  }
  watchdog_ = std::make_unique<fault::Watchdog>(std::move(watched), fault_manager_,
                                                [this](const std::string& m) { warn(m); });
  watchdog_->start();
  fault_manager_.armSafetyNet();  // here, not in a recovery's path (HandlingQueue::armSafetyNet)
  if (injector_) injector_->start(runtime::steadyNs());
}

void Engine::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  if (dds_) dds_->stopReporting();  // what goes silent from here on is the run's end
  side_->windDownNodes();           // its managed nodes' way down goes through DDS
  if (dds_) dds_->close();          // no sample in, no remote fault, from here on
  if (injector_) injector_->stop();
  if (watchdog_) watchdog_->stop();
  fault_manager_.stop();           // handles and logs what is queued; adds no executor after this
  for (auto& inst : instances_) {  // injected hangs, of replaced components too
    runtime::coreOf(*inst.component).injection.release_hang.store(true);
    runtime::coreOf(*inst.serving()).injection.release_hang.store(true);
  }
  for (auto& ex : executors_) ex->requestStop();
  crossings_.stop();  // no more values from other processes into components that stop
  // Every executor ends its last cycle before any stops its members: a call in a last cycle
  // finds its provider Active. One stuck in a callback holds the others up to the timeout.
  (void)stop_barrier_.waitClear(std::chrono::steady_clock::now() + options_.stop_timeout);
  stop_barrier_.release();
  std::vector<const runtime::Executor*> abandoned;
  for (auto& ex : executors_) {
    if (!ex->abandoned() && ex->join(options_.stop_timeout)) continue;
    if (ex->abandoned() && ex->join(std::chrono::milliseconds(50))) continue;  // it came back meanwhile
    abandoned.push_back(ex.get());
    if (ex->abandoned()) continue;
    warn(fmt::format("executor '{}' did not stop within {} ms; abandoned with its components", ex->config().name,
                     options_.stop_timeout.count()));
    ex->abandon();  // should it come back, it touches neither its members nor the engine
  }
  // A component whose executor is abandoned may still be in use by its stuck thread.
  auto stuck = [&abandoned](const Component& c) {
    const runtime::Executor* ex = runtime::coreOf(c).executor.load(std::memory_order_acquire);
    return ex && std::find(abandoned.begin(), abandoned.end(), ex) != abandoned.end();
  };
  for (auto& inst : instances_) {
    if (inst.executor) continue;
    Component& c = *inst.serving();
    std::lock_guard lock(runtime::coreOf(c).passive_mutex);
    runtime::transition(c, Transition::Stop);
  }
  fault_manager_.flushUndetected(components());
  if (started_) logCounts();
  // A component out of service (one an alternative replaced, an alternative standing by) ends
  // too, its records marked `serving: false`; a failing onDestroy of it is no fault to handle.
  auto destroyOutOfService = [](Component& c) {
    runtime::coreOf(c).fault_sink = nullptr;
    runtime::transition(c, Transition::Destroy);
  };
  for (auto it = instances_.rbegin(); it != instances_.rend(); ++it) {
    if (!stuck(*it->serving())) runtime::transition(*it->serving(), Transition::Destroy);
    if (it->serving() != it->component.get() && !stuck(*it->component)) destroyOutOfService(*it->component);
  }
  {
    std::lock_guard lock(alternatives_mutex_);
    for (auto& alt : alternatives_)  // alternatives still standing by
      if (alt->state() != State::Destroyed && !stuck(*alt)) destroyOutOfService(*alt);
  }
  side_->stopProcesses();
  cpu_latency_ = runtime::CpuLatencyRequest();  // the CPUs may sleep again
  warnTeeDropped();
  side_->stopped();
  if (auto end = run_end_.get(); end && !end->event.empty()) log_.write(runEndRecord(*end, log_.now()));
  // A stuck thread still uses its components: they are left allocated (the process is ending).
  for (auto it = instances_.rbegin(); it != instances_.rend(); ++it) {
    it->serving_slot->store(nullptr, std::memory_order_release);
    if (stuck(*it->component)) (void)it->component.release();
    else it->component.reset();
  }
  for (auto& alt : alternatives_)
    if (stuck(*alt)) (void)alt.release();
  alternatives_.clear();
  for (auto& ex : executors_)
    if (std::find(abandoned.begin(), abandoned.end(), ex.get()) != abandoned.end()) (void)ex.release();
}

void Engine::warnTeeDropped() {
  if (const std::uint64_t dropped = log_.teeDropped(); dropped > 0)
    warn(fmt::format("the log's tee '{}' dropped {} of {} lines: its reader was behind, or gone", options_.log_tee,
                     dropped, log_.teeLines()));
}

void Engine::logCounts() {
  auto tagged = [this](nlohmann::json r) {
    if (!side_->process().empty()) r[log::schema::field::kProcess] = side_->process();
    log_.write(std::move(r));
  };
  for (const auto& inst : instances_) {
    if (!isLocal(*inst.plan)) continue;
    const Component& c = *inst.serving();
    const auto& core = runtime::coreOf(c);
    std::uint64_t executions = core.executions.load();
    std::uint64_t misses = core.deadline_overruns.load();
    if (&c != inst.component.get()) {  // replaced: the name's counts include the first one's
      executions += runtime::coreOf(*inst.component).executions.load();
      misses += runtime::coreOf(*inst.component).deadline_overruns.load();
    }
    tagged(log::schema::componentCounts(inst.plan->name, core.class_name,
                                        inst.executor ? inst.executor->config().name : "passive", executions, misses));
  }
  for (const auto& ex : executors_) {
    const auto& c = ex->config();
    const auto s = ex->stats();
    const double period_ms = c.kind == runtime::ExecutorKind::Periodic ? c.period.count() / 1e6 : 0;
    tagged(log::schema::executorCounts(c.name, period_ms, s.cycles, s.overruns));
  }
}

void Engine::stateChanged(Component& c, State from, State to) {
  if (side_->holdsState(c, from, to)) return;
  const detail::ComponentCore& core = runtime::coreOf(c);
  log_.write(log::schema::componentState(c.instanceName(), {core.class_name, core.alternative, serves(c)},
                                         toString(from), toString(to), 0, log_.now()));
  side_->stateLogged(c.instanceName());
  if (dds_) dds_->pokeDiagnostics();
}

void Engine::endRun(Component& c, std::string_view summary, std::string_view event, std::string_view fields) {
  RunEnd end{c.instanceName(), std::string(summary), std::string(event), std::string(fields)};
  if (!run_end_.request(end)) return;  // the first request wins
  nlohmann::json rec = {{log::schema::field::kEvent, log::schema::event::kEndRequested},
                        {log::schema::field::kComponent, end.component},
                        {log::schema::field::kSummary, end.summary}};
  log_.write(std::move(rec));
}

bool Engine::clearEmergency(std::string_view by) {
  const bool cleared = fault_manager_.clearEmergency(by);
  if (cleared) side_->emergencyCleared();
  return cleared;
}

std::vector<const runtime::Executor*> Engine::executors() const {
  std::lock_guard lock(executors_mutex_);
  std::vector<const runtime::Executor*> out;
  for (const auto& ex : executors_) out.push_back(ex.get());
  return out;
}

std::vector<Component*> Engine::components() const {
  std::vector<Component*> out;
  for (const auto& i : instances_)
    if (Component* c = i.serving()) out.push_back(c);
  return out;
}

}  // namespace keel::engine
