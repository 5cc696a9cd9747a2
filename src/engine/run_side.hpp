// keel run's side of the engine (side.hpp): it opens the run's log and writes its `load`,
// `started` and `stopped` records and the composites' derived states; when the plan has
// <process>es, it makes their shared session and rings, holds the supervisor lock for the
// run (its release by death tells every component process), and has the supervisor start,
// watch and stop them, with a proxy standing in for each instance they run; when it has ROS 2
// nodes, it has the node supervisor start and watch them likewise. It owns the spawner
// every process keel run starts comes from, whose thread lives as long as the run.
// Thread-safety: as Side's.
#pragma once

#include <atomic>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "engine/side.hpp"
#include "supervision/node_supervisor.hpp"
#include "supervision/process_supervisor.hpp"
#include "supervision/spawner.hpp"

namespace keel::dds {
class DdsPorts;
}  // namespace keel::dds

namespace keel::engine {

class Engine;

class RunSide final : public Side, private dds::GraphWatch, private dds::ParameterWatch, private dds::LifecycleWatch {
 public:
  explicit RunSide(Engine& engine);
  ~RunSide() override;
  RunSide(const RunSide&) = delete;
  RunSide& operator=(const RunSide&) = delete;

  const std::string& process() const override { return process_; }
  Result<void> openLog() override;
  Result<void> setUpProcesses() override;
  std::unique_ptr<Component> standIn(const plan::PlannedInstance& pi) override;
  void adopt(const plan::PlannedInstance&, detail::ComponentCore&) override {}
  runtime::ipc::Session& session() override { return *session_; }
  std::map<std::size_t, int> ringDescriptors() override { return supervisor_->ringDescriptors(); }
  bool publishesDiagnostics() const override;
  bool joinsRosGraph() const override;
  dds::GraphWatch* graphWatch() override { return nodes_ ? this : nullptr; }
  bool quiet(std::string_view instance) const override { return nodes_ && nodes_->quiet(instance); }
  std::int64_t firstSampleDue(std::string_view instance) const override {
    return nodes_ ? nodes_->firstSampleDue(instance) : 0;
  }
  dds::ParameterWatch* parameterWatch() override { return nodes_ ? this : nullptr; }
  dds::LifecycleWatch* lifecycleWatch() override { return nodes_ ? this : nullptr; }
  void lifecyclesReachable() override;
  bool standingBy() const override { return false; }
  bool injects(const injection::ScheduledFault& f, const plan::PlannedInstance* pi) const override;
  Result<void> launch() override;
  Result<void> waitReady() override;
  Result<void> run() override;
  bool holdsState(const Component&, State, State) override { return false; }
  void stateLogged(std::string_view instance) override;
  void emergencyCleared() override;
  void windDownNodes() override;
  void stopProcesses() override;
  void stopped() override;
  void close() override;

 private:
  // What the ROS 2 graph shows of a node: to the node supervisor.
  void nodeSeen(const std::string& instance, const std::vector<dds::NodeSighting>& sightings) override;
  bool ownsParticipant(const std::string& instance, pid_t pid, bool listed) override {
    return nodes_->owns(instance, pid, listed);
  }
  void nodeReported(const std::string& instance, bool error, const std::string& what) override {
    nodes_->nodeReported(instance, error, what);
  }
  // A node's parameter changes: to the node supervisor, for its restarts.
  void parametersChanged(const std::string& instance, const profile::ParameterUpdate& update) override {
    nodes_->parametersChanged(instance, update);
  }
  // What the managed nodes say of their lifecycle: to the node supervisor, which drives them.
  void transitioned(const std::string& instance, const std::string& name, std::uint8_t start,
                    std::uint8_t goal) override {
    nodes_->lifecycleTransition(instance, name, start, goal);
  }
  void stateIs(const std::string& instance, const std::string& name, std::uint8_t state) override {
    nodes_->lifecycleState(instance, name, state);
  }
  bool runs(const std::string& instance, const std::string& name, pid_t pid) override {
    return nodes_->runs(instance, name, pid);
  }
  Result<void> setUpNodes();

  Engine& e_;
  const std::string process_;  // keel run's own: ""
  // Every child keel run starts is started from its thread, whose end kills them
  // (PR_SET_PDEATHSIG): it lives until the side goes, after those who use it.
  supervision::Spawner spawner_;
  // Process isolation: the session before the supervisor, which uses it (destroyed after).
  std::optional<runtime::ipc::Session> session_;
  bool holds_supervisor_lock_ = false;
  std::unique_ptr<supervision::ProcessSupervisor> supervisor_;
  std::unique_ptr<supervision::NodeSupervisor> nodes_;  // when the plan has ROS 2 nodes
  /// The engine's DDS side once its lifecycle clients are open: the supervisor's threads reach
  /// the managed nodes through it (null before, and once the nodes are wound down).
  std::atomic<dds::DdsPorts*> lifecycle_dds_{nullptr};
  // Composites (plan().composites): OPRoS gives them no state; keel run logs one derived from
  // their members' (compositeStates). Guarded by composite_mutex_ (any component's thread).
  std::mutex composite_mutex_;
  std::vector<State> composite_states_;                                         // as last logged, per composite
  std::map<std::string, std::vector<std::size_t>, std::less<>> composites_of_;  // instance → composites
};

}  // namespace keel::engine
