// keel's data ports on DDS topics (docs/dds.md): the plan's <publish> and <subscribe> bindings
// of one process made into CycloneDDS writers and readers, with ROS 2's conventions (topic
// `/a/b` is DDS topic `rt/a/b`, type `pkg/msg/Name` is `pkg::msg::dds_::Name_`, ROS 2's QoS).
//   publish:   the output port attaches a connection whose sink converts each value and writes
//              it (on the sending component's thread: no copy, no queue, no thread of keel's).
//   subscribe: a connection made by the input port; CycloneDDS's listener takes each sample,
//              converts it and sends it there (queue policy, validity, wake-ups as for a local
//              connection), and reports a missed deadline or a writer's lost liveliness to the
//              PeerWatch once per outage, and the outage's end.
// Both ends are connections the engine re-points when it replaces a component.
// A standby host's (docs/isolation.md) are made ahead and matched by their peers, but its
// readers stand by: they take and drop each sample and keep an outage to themselves until
// takeOver() (decision 0019).
// Thread-safety: open/close from one thread; takeOver and reportHeldOutages from any one thread
// after open; listeners run on CycloneDDS's threads.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "dds/diagnostics.hpp"
#include "dds/lifecycle.hpp"
#include "dds/node_diagnostics.hpp"
#include "dds/parameter_events.hpp"
#include "dds/ros2_graph.hpp"
#include "dds/safe_commands.hpp"
#include "keel/detail/port_base.hpp"
#include "keel/fault_event.hpp"
#include "keel/result.hpp"
#include "plan/plan.hpp"
#include "runtime/warning.hpp"
#include "runtime/wire.hpp"

namespace keel::dds {

/// What the DDS layer reports of a subscription's writers (the engine: to its fault manager).
class PeerWatch {
 public:
  virtual ~PeerWatch() = default;
  /// The writers feeding a subscription of `instance` were lost (deadline missed, liveliness
  /// lost): a `remote` fault of it. Returns the fault's id (0: not reported).
  virtual std::uint64_t peerLost(const std::string& instance, const FaultEvent& fault) = 0;
  /// Samples (or a live writer) came back after fault `id`, at steady time `t_ns`.
  virtual void peerBack(const std::string& instance, std::uint64_t id, std::int64_t t_ns) = 0;
  /// Whether `instance`'s silence is its own doing (a ROS 2 node not up: dead, restarting,
  /// stopped, not come up yet): its output topics' deadlines then count from its next sample.
  virtual bool quiet(const std::string& instance) = 0;
  /// When (steady ns) the first sample of `instance`'s current life is due on each of its timed
  /// topics (a ROS 2 node's start plus its start timeout); 0: none is (not a node, or quiet).
  virtual std::int64_t firstSampleDue(const std::string& instance) = 0;
};

/// The DDS name of ROS 2 topic `topic` ("/a/b" → "rt/a/b").
std::string ddsTopicName(const std::string& topic);
/// The DDS type name of ROS 2 type `type` ("pkg/msg/Name" → "pkg::msg::dds_::Name_").
std::string ddsTypeName(const std::string& type);
/// `name` as a ROS 2 node name: each character a node name cannot hold ([A-Za-z0-9_]) becomes `_`,
/// and one that would start with a digit or `_` (or be empty) gets `keel_` in front.
std::string rosNodeName(std::string_view name);

/// The domain a <dds domain> means in this process: ROS_DOMAIN_ID when set (and not empty),
/// else `domain`. An error if ROS_DOMAIN_ID is not a domain id (0-232), as ROS 2's rcl refuses it.
Result<int> effectiveDomain(int domain);

class DdsPorts {
 public:
  using FindPort = std::function<detail::PortBase*(const profile::Endpoint&)>;

  DdsPorts(PeerWatch& watch, runtime::Warn warn);
  ~DdsPorts();
  DdsPorts(const DdsPorts&) = delete;
  DdsPorts& operator=(const DdsPorts&) = delete;

  /// Whether the readers deliver from open() on, or stand by until takeOver().
  enum class Readers { Serving, StandingBy };

