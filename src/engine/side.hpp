// The engine's side: what differs between the engine of keel run and the engine of a component
// process (keel-host), behind one interface, so that the engine itself has no mode. keel run's
// side (run_side.hpp) writes the run's first and last records, starts the component processes
// and stands in for their instances; a component process's side (host_side.hpp) joins that
// log and runs its instances once it holds its role — at once, or as a standby when the active
// process dies. The engine calls its side at fixed points of a run, in the order below.
// Thread-safety: as the engine's (engine.hpp); holdsState() and stateLogged() from any thread.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <string_view>

#include "dds/lifecycle.hpp"
#include "dds/parameter_events.hpp"
#include "dds/ros2_graph.hpp"
#include "injection/scenario.hpp"
#include "keel/component.hpp"
#include "keel/result.hpp"
#include "plan/plan.hpp"
#include "runtime/component_core.hpp"
#include "runtime/ipc/session.hpp"

namespace keel::engine {

class Side {
 public:
  virtual ~Side() = default;

  /// The <process> whose instances this engine runs: "" for keel run's own.
  virtual const std::string& process() const = 0;

  // ---- create() ----
  /// The log opened (keel run) or joined (a component process), and the run's first records.
  virtual Result<void> openLog() = 0;
  /// The processes' shared session, rings and supervisor (not for keel validate --load).
  virtual Result<void> setUpProcesses() = 0;
  /// The stand-in for `pi`, which runs in another process (keel run's proxy); null: none here.
  virtual std::unique_ptr<Component> standIn(const plan::PlannedInstance& pi) = 0;
  /// What this side sets in a component it runs: where its faults go, its shared checkpoint.
  virtual void adopt(const plan::PlannedInstance& pi, detail::ComponentCore& core) = 0;
  /// The session and the rings' descriptors (by ring index) the crossings are made in.
  virtual runtime::ipc::Session& session() = 0;
  virtual std::map<std::size_t, int> ringDescriptors() = 0;
  /// Whether this process writes keel's /diagnostics (keel run's, for every component).
  virtual bool publishesDiagnostics() const = 0;
  /// Whether this process is keel's node of the ROS 2 graph (keel run's), when it is in DDS at
  /// all: it has DDS topics of its own, /diagnostics, or ROS 2 nodes.
  virtual bool joinsRosGraph() const = 0;
  /// Where what the ROS 2 graph shows of the plan's nodes goes (keel run's node supervisor);
  /// null: this side watches no node.
  virtual dds::GraphWatch* graphWatch() = 0;
  /// Whether instance `instance`'s topics are quiet by its own start, death or stop (a ROS 2
  /// node that is not up): a missed deadline on them is then no fault. Any thread.
  virtual bool quiet(std::string_view instance) const = 0;
  /// When (steady ns) node `instance`'s current life owes its first sample on its timed topics;
  /// 0: it owes none (not a node, or quiet). Any thread.
  virtual std::int64_t firstSampleDue(std::string_view) const { return 0; }
  /// Where the parameter changes of the nodes keel runs go (keel run's node supervisor, which
  /// restarts a node with them); null: this side restarts no node.
  virtual dds::ParameterWatch* parameterWatch() { return nullptr; }
  /// Where what the managed (lifecycle) nodes keel runs say goes (keel run's node supervisor,
  /// which drives them through their transitions); null: this side drives no node.
  virtual dds::LifecycleWatch* lifecycleWatch() { return nullptr; }
  /// The DDS side reaches the managed nodes from now on (its lifecycle clients are open; the
  /// engine's thread, once, before the run): requests may be written.
  virtual void lifecyclesReachable() {}
  /// At the engine's shutdown, before its DDS side closes: the managed nodes it runs are
  /// deactivated and shut down while they can still be asked (keel run's).
  virtual void windDownNodes() {}
  /// Whether this process stands by: its DDS readers wait until it takes over.
  virtual bool standingBy() const = 0;
  /// Whether fault `f` of the scenario is injected by this process; `pi`: the instance it
  /// names, null if the plan has none of that name.
  virtual bool injects(const injection::ScheduledFault& f, const plan::PlannedInstance* pi) const = 0;

  // ---- start() ----
  /// Before the components initialize: the component processes started (they load meanwhile).
  virtual Result<void> launch() = 0;
  /// Once the connections are made: the component processes run theirs.
  virtual Result<void> waitReady() = 0;
  /// Once the fault manager runs: the executors made and the components started.
  virtual Result<void> run() = 0;

  // ---- while it runs ----
  /// A component's state changed: true if its record waits (a takeover under way).
  virtual bool holdsState(const Component& c, State from, State to) = 0;
  /// A component's state record was written.
  virtual void stateLogged(std::string_view instance) = 0;
  /// An operator cleared the emergency here.
  virtual void emergencyCleared() = 0;

  // ---- shutdown() and after ----
  /// The executors stopped and the components destroyed: the processes this one started stop.
  virtual void stopProcesses() = 0;
  /// The run's last record of this side (before a requested end's).
  virtual void stopped() = 0;
  /// Before the engine's members go: nothing of this side reports to them from here.
  virtual void close() = 0;
};

}  // namespace keel::engine
