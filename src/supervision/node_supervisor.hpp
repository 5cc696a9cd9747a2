// keel run's side of ROS 2 nodes (docs/ros2-nodes.md): it starts each node a node profile
// describes, in a process group of its own, through keel-node-exec (so that the node dies with
// keel run, kill -9 included), its output appended to a file beside the run's log; it sees the
// node's death the moment it happens (exit_watch.hpp) and reports it as a `process` fault of the
// node's proxy, keel run's stand-in for the node in the engine, with its exit status and its last
// output lines. The proxy is passive: its reset restarts the node (with the parameter values it
// last had: node_parameters.hpp), its stop stops it (SIGINT to its group, a grace period, then
// SIGKILL), its emergency stop stops it when its profile says so and has its safe commands
// written (setEmergency).
// A managed node (<lifecycle/>) is driven through ROS 2's lifecycle (LifecycleLink): configured
// and activated once it is in the graph and the managed nodes it needs (<needs>, through any
// component) are Active, deactivated and shut down before it is stopped (at keel run's end,
// before the managed nodes it needs); its
// reset, while it lives and answers, goes deactivate → cleanup → configure → activate in the
// same process. Each transition is confirmed by the node's own transition event (or its state,
// asked), within its transition timeout; a failed or late one, or a node falling into
// ErrorProcessing or Finalized by itself, is a `lifecycle` fault of it.
// Every start, exit and stop is a `node` record of the log. A guard process (keel-node-exec
// --guard) knows every node's process group: when keel run dies, kill -9 included, it kills what
// is left of them (what a node forked, which dies with keel run no other way).
// Nodes are started by keel run's spawner (spawner.hpp), which outlives the supervisor.
// Thread-safety: launch() and stop() from the engine's thread; the proxies from any thread.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "keel/component.hpp"
#include "keel/detail/port_base.hpp"
#include "keel/result.hpp"
#include "log/fault_log.hpp"
#include "plan/plan.hpp"
#include "runtime/warning.hpp"
#include "supervision/exit_watch.hpp"
#include "supervision/node_parameters.hpp"
#include "supervision/spawner.hpp"

namespace keel::supervision {

/// What every node keel run starts shares.
struct NodeLaunch {
  std::string node_exec;   // keel-node-exec
  std::string output_dir;  // where each node's output file is
  /// Each node's output file is `<output_dir>/<output_stem>.<instance>.out` ("run.wander.out"
  /// beside run.jsonl); a process under a standby's name writes to
  /// `<output_stem>.<instance>.<its node name>.out` ("run.planner.planner_standby_1.out").
  std::string output_stem = "run";
  int domain = 0;  // ROS_DOMAIN_ID of every node: keel run's own domain
  /// Each output file is emptied when the run first starts a process into it; false: appended to
  /// (keel soak's later rounds, whose log is appended to too).
  bool fresh_output = true;
};

/// keel-node-exec: $KEEL_NODE_EXEC if set, else beside the running executable.
std::string defaultNodeExec();

/// The last `n` lines of the text file `path` (its last 4 KiB at most), without their line ends.
std::vector<std::string> lastLines(const std::string& path, std::size_t n);

/// How keel reaches the services of the managed nodes it runs (keel run's DDS side).
struct LifecycleLink {
  /// What became of a request.
  enum class Asked {
    Written,  // on its way to the node's current process
    NotYet,   // no reader of the node's current process matched yet: ask again later
    Cyclone,  // the node runs on rmw_cyclonedds, whose requests keel does not write
  };
  /// Asks the process named `name` ("/ns/node", or a standby's) of node `instance` for transition
  /// `transition` (a lifecycle_msgs/msg/Transition id).
  std::function<Asked(const std::string& instance, const std::string& name, std::uint8_t transition)> request;
  /// Asks the process named `name` of node `instance` its state, answered to lifecycleState().
  std::function<Asked(const std::string& instance, const std::string& name)> ask_state;
  /// A new process is about to run as `name` of node `instance`: what was asked of an earlier
  /// process of that name must not reach it (may be empty).
  std::function<void(const std::string& instance, const std::string& name)> renew;
};

/// One participant of the ROS 2 graph that lists a node (what keel run's graph watch saw).
struct GraphSighting {
  pid_t pid = 0;        // the process it announces; 0: none announced
  bool listed = false;  // it lists the node by name (else it publishes one of the node's topics)
  /// The node's declared output topics it does not publish (yet): none when the node is up.
  std::vector<std::string> missing;
};

class NodeSupervisor {
 public:
  /// Every instance of `plan` whose `node` is set is a node this supervisor runs (an attached
  /// one: watches); `log` gets the `node` records; `spawner` starts the nodes.
  NodeSupervisor(const plan::Plan& plan, NodeLaunch launch, runtime::Warn warn, log::FaultLog& log, Spawner& spawner);
  ~NodeSupervisor();
  NodeSupervisor(const NodeSupervisor&) = delete;
  NodeSupervisor& operator=(const NodeSupervisor&) = delete;

