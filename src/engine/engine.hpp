// The engine carries a plan out (docs/architecture.md, "How a run goes"): load libraries and
// create instances, check their ports against the profiles, initialize, connect, start the
// executors; at the end stop and destroy everything in reverse order. It is the runtime's
// runtime::RunHooks (state changes reach the fault log from here, endRun ends the run); the
// runtime's faults go straight to the fault manager, which is the runtime's runtime::FaultSink.
// What differs between keel run's engine and a component process's is the engine's side
// (side.hpp): one engine, no mode.
// Thread-safety: build/start/stop from one thread; hooks are called from executor threads.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "dds/dds_ports.hpp"
#include "engine/run_end.hpp"
#include "engine/side.hpp"
#include "fault/dependency_graph.hpp"
#include "fault/fault_manager.hpp"
#include "fault/watchdog.hpp"
#include "injection/injector.hpp"
#include "injection/scenario.hpp"
#include "keel/component.hpp"
#include "keel/result.hpp"
#include "log/fault_log.hpp"
#include "plan/plan.hpp"
#include "plan/property_settings.hpp"
#include "profile/loader.hpp"
#include "runtime/alarm.hpp"
#include "runtime/component_core.hpp"
#include "runtime/cpu_latency.hpp"
#include "runtime/execution_gate.hpp"
#include "runtime/executor.hpp"
#include "runtime/field_rules.hpp"
#include "runtime/loader.hpp"
#include "runtime/warning.hpp"
#include "runtime/wire.hpp"
#include "supervision/crossing.hpp"
#include "supervision/process_host.hpp"
#include "supervision/process_supervisor.hpp"  // HostLaunch

namespace keel::engine {

struct EngineOptions {
  std::string log_path;     // empty: no log file
  bool log_append = false;  // append to log_path (keel soak's rounds) instead of truncating it
  /// A second copy of every log line, written right after the log has it (keel run
  /// --log-tee; log::FaultLog::openTee). keel run passes it on to its hosts as
  /// /proc/<pid>/fd/<fd>, so that they write to the same pipe.
  std::string log_tee;
  std::vector<std::string> search_path = runtime::Loader::defaultSearchPath();
  /// Warnings (e.g. a scheduling policy the OS refused); default prints to stderr.
  runtime::Warn warn;
  // To end the last cycles, then per executor to stop its members, before one is abandoned.
  std::chrono::milliseconds stop_timeout{2000};
  std::optional<injection::Scenario> scenario;  // faults to inject (keel run --inject)
  /// Properties set for this run (keel run --set), applied after the profiles' overrides.
  std::vector<plan::PropertySetting> property_settings;
  /// Hold the CPUs' wake-up latency at this many µs while running (keel run --cpu-dma-latency;
  /// src/runtime/cpu_latency.hpp). Not permitted: a warning, and the run goes on without it.
  std::optional<std::int32_t> cpu_dma_latency_us;
  /// keel run: how to start the component processes of the plan's <process>es (docs/isolation.md).
  supervision::HostLaunch host_launch{supervision::defaultHostExecutable(), {}};
  /// keel-host: this engine runs the components of one <process> only (src/host); null in keel run.
  supervision::ProcessHost* host = nullptr;
  /// How long connections between processes wait for their ring, and keel run for its hosts.
  std::chrono::milliseconds host_start_timeout{10000};
  /// keel validate --load: the code of every instance, whatever its <process>, is loaded in
  /// this process and checked against its profile, and so is each connection between processes;
  /// no process is started and the engine is never started.
  bool check_only = false;
};

/// One running instance and what the plan says of it.
struct Instance {
  const plan::PlannedInstance* plan = nullptr;
  std::unique_ptr<Component> component;   // as created from the plan
  runtime::Executor* executor = nullptr;  // null: passive
  /// The serving component: the one this name stands for now, `component` or the alternative
  /// that replaced it (an atomic of its own: the address stays put while instances_ grows).
  std::unique_ptr<std::atomic<Component*>> serving_slot = std::make_unique<std::atomic<Component*>>(nullptr);
  std::unique_ptr<fault::ComponentHandling> handling;  // its compiled rules (src/fault/rules.hpp)

  Component* serving() const { return serving_slot->load(std::memory_order_acquire); }
};

class Engine final : public runtime::RunHooks, public fault::RecoveryActions, public dds::PeerWatch {
 public:
  /// Plans `set` with options.property_settings applied, then as below.
  static Result<std::unique_ptr<Engine>> create(profile::ProfileSet set, EngineOptions options);
  /// Loads and instantiates `planned` (options.property_settings already applied to it: they
  /// are only logged); checks every port of code against its profile.
  static Result<std::unique_ptr<Engine>> create(plan::PlannedProfiles planned, EngineOptions options);
  ~Engine() override;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  /// initialize → connect → start executors. On failure, what failed and why.
  Result<void> start();
  /// Stops executors (members get onStop), logs the run's `counts`, then destroys instances in
  /// reverse order. Idempotent; called by the destructor if not before.
  void shutdown();

