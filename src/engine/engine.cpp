#include "engine/engine.hpp"

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
  if (options_.host) options_.host->setLog(nullptr);
  supervisor_.reset();  // its threads report to the fault manager: gone before it is
  if (holds_supervisor_lock_) (void)session_->supervisor().unlock();
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
  supervision::ProcessHost* host = e->options_.host;
  if (!e->options_.log_path.empty()) {
    auto opened = host ? e->log_.join(e->options_.log_path, host->session().logEpoch().load())
                       : e->log_.open(e->options_.log_path, e->options_.log_append);
    if (!opened) return opened.error();
  }
  // Opened before the first record, so that the tee has them all. A host that cannot open it
  // (keel run's pipe lost its reader) runs without: its warning waits for the log to be shared.
  std::string tee_error;
  if (!e->options_.log_tee.empty()) {
    if (auto r = e->log_.openTee(e->options_.log_tee); !r) {
      if (!host) return r.error();
      tee_error = r.error().message;
    } else if (!host) {
      e->options_.host_launch.args.insert(e->options_.host_launch.args.end(),
                                          {"--log-tee",
                                           fmt::format("/proc/{}/fd/{}", ::getpid(), e->log_.teeDescriptor())});
    }
  }
  if (!host) {
    nlohmann::json load = log::schema::engine("load");
    load[log::schema::field::kProfile] = e->set().root;
    load[log::schema::field::kName] = e->planned_.plan.name;
    nlohmann::json& names = load[log::schema::field::kComponents] = nlohmann::json::array();
    for (const auto& pi : e->planned_.plan.instances) names.push_back(pi.name);
    load[log::schema::field::kInstances] = e->planned_.plan.instances.size();
    for (const auto& s : e->options_.property_settings) load[log::schema::field::kSet].push_back(s.text);
    e->log_.write(std::move(load));
  }
  if (!e->options_.check_only) {
    if (auto r = e->setUpProcesses(); !r) return r.error();
  }
  if (!tee_error.empty()) e->warn(tee_error + "; this process's records are in the log only");
  if (auto r = e->instantiate(); !r) return r.error();
  if (e->options_.check_only) {
    if (auto r = e->checkCrossings(); !r) return r.error();
  }
  e->setUpHandling();
  if (e->options_.scenario) {
    // Each process injects into its own components; keel run also kills component processes.
    auto& faults = e->options_.scenario->faults;
    std::erase_if(faults, [e](const injection::ScheduledFault& f) {
      const plan::PlannedInstance* pi = e->planned_.plan.find(f.component);
      if (pi == nullptr) return e->options_.host != nullptr;  // keel run reports it
      const bool kill = !f.hardware && f.kind == runtime::InjectKind::Kill;
      return e->options_.host ? (!e->isLocal(*pi) || kill) : (!e->isLocal(*pi) && !kill);
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

const std::string& Engine::myProcess() const {
  static const std::string keel_run;
  return options_.host ? options_.host->role().process : keel_run;
}

bool Engine::isLocal(const plan::PlannedInstance& pi) const { return options_.check_only || pi.process == myProcess(); }

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

Result<void> Engine::setUpProcesses() {
  const plan::Plan& plan = planned_.plan;
  if (supervision::ProcessHost* host = options_.host) {
    fault_manager_.shareIds(&host->session().faultIds());
    log_.tag(log::schema::field::kPid, ::getpid());  // one log for the run: whose record
    log_.share(host->session().log(), runtime::ipc::logParticipant(host->processIndex(), host->role().slot),
               supervision::logParticipants(plan));
    host->setLog(&log_);  // should keel run die: its line repaired, this one's finished (process_host.hpp)
    return {};
  }
  if (plan.processes.empty()) return {};
  auto session = runtime::ipc::Session::create(supervision::sessionShape(plan));
  if (!session) return session.error();
  session_.emplace(std::move(*session));
  // Held by this (the main) thread for the whole run: its release by death tells every host.
  if (auto locked = session_->supervisor().lock(); !locked) return locked.error();
  holds_supervisor_lock_ = true;
  session_->logEpoch().store(log_.epoch(), std::memory_order_release);
  log_.share(session_->log(), runtime::ipc::logParticipant(std::nullopt, 0), supervision::logParticipants(plan));
  fault_manager_.shareIds(&session_->faultIds());
  std::vector<runtime::ipc::SharedMemory> rings;
  const std::vector<std::size_t> crossing = supervision::crossingConnections(plan);
  for (std::size_t k = 0; k < crossing.size(); ++k) {
    auto ring = runtime::ipc::SharedMemory::createUnsized(fmt::format("keel-ring-{}", k));
    if (!ring) return ring.error();
    rings.push_back(std::move(*ring));
  }
  supervisor_ = std::make_unique<supervision::ProcessSupervisor>(
      plan, *session_, std::move(rings), options_.host_launch, [this](const std::string& m) { warn(m); }, log_);
  return {};
}

Component* Engine::find(std::string_view instance) const {
  const auto it = by_name_.find(instance);
  return it == by_name_.end() ? nullptr : it->second->serving();
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
    cfg.policy = pe.policy == profile::SchedPolicy::Fifo         ? runtime::Policy::Fifo
                 : pe.policy == profile::SchedPolicy::RoundRobin ? runtime::Policy::RoundRobin
                                                                 : runtime::Policy::Other;
    auto ex = std::make_unique<runtime::Executor>(cfg, [this](const std::string& m) { warn(m); });
    for (const auto& m : pe.members) {
      for (auto& inst : instances_) {
        if (inst.plan->name != m) continue;
        ex->add(*inst.component);
        inst.executor = ex.get();
      }
    }
    executors_.push_back(std::move(ex));
  }
}

void Engine::raiseToProcessPriority() {
  const plan::PlannedExecutor* top = nullptr;
  for (const auto& pe : planned_.plan.executors) {
    const plan::PlannedInstance* first = pe.members.empty() ? nullptr : planned_.plan.find(pe.members.front());
    if (first == nullptr || !isLocal(*first) || pe.policy == profile::SchedPolicy::Other) continue;
    if (top == nullptr || pe.priority > top->priority) top = &pe;
  }
  if (top != nullptr) {
    sched_param sp{};
    sp.sched_priority = top->priority;
    const int policy = top->policy == profile::SchedPolicy::Fifo ? SCHED_FIFO : SCHED_RR;
    if (int err = pthread_setschedparam(pthread_self(), policy, &sp); err != 0)
      warn(
          fmt::format("process '{}': its main thread cannot take task '{}''s priority {} ({}): it waits for its "
                      "role at the default priority",
                      myProcess(), top->name, top->priority, std::generic_category().message(err)));
  }
}

Result<Engine::RoleTaken> Engine::takeRoleAsHost() {
  supervision::ProcessHost& host = *options_.host;
  auto died = host.takeRole();  // a standby sleeps here
  if (!died) return died.error();
  // The active host left because keel run is gone (it ran the emergency stop): the run is over,
  // and taking over would drive the actuators again. Ends this process.
  if (host.runLost()) host.supervisorLost();
  if (host.stopRequested()) return RoleTaken{};
  if (dds_) dds_->takeOver();  // samples into the ports from here, before the components start
  RoleTaken taken{host.role().respawn ? "respawned" : *died ? "took_over" : "starting", 0};
  if (*died || host.role().respawn) {
    for (auto& inst : instances_)
      taken.restored += runtime::restoreSharedCheckpoint(runtime::coreOf(*inst.component)) != 0;
  }
  if (auto r = crossings_.takeOver(); !r) return r.error();
  return taken;
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

runtime::Executor* Engine::roleExecutor() const {
  // The task that runs first: the highest real-time priority (SCHED_OTHER below any), the first
  // declared among equals.
  runtime::Executor* best = nullptr;
  auto rank = [](const runtime::ExecutorConfig& c) { return c.policy == runtime::Policy::Other ? -1 : c.priority; };
  for (const auto& ex : executors_)
    if (best == nullptr || rank(ex->config()) > rank(best->config())) best = ex.get();
  return best;
}

void Engine::standBy(runtime::Executor& self) {
  auto taken = takeRoleAsHost();  // this thread sleeps here, and holds the role from here
  const bool runs = taken && taken->phase;
  if (runs) runComponents(&self);
  role_taken_ = std::move(taken);  // the main thread reads it once role_settled_ says so
  role_settled_.store(1, std::memory_order_release);
  if (!runs) {
    role_alarm_.setIn(std::chrono::nanoseconds(0));
    return;
  }
  // The main thread's part (records, detectors, telling keel run) waits for the first cycle:
  // its wake-up would cost this thread a CPU-to-CPU interrupt before the step. The alarm is
  // set for later in case the step hangs, and then to now between this thread's first cycles.
  role_alarm_.setIn(kFirstStepWait);
  self.post([this] { role_alarm_.setIn(std::chrono::nanoseconds(0)); });
}

void Engine::leaveRole(const runtime::Executor& self) const {
  supervision::ProcessHost& host = *options_.host;
  if (!host.holdsRole()) return;
  // Abandoned in a hung callback and back, the process running on: its release would tell the
  // standbys this process died while it still runs. It parks until the process ends.
  if (self.abandoned() && !host.stopRequested())
    for (;;) ::pause();
  host.releaseRole();
}

Result<Engine::RoleTaken> Engine::startAsHost() {
  supervision::ProcessHost& host = *options_.host;
  // Its main thread holds the locks whose release tells of its death (its life; the role,
  // unless a standby's task took it), and must get to die as promptly under load. Its
  // executors' threads wait ready: a takeover starts none, and writes its records once the
  // components run.
  raiseToProcessPriority();
  buildExecutors();
  holdCpuLatency();     // before the executors' first sleep
  crossings_.attach();  // values from other processes: read by the executors
  runtime::Executor* self = host.role().standby ? roleExecutor() : nullptr;
  for (auto& ex : executors_)
    if (ex.get() != self) ex->prepare();
  for (auto& inst : instances_) {
    runtime::reserveCheckpoint(runtime::coreOf(*inst.component));
    // The first good cycle of any of them tells keel run the process runs.
    if (inst.executor)
      runtime::coreOf(*inst.component).fault.recovering_id.store(supervision::HostFaultSink::kFirstRun);
  }
  {
    std::lock_guard lock(held_mutex_);
    hold_records_ = true;  // the log's lock and write off the way to the first step
    held_.reserve(2 * instances_.size());
  }
  if (host.role().standby) log_.write(log::schema::host(host.role().process, ::getpid(), "standby"));
  if (self == nullptr) {
    auto taken = takeRoleAsHost();
    if (!taken || !taken->phase) return taken;
    runComponents(nullptr);
    return taken;
  }
  // The standby's role is taken by the thread of the task that runs first: the thread its
  // active's death wakes runs the takeover and then the component, with no second wake. Made
  // last: it may take the role at once (its active already dead).
  auto alarm = runtime::Alarm::create();
  if (!alarm) return alarm.error();
  role_alarm_ = std::move(*alarm);
  self->prepare([this, self] { standBy(*self); }, [this, self] { leaveRole(*self); });
  while (role_settled_.load(std::memory_order_acquire) == 0) role_alarm_.wait();
  if (*role_taken_ && (*role_taken_)->phase)
    for (auto& ex : executors_) ex->waitStarted();
  return *role_taken_;
}

void Engine::holdCpuLatency() {
  if (!options_.cpu_dma_latency_us) return;
  auto held = runtime::CpuLatencyRequest::hold(*options_.cpu_dma_latency_us);
  if (held) cpu_latency_ = std::move(*held);
  else warn(held.error().message);
}

Result<void> Engine::start() {
  runtime::installSignalHandlers();
  if (supervisor_) {
    supervisor_->setReport(
        [this](Component& proxy, const FaultEvent& fault) { fault_manager_.onFault(proxy, fault, "supervisor"); });
    if (auto r = supervisor_->launch(); !r) return r;
  }
  if (options_.host && options_.host->role().standby) {
    // A standby's components serve only if it takes over: their `state` records wait for it
    // (the log's records of a name are the lifecycle of its serving component).
    std::lock_guard lock(held_mutex_);
    hold_records_ = true;
  }
  for (auto& inst : instances_) {
    if (runtime::transition(*inst.component, Transition::Initialize)) continue;
    const auto& w = inst.plan->where;
    const std::string& why = runtime::coreOf(*inst.component).transition_fault;
    return fail(fmt::format("{}:{}: component '{}' failed to initialize: {}", w.file, w.line, inst.plan->name,
                            why.empty() ? "onInitialize returned an error" : why));
  }
  if (auto r = connect(); !r) return r;
  if (supervisor_) {
    if (auto r = supervisor_->waitReady(options_.host_start_timeout); !r) return r;
  }
  if (auto r = preloadAlternatives(); !r) return r;
  fault_manager_.start();
  if (options_.host) {
    auto taken = startAsHost();
    if (!taken) return taken.error();
    if (taken->phase) {
      crossings_.start();  // pumps for components without an executor, from here
      nlohmann::json rec = log::schema::host(options_.host->role().process, ::getpid(), taken->phase);
      rec["restored"] = taken->restored;
      log_.write(std::move(rec));
    }
    std::vector<HeldState> held;
    {
      std::lock_guard lock(held_mutex_);
      if (!taken->phase) {  // stopped while standing by: its components never served, and the
        held_.clear();      // log's `state` records of their names stay the active host's
        return {};          // (hold_records_ stays set: their onDestroy goes unrecorded too)
      }
      hold_records_ = false;
      held.swap(held_);
    }
    for (const auto& h : held)
      log_.write(log::schema::componentState(h.component->instanceName(), toString(h.from), toString(h.to), 0, h.t));
    started_ = true;
    startDetectors();
    options_.host->becameActive();
    log_.write(log::schema::host(myProcess(), ::getpid(), "active"));
    if (dds_) dds_->reportHeldOutages();  // a writer lost while it stood by: its fault now
    return {};
  }
  if (auto r = crossings_.takeOver(); !r) return r;
  buildExecutors();
  holdCpuLatency();  // before the executors' first sleep
  std::size_t executors = 0;
  {
    std::lock_guard lock(executors_mutex_);
    crossings_.attach();  // values from other processes: read by the executors
    executors = executors_.size();
  }
  runComponents(nullptr);
  crossings_.start();  // and by pumps for components without one, from here
  started_ = true;
  startDetectors();
  nlohmann::json started = log::schema::engine("started");
  started[log::schema::field::kExecutors] = executors;
  if (cpu_latency_.held()) started[log::schema::field::kCpuDmaLatencyUs] = cpu_latency_.microseconds();
  log_.write(std::move(started));
  return {};
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
  if (injector_) injector_->start(runtime::steadyNs());
}

void Engine::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  if (dds_) dds_->close();  // no sample in, no remote fault, from here on
  if (injector_) injector_->stop();
  if (watchdog_) watchdog_->stop();
  fault_manager_.stop();           // handles and logs what is queued; adds no executor after this
  for (auto& inst : instances_) {  // injected hangs, of replaced components too
    runtime::coreOf(*inst.component).injection.release_hang.store(true);
    runtime::coreOf(*inst.serving()).injection.release_hang.store(true);
  }
  for (auto& ex : executors_) ex->requestStop();
  crossings_.stop();  // no more values from other processes into components that stop
  std::vector<const runtime::Executor*> abandoned;
  for (auto& ex : executors_) {
    if (!ex->abandoned() && ex->join(options_.stop_timeout)) continue;
    if (ex->abandoned() && ex->join(std::chrono::milliseconds(50))) continue;  // it came back meanwhile
    abandoned.push_back(ex.get());
    if (!ex->abandoned())
      warn(fmt::format("executor '{}' did not stop within {} ms; abandoned with its components", ex->config().name,
                       options_.stop_timeout.count()));
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
  // The log's `state` records of a name are the lifecycle of its serving component: a primary it
  // replaced and an alternative standing by get onDestroy without records of their own.
  auto destroyQuietly = [](Component& c) {
    detail::ComponentCore& core = runtime::coreOf(c);
    core.hooks = nullptr;
    core.fault_sink = nullptr;
    runtime::transition(c, Transition::Destroy);
  };
  for (auto it = instances_.rbegin(); it != instances_.rend(); ++it) {
    if (!stuck(*it->serving())) runtime::transition(*it->serving(), Transition::Destroy);
    if (it->serving() != it->component.get() && !stuck(*it->component)) destroyQuietly(*it->component);  // replaced
  }
  {
    std::lock_guard lock(alternatives_mutex_);
    for (auto& alt : alternatives_)  // alternatives still standing by
      if (alt->state() != State::Destroyed && !stuck(*alt)) destroyQuietly(*alt);
  }
  if (supervisor_) supervisor_->stop(options_.stop_timeout);  // hosts the proxies' onStop did not stop
  cpu_latency_ = runtime::CpuLatencyRequest();                // the CPUs may sleep again
  warnTeeDropped();
  if (started_ && !options_.host) log_.write(log::schema::engine("stopped"));
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
    if (options_.host) r[log::schema::field::kProcess] = myProcess();
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
  {
    std::lock_guard lock(held_mutex_);
    if (hold_records_) {  // a takeover's first step waits for no JSON (engine.hpp)
      held_.push_back({&c, from, to, log_.now()});
      return;
    }
  }
  log_.write(log::schema::componentState(c.instanceName(), toString(from), toString(to), 0, log_.now()));
  compositeStates(c.instanceName());
  if (dds_) dds_->pokeDiagnostics();
}

// A composite's state, derived from its members': Error as soon as one is in Error, otherwise
// the state they all share; while they are between states (one started, the next not yet), the
// last one holds. Logged by keel run only (a component process sees part of its members).
void Engine::compositeStates(std::string_view instance) {
  if (options_.host) return;
  const auto of = composites_of_.find(instance);
  if (of == composites_of_.end()) return;
  std::lock_guard lock(composite_mutex_);
  for (std::size_t i : of->second) {
    const plan::PlannedComposite& comp = planned_.plan.composites[i];
    std::optional<State> shared;
    bool error = false, agree = true;
    for (const auto& m : comp.members) {
      const Component* member = find(m);
      if (!member) continue;
      const State s = member->state();
      error |= s == State::Error;
      if (!shared) shared = s;
      agree &= *shared == s;
    }
    if (!shared) continue;
    const State derived = error ? State::Error : agree ? *shared : composite_states_[i];
    if (derived == composite_states_[i]) continue;
    log_.write(log::schema::compositeState(comp.name, toString(composite_states_[i]), toString(derived), log_.now()));
    composite_states_[i] = derived;
  }
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
  if (cleared && supervisor_) supervisor_->clearEmergency();
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
