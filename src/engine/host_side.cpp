#include "engine/host_side.hpp"

#include <fmt/format.h>

#include <pthread.h>
#include <unistd.h>

#include <system_error>

#include "engine/engine.hpp"
#include "log/schema.hpp"
#include "runtime/checkpoint.hpp"
#include "runtime/invoke.hpp"
#include "supervision/crossing.hpp"

namespace keel::engine {

HostSide::HostSide(Engine& engine, supervision::ProcessHost& host) : e_(engine), host_(host) {}

Result<void> HostSide::openLog() {
  const EngineOptions& o = e_.options_;
  if (!o.log_path.empty()) {
    if (auto joined = e_.log_.join(o.log_path, host_.session().logEpoch().load()); !joined) return joined.error();
  }
  // A host that cannot open the tee (keel run's pipe lost its reader) runs without: its
  // warning waits for the log to be shared.
  if (!o.log_tee.empty()) {
    if (auto r = e_.log_.openTee(o.log_tee); !r) tee_error_ = r.error().message;
  }
  return {};
}

Result<void> HostSide::setUpProcesses() {
  const plan::Plan& plan = e_.planned_.plan;
  e_.fault_manager_.shareIds(&host_.session().faultIds());
  e_.log_.tag(log::schema::field::kPid, ::getpid());  // one log for the run: whose record
  e_.log_.share(host_.session().log(), runtime::ipc::logParticipant(host_.processIndex(), host_.role().slot),
                supervision::logParticipants(plan));
  host_.setLog(&e_.log_);  // should keel run die: its line repaired, this one's finished (process_host.hpp)
  if (!tee_error_.empty()) e_.warn(tee_error_ + "; this process's records are in the log only");
  return {};
}

void HostSide::adopt(const plan::PlannedInstance& pi, detail::ComponentCore& core) {
  if (!sink_) sink_ = std::make_unique<supervision::HostFaultSink>(e_.fault_manager_, host_);
  core.fault_sink = sink_.get();
  if (auto i = supervision::checkpointIndex(e_.planned_.plan, pi.name))
    core.checkpoints.shared = &host_.session().checkpoint(*i);
}

// A component process injects into its own components; keel run kills processes.
bool HostSide::injects(const injection::ScheduledFault& f, const plan::PlannedInstance* pi) const {
  const bool kill = !f.hardware && f.kind == runtime::InjectKind::Kill;
  return pi != nullptr && e_.isLocal(*pi) && !kill;
}

Result<void> HostSide::launch() {
  if (host_.role().standby) {
    // A standby's components serve only if it takes over: their `state` records wait for it
    // (the log's records of a name are the lifecycle of its serving component).
    std::lock_guard lock(held_mutex_);
    hold_records_ = true;
  }
  return {};
}

bool HostSide::holdsState(const Component& c, State from, State to) {
  std::lock_guard lock(held_mutex_);
  if (!hold_records_) return false;
  held_.push_back({&c, from, to, e_.log_.now()});  // a takeover's first step waits for no JSON
  return true;
}

Result<void> HostSide::run() {
  auto taken = start();
  if (!taken) return taken.error();
  if (taken->phase) {
    e_.crossings_.start();  // pumps for components without an executor, from here
    nlohmann::json rec = log::schema::host(process(), ::getpid(), taken->phase);
    rec["restored"] = taken->restored;
    e_.log_.write(std::move(rec));
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
    e_.log_.write(log::schema::componentState(h.component->instanceName(), {runtime::coreOf(*h.component).class_name},
                                              toString(h.from), toString(h.to), 0, h.t));
  e_.started_ = true;
  e_.startDetectors();
  host_.becameActive();
  e_.log_.write(log::schema::host(process(), ::getpid(), "active"));
  if (e_.dds_) e_.dds_->reportHeldOutages();  // a writer lost while it stood by: its fault now
  return {};
}

void HostSide::raiseToProcessPriority() {
  const plan::PlannedExecutor* top = nullptr;
  for (const auto& pe : e_.planned_.plan.executors) {
    const plan::PlannedInstance* first = pe.members.empty() ? nullptr : e_.planned_.plan.find(pe.members.front());
    if (first == nullptr || !e_.isLocal(*first) || pe.policy == SchedPolicy::Other) continue;
    if (top == nullptr || pe.priority > top->priority) top = &pe;
  }
  if (top == nullptr) return;
  sched_param sp{};
  sp.sched_priority = top->priority;
  const int policy = top->policy == SchedPolicy::Fifo ? SCHED_FIFO : SCHED_RR;
  if (int err = pthread_setschedparam(pthread_self(), policy, &sp); err != 0)
    e_.warn(
        fmt::format("process '{}': its main thread cannot take task '{}''s priority {} ({}): it waits for its "
                    "role at the default priority",
                    process(), top->name, top->priority, std::generic_category().message(err)));
}

Result<HostSide::RoleTaken> HostSide::takeRole() {
  auto died = host_.takeRole();  // a standby sleeps here
  if (!died) return died.error();
  // The active host left because keel run is gone (it ran the emergency stop): the run is over,
  // and taking over would drive the actuators again. Ends this process.
  if (host_.runLost()) host_.supervisorLost();
  if (host_.stopRequested()) return RoleTaken{};
  if (e_.dds_) e_.dds_->takeOver();  // samples into the ports from here, before the components start
  RoleTaken taken{host_.role().respawn ? "respawned" : *died ? "took_over" : "starting", 0};
  if (*died || host_.role().respawn) {
    for (auto& inst : e_.instances_)
      taken.restored += runtime::restoreSharedCheckpoint(runtime::coreOf(*inst.component)) != 0;
  }
  if (auto r = e_.crossings_.takeOver(); !r) return r.error();
  return taken;
}

runtime::Executor* HostSide::roleExecutor() const {
  // The task that runs first: the highest real-time priority (SCHED_OTHER below any), the first
  // declared among equals.
  runtime::Executor* best = nullptr;
  auto rank = [](const runtime::ExecutorConfig& c) { return c.policy == SchedPolicy::Other ? -1 : c.priority; };
  for (const auto& ex : e_.executors_)
    if (best == nullptr || rank(ex->config()) > rank(best->config())) best = ex.get();
  return best;
}

void HostSide::standBy(runtime::Executor& self) {
  auto taken = takeRole();  // this thread sleeps here, and holds the role from here
  const bool runs = taken && taken->phase;
  if (runs) e_.runComponents(&self);
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

void HostSide::leaveRole(const runtime::Executor& self) const {
  if (!host_.holdsRole()) return;
  // Abandoned in a hung callback and back, the process running on: its release would tell the
  // standbys this process died while it still runs. It parks until the process ends.
  if (self.abandoned() && !host_.stopRequested())
    for (;;) ::pause();
  host_.releaseRole();
}

Result<HostSide::RoleTaken> HostSide::start() {
  // Its main thread holds the locks whose release tells of its death (its life; the role,
  // unless a standby's task took it), and must get to die as promptly under load. Its
  // executors' threads wait ready: a takeover starts none, and writes its records once the
  // components run.
  raiseToProcessPriority();
  e_.buildExecutors();
  e_.holdCpuLatency();     // before the executors' first sleep
  e_.crossings_.attach();  // values from other processes: read by the executors
  runtime::Executor* self = host_.role().standby ? roleExecutor() : nullptr;
  for (auto& ex : e_.executors_)
    if (ex.get() != self) ex->prepare();
  for (auto& inst : e_.instances_) {
    runtime::reserveCheckpoint(runtime::coreOf(*inst.component));
    // The first good cycle of any of them tells keel run the process runs.
    if (inst.executor)
      runtime::coreOf(*inst.component).fault.recovering_id.store(supervision::HostFaultSink::kFirstRun);
  }
  {
    std::lock_guard lock(held_mutex_);
    hold_records_ = true;  // the log's lock and write off the way to the first step
    held_.reserve(2 * e_.instances_.size());
  }
  if (host_.role().standby) e_.log_.write(log::schema::host(process(), ::getpid(), "standby"));
  if (self == nullptr) {
    auto taken = takeRole();
    if (!taken || !taken->phase) return taken;
    e_.runComponents(nullptr);
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
    for (auto& ex : e_.executors_) ex->waitStarted();
  return *role_taken_;
}

void HostSide::close() { host_.setLog(nullptr); }

}  // namespace keel::engine
