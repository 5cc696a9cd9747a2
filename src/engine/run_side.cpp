#include "engine/run_side.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "dds/dds_ports.hpp"
#include "dds/type_registry.hpp"
#include "engine/engine.hpp"
#include "log/schema.hpp"
#include "supervision/crossing.hpp"

namespace keel::engine {

RunSide::RunSide(Engine& engine) : e_(engine) {
  const auto& composites = e_.planned_.plan.composites;
  composite_states_.assign(composites.size(), State::Created);
  for (std::size_t i = 0; i < composites.size(); ++i)
    for (const auto& m : composites[i].members) composites_of_[m].push_back(i);
}

RunSide::~RunSide() {
  if (holds_supervisor_lock_) (void)session_->supervisor().unlock();
}

Result<void> RunSide::openLog() {
  EngineOptions& o = e_.options_;
  if (!o.log_path.empty()) {
    if (auto opened = e_.log_.open(o.log_path, o.log_append); !opened) return opened.error();
  }
  // Opened before the first record, so that the tee has them all; the component processes
  // write to the same pipe.
  if (!o.log_tee.empty()) {
    if (auto r = e_.log_.openTee(o.log_tee); !r) return r.error();
    o.host_launch.args.insert(o.host_launch.args.end(),
                              {"--log-tee", fmt::format("/proc/{}/fd/{}", ::getpid(), e_.log_.teeDescriptor())});
  }
  namespace field = log::schema::field;
  nlohmann::json load = log::schema::engine("load");
  load[field::kProfile] = e_.set().root;
  load[field::kName] = e_.planned_.plan.name;
  nlohmann::json& names = load[field::kComponents] = nlohmann::json::array();
  for (const auto& pi : e_.planned_.plan.instances) names.push_back(pi.name);
  load[field::kInstances] = e_.planned_.plan.instances.size();
  load[field::kEpochNs] = e_.log_.epoch();  // the steady clock is CLOCK_MONOTONIC: other programs' times line up
  for (const auto& s : o.property_settings) load[field::kSet].push_back(s.text);
  e_.log_.write(std::move(load));
  return {};
}

Result<void> RunSide::setUpProcesses() {
  const plan::Plan& plan = e_.planned_.plan;
  if (auto r = setUpNodes(); !r) return r;
  if (plan.processes.empty()) return {};
  auto session = runtime::ipc::Session::create(supervision::sessionShape(plan));
  if (!session) return session.error();
  session_.emplace(std::move(*session));
  // Held by this (the main) thread for the whole run: its release by death tells every host.
  if (auto locked = session_->supervisor().lock(); !locked) return locked.error();
  holds_supervisor_lock_ = true;
  session_->logEpoch().store(e_.log_.epoch(), std::memory_order_release);
  e_.log_.share(session_->log(), runtime::ipc::logParticipant(std::nullopt, 0), supervision::logParticipants(plan));
  e_.fault_manager_.shareIds(&session_->faultIds());
  std::vector<runtime::ipc::SharedMemory> rings;
  const std::vector<std::size_t> crossing = supervision::crossingConnections(plan);
  for (std::size_t k = 0; k < crossing.size(); ++k) {
    auto ring = runtime::ipc::SharedMemory::createUnsized(fmt::format("keel-ring-{}", k));
    if (!ring) return ring.error();
    rings.push_back(std::move(*ring));
  }
  supervisor_ = std::make_unique<supervision::ProcessSupervisor>(
      plan, *session_, std::move(rings), e_.options_.host_launch, [this](const std::string& m) { e_.warn(m); }, e_.log_,
      spawner_);
  return {};
}

// The nodes' domain is keel run's (Plan::rosDomain). Their output files are beside the log, else in a folder of keel
// run's.
Result<void> RunSide::setUpNodes() {
  const plan::Plan& plan = e_.planned_.plan;
  if (std::none_of(plan.instances.begin(), plan.instances.end(), [](const auto& pi) { return pi.node != nullptr; }))
    return {};
  supervision::NodeLaunch launch;
  launch.node_exec = supervision::defaultNodeExec();
  auto domain = dds::effectiveDomain(plan.rosDomain());
  if (!domain) return domain.error();
  launch.domain = *domain;
  const EngineOptions& o = e_.options_;
  namespace fs = std::filesystem;
  if (!o.log_path.empty()) {
    const fs::path log(o.log_path);
    launch.output_dir = log.has_parent_path() ? log.parent_path().string() : ".";
    launch.output_stem = log.stem().string();
    launch.fresh_output = !o.log_append;
  } else {
    const char* tmp = std::getenv("TMPDIR");
    launch.output_dir = fmt::format("{}/keel-run-{}", tmp && *tmp ? tmp : "/tmp", ::getpid());
    std::error_code ec;
    fs::create_directories(launch.output_dir, ec);
    if (ec) return fail(fmt::format("cannot make '{}' for the nodes' output: {}", launch.output_dir, ec.message()));
  }
  nodes_ = std::make_unique<supervision::NodeSupervisor>(
      plan, std::move(launch), [this](const std::string& m) { e_.warn(m); }, e_.log_, spawner_);
  return {};
}

std::unique_ptr<Component> RunSide::standIn(const plan::PlannedInstance& pi) {
  if (pi.node) {
    if (!nodes_) return nullptr;
    // Its output ports are of the types its topics carry, keel::msg's.
    return nodes_->makeProxy(pi, [](Component* owner, const profile::DataPort& d) -> std::unique_ptr<detail::PortBase> {
      const detail::DdsType* type = dds::findType(d.data_type);
      return type ? type->make_output(owner, d.name) : nullptr;
    });
  }
  std::unique_ptr<Component> proxy = supervisor_ ? supervisor_->makeProxy(pi) : nullptr;
  if (proxy) runtime::coreOf(*proxy).hooks = nullptr;  // its states are logged by the process that runs it
  return proxy;
}

// /diagnostics: keel run's, for every component; those of component processes as keel run
// knows them (their proxies' states, the faults it handles).
bool RunSide::publishesDiagnostics() const { return e_.planned_.plan.diagnostics_domain.has_value(); }

bool RunSide::joinsRosGraph() const { return !e_.options_.check_only; }

// keel run injects into its own components, reports a fault of no instance, and kills
// component processes; the rest is injected by the process that runs the instance.
bool RunSide::injects(const injection::ScheduledFault& f, const plan::PlannedInstance* pi) const {
  if (pi == nullptr) return true;
  const bool kill = !f.hardware && f.kind == runtime::InjectKind::Kill;
  return e_.isLocal(*pi) || kill;
}

void RunSide::nodeSeen(const std::string& instance, const std::vector<dds::NodeSighting>& sightings) {
  std::vector<supervision::GraphSighting> seen;
  seen.reserve(sightings.size());
  for (const dds::NodeSighting& s : sightings) seen.push_back({s.pid, s.listed, s.missing});
  nodes_->nodeSeen(instance, std::move(seen));
}

Result<void> RunSide::launch() {
  if (nodes_) {
    nodes_->setReport(
        [this](Component& proxy, const FaultEvent& fault) { e_.fault_manager_.report(proxy, fault, "supervisor"); });
    // A node's topics' deadlines start again with its next life; keel's subscribers of a dead
    // node's topics lose its writers at once, not at their deadline.
    nodes_->setExited([this](const std::string& instance, pid_t pid, const std::string& who, bool died) {
      if (e_.dds_) e_.dds_->nodeExited(instance, pid, who, died);
    });
    nodes_->setEmergency([this](const std::string& instance) {
      if (e_.dds_) e_.dds_->safeCommandsOn(instance);
    });
    using Asked = supervision::LifecycleLink::Asked;
    auto asked = [](dds::LifecycleClients::Sent sent) {
      switch (sent) {
        case dds::LifecycleClients::Sent::Written: return Asked::Written;
        case dds::LifecycleClients::Sent::Cyclone: return Asked::Cyclone;
        default: return Asked::NotYet;
      }
    };
    nodes_->setLifecycle({[this, asked](const std::string& instance, const std::string& name, std::uint8_t transition) {
                            dds::DdsPorts* d = lifecycle_dds_.load(std::memory_order_acquire);
                            return d ? asked(d->requestTransition(instance, name, transition)) : Asked::NotYet;
                          },
                          [this, asked](const std::string& instance, const std::string& name) {
                            dds::DdsPorts* d = lifecycle_dds_.load(std::memory_order_acquire);
                            return d ? asked(d->askLifecycleState(instance, name)) : Asked::NotYet;
                          },
                          [this](const std::string& instance, const std::string& name) {
                            if (dds::DdsPorts* d = lifecycle_dds_.load(std::memory_order_acquire))
                              d->renewLifecycleRequests(instance, name);
                          }});
    nodes_->setRecovered([this](Component& proxy, std::int64_t t_ns) { e_.fault_manager_.recovered(proxy, t_ns); });
    if (auto r = nodes_->launch(); !r) return r;
  }
  if (!supervisor_) return {};
  supervisor_->setReport(
      [this](Component& proxy, const FaultEvent& fault) { e_.fault_manager_.report(proxy, fault, "supervisor"); });
  return supervisor_->launch();
}

Result<void> RunSide::waitReady() {
  return supervisor_ ? supervisor_->waitReady(e_.options_.host_start_timeout) : Result<void>{};
}

Result<void> RunSide::run() {
  if (auto r = e_.crossings_.takeOver(); !r) return r;
  e_.buildExecutors();
  e_.holdCpuLatency();  // before the executors' first sleep
  std::size_t executors = 0;
  {
    std::lock_guard lock(e_.executors_mutex_);
    e_.crossings_.attach();  // values from other processes: read by the executors
    executors = e_.executors_.size();
  }
  e_.runComponents(nullptr);
  e_.crossings_.start();  // and by pumps for components without one, from here
  e_.started_ = true;
  e_.startDetectors();
  nlohmann::json started = log::schema::engine("started");
  started[log::schema::field::kExecutors] = executors;
  if (e_.cpu_latency_.held()) started[log::schema::field::kCpuDmaLatencyUs] = e_.cpu_latency_.microseconds();
  e_.log_.write(std::move(started));
  return {};
}

// A composite's state, derived from its members': Error as soon as one is in Error, otherwise
// the state they all share; while they are between states (one started, the next not yet), the
// last one holds. Logged by keel run only (a component process sees part of its members).
void RunSide::stateLogged(std::string_view instance) {
  const auto of = composites_of_.find(instance);
  if (of == composites_of_.end()) return;
  std::lock_guard lock(composite_mutex_);
  for (std::size_t i : of->second) {
    const plan::PlannedComposite& comp = e_.planned_.plan.composites[i];
    std::optional<State> shared;
    bool error = false, agree = true;
    for (const auto& m : comp.members) {
      const Component* member = e_.find(m);
      if (!member) continue;
      const State s = member->state();
      error |= s == State::Error;
      if (!shared) shared = s;
      agree &= *shared == s;
    }
    if (!shared) continue;
    const State derived = error ? State::Error : agree ? *shared : composite_states_[i];
    if (derived == composite_states_[i]) continue;
    e_.log_.write(
        log::schema::compositeState(comp.name, toString(composite_states_[i]), toString(derived), e_.log_.now()));
    composite_states_[i] = derived;
  }
}

void RunSide::emergencyCleared() {
  if (supervisor_) supervisor_->clearEmergency();
  if (e_.dds_) e_.dds_->safeCommandsOff();
}

void RunSide::lifecyclesReachable() { lifecycle_dds_.store(e_.dds_.get(), std::memory_order_release); }

void RunSide::windDownNodes() {
  if (nodes_) nodes_->windDownManaged(e_.options_.stop_timeout);
  lifecycle_dds_.store(nullptr, std::memory_order_release);  // its DDS side closes next
}

void RunSide::stopProcesses() {
  if (nodes_) nodes_->stop(e_.options_.stop_timeout);            // nodes the proxies' onStop did not stop
  if (supervisor_) supervisor_->stop(e_.options_.stop_timeout);  // hosts the proxies' onStop did not stop
}

void RunSide::stopped() {
  if (e_.started_) e_.log_.write(log::schema::engine("stopped"));
}

void RunSide::close() {  // their threads report to the fault manager
  nodes_.reset();
  supervisor_.reset();
}

}  // namespace keel::engine