  /// Makes output port `port` of type `port.data_type` on `owner` (null: no such type here).
  using PortMaker = std::function<std::unique_ptr<detail::PortBase>(Component* owner, const profile::DataPort& port)>;
  /// keel run's stand-in for node `instance`, with an output port (made by `make`) for each
  /// output topic its profile declares, which keel fills from DDS; null when it is not a node.
  /// An instance planned for a role's alternative (the role's name, `node` the alternative's
  /// profile) gives the alternative's stand-in: its onStart stops the role's node (SIGINT, its
  /// grace, SIGKILL) and starts the alternative in its place (a `node` record `replaced`), with
  /// the alternative's own parameters; its resets restart the alternative from then on.
  std::unique_ptr<Component> makeProxy(const plan::PlannedInstance& instance, const PortMaker& make = {});
  /// Where the proxies' faults go (the fault manager), before launch().
  using Report = std::function<void(Component& proxy, const FaultEvent& fault)>;
  void setReport(Report report) { report_ = std::move(report); }
  /// Where each end of a node's process goes besides its record and fault (keel's readers of its
  /// topics), before launch(): the node's instance, its pid, what ended how ("node '/wander'
  /// (pid 7) killed by signal 9 (SIGKILL)"), and whether it died (an exit keel did not ask for).
  using Exited = std::function<void(const std::string& instance, pid_t pid, const std::string& who, bool died)>;
  void setExited(Exited exited) { exited_ = std::move(exited); }
  /// Where a node's part of keel's emergency stop goes besides its <stop/> (its safe commands'
  /// writer), before launch(): the node's instance, for each node whose profile has <emergency>.
  using Emergency = std::function<void(const std::string& instance)>;
  void setEmergency(Emergency emergency) { emergency_ = std::move(emergency); }
  /// How the managed nodes' transitions are asked for, before launch() (without it, a managed
  /// node is started and never configured).
  void setLifecycle(LifecycleLink link) { lifecycle_ = std::move(link); }
  /// Where a managed node's recovery goes, before launch(): its reset ends when it is Active
  /// again, after the reset's handling (the fault manager's `recovered`, at steady time t_ns).
  using Recovered = std::function<void(Component& proxy, std::int64_t t_ns)>;
  void setRecovered(Recovered recovered) { recovered_ = std::move(recovered); }

  /// Starts every node keel runs (not the attached ones); each one that cannot be started is
  /// an error, all said.
  Result<void> launch();
  /// Stops every node still running: SIGINT to its group, then SIGKILL to those still there
  /// after their grace period (at most `within`). Its exit is then no fault.
  void stop(std::chrono::milliseconds within);
  /// Deactivates and shuts down every managed node still running, each before the managed
  /// nodes it needs (<needs>), within `within` in all; their processes are left for stop().
  /// For keel run's end, while its DDS side still reaches them.
  void windDownManaged(std::chrono::milliseconds within);

  /// What the ROS 2 graph shows of node `instance` now (every participant listing its name or
  /// publishing one of its output topics), from the graph's watch (any thread). The first call
  /// for a node arms its start timeout (counted from its start): without a graph to watch, a
  /// node is never late. A node keel started is up when a participant of its process (or of its
  /// process group) publishes every declared output topic (one with none: lists its name); an
  /// attached node when a participant listing its name does. Up and then not, while its process
  /// runs, it left: a `remote` fault.
  void nodeSeen(std::string_view instance, std::vector<GraphSighting> sightings);

  /// Whether a participant of process `pid` that lists node `instance` by name or not
  /// (`listed`) is the node's own: its process or process group; an attached node's, one
  /// that lists it. Its writers' samples are the node's (any thread).
  bool owns(std::string_view instance, pid_t pid, bool listed) const;
  /// Node `instance` published its own /diagnostics status (its profile's <diagnostics name>),
  /// at ERROR (`error`) or not; `what`: its name and message (any thread). The first at ERROR
  /// of a life, or after one below ERROR, is a `reported` fault: one fault per episode.
  void nodeReported(std::string_view instance, bool error, const std::string& what);
  /// Whether node `instance`'s topics are quiet by its death or keel's doing: it has no process
  /// (dead, being restarted) or keel is stopping it; an attached node: it is not up. A deadline
  /// missed then is no fault of its own: its death or its stop speaks for it (any thread).
  bool quiet(std::string_view instance) const;
  /// When (steady ns) node `instance`'s current life is to have sent its first sample on each
  /// output topic with a deadline: its start (an attached node: the run's) plus its start
  /// timeout, the time it has to come up. 0 while it is quiet or not up (its start fault
  /// speaks then), or for no such node (any thread).
  std::int64_t firstSampleDue(std::string_view instance) const;
  /// Node `instance` announced `update` on /parameter_events (any thread): its values for its
  /// next restart, which starts it with them all in a params file (node_parameters.hpp).
  void parametersChanged(std::string_view instance, const profile::ParameterUpdate& update);
  /// The parameter values node `instance` would be restarted with now (empty for no such node).
  ParameterMap parametersOf(std::string_view instance) const;