  /// The serving component of `instance` (an alternative, once one replaced it).
  Component* find(std::string_view instance) const override;
  /// Whether `c` stands for its instance's name now; false for an alternative standing by and
  /// for the component an alternative replaced.
  bool serves(const Component& c) const;
  const plan::Plan& plan() const { return planned_.plan; }
  const std::vector<Instance>& instances() const { return instances_; }
  /// The executors, including those that took over from an abandoned one (a snapshot).
  std::vector<const runtime::Executor*> executors() const;
  log::FaultLog& log() { return log_; }
  fault::FaultManager& faultManager() { return fault_manager_; }
  const fault::FaultManager& faultManager() const { return fault_manager_; }
  std::vector<fault::FaultCount> faultCounts() const { return fault_manager_.counts(); }
  /// Every serving component, for detectors that scan them and the fault manager.
  std::vector<Component*> components() const override;
  const fault::DependencyGraph* graph() const { return graph_ ? &*graph_ : nullptr; }

  /// Emergency stop from outside (an operator, `keel run`'s console): logged with `by`.
  std::vector<std::string> emergencyStop(std::string_view by) { return fault_manager_.emergencyStop(by); }
  /// Clears a latched emergency (an operator's explicit call); false if none was latched.
  bool clearEmergency(std::string_view by);

  /// A component ended the run (RunControl::endRun; the first call wins). The run's owner
  /// (`keel run`) waits for it and then stops as at the end of its duration; shutdown() logs
  /// the request's record last. Any thread.
  bool endRequested() const { return run_end_.requested(); }
  std::optional<RunEnd> runEnd() const { return run_end_.get(); }
  /// Blocks until a component ends the run or `until` passes; true if one did.
  bool waitForEnd(std::chrono::steady_clock::time_point until) const { return run_end_.waitUntil(until); }

  // runtime::RunHooks (faults go from the runtime to the fault manager directly: its FaultSink)
  void stateChanged(Component& c, State from, State to) override;
  void endRun(Component& c, std::string_view summary, std::string_view event, std::string_view fields) override;

  // fault::RecoveryActions (engine_recovery.cpp)
  Result<Component*> createAlternative(fault::ComponentHandling& h, Component& failed) override;
  void switchTo(Component& failed, Component& alternative) override;
  Result<std::string> abandonExecutor(Component& hung, Component* alternative) override;

  // dds::PeerWatch: a subscription's writers lost (a `remote` fault), and back.
  std::uint64_t peerLost(const std::string& instance, const FaultEvent& fault) override;
  void peerBack(const std::string& instance, std::uint64_t id, std::int64_t t_ns) override;
  bool quiet(const std::string& instance) override { return side_->quiet(instance); }
  std::int64_t firstSampleDue(const std::string& instance) override { return side_->firstSampleDue(instance); }
  /// Each component's health as /diagnostics reports it (engine_recovery.cpp).
  std::vector<dds::Health> health() const;
  /// How long a handled fault keeps a running component's /diagnostics level at WARN.
  static constexpr std::chrono::nanoseconds kRecentFault{std::chrono::seconds(5)};