  /// Makes the writers and readers of `bindings` (this process's), their ports found by
  /// `find`. Every problem is in the error, each line `file:line: what and why`; nothing is
  /// left open after a failure.
  Result<void> open(const std::vector<plan::PlannedDds>& bindings, const FindPort& find,
                    Readers readers = Readers::Serving);
  /// A standby took over: its readers deliver each sample from here (the takeover's thread,
  /// before its components start). Does not report: see reportHeldOutages().
  void takeOver();
  /// After takeOver(), once the components run: an outage that began while standing by and
  /// lasts (a writer lost before the takeover) is reported now, as a fault of the new active.
  void reportHeldOutages();
  /// The connections made between the ports and their topics (the topic's side has no port).
  const std::vector<runtime::Wire>& wires() const { return wires_; }
  /// Publishes /diagnostics in `domain` (ROS_DOMAIN_ID overrides it): `snapshot()` at 1 Hz and
  /// after each pokeDiagnostics().
  Result<void> publishDiagnostics(int domain, DiagnosticsWriter::Snapshot snapshot);
  /// A component's state changed: /diagnostics says so now (any thread; nothing without one).
  void pokeDiagnostics() {
    if (diagnostics_) diagnostics_->poke();
  }
  /// keel's run as a node of the ROS 2 graph: `/keel/<name>` (name as rosNodeName() makes it),
  /// with the topics of its writers and readers, in every domain it has joined and in `domain`
  /// (ROS_DOMAIN_ID overrides it) — published on `ros_discovery_info` as every rmw does, so that
  /// `ros2 node list` shows it until its participant leaves. Call once open() and
  /// publishDiagnostics() made what it has.
  Result<void> joinGraph(int domain, std::string_view name);
  /// Watches `nodes` in the ROS 2 graph of `domain` (ROS_DOMAIN_ID overrides it): what it shows
  /// of each goes to `watch` (ros2_graph.hpp), and so does the status of each that names one of
  /// its own on /diagnostics (node_diagnostics.hpp), from now until close().
  Result<void> watchNodes(int domain, std::vector<WatchedNode> nodes, GraphWatch& watch);
  /// One output topic of a ROS 2 node keel watches, read into its stand-in's output port.
  struct NodeOutput {
    std::string instance;
    profile::DdsBinding binding;  // as a <subscribe>'s: topic, type, QoS, deadline, liveliness
    detail::PortBase* port = nullptr;
  };
  /// Reads each of `outputs` in `domain` into its port, taking only the samples of the node's own
  /// writers (as watchNodes' watch judges their participants: call watchNodes first). keel times
  /// the node's samples against the port's deadline itself (a ROS 2 writer offers none, and other
  /// writers of the topic must not count); a miss goes to the PeerWatch as a <subscribe>'s does,
  /// once the node has sent a sample since it was quiet.
  Result<void> readNodeOutputs(int domain, const std::vector<NodeOutput>& outputs);
  /// Reads /parameter_events in `domain` (ROS_DOMAIN_ID overrides it) for `nodes`, the nodes keel
  /// runs: each change one of them announces goes to `watch` (parameter_events.hpp), until close().
  Result<void> watchParameters(int domain, std::vector<WatchedNode> nodes, ParameterWatch& watch);
  /// Reaches the lifecycle services and transition events of `nodes` (the managed nodes keel
  /// runs) in `domain` (ROS_DOMAIN_ID overrides it): what they say goes to `watch`
  /// (lifecycle.hpp), until close(). Call watchNodes first: its graph judges whose they are.
  Result<void> watchLifecycles(int domain, const std::vector<LifecycleNode>& nodes, LifecycleWatch& watch);
  /// Asks the process named `name` of managed node `instance` for transition `transition` (any
  /// thread): what became of it.
  LifecycleClients::Sent requestTransition(const std::string& instance, const std::string& name,
                                           std::uint8_t transition) {
    return lifecycles_ ? lifecycles_->request(instance, name, transition) : LifecycleClients::Sent::NoSuchNode;
  }
  /// Asks the process named `name` of managed node `instance` its state (any thread).
  LifecycleClients::Sent askLifecycleState(const std::string& instance, const std::string& name) {
    return lifecycles_ ? lifecycles_->askState(instance, name) : LifecycleClients::Sent::NoSuchNode;
  }
  /// A new process is to run as `name` of managed node `instance`: requests to it go through new
  /// writers (LifecycleClients::renew), listed in the graph in place of the old (any thread).
  void renewLifecycleRequests(const std::string& instance, const std::string& name);
  /// Writes each node's safe command of `commands` (its <emergency>'s <publish>) in `domain` while
  /// keel's emergency stop holds: from safeCommandsOn(its node) until safeCommandsOff().
  Result<void> openSafeCommands(int domain, const std::vector<NodeSafeCommand>& commands);
  /// Node `instance`'s safe commands are written from now on (the emergency stop; any thread).
  void safeCommandsOn(const std::string& instance) {
    if (safe_commands_) safe_commands_->start(instance);
  }
  /// The emergency stop was cleared: no safe command is written any more (any thread).
  void safeCommandsOff() {
    if (safe_commands_) safe_commands_->clear();
  }
  /// A life of node `instance` ended, its process `pid` gone (`who`: which node, how), seen by
  /// keel run the moment it happened (any thread; nothing before watchNodes). Its output topics'
  /// deadlines count again from its next life's first sample. When it `died` (an exit keel did
  /// not ask for), each <subscribe> watching its writers (a deadline or a liveliness) whose every
  /// matched writer belonged to that process, or to one that died before, loses them now,
  /// without waiting for its deadline or lease.
  void nodeExited(const std::string& instance, pid_t pid, const std::string& who, bool died);
  /// Node `instance`'s role is served by another stand-in (its alternative took the node's
  /// place): each of its output topics goes into that stand-in's port of the same name, as
  /// `port` finds it, from the next sample on (the fault manager's thread, at the switch); the
  /// writers of the node it replaced are not heard again, though it may publish until ended.
  void nodeServedBy(const std::string& instance, const std::function<detail::PortBase*(const std::string&)>& port);
  /// Deletes every DDS entity; no listener runs once it returns. Idempotent.
  void close();
  /// keel run is ending: a reader that goes silent from here on (the nodes keel winds down, the
  /// writers it closes) is no `remote` fault. Before the run's nodes are wound down; any thread.
  void stopReporting() { ending_.store(true, std::memory_order_release); }