  /// The process named `name` of managed node `instance` went from state `start` to `goal`
  /// (lifecycle_msgs/msg/State ids), as its transition event says (any thread).
  void lifecycleTransition(std::string_view instance, const std::string& name, std::uint8_t start, std::uint8_t goal);
  /// The process named `name` of managed node `instance` said it is in state `state` (a
  /// get_state reply; any thread).
  void lifecycleState(std::string_view instance, const std::string& name, std::uint8_t state);
  /// Whether process `pid` is the one keel runs as `name` of node `instance` now: its serving
  /// process under its current name, or one of its standbys (any thread).
  bool runs(std::string_view instance, const std::string& name, pid_t pid) const;
  /// Managed node `instance`'s state as keel last knew it (0: unknown, or no such node).
  std::uint8_t lifecycleStateOf(std::string_view instance) const;

  /// The output file of node `instance`'s processes under its own name ("" for no such node).
  std::string outputOf(std::string_view instance) const;
  /// The pid of node `instance` now; 0 when it does not run.
  pid_t pidOf(std::string_view instance) const;

 private:
  struct Node;
  struct Proxy;
  friend struct Proxy;

  Result<pid_t> start(Node& n, std::string_view phase, const std::string& params_file = {});
  void exited(Node& n, pid_t pid, const Exit& exit);
  Result<void> restart(Node& n);
  Result<void> replace(Node& n, const profile::NodeProfile& alternative, Proxy& by);
  void stopNode(Node& n, std::chrono::milliseconds grace);
  ChildSpec childOf(const Node& n, const std::string& params_file, const std::string& ros_name);
  static std::string fileOf(const Node& n, const std::string& role_file, std::string_view ros_name,
                            std::string_view extension);
  bool firstUseOf(const std::string& output);
  std::string writeParameters(Node& n, std::string ros_name = {});
  Result<void> startGuard();
  void tellGuard(char op, pid_t pgid) const;
  void endGuard();
  void timerLoop();
  void pokeTimer();
  std::int64_t checkTimes(Node& n, std::int64_t now_ns);
  std::int64_t driveLifecycle(Node& n, std::int64_t now_ns);
  bool resetByTransitions(Node& n);
  void recoveredAt(Proxy& proxy, std::int64_t t_ns);
  Node* managedNode(std::string_view instance);
  void heard(Node& n, const std::string& name, bool from_event, std::uint8_t start, std::uint8_t goal);
  Result<void> startStandby(Node& n);
  bool standbyExited(Node& n, pid_t pid, const Exit& exit);
  bool promote(Node& n);
  std::string fence(Node& n, pid_t pid, const std::string& name);
  void endStandbys(Node& n, std::chrono::milliseconds grace);

 public:
  struct Step;  // one process's next lifecycle step (node_supervisor.cpp)

 private:
  void windDown(Node& n, std::chrono::steady_clock::time_point until);
  void orderManaged(const plan::Plan& plan);
  void report(Node& n, FaultKind kind, const std::string& detail, std::int64_t t_ns);

  NodeLaunch launch_;
  runtime::Warn warn_;
  log::FaultLog& log_;
  Spawner& spawner_;
  Report report_;
  Exited exited_;
  Emergency emergency_;
  LifecycleLink lifecycle_;
  Recovered recovered_;
  std::vector<std::shared_ptr<Node>> nodes_;  // shared with their proxies, which may outlive this
  std::vector<Node*> wind_down_order_;        // the managed nodes, each before those it needs
  std::mutex outputs_mutex_;
  std::set<std::string> outputs_begun_;  // the output files this run started a process into
  int guard_fd_ = -1;                    // keel run's end of the guard's socket: "+PGID\n", "-PGID\n"
  pid_t guard_pid_ = 0;
  std::mutex guard_mutex_;
  std::condition_variable guard_ended_;
  bool guard_gone_ = false;
  bool guard_closing_ = false;
  // The timer: start timeouts, and a node gone from the graph while its process lives.
  std::mutex timer_mutex_;
  std::condition_variable timer_changed_;
  bool timer_ending_ = false;
  std::uint64_t timer_pokes_ = 0;  // a node's times changed: the timer looks again
  std::thread timer_;
  ExitWatch watch_;  // last: its thread ends (stop()) before the nodes it reports on go
};

}  // namespace keel::supervision