 private:
  explicit Engine(EngineOptions options);
  /// OPRoS's execution order (<depends>) as gates, before any instance is made.
  void makeExecutionGates();
  Result<void> instantiate();
  Result<Instance> makeInstance(const plan::PlannedInstance& pi);              // created, named, ports checked
  Instance makeStandIn(const plan::PlannedInstance& pi, std::string& errors);  // keel run's proxy of it, or none
  /// The node profile of node instance `pi`'s <alternative>; null: none, or `pi` is no node.
  const profile::NodeProfile* alternativeNode(const plan::PlannedInstance& pi) const;
  Result<std::string> findLibrary(const profile::ComponentProfile& cp) const;  // kept; "": linked in
  void setUpHandling();  // rules and checkpoints per instance, the dependency graph
  Result<void> preloadAlternatives();
  /// Re-points the input connections and provided services of `failed` to `alternative`.
  void redirectInputs(Component& failed, Component& alternative);
  Result<void> checkPorts(const Instance& inst);  // an OPRoS component's differences: warnings
  Result<void> configurePorts(Instance& inst);    // queues, validity rules, call timeouts
  /// The <validity field=".."> of `d` resolved in `port`'s message type and set on the port.
  Result<void> configureFieldRules(const Instance& inst, const profile::DataPort& d, detail::PortBase& port);
  /// Each node's <validity field=".."> names a numeric field of its port's message type.
  Result<void> checkNodeFieldRules() const;
  /// Connects field `field` of output port `src`'s messages to `connection` (a double input's):
  /// a port of src's owner sends each message's number on it (any thread before src's owner
  /// starts: at connect, or for an alternative before its switch).
  /// Returns that port.
  Result<detail::PortBase*> tapField(detail::PortBase& src, const std::string& field,
                                     detail::ConnectionBase& connection);
  /// An input data port's queue: the profile's, or the one an OPRoS component's code fixed.
  void configureQueue(const Instance& inst, const profile::DataPort& d, detail::InputPortBase& port);
  Result<void> connect();
  void buildExecutors();
  void startDetectors();
  void warn(const std::string& message);
  /// Whether `pi` runs in this engine's process (keel run's own, or the host's <process>); never
  /// a ROS 2 node.
  bool isLocal(const plan::PlannedInstance& pi) const;
  /// check_only: what each component process checks when it connects its ends (a value that
  /// cannot cross processes), for every connection between processes.
  Result<void> checkCrossings() const;
  /// Logs a `counts` record per component of this process and per executor (at shutdown).
  void logCounts();
  /// A warning of how many lines the log's tee dropped, if any (at shutdown).
  void warnTeeDropped();
  void holdCpuLatency();
  /// Passive components started, the rings read from where they were left, the executors let
  /// go: by the main thread (waiting for each onStart), or `self`'s (a standby's takeover).
  void runComponents(runtime::Executor* self);

  EngineOptions options_;
  plan::PlannedProfiles planned_;  // the plan, and the profiles it points into
  const profile::ProfileSet& set() const { return *planned_.profiles; }
  runtime::Loader loader_;
  log::FaultLog log_;
  /// A connection carrying one numeric field of a message port (a <source field="..">): the
  /// port of `owner` that sends the field's numbers (destroyed after the components).
  struct FieldTapPort {
    Component* owner;
    std::string port;  // the message port
    std::string field;
    std::unique_ptr<detail::PortBase> out;
    detail::ConnectionBase* connection;
  };
  std::vector<FieldTapPort> taps_;
  std::vector<Instance> instances_;
  // Instance by name, built once instantiate() has made them all (read-only afterwards, from
  // any thread): find() is on the fault manager's path, once per stopped component.
  std::unordered_map<std::string_view, const Instance*> by_name_;
  std::vector<std::unique_ptr<detail::ConnectionBase>> connections_;
  // keel run's or a component process's (declared before what uses its session: destroyed after).
  std::unique_ptr<Side> side_;
  supervision::Crossings crossings_;
  std::unique_ptr<dds::DdsPorts> dds_;  // this process's <publish>/<subscribe>; null: none
  std::vector<runtime::Wire> wires_;    // every connection as made: a replacement re-points them
  std::optional<fault::DependencyGraph> graph_;
  std::mutex create_mutex_;                               // one alternative created at a time (any thread)
  std::mutex alternatives_mutex_;                         // guards the two below
  std::deque<plan::PlannedInstance> alternative_plans_;   // the alternatives' plans (stable addresses)
  std::vector<std::unique_ptr<Component>> alternatives_;  // alternatives created: standing by or serving
  std::vector<std::unique_ptr<detail::ValidityRule>> rules_;
  std::vector<std::unique_ptr<detail::FieldRules>> field_rules_;
  std::map<std::string, std::unique_ptr<runtime::ExecutionGate>> gates_;  // by instance: OPRoS's depends
  mutable std::mutex executors_mutex_;  // the fault manager's thread adds to executors_
  // Opened once every executor has started its members: no first cycle before that (runComponents).
  std::atomic<std::uint32_t> first_cycle_{0};
  runtime::StopBarrier stop_barrier_;  // every executor's last cycle before any member stops
  std::vector<std::unique_ptr<runtime::Executor>> executors_;
  fault::FaultManager fault_manager_;
  std::unique_ptr<fault::Watchdog> watchdog_;
  runtime::CpuLatencyRequest cpu_latency_;  // held from start() to shutdown()
  std::unique_ptr<injection::Injector> injector_;
  bool started_ = false;
  bool shut_down_ = false;
  RunEndLatch run_end_;  // RunControl::endRun, from any component's thread

  // The two sides are parts of the engine, in files of their own.
  friend class RunSide;
  friend class HostSide;
};

}  // namespace keel::engine