  struct Reader;  // dds_ports.cpp

  /// keel's own deadline timer of the node readers (its thread's body).
  void timeNodeOutputs();

 private:
  /// writersDied: the <subscribe>s whose writers were all of `pid` or earlier dead processes.
  void writersDied(pid_t pid, const std::string& who);
  /// The participant of `domain` in this process, joined on first use.
  Result<std::int32_t> participant(int domain);

  PeerWatch& watch_;
  runtime::Warn warn_;
  std::map<int, std::int32_t> participants_;  // by domain
  std::vector<std::unique_ptr<Reader>> readers_;
  std::vector<std::unique_ptr<detail::ByteEnd>> outlets_;
  std::vector<std::unique_ptr<detail::ConnectionBase>> inlets_;
  std::vector<runtime::Wire> wires_;
  std::unique_ptr<DiagnosticsWriter> diagnostics_;
  std::unique_ptr<Ros2Graph> graph_;
  std::unique_ptr<NodeDiagnostics> node_diagnostics_;
  std::vector<Reader*> timed_;  // node readers with a deadline, timed by node_timer_
  std::mutex node_timer_mutex_;
  std::condition_variable node_timer_wake_;
  bool node_timer_ending_ = false;
  std::thread node_timer_;
  std::unique_ptr<ParameterEvents> parameters_;
  std::unique_ptr<LifecycleClients> lifecycles_;
  std::unique_ptr<SafeCommands> safe_commands_;
  struct Endpoint {
    std::int32_t participant;
    std::int32_t entity;
    bool writer;
  };
  /// keel's node in one participant's ros_discovery_info: its writer.
  struct Listing {
    std::int32_t participant;
    std::shared_ptr<detail::ByteEnd> outlet;
  };
  /// Writes `l`'s participant's ros_discovery_info: keel's node and its endpoints_ there.
  void publishListing(const Listing& l);
  std::mutex graph_mutex_;           // endpoints_, the listings: renewLifecycleRequests runs any time
  std::vector<Endpoint> endpoints_;  // every writer and reader made, for the graph
  std::string graph_name_;           // keel's node name in the graph
  std::vector<Listing> listings_;
  std::atomic<bool> ending_{false};  // stopReporting() was called
  std::mutex dead_mutex_;
  std::set<pid_t> dead_;  // processes writersDied() was told of: their writers are gone
};

}  // namespace keel::dds
