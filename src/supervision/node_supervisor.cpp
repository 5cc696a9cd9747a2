#include "supervision/node_supervisor.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <system_error>
#include <thread>

#include "keel/msg/lifecycle_msgs/msg/state.hpp"
#include "keel/msg/lifecycle_msgs/msg/transition.hpp"
#include "log/schema.hpp"
#include "runtime/clock.hpp"
#include "runtime/component_core.hpp"
#include "runtime/injection.hpp"

namespace keel::supervision {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

/// A managed node's reset (`resetting`): its recovery comes when it is Active again, not at
/// the handling's end. Called with its mutex held.
void recoversLater(Component* proxy) {
  if (proxy) runtime::coreOf(*proxy).fault.recovers_later.store(true, std::memory_order_release);
}

}  // namespace

std::string defaultNodeExec() {
  if (const char* env = std::getenv("KEEL_NODE_EXEC"); env && *env) return env;
  std::error_code ec;
  const auto self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "keel-node-exec";
  return (self.parent_path() / "keel-node-exec").string();
}

std::vector<std::string> lastLines(const std::string& path, std::size_t n) {
  constexpr std::streamoff kTail = 4096;
  std::ifstream in(path, std::ios::binary);
  if (!in || n == 0) return {};
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff from = std::max<std::streamoff>(0, size - kTail);
  in.seekg(from);
  std::string text(static_cast<std::size_t>(size - from), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  std::vector<std::string> lines;
  std::size_t start = 0;
  if (from > 0) start = text.find('\n') == std::string::npos ? text.size() : text.find('\n') + 1;  // a cut line
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  if (lines.size() > n) lines.erase(lines.begin(), lines.end() - static_cast<std::ptrdiff_t>(n));
  return lines;
}

// One process of a managed node (the serving one, or a standby): its lifecycle as keel knows it,
// and the transitions keel has yet to make it go through (requested one at a time, each
// confirmed before the next).
struct Lifecycle {
  std::uint8_t state = 0;          // lifecycle_msgs/msg/State id; 0: unknown
  std::deque<std::uint8_t> steps;  // transitions to request, in order
  int asked = -1;                  // the transition requested and not confirmed yet; -1: none
  std::uint8_t asked_from = 0;     // its state when it was requested
  std::int64_t asked_ns = 0;       // when it was first requested: its timeout counts from then
  std::int64_t sent_ns = 0;        // when the request was last written
  std::int64_t probed_ns = 0;      // when the process's state was last asked
  bool unresponsive = false;       // a transition of this process timed out
  bool answered = false;           // it has said something (an event, its state): it reads requests
  std::int64_t active_ns = 0;      // when it became Active; 0: not Active
};

// A standby of a managed node (<process standby>): a process of its own name, started and
// configured, waiting Inactive to be promoted.
struct Standby {
  pid_t pid = 0;
  std::string name;  // its fully qualified node name: "/ns/name_standby_K"
  Lifecycle life;
  std::int64_t started_ns = 0;
  bool ready = false;   // configured: Inactive, promotable
  bool ending = false;  // keel ends it (failed, or the role's end): its exit is no loss to report
};

// One node keel runs or watches. Its process fields are guarded by `mutex`; `changed` is
// notified on every exit.
struct NodeSupervisor::Node {
  const plan::PlannedInstance* plan = nullptr;
  const profile::NodeProfile* profile = nullptr;  // the role's: its name, topics and diagnostics
  /// The node that serves the role: `profile`'s, or its alternative's once that took its place
  /// (the same name and output topics: the loader checked). Its command, environment,
  /// parameters, times and emergency are the ones keel uses.
  std::atomic<const profile::NodeProfile*> serving{nullptr};
  std::string output;  // its output file

  mutable std::mutex mutex;
  std::condition_variable changed;
  Proxy* proxy = nullptr;  // null once the engine destroyed it
  pid_t pid = 0;           // its running process; 0: none
  bool stopping = false;   // keel asked it to end: its exit is no fault
  std::uint64_t exits = 0;
  std::mutex restart_mutex;  // one restart or stop at a time
  // What the ROS 2 graph shows of it (nodeSeen), and what keel made of that.
  bool watched = false;             // the graph reports on it: its start timeout runs
  bool up = false;                  // its process lists it and publishes every output topic
  std::int64_t started_ns = 0;      // its last start (an attached node: the launch), steady
  bool late = false;                // its start fault of this life was raised
  std::int64_t left_ns = 0;         // it went from the graph while its process runs: when; 0: not
  bool outage = false;              // an attached node's start or remote fault, until it is up again
  bool warned_unknown_pid = false;  // a participant listing it announced no pid
  bool has_outputs = false;         // its profile declares output topics
  bool reported = false;            // its own /diagnostics status is at ERROR (a fault raised)
  std::vector<GraphSighting> seen;
  // Its parameter values for a restart: the profile's, overlaid by /parameter_events.
  ParameterMap parameters;
  std::string params_file;  // where its restart's params file is written
  // A managed node (<lifecycle/>).
  bool managed = false;
  std::string ros_name;                  // the serving process's node name: the profile's, or a promoted standby's
  Lifecycle life;                        // the serving process's
  bool resetting = false;                // its steps are a reset's (or a promotion's): recovered once Active
  std::vector<const Node*> needs;        // the managed nodes it needs (<needs>, through any component)
  int standby_count = 0;                 // <process standby="N">
  std::vector<Standby> standbys;         // the standbys running (at most standby_count)
  bool standbys_end = false;             // the role ended: no standby is started any more
  std::map<pid_t, std::string> retired;  // former serving processes keel fenced and ends, by name: no fault
  int standby_losses = 0;                // standbys lost in a row: the next waits longer
  std::int64_t standby_due_ns = 0;       // when the next standby may be started
};

// The stand-in of a node's role: of the node its profile names, or (`serves` set) of its
// alternative, which takes the role's place when its onStart runs (the fault manager's switch).
struct NodeSupervisor::Proxy final : Component, runtime::ProcessTarget {
  Proxy(NodeSupervisor& s, std::shared_ptr<Node> n, const PortMaker& make, const profile::NodeProfile* alternative)
      : sup(s), held(std::move(n)), node(*held), serves(alternative) {
    if (!make) return;
    const profile::NodeProfile& p = serves ? *serves : *node.profile;
    for (const profile::DataPort& d : p.component.data_ports) {
      if (d.usage != PortDirection::Output) continue;
      const bool has_topic = std::any_of(p.topics.begin(), p.topics.end(),
                                         [&](const auto& t) { return t.port == d.name; });
      if (!has_topic) continue;
      if (auto port = make(this, d)) ports.push_back(std::move(port));
    }
  }
  ~Proxy() override {  // may come after the supervisor's end: the engine closes its side first
    std::lock_guard lock(node.mutex);
    if (node.proxy == this) node.proxy = nullptr;
  }
  Proxy(const Proxy&) = delete;
  Proxy& operator=(const Proxy&) = delete;
  Proxy(Proxy&&) = delete;
  Proxy& operator=(Proxy&&) = delete;
  ReturnCode onStart() override {
    if (serves == nullptr) return ReturnCode::Ok;  // the role's own node: launch() started it
    if (auto r = sup.replace(node, *serves, *this); !r) {
      sup.warn_(fmt::format("node '{}': {}", node.plan->name, r.error().message));
      return ReturnCode::InternalFault;
    }
    return ReturnCode::Ok;
  }
  ReturnCode onReset() override {
    if (auto r = sup.restart(node); !r) {
      sup.warn_(fmt::format("node '{}': {}", node.plan->name, r.error().message));
      return ReturnCode::InternalFault;
    }
    return ReturnCode::Ok;
  }
  ReturnCode onStop() override {
    sup.stopNode(node, graceOf(node));
    sup.endStandbys(node, graceOf(node));  // the role ends: what stands by for it too
    return ReturnCode::Ok;
  }
  // The role's <emergency> holds whichever node serves it, and so does its alternative's: keel
  // run registered the safe commands of both under the role; stopped if the one serving asks.
  ReturnCode onEmergencyStop() override {
    if (sup.emergency_) sup.emergency_(node.plan->name);  // its safe commands first: what listens stands still
    const auto stops = [](const profile::NodeProfile* p) { return p->emergency && p->emergency->stop; };
    if (stops(node.profile) || stops(node.serving.load(std::memory_order_acquire))) sup.stopNode(node, graceOf(node));
    return ReturnCode::Ok;
  }
  void endProcess() override {  // a fault stop: the role ends, its standbys too
    sup.stopNode(node, graceOf(node));
    sup.endStandbys(node, graceOf(node));
  }
  bool signalProcess(int signal) override {
    std::lock_guard lock(node.mutex);
    return node.pid > 0 && ::kill(node.pid, signal) == 0;
  }
  static std::chrono::milliseconds graceOf(const Node& n) {
    return std::chrono::milliseconds(
        static_cast<std::int64_t>(n.serving.load(std::memory_order_acquire)->stop_grace_ms));
  }
  NodeSupervisor& sup;  // not used once the engine shut down: only the destructor runs then
  std::shared_ptr<Node> held;
  Node& node;
  const profile::NodeProfile* serves;  // the alternative this proxy starts in the role's place; null: the role's own
  std::vector<std::unique_ptr<detail::PortBase>> ports;  // its output topics' values, from DDS
};

NodeSupervisor::NodeSupervisor(const plan::Plan& plan, NodeLaunch launch, runtime::Warn warn, log::FaultLog& log,
                               Spawner& spawner)
    : launch_(std::move(launch)), warn_(std::move(warn)), log_(log), spawner_(spawner) {
  for (const auto& pi : plan.instances) {
    if (!pi.node) continue;
    auto n = std::make_shared<Node>();
    n->plan = &pi;
    n->profile = pi.node;
    n->serving.store(pi.node, std::memory_order_release);
    n->managed = pi.node->lifecycle.has_value() && !pi.attached;
    n->ros_name = pi.node->fullName();
    n->standby_count = pi.node_standby;
    for (const auto& t : pi.node->topics)
      for (const auto& d : pi.node->component.data_ports)
        n->has_outputs |= d.name == t.port && d.usage == PortDirection::Output;
    if (!pi.attached) {
      n->output = (fs::path(launch_.output_dir) / fmt::format("{}.{}.out", launch_.output_stem, pi.name)).string();
      // Absolute: the node reads it from its own folder.
      n->params_file = fs::absolute(fs::path(launch_.output_dir) /
                                    fmt::format("{}.{}.params.yaml", launch_.output_stem, pi.name))
                           .string();
      n->parameters = typedParameters(pi.node->parameters);
    }
    nodes_.push_back(std::move(n));
  }
  orderManaged(plan);
}

// Each managed node's prerequisites: the managed nodes it reaches through <needs>, any component
// on the way; two that need each other (a cycle) wait for neither. And the order they wind down
// in: a node before those it needs.
void NodeSupervisor::orderManaged(const plan::Plan& plan) {
  std::map<std::string, std::vector<std::string>, std::less<>> needs;
  for (const profile::Depends& d : plan.depends) needs[d.source].push_back(d.target);
  auto managed = [&](std::string_view name) -> Node* {
    for (auto& n : nodes_)
      if (n->managed && n->plan->name == name) return n.get();
    return nullptr;
  };
  std::map<Node*, std::set<Node*>> reach;
  for (auto& n : nodes_) {
    if (!n->managed) continue;
    std::set<std::string> seen{n->plan->name};
    std::vector<std::string> todo{n->plan->name};
    while (!todo.empty()) {
      const std::string at = todo.back();
      todo.pop_back();
      for (const std::string& next : needs[at]) {
        if (!seen.insert(next).second) continue;
        if (Node* m = managed(next)) reach[n.get()].insert(m);
        todo.push_back(next);
      }
    }
  }
  for (auto& [n, targets] : reach)
    for (Node* m : targets)
      if (!reach[m].contains(n)) n->needs.push_back(m);
  // Wind-down order: repeatedly the nodes no remaining node needs (a cycle's last, as they come).
  std::vector<Node*> left;
  for (auto& n : nodes_)
    if (n->managed) left.push_back(n.get());
  while (!left.empty()) {
    auto needed = [&](const Node* m) {
      return std::any_of(left.begin(), left.end(), [&](const Node* o) {
        return std::find(o->needs.begin(), o->needs.end(), m) != o->needs.end();
      });
    };
    auto free = std::find_if(left.begin(), left.end(), [&](const Node* m) { return !needed(m); });
    if (free == left.end()) free = left.begin();
    wind_down_order_.push_back(*free);
    left.erase(free);
  }
}

NodeSupervisor::~NodeSupervisor() {
  {
    std::lock_guard lock(timer_mutex_);
    timer_ending_ = true;
    timer_changed_.notify_all();
  }
  if (timer_.joinable()) timer_.join();
  try {
    stop(std::chrono::seconds(2));  // a managed node's way down writes records: it may throw (memory)
  } catch (...) {                   // what still runs then dies with the guard, below
  }
  endGuard();
  watch_.stop();
}

Result<void> NodeSupervisor::startGuard() {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
    return fail(fmt::format("cannot make the node guard's socket: {}", std::generic_category().message(errno)));
  // Not through the shim: the guard is there to outlive keel run.
  auto pid = spawner_.start({launch_.node_exec, {"--guard"}, {fds[1]}});
  ::close(fds[1]);
  if (!pid) {
    ::close(fds[0]);
    return fail(fmt::format("cannot start the node guard: {}", pid.error().message));
  }
  guard_fd_ = fds[0];
  guard_pid_ = *pid;
  auto watched = watch_.watch(*pid, [this](pid_t p, const Exit& e) {
    std::lock_guard lock(guard_mutex_);
    guard_gone_ = true;
    guard_ended_.notify_all();
    if (!guard_closing_)
      warn_(fmt::format("the node guard (pid {}) {}: if keel run dies now, what its nodes forked outlives it", p,
                        describe(e)));
  });
  if (!watched) return fail(fmt::format("cannot watch the node guard: {}", watched.error().message));
  return {};
}

void NodeSupervisor::tellGuard(char op, pid_t pgid) const {
  if (guard_fd_ < 0) return;
  const std::string line = fmt::format("{}{}\n", op, pgid);
  (void)!::send(guard_fd_, line.data(), line.size(), MSG_NOSIGNAL);  // one line, one send: never torn
}

// Its socket's end ends the guard, with no group left to kill: every node is stopped.
void NodeSupervisor::endGuard() {
  if (guard_fd_ < 0) return;
  std::unique_lock lock(guard_mutex_);
  guard_closing_ = true;
  ::close(guard_fd_);
  guard_fd_ = -1;
  if (!guard_ended_.wait_for(lock, std::chrono::seconds(5), [&] { return guard_gone_; }))
    warn_(fmt::format("the node guard (pid {}) did not end 5 s after keel run closed its socket", guard_pid_));
}

std::unique_ptr<Component> NodeSupervisor::makeProxy(const plan::PlannedInstance& instance, const PortMaker& make) {
  for (auto& n : nodes_) {
    if (n->plan != &instance) continue;
    auto proxy = std::make_unique<Proxy>(*this, n, make, nullptr);
    std::lock_guard lock(n->mutex);
    n->proxy = proxy.get();
    return proxy;
  }
  // The alternative of a node's role: an instance of the role's name planned with another node.
  for (auto& n : nodes_)
    if (instance.node != nullptr && n->plan->name == instance.name && !n->plan->attached)
      return std::make_unique<Proxy>(*this, n, make, instance.node);
  return nullptr;
}

ChildSpec NodeSupervisor::childOf(const Node& n, const std::string& params_file, const std::string& ros_name) {
  const profile::NodeProfile& p = *n.serving.load(std::memory_order_acquire);
  ChildSpec child{p.executable, {}, {}};
  child.args.assign(p.command.begin() + (p.command.empty() ? 0 : 1), p.command.end());
  // ROS 2's own section last, as launch_ros writes it: rcl reads what follows --ros-args.
  const std::string node_name = ros_name.substr(ros_name.rfind('/') + 1);
  child.args.insert(child.args.end(), {"--ros-args", "-r", "__node:=" + node_name, "-r", "__ns:=" + p.node_namespace});
  // A restart's values are all in its params file: a `-p` would win over the file in rcl.
  if (!params_file.empty()) child.args.insert(child.args.end(), {"--params-file", params_file});
  else
    for (const auto& param : p.parameters) child.args.insert(child.args.end(), {"-p", param.name + ":=" + param.value});
  // Defaults first, the profile's over them; the domain is keel's, always.
  child.environment = {"RCUTILS_COLORIZED_OUTPUT=0", "PYTHONUNBUFFERED=1"};
  for (const auto& v : p.environment) child.environment.push_back(v.name + "=" + v.value);
  child.environment.push_back(fmt::format("ROS_DOMAIN_ID={}", launch_.domain));
  child.directory = fs::path(p.file).parent_path().string();
  child.output = fileOf(n, n.output, ros_name, ".out");
  child.fresh_output = firstUseOf(child.output);
  child.shim = launch_.node_exec;
  return child;
}

Result<pid_t> NodeSupervisor::start(Node& n, std::string_view phase, const std::string& params_file) {
  std::string ros_name;
  {
    std::lock_guard lock(n.mutex);
    ros_name = n.ros_name;
  }
  if (n.managed && lifecycle_.renew) lifecycle_.renew(n.plan->name, ros_name);
  auto pid = spawner_.start(childOf(n, params_file, ros_name));
  if (!pid) return fail(fmt::format("node '{}': {}", n.plan->name, pid.error().message));
  tellGuard('+', *pid);  // its process group's id is its pid
  {
    std::lock_guard lock(n.mutex);
    n.pid = *pid;
    n.stopping = false;
    n.up = false;
    n.started_ns = runtime::steadyNs();
    n.late = false;
    n.left_ns = 0;
    n.reported = false;
    if (n.managed) {  // a new process is Unconfigured: configured and activated once it reads requests
      n.life = Lifecycle{};
      n.life.state = msg::lifecycle_msgs::State::PRIMARY_STATE_UNCONFIGURED;
      n.life.steps = {msg::lifecycle_msgs::Transition::TRANSITION_CONFIGURE,
                      msg::lifecycle_msgs::Transition::TRANSITION_ACTIVATE};
    }
  }
  pokeTimer();
  nlohmann::json rec = log::schema::node(n.plan->name, ros_name, *pid, phase);
  rec[log::schema::field::kOutput] = fileOf(n, n.output, ros_name, ".out");
  if (!params_file.empty()) rec[log::schema::field::kParams] = params_file;
  rec[log::schema::field::kTime] = log_.now();
  log_.write(std::move(rec));
  if (auto watched = watch_.watch(*pid, [this, &n](pid_t p, const Exit& e) { exited(n, p, e); }); !watched) {
    ::kill(*pid, SIGKILL);  // unwatched, it would be nobody's to stop
    return fail(fmt::format("node '{}': {}", n.plan->name, watched.error().message));
  }
  return *pid;
}

void NodeSupervisor::exited(Node& n, pid_t pid, const Exit& exit) {
  if (standbyExited(n, pid, exit)) return;
  bool asked = false;
  Proxy* proxy = nullptr;
  std::string name = n.profile->fullName();  // the process's own: a promoted standby's is another
  {
    std::lock_guard lock(n.mutex);
    if (const auto r = n.retired.find(pid); r != n.retired.end()) {  // a serving process a standby took over from
      asked = true;
      name = r->second;
      n.retired.erase(r);
    }
    if (n.pid == pid) {
      name = n.ros_name;
      n.pid = 0;
    }
    if (!asked) {
      n.up = false;
      n.left_ns = 0;
      asked = n.stopping;
    }
    proxy = n.proxy;
    ++n.exits;
  }
  if (asked) ::killpg(pid, SIGKILL);  // whatever the node forked and left in its group
  tellGuard('-', pid);
  const std::string how = describe(exit);
  nlohmann::json rec = log::schema::node(n.plan->name, name, pid, asked ? "stopped" : "exited");
  rec[log::schema::field::kDetail] = how;
  std::vector<std::string> last;
  if (!asked && !n.output.empty()) {
    last = lastLines(fileOf(n, n.output, name, ".out"), 10);
    rec[log::schema::field::kLastLines] = last;
  }
  rec[log::schema::field::kTime] = log_.sinceStart(exit.at_ns);
  log_.write(std::move(rec));
  n.changed.notify_all();
  const std::string who = fmt::format("node '{}' (pid {}) {}", name, pid, how);
  if (!asked && proxy && report_) {  // the node's fault first: the cause before what it causes
    FaultEvent ev(FaultKind::Process, n.plan->name, last.empty() ? who : who + ": " + last.back());
    ev.t_ns = exit.at_ns;
    report_(*proxy, ev);
  }
  if (exited_) exited_(n.plan->name, pid, who, !asked);
}

Result<void> NodeSupervisor::restart(Node& n) {
  if (n.plan->attached) return fail("an attached node is not keel's to restart");
  std::lock_guard one(n.restart_mutex);
  if (promote(n)) return {};
  if (resetByTransitions(n)) return {};
  stopNode(n, Proxy::graceOf(n));  // alive when its fault came from its topics
  auto pid = start(n, "restarted", writeParameters(n));
  if (!pid) return pid.error();
  std::lock_guard lock(n.mutex);
  if (n.managed) {  // recovered once configured and Active again, not at the handling's end
    n.resetting = true;
    recoversLater(n.proxy);
  } else if (n.proxy)
    runtime::coreOf(*n.proxy).fault.recovered_at_ns.store(runtime::steadyNs(), std::memory_order_release);
  return {};
}

Result<void> NodeSupervisor::replace(Node& n, const profile::NodeProfile& alternative, Proxy& by) {
  std::lock_guard one(n.restart_mutex);
  stopNode(n, Proxy::graceOf(n));  // alive when its fault came from its topics: never two writers
  n.serving.store(&alternative, std::memory_order_release);
  {
    std::lock_guard lock(n.mutex);
    n.proxy = &by;                                           // its faults from now on
    n.parameters = typedParameters(alternative.parameters);  // another node: its own values
    n.ros_name = alternative.fullName();
  }
  auto pid = start(n, "replaced");
  if (!pid) return pid.error();
  runtime::coreOf(by).fault.recovered_at_ns.store(runtime::steadyNs(), std::memory_order_release);
  return {};
}

void NodeSupervisor::stopNode(Node& n, std::chrono::milliseconds grace) {
  if (n.managed) {  // its own way down first, within its grace: deactivated, shut down
    {
      std::lock_guard lock(n.mutex);
      if (n.pid == 0) return;
      n.stopping = true;
    }
    windDown(n, Clock::now() + grace);
  }
  std::unique_lock lock(n.mutex);
  const pid_t pid = n.pid;
  if (pid == 0) return;
  n.stopping = true;
  auto gone = [&] { return n.pid != pid; };
  ::killpg(pid, SIGINT);
  if (!n.changed.wait_for(lock, grace, gone)) {
    ::killpg(pid, SIGKILL);
    // The kernel ends a killed process promptly; the bound is against a watch that stopped.
    if (!n.changed.wait_for(lock, std::chrono::seconds(5), gone))
      warn_(fmt::format("node '{}' (pid {}): no exit seen 5 s after SIGKILL", n.plan->name, pid));
  }
}

Result<void> NodeSupervisor::launch() {
  if (std::any_of(nodes_.begin(), nodes_.end(), [](const auto& n) { return !n->plan->attached; }))
    if (auto r = startGuard(); !r) return r;
  if (!nodes_.empty() && !timer_.joinable()) timer_ = std::thread([this] { timerLoop(); });
  std::string errors;
  for (auto& n : nodes_) {
    if (n->plan->attached) {  // someone else starts it: its start timeout counts from here
      std::lock_guard lock(n->mutex);
      n->started_ns = runtime::steadyNs();
      continue;
    }
    if (auto pid = start(*n, "started"); !pid) errors += pid.error().message + '\n';
  }
  if (!errors.empty()) {
    errors.pop_back();
    return fail(errors);
  }
  return {};
}

void NodeSupervisor::windDownManaged(std::chrono::milliseconds within) {
  const auto until = Clock::now() + within;
  for (Node* n : wind_down_order_) {
    {
      std::lock_guard lock(n->mutex);
      n->standbys_end = true;  // none started any more
      if (n->pid == 0 || n->stopping) continue;
      n->stopping = true;  // its silence from here on is keel's doing
    }
    windDown(*n, until);
  }
}

void NodeSupervisor::stop(std::chrono::milliseconds within) {
  for (auto& n : nodes_) {
    std::lock_guard one(n->restart_mutex);
    stopNode(*n, std::min(within, Proxy::graceOf(*n)));
    endStandbys(*n, std::min(within, Proxy::graceOf(*n)));
  }
}

std::string NodeSupervisor::outputOf(std::string_view instance) const {
  for (const auto& n : nodes_)
    if (n->plan->name == instance) return n->output;
  return {};
}

pid_t NodeSupervisor::pidOf(std::string_view instance) const {
  for (const auto& n : nodes_) {
    if (n->plan->name != instance) continue;
    std::lock_guard lock(n->mutex);
    return n->pid;
  }
  return 0;
}

// ---- parameters: the values it last had, for its restart ----

void NodeSupervisor::parametersChanged(std::string_view instance, const profile::ParameterUpdate& update) {
  for (auto& n : nodes_) {
    if (n->plan->name != instance || n->plan->attached) continue;
    std::lock_guard lock(n->mutex);
    overlay(n->parameters, update);
  }
}

ParameterMap NodeSupervisor::parametersOf(std::string_view instance) const {
  for (const auto& n : nodes_) {
    if (n->plan->name != instance) continue;
    std::lock_guard lock(n->mutex);
    return n->parameters;
  }
  return {};
}

// The params file of its process named `ros_name` ("": the serving one's), written now: the
// file, or "" when it could not be (warned) or would hold no value (rcl refuses a params file
// whose node has no parameters): then the process has the profile's `-p`s, as its first start
// had. rcl takes a params file's values by node name: a standby's file is keyed by its own name,
// and is a file of its own (`run.talker.talker_standby_1.params.yaml`).
// `role_file` ("run.planner.out") for a process under the role's own name; for one under
// another (a standby's, "/nav/planner_standby_1"), that name's last part before the extension:
// "run.planner.planner_standby_1.out". One file per process alive at a time: their lines never
// interleave.
std::string NodeSupervisor::fileOf(const Node& n, const std::string& role_file, std::string_view ros_name,
                                   std::string_view extension) {
  if (ros_name == n.profile->fullName()) return role_file;
  std::string path = role_file;
  path.insert(path.size() - extension.size(), "." + std::string(ros_name.substr(ros_name.rfind('/') + 1)));
  return path;
}

bool NodeSupervisor::firstUseOf(const std::string& output) {
  if (!launch_.fresh_output) return false;
  std::lock_guard lock(outputs_mutex_);
  return outputs_begun_.insert(output).second;
}

std::string NodeSupervisor::writeParameters(Node& n, std::string ros_name) {
  ParameterMap values;
  {
    std::lock_guard lock(n.mutex);
    values = n.parameters;
    if (ros_name.empty()) ros_name = n.ros_name;
  }
  if (values.empty()) return {};
  std::string path = fileOf(n, n.params_file, ros_name, ".params.yaml");
  if (auto written = writeParamsFile(path, ros_name, values); !written) {
    warn_(
        fmt::format("node '{}': {}: it restarts with its profile's parameters", n.plan->name, written.error().message));
    return {};
  }
  return path;
}

// ---- the ROS 2 graph: up, late, left ----

namespace {

/// How long a node may be gone from the graph before that is a fault: a node that ends by itself
/// leaves the graph a moment before its process ends, and that exit is its fault (one outage,
/// one fault); and its writers go a moment before its participant, which says more.
constexpr std::int64_t kLeaveGraceNs = 250'000'000;

/// Whether sighting `g` is of the node's own process (pid `pid`, 0: none runs): its pid, or a
/// process of its group (a launcher's child). A participant that announces no pid cannot be told
/// from an earlier life: it counts if it lists the node. An attached node's is whoever lists it.
bool owns(bool attached, pid_t pid, const GraphSighting& g) {
  if (attached || g.pid == 0) return g.listed && (attached || pid != 0);
  return pid != 0 && (g.pid == pid || ::getpgid(g.pid) == pid);
}

/// Whether `g` shows the node up: every output topic published (a node with none: listed). A
/// managed node: listed, or configured (its topics come with its configuration, which keel asks
/// for once it is listed; a promoted standby is configured long before its listing may reach keel:
/// a Fast DDS participant's comes with a heartbeat, up to 3 s after it started).
bool completeWith(const GraphSighting& g, bool has_outputs, bool managed) {
  const bool publishes = g.missing.empty() && has_outputs;
  return managed ? g.listed || publishes : publishes || (g.missing.empty() && g.listed);
}

/// The sighting that speaks for the node: its own that is complete, else any of its own.
const GraphSighting* ownSighting(bool attached, pid_t pid, const std::vector<GraphSighting>& seen, bool has_outputs,
                                 bool managed) {
  const GraphSighting* own = nullptr;
  for (const GraphSighting& g : seen)
    if (owns(attached, pid, g) && (own == nullptr || completeWith(g, has_outputs, managed))) own = &g;
  return own;
}

std::string topicList(const std::vector<std::string>& topics) {
  std::string out;
  for (const auto& t : topics) out += (out.empty() ? "" : ", ") + t;
  return out;
}

}  // namespace

void NodeSupervisor::pokeTimer() {
  std::lock_guard lock(timer_mutex_);
  ++timer_pokes_;
  timer_changed_.notify_all();
}

void NodeSupervisor::nodeSeen(std::string_view instance, std::vector<GraphSighting> sightings) {
  const auto it = std::find_if(nodes_.begin(), nodes_.end(), [&](const auto& n) { return n->plan->name == instance; });
  if (it == nodes_.end()) return;
  Node& n = **it;
  const std::int64_t now = runtime::steadyNs();
  std::optional<nlohmann::json> record;
  bool unknown_pid = false;
  {
    std::lock_guard lock(n.mutex);
    n.seen = std::move(sightings);
    n.watched = true;
    const GraphSighting* own = ownSighting(n.plan->attached, n.pid, n.seen, n.has_outputs, n.managed);
    if (own != nullptr && own->pid == 0 && !n.plan->attached && !n.warned_unknown_pid)
      unknown_pid = n.warned_unknown_pid = true;
    const bool complete = own != nullptr && completeWith(*own, n.has_outputs, n.managed);
    const bool running = n.plan->attached || (n.pid != 0 && !n.stopping);
    if (!n.up && complete && running) {
      n.up = true;
      n.left_ns = 0;
      record = log::schema::node(n.plan->name, n.profile->fullName(), own->pid ? own->pid : n.pid, "up");
      (*record)[log::schema::field::kAfterMs] = static_cast<double>(now - n.started_ns) / 1e6;
      if (n.outage && n.proxy)  // an attached node back: its outage ends
        runtime::coreOf(*n.proxy).fault.recovered_at_ns.store(now, std::memory_order_release);
      n.outage = false;
    } else if (n.up && !complete) {
      n.up = false;
      if (running) {
        n.left_ns = now;
        record = log::schema::node(n.plan->name, n.profile->fullName(), n.pid, "left");
        (*record)[log::schema::field::kDetail] = own == nullptr ? "not in the ROS 2 graph"
                                                                : "publishes no " + topicList(own->missing);
      }
    }
  }
  if (unknown_pid)
    warn_(
        fmt::format("node '{}': a participant listing {} announces no process id: keel cannot tell it from an "
                    "earlier life of the node",
                    n.plan->name, n.profile->fullName()));
  if (record) {
    (*record)[log::schema::field::kTime] = log_.sinceStart(now);
    log_.write(std::move(*record));
  }
  pokeTimer();
}

bool NodeSupervisor::owns(std::string_view instance, pid_t pid, bool listed) const {
  for (const auto& n : nodes_) {
    if (n->plan->name != instance) continue;
    std::lock_guard lock(n->mutex);
    return supervision::owns(n->plan->attached, n->pid, GraphSighting{pid, listed, {}});
  }
  return false;
}

void NodeSupervisor::nodeReported(std::string_view instance, bool error, const std::string& what) {
  const auto it = std::find_if(nodes_.begin(), nodes_.end(), [&](const auto& n) { return n->plan->name == instance; });
  if (it == nodes_.end()) return;
  Node& n = **it;
  bool raise = false;
  {
    std::lock_guard lock(n.mutex);
    raise = error && !n.reported && (n.plan->attached || (n.pid != 0 && !n.stopping));
    if (error) n.reported = n.reported || raise;
    if (!error) n.reported = false;  // the episode is over: the next ERROR is a fault again
  }
  if (raise)
    report(n, FaultKind::Reported, fmt::format("node '{}' reported ERROR: {}", n.profile->fullName(), what),
           runtime::steadyNs());
}

bool NodeSupervisor::quiet(std::string_view instance) const {
  for (const auto& n : nodes_) {
    if (n->plan->name != instance) continue;
    std::lock_guard lock(n->mutex);
    // A node keel runs: while it has no process, or keel is stopping it (its samples are its
    // life's only, so a new life's deadline counts from its own first sample). An attached one:
    // while it is not up (its leaving the graph is its fault).
    // A managed node: also while it is not Active (its lifecycle publishers are silent then).
    return n->plan->attached ? !n->up : n->pid == 0 || n->stopping || (n->managed && n->life.active_ns == 0);
  }
  return false;
}

std::int64_t NodeSupervisor::firstSampleDue(std::string_view instance) const {
  for (const auto& n : nodes_) {
    if (n->plan->name != instance) continue;
    std::lock_guard lock(n->mutex);
    // Not up: its start fault speaks for it (at the same timeout).
    if (!n->up || (!n->plan->attached && (n->pid == 0 || n->stopping))) return 0;
    const double timeout_ms = n->serving.load(std::memory_order_acquire)->start_timeout_ms;
    if (n->managed) return n->life.active_ns == 0 ? 0 : n->life.active_ns + static_cast<std::int64_t>(timeout_ms * 1e6);
    return n->started_ns + static_cast<std::int64_t>(timeout_ms * 1e6);
  }
  return 0;
}

void NodeSupervisor::timerLoop() {
  std::unique_lock lock(timer_mutex_);
  while (!timer_ending_) {
    const std::uint64_t pokes = timer_pokes_;
    lock.unlock();
    const std::int64_t now = runtime::steadyNs();
    std::int64_t next = std::numeric_limits<std::int64_t>::max();
    for (auto& n : nodes_) next = std::min({next, checkTimes(*n, now), driveLifecycle(*n, now)});
    lock.lock();
    auto poked = [&] { return timer_ending_ || timer_pokes_ != pokes; };
    if (next == std::numeric_limits<std::int64_t>::max()) timer_changed_.wait(lock, poked);
    else timer_changed_.wait_for(lock, std::chrono::nanoseconds(next - now), poked);
  }
}

// A node's start timeout, and its leaving the graph: a fault when due. Returns when next to look.
std::int64_t NodeSupervisor::checkTimes(Node& n, std::int64_t now) {
  constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();
  std::int64_t next = kNever;
  FaultKind kind = FaultKind::Start;
  std::string detail;
  {
    std::lock_guard lock(n.mutex);
    const bool running = n.plan->attached || (n.pid != 0 && !n.stopping);
    const std::string name = n.profile->fullName();
    if (n.watched && running && !n.up && !n.late) {
      const double timeout_ms = n.serving.load(std::memory_order_acquire)->start_timeout_ms;
      const auto timeout_ns = static_cast<std::int64_t>(timeout_ms * 1e6);
      if (now - n.started_ns < timeout_ns) {
        next = n.started_ns + timeout_ns;
      } else {
        n.late = true;
        const std::string within = fmt::format("within {:g} ms", timeout_ms);
        const GraphSighting* own = ownSighting(n.plan->attached, n.pid, n.seen, n.has_outputs, n.managed);
        const auto other = std::find_if(n.seen.begin(), n.seen.end(), [](const auto& g) { return g.listed; });
        if (own != nullptr)
          detail = fmt::format("node '{}' not up {}: it publishes no {}", name, within, topicList(own->missing));
        else if (other != n.seen.end())
          detail = fmt::format("node '{}' not up {}: only pid {} lists that name, not its process", name, within,
                               other->pid);
        else detail = fmt::format("node '{}' not in the ROS 2 graph {}", name, within);
      }
    }
    if (detail.empty() && n.left_ns != 0) {
      const std::int64_t due = n.left_ns + kLeaveGraceNs;
      if (now < due) {
        next = std::min(next, due);
      } else {
        n.left_ns = 0;
        if (running && !n.up) {
          kind = FaultKind::Remote;
          const GraphSighting* own = ownSighting(n.plan->attached, n.pid, n.seen, n.has_outputs, n.managed);
          detail = own == nullptr ? fmt::format("node '{}' left the ROS 2 graph", name)
                                  : fmt::format("node '{}' stopped publishing {}", name, topicList(own->missing));
        }
      }
    }
    if (!detail.empty() && n.plan->attached) n.outage = true;
  }
  if (!detail.empty()) report(n, kind, detail, now);
  return next;
}

void NodeSupervisor::report(Node& n, FaultKind kind, const std::string& detail, std::int64_t t_ns) {
  Proxy* proxy = nullptr;
  {
    std::lock_guard lock(n.mutex);
    proxy = n.proxy;
  }
  if (!proxy || !report_) return;
  FaultEvent ev(kind, n.plan->name, detail);
  ev.t_ns = t_ns;
  report_(*proxy, ev);
}

// ---- managed nodes: their lifecycle ----

namespace {

using LState = msg::lifecycle_msgs::State;
using LTransition = msg::lifecycle_msgs::Transition;

/// How often keel asks a managed node its state while a transition it asked for is unconfirmed
/// (a transition event lost on the way, or the request), and resends a request the node's state
/// shows was not received or failed unseen: a second try is answered by events that arrive (the
/// sample a Fast DDS writer loses is the first after matching).
constexpr std::int64_t kProbeNs = 500'000'000;
constexpr std::int64_t kResendNs = 1'000'000'000;
/// How soon keel asks again when no reader of the node's process is matched yet.
constexpr std::int64_t kUnmatchedRetryNs = 20'000'000;
/// A standby lost right after another waits before it is started again: 0.5 s, doubling, at
/// most 30 s (a node that cannot stand by must not be restarted in a loop); one that could not be
/// started at all is tried again after 5 s.
constexpr std::int64_t kStandbyBackoffNs = 500'000'000;
constexpr std::int64_t kStandbyBackoffMaxNs = 30'000'000'000;
constexpr std::int64_t kStandbyRetryNs = 5'000'000'000;

bool primary(std::uint8_t s) { return s >= LState::PRIMARY_STATE_UNCONFIGURED && s <= LState::PRIMARY_STATE_FINALIZED; }

/// The primary state transition `t` ends in when it succeeds.
std::uint8_t goalOf(std::uint8_t t) {
  switch (t) {
    case LTransition::TRANSITION_CONFIGURE: return LState::PRIMARY_STATE_INACTIVE;
    case LTransition::TRANSITION_CLEANUP: return LState::PRIMARY_STATE_UNCONFIGURED;
    case LTransition::TRANSITION_ACTIVATE: return LState::PRIMARY_STATE_ACTIVE;
    case LTransition::TRANSITION_DEACTIVATE: return LState::PRIMARY_STATE_INACTIVE;
    default: return LState::PRIMARY_STATE_FINALIZED;  // the three shutdowns
  }
}

/// The transition state the node is in while it goes through `t`.
std::uint8_t throughOf(std::uint8_t t) {
  switch (t) {
    case LTransition::TRANSITION_CONFIGURE: return LState::TRANSITION_STATE_CONFIGURING;
    case LTransition::TRANSITION_CLEANUP: return LState::TRANSITION_STATE_CLEANINGUP;
    case LTransition::TRANSITION_ACTIVATE: return LState::TRANSITION_STATE_ACTIVATING;
    case LTransition::TRANSITION_DEACTIVATE: return LState::TRANSITION_STATE_DEACTIVATING;
    default: return LState::TRANSITION_STATE_SHUTTINGDOWN;
  }
}

std::string_view transitionName(std::uint8_t t) {
  switch (t) {
    case LTransition::TRANSITION_CONFIGURE: return "configure";
    case LTransition::TRANSITION_CLEANUP: return "cleanup";
    case LTransition::TRANSITION_ACTIVATE: return "activate";
    case LTransition::TRANSITION_DEACTIVATE: return "deactivate";
    default: return "shutdown";
  }
}

/// The `node` record's phase once transition `t` is confirmed.
std::string_view confirmedPhase(std::uint8_t t) {
  switch (t) {
    case LTransition::TRANSITION_CONFIGURE: return "configured";
    case LTransition::TRANSITION_CLEANUP: return "cleaned_up";
    case LTransition::TRANSITION_ACTIVATE: return "activated";
    case LTransition::TRANSITION_DEACTIVATE: return "deactivated";
    default: return "shut_down";
  }
}

std::string stateName(std::uint8_t s) {
  switch (s) {
    case LState::PRIMARY_STATE_UNCONFIGURED: return "unconfigured";
    case LState::PRIMARY_STATE_INACTIVE: return "inactive";
    case LState::PRIMARY_STATE_ACTIVE: return "active";
    case LState::PRIMARY_STATE_FINALIZED: return "finalized";
    case LState::TRANSITION_STATE_CONFIGURING: return "configuring";
    case LState::TRANSITION_STATE_CLEANINGUP: return "cleaningup";
    case LState::TRANSITION_STATE_SHUTTINGDOWN: return "shuttingdown";
    case LState::TRANSITION_STATE_ACTIVATING: return "activating";
    case LState::TRANSITION_STATE_DEACTIVATING: return "deactivating";
    case LState::TRANSITION_STATE_ERRORPROCESSING: return "errorprocessing";
    default: return fmt::format("unknown ({})", s);
  }
}

std::string stepList(const std::deque<std::uint8_t>& steps) {
  std::string out;
  for (std::uint8_t t : steps) out += fmt::format("{}{}", out.empty() ? "" : " → ", transitionName(t));
  return out;
}

}  // namespace

// What an event or a state means for the transition a process was asked for.
struct Heard {
  enum Kind { Nothing, Done, Failed, Fell, Moved } kind = Nothing;
  std::uint8_t transition = 0;
  double after_ms = 0;      // Done: since it was asked
  bool with_error = false;  // Failed: through ErrorProcessing
  bool by_state = false;    // Done: confirmed by a get_state reply
  std::uint8_t from = 0;    // Fell, Moved: the state it left
  bool resend = false;      // a get_state reply shows the request never arrived
};

namespace {

void confirm(Lifecycle& l, std::uint8_t t, std::int64_t now, Heard& h) {
  l.asked = -1;
  if (!l.steps.empty() && l.steps.front() == t) l.steps.pop_front();
  if (goalOf(t) == LState::PRIMARY_STATE_ACTIVE) l.active_ns = now;
  h.kind = Heard::Done;
  h.transition = t;
  h.after_ms = static_cast<double>(now - l.asked_ns) / 1e6;
}

/// A transition event of the process: its state, and the transition asked of it confirmed or
/// failed; unasked (and not while keel stops it), a fall into ErrorProcessing or Finalized, or
/// another client's doing.
Heard hearEvent(Lifecycle& l, std::uint8_t start, std::uint8_t goal, std::int64_t now, bool stopping) {
  Heard h;
  const std::uint8_t known = l.state;
  l.state = goal;
  if (goal != LState::PRIMARY_STATE_ACTIVE) l.active_ns = 0;
  if (l.asked >= 0) {
    const auto t = static_cast<std::uint8_t>(l.asked);
    const bool ends = primary(goal) && (start == throughOf(t) || start == LState::TRANSITION_STATE_ERRORPROCESSING);
    if (ends && goal == goalOf(t)) {
      confirm(l, t, now, h);
    } else if (ends && !stopping) {
      l.asked = -1;
      l.steps.clear();
      h.kind = Heard::Failed;
      h.transition = t;
      h.with_error = start == LState::TRANSITION_STATE_ERRORPROCESSING;
    }
    return h;
  }
  if (stopping) return h;
  h.from = start;
  if (goal == LState::TRANSITION_STATE_ERRORPROCESSING || goal == LState::PRIMARY_STATE_FINALIZED) {
    l.steps.clear();
    h.kind = Heard::Fell;
  } else if (primary(goal) && !primary(start) && goal != known) {
    // Another client moved it (`ros2 lifecycle set`). (An event of keel's own transition that
    // its state confirmed first changes no state it knew.)
    h.kind = Heard::Moved;
  }
  return h;
}

/// A get_state reply: the confirmation of a transition whose event was lost, or the sign that a
/// request was (its state still the one it had, a while after it was sent).
Heard hearState(Lifecycle& l, std::uint8_t state, std::int64_t now) {
  Heard h;
  if (l.asked >= 0) {
    const auto t = static_cast<std::uint8_t>(l.asked);
    if (state == goalOf(t)) {
      l.state = state;
      confirm(l, t, now, h);
      h.by_state = true;
    } else if (state == l.asked_from && now - l.sent_ns >= kResendNs) {
      h.resend = true;
      h.transition = t;
      l.sent_ns = now;
    }
  } else if (primary(state)) {
    l.state = state;
  }
  return h;
}

}  // namespace

NodeSupervisor::Node* NodeSupervisor::managedNode(std::string_view instance) {
  for (auto& n : nodes_)
    if (n->managed && n->plan->name == instance) return n.get();
  return nullptr;
}

// What a process of a managed node said: the serving one's confirmations and faults, or a
// standby's readiness and loss.
void NodeSupervisor::heard(Node& n, const std::string& name, bool from_event, std::uint8_t start, std::uint8_t goal) {
  const std::int64_t now = runtime::steadyNs();
  std::optional<nlohmann::json> record;
  std::string fault;
  pid_t lost = 0;
  Proxy* back = nullptr;  // the node is back after its reset: its recovery
  Heard h;
  {
    std::lock_guard lock(n.mutex);
    if (n.pid != 0 && name == n.ros_name) {
      n.life.answered = true;
      h = from_event ? hearEvent(n.life, start, goal, now, n.stopping) : hearState(n.life, goal, now);
      switch (h.kind) {
        case Heard::Done:
          record = log::schema::node(n.plan->name, name, n.pid, confirmedPhase(h.transition));
          (*record)[log::schema::field::kAfterMs] = h.after_ms;
          if (h.by_state)
            (*record)[log::schema::field::kDetail] = "confirmed by its state (its transition event was not seen)";
          if (n.resetting && n.life.steps.empty() && n.life.state == LState::PRIMARY_STATE_ACTIVE) {
            n.resetting = false;
            back = n.proxy;
          }
          break;
        case Heard::Failed:
          fault = fmt::format("node '{}': {} failed{}: it is {}", name, transitionName(h.transition),
                              h.with_error ? " with an error" : "", stateName(n.life.state));
          n.resetting = false;
          break;
        case Heard::Fell:
          fault = fmt::format("node '{}' went from {} to {} by itself", name, stateName(h.from),
                              stateName(n.life.state));
          break;
        case Heard::Moved:
          record = log::schema::node(n.plan->name, name, n.pid, stateName(n.life.state));
          (*record)[log::schema::field::kDetail] = fmt::format("{} → {}, not asked by keel", stateName(h.from),
                                                               stateName(n.life.state));
          break;
        case Heard::Nothing: break;
      }
    } else {
      const auto sb = std::find_if(n.standbys.begin(), n.standbys.end(),
                                   [&](const Standby& b) { return b.name == name && b.pid != 0; });
      if (sb == n.standbys.end()) return;  // a life that ended: its last words change nothing
      sb->life.answered = true;
      h = from_event ? hearEvent(sb->life, start, goal, now, sb->ending) : hearState(sb->life, goal, now);
      if (h.kind == Heard::Done && sb->life.steps.empty() && sb->life.state == LState::PRIMARY_STATE_INACTIVE) {
        sb->ready = true;
        n.standby_losses = 0;
        record = log::schema::node(n.plan->name, name, sb->pid, "standby_ready");
        (*record)[log::schema::field::kAfterMs] = static_cast<double>(now - sb->started_ns) / 1e6;
      } else if (h.kind == Heard::Failed || h.kind == Heard::Fell ||
                 (h.kind == Heard::Moved && sb->life.state != LState::PRIMARY_STATE_INACTIVE)) {
        // A standby is promoted Inactive or not at all: this one is ended, and another started.
        sb->ending = true;
        sb->ready = false;
        lost = sb->pid;
        record = log::schema::node(n.plan->name, name, sb->pid, "standby_failed");
        (*record)[log::schema::field::kDetail] = fmt::format("it is {}", stateName(sb->life.state));
      }
    }
  }
  n.changed.notify_all();
  if (lost != 0) ::killpg(lost, SIGKILL);
  if (record) {
    (*record)[log::schema::field::kTime] = log_.sinceStart(now);
    log_.write(std::move(*record));
  }
  if (back) recoveredAt(*back, now);
  if (h.resend && lifecycle_.request) (void)lifecycle_.request(n.plan->name, name, h.transition);
  if (!fault.empty()) report(n, FaultKind::Lifecycle, fault, now);
  pokeTimer();
}

// A managed node's reset is over: it is Active again.
void NodeSupervisor::recoveredAt(Proxy& proxy, std::int64_t t_ns) {
  runtime::coreOf(proxy).fault.recovers_later.store(false, std::memory_order_release);
  if (recovered_) recovered_(proxy, t_ns);
}

void NodeSupervisor::lifecycleTransition(std::string_view instance, const std::string& name, std::uint8_t start,
                                         std::uint8_t goal) {
  if (Node* n = managedNode(instance)) heard(*n, name, true, start, goal);
}

void NodeSupervisor::lifecycleState(std::string_view instance, const std::string& name, std::uint8_t state) {
  if (Node* n = managedNode(instance)) heard(*n, name, false, 0, state);
}

bool NodeSupervisor::runs(std::string_view instance, const std::string& name, pid_t pid) const {
  for (const auto& n : nodes_) {
    if (n->plan->name != instance) continue;
    std::lock_guard lock(n->mutex);
    if (n->pid == pid && n->ros_name == name) return true;
    return std::any_of(n->standbys.begin(), n->standbys.end(),
                       [&](const Standby& b) { return b.pid == pid && b.name == name; });
  }
  return false;
}

std::uint8_t NodeSupervisor::lifecycleStateOf(std::string_view instance) const {
  for (const auto& n : nodes_) {
    if (n->plan->name != instance) continue;
    std::lock_guard lock(n->mutex);
    return n->life.state;
  }
  return 0;
}

// One process's next step: requested once its reader is matched; an unconfirmed one probed, and
// late, `late` says so. Called with the node's mutex held; the requests are made by the caller.
struct NodeSupervisor::Step {
  int ask = -1;                 // the transition to request now; -1: none
  bool probe = false;           // to ask its state
  bool late = false;            // its transition timed out
  std::uint8_t transition = 0;  // late: which
  std::int64_t next = std::numeric_limits<std::int64_t>::max();
};

namespace {

NodeSupervisor::Step nextStep(Lifecycle& l, std::int64_t now, std::int64_t timeout_ns) {
  NodeSupervisor::Step step;
  if (l.asked >= 0) {
    const auto t = static_cast<std::uint8_t>(l.asked);
    if (now - l.asked_ns >= timeout_ns) {
      step.late = true;
      step.transition = t;
      l.asked = -1;
      l.steps.clear();
      l.unresponsive = true;
    } else {
      if (now - l.probed_ns >= kProbeNs) {
        step.probe = true;
        l.probed_ns = now;
      }
      step.next = std::min(l.asked_ns + timeout_ns, l.probed_ns + kProbeNs);
    }
  } else if (!l.steps.empty()) {
    step.ask = l.steps.front();
  }
  return step;
}

/// After a request of `t` was written: its timeout counts from now.
// Transition `t` is asked of the process: marked before its request is written, for the
// process's events can come back before the writer's call returns.
void asked(Lifecycle& l, std::uint8_t t, std::int64_t now) {
  if (l.asked >= 0 || l.steps.empty() || l.steps.front() != t) return;
  l.asked = t;
  l.asked_from = l.state;
  l.asked_ns = l.sent_ns = l.probed_ns = now;
}

// Its request was not written after all: asked again later.
void unasked(Lifecycle& l, std::uint8_t t) {
  if (l.asked == t) l.asked = -1;
}

}  // namespace

// The serving process's steps, once it is in the graph and what it needs is Active; then each
// standby's (its configuration), and a standby started where one is missing. Returns when next
// to look.
std::int64_t NodeSupervisor::driveLifecycle(Node& n, std::int64_t now) {
  constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();
  if (!n.managed || !lifecycle_.request) return kNever;
  const double timeout_ms = n.serving.load(std::memory_order_acquire)->lifecycle->transition_timeout_ms;
  const auto timeout_ns = static_cast<std::int64_t>(timeout_ms * 1e6);
  std::int64_t next = kNever;
  Step serving;
  std::string name;
  std::vector<std::pair<std::string, Step>> standby_steps;
  bool start_standby = false;
  {
    std::lock_guard lock(n.mutex);
    name = n.ros_name;
    // Asked as soon as its request reader is matched (request() says when), not once it is
    // listed in the graph: a Fast DDS node's listing can come seconds later.
    if (n.pid != 0 && !n.stopping) serving = nextStep(n.life, now, timeout_ns);
    for (Standby& b : n.standbys)
      if (b.pid != 0 && !b.ending) standby_steps.emplace_back(b.name, nextStep(b.life, now, timeout_ns));
    const bool running = n.pid != 0 || !n.standbys.empty();
    if (!n.standbys_end && running && static_cast<int>(n.standbys.size()) < n.standby_count) {
      if (now >= n.standby_due_ns) start_standby = true;
      else next = std::min(next, n.standby_due_ns);
    }
  }
  next = std::min(next, serving.next);
  // Configured and activated once what it needs is Active (their transitions poke the timer).
  if (serving.ask == LTransition::TRANSITION_CONFIGURE || serving.ask == LTransition::TRANSITION_ACTIVATE)
    for (const Node* m : n.needs) {
      std::lock_guard lock(m->mutex);
      if (m->life.active_ns == 0) serving.ask = -1;
    }
  if (serving.late) {
    {
      std::lock_guard lock(n.mutex);
      n.resetting = false;
    }
    report(n, FaultKind::Lifecycle,
           fmt::format("node '{}': {} not done within {:g} ms: it is {}", name, transitionName(serving.transition),
                       timeout_ms, stateName(lifecycleStateOf(n.plan->name))),
           now);
  }
  if (serving.probe && lifecycle_.ask_state) (void)lifecycle_.ask_state(n.plan->name, name);
  if (serving.ask >= 0) {
    const auto t = static_cast<std::uint8_t>(serving.ask);
    {
      std::lock_guard lock(n.mutex);
      if (!n.stopping && n.ros_name == name) asked(n.life, t, now);
    }
    const LifecycleLink::Asked sent = lifecycle_.request(n.plan->name, name, t);
    if (sent != LifecycleLink::Asked::Written) {
      std::lock_guard lock(n.mutex);
      if (n.ros_name == name) unasked(n.life, t);
    }
    if (sent == LifecycleLink::Asked::NotYet) {
      next = std::min(next, now + kUnmatchedRetryNs);  // its reader not matched yet
    } else if (sent == LifecycleLink::Asked::Cyclone) {
      {
        std::lock_guard lock(n.mutex);
        n.life.steps.clear();
        n.life.unresponsive = true;  // it cannot be asked: a reset restarts it (and it says so again)
        n.resetting = false;
      }
      report(n, FaultKind::Lifecycle,
             fmt::format("node '{}' runs on rmw_cyclonedds (its participant's vendor id is CycloneDDS's), whose "
                         "service requests keel does not write: run it on rmw_fastrtps_cpp to have keel drive it",
                         name),
             now);
    } else {
      next = std::min(next, now + std::min(kProbeNs, timeout_ns));
    }
  }
  for (auto& [standby, step] : standby_steps) {
    next = std::min(next, step.next);
    pid_t lost = 0;
    if (step.late) {  // a standby that does not answer is no standby: ended, another started
      std::lock_guard lock(n.mutex);
      for (Standby& b : n.standbys)
        if (b.name == standby && !b.ending) {
          b.ending = true;
          lost = b.pid;
        }
    }
    if (lost != 0) {
      nlohmann::json record = log::schema::node(n.plan->name, standby, lost, "standby_failed");
      record[log::schema::field::kDetail] = fmt::format("{} not done within {:g} ms", transitionName(step.transition),
                                                        timeout_ms);
      record[log::schema::field::kTime] = log_.sinceStart(now);
      log_.write(std::move(record));
      ::killpg(lost, SIGKILL);
      continue;
    }
    if (step.probe && lifecycle_.ask_state) (void)lifecycle_.ask_state(n.plan->name, standby);
    if (step.ask < 0) continue;
    const auto t = static_cast<std::uint8_t>(step.ask);
    const std::string& which = standby;  // a lambda cannot capture a structured binding (clang 14)
    auto mark = [&](bool written) {
      std::lock_guard lock(n.mutex);
      for (Standby& b : n.standbys)
        if (b.name == which) written ? asked(b.life, t, now) : unasked(b.life, t);
    };
    mark(true);
    if (lifecycle_.request(n.plan->name, standby, t) != LifecycleLink::Asked::Written) {
      mark(false);
      next = std::min(next, now + kUnmatchedRetryNs);
      continue;
    }
    next = std::min(next, now + std::min(kProbeNs, timeout_ns));
  }
  if (start_standby) {
    if (auto started = startStandby(n); !started) {
      warn_(started.error().message);
      std::lock_guard lock(n.mutex);
      n.standby_due_ns = now + kStandbyRetryNs;
      next = std::min(next, n.standby_due_ns);
    } else {
      next = std::min(next, now + kUnmatchedRetryNs);
    }
  }
  return next;
}

// A standby started for `n`: its process under the lowest free standby name, configured once its
// reader is matched (driveLifecycle), promotable once Inactive.
Result<void> NodeSupervisor::startStandby(Node& n) {
  std::string name;
  {
    std::lock_guard lock(n.mutex);
    const profile::NodeProfile& p = *n.serving.load(std::memory_order_acquire);
    for (int k = 1;; ++k) {
      const std::string candidate = p.inNamespace(p.standbyName(k));
      // A name of a process still running (a fenced one ending too) is taken: one process of a
      // name in the graph, and in its output file, at a time.
      const bool taken = candidate == n.ros_name ||
                         std::any_of(n.standbys.begin(), n.standbys.end(),
                                     [&](const Standby& b) { return b.name == candidate; }) ||
                         std::any_of(n.retired.begin(), n.retired.end(),
                                     [&](const auto& r) { return r.second == candidate; });
      if (!taken) {
        name = candidate;
        break;
      }
    }
  }
  if (lifecycle_.renew) lifecycle_.renew(n.plan->name, name);
  auto pid = spawner_.start(childOf(n, writeParameters(n, name), name));
  if (!pid) return fail(fmt::format("node '{}': its standby {}: {}", n.plan->name, name, pid.error().message));
  tellGuard('+', *pid);
  const std::int64_t now = runtime::steadyNs();
  {
    std::lock_guard lock(n.mutex);
    Standby b;
    b.pid = *pid;
    b.name = name;
    b.started_ns = now;
    b.life.state = LState::PRIMARY_STATE_UNCONFIGURED;
    b.life.steps = {LTransition::TRANSITION_CONFIGURE};
    n.standbys.push_back(std::move(b));
  }
  nlohmann::json rec = log::schema::node(n.plan->name, name, *pid, "standby_started");
  rec[log::schema::field::kOutput] = fileOf(n, n.output, name, ".out");
  rec[log::schema::field::kTime] = log_.sinceStart(now);
  log_.write(std::move(rec));
  if (auto watched = watch_.watch(*pid, [this, &n](pid_t p, const Exit& e) { exited(n, p, e); }); !watched) {
    ::kill(*pid, SIGKILL);
    return fail(fmt::format("node '{}': its standby {}: {}", n.plan->name, name, watched.error().message));
  }
  pokeTimer();
  return {};
}

// The exit of a standby: logged, and another started after it (later each time one is lost in
// a row). No fault: the role is served all along. False: `pid` is no standby of `n`.
bool NodeSupervisor::standbyExited(Node& n, pid_t pid, const Exit& exit) {
  std::string name;
  bool asked = false;
  {
    std::lock_guard lock(n.mutex);
    const auto b = std::find_if(n.standbys.begin(), n.standbys.end(), [&](const Standby& s) { return s.pid == pid; });
    if (b == n.standbys.end()) return false;
    name = b->name;
    asked = b->ending && n.standbys_end;
    n.standbys.erase(b);
    if (!asked) {
      ++n.standby_losses;
      const std::int64_t backoff = std::min<std::int64_t>(kStandbyBackoffMaxNs,
                                                          kStandbyBackoffNs << std::min(n.standby_losses - 1, 8));
      n.standby_due_ns = runtime::steadyNs() + (n.standby_losses > 1 ? backoff : 0);
    }
    ++n.exits;
  }
  ::killpg(pid, SIGKILL);  // what it forked
  tellGuard('-', pid);
  nlohmann::json rec = log::schema::node(n.plan->name, name, pid, asked ? "stopped" : "standby_exited");
  rec[log::schema::field::kDetail] = describe(exit);
  if (!asked && !n.output.empty())
    rec[log::schema::field::kLastLines] = lastLines(fileOf(n, n.output, name, ".out"), 10);
  rec[log::schema::field::kTime] = log_.sinceStart(exit.at_ns);
  log_.write(std::move(rec));
  n.changed.notify_all();
  pokeTimer();
  return true;
}

// The reset of a node with a standby ready: the serving process fenced first — deactivated, or
// killed when it does not answer (never two active writers) — then the standby activated in its
// place and another standby started behind it. False: no standby is ready.
bool NodeSupervisor::promote(Node& n) {
  if (!n.managed || !lifecycle_.request) return false;
  const std::int64_t t0 = runtime::steadyNs();
  pid_t old = 0;
  std::string old_name;
  {
    std::lock_guard lock(n.mutex);
    const bool ready = std::any_of(n.standbys.begin(), n.standbys.end(), [](const Standby& b) {
      return b.ready && !b.ending && b.life.asked < 0 && b.life.state == LState::PRIMARY_STATE_INACTIVE;
    });
    if (!ready) return false;
    old = n.pid;
    old_name = n.ros_name;
  }
  std::string fenced = "its process had ended";
  if (old != 0) fenced = fence(n, old, old_name);
  Standby b;
  {
    std::lock_guard lock(n.mutex);
    const auto it = std::find_if(n.standbys.begin(), n.standbys.end(), [](const Standby& s) {
      return s.ready && !s.ending && s.life.asked < 0 && s.life.state == LState::PRIMARY_STATE_INACTIVE;
    });
    if (it == n.standbys.end()) return false;  // it went meanwhile: a restart instead
    b = std::move(*it);
    n.standbys.erase(it);
    n.pid = b.pid;
    n.ros_name = b.name;
    n.life = b.life;
    n.life.steps = {LTransition::TRANSITION_ACTIVATE};
    n.resetting = true;
    recoversLater(n.proxy);
    n.stopping = false;
    n.up = true;  // its request reader is matched: it is in the graph
    n.late = false;
    n.left_ns = 0;
    n.reported = false;
    n.started_ns = b.started_ns;
  }
  // At once, not at the timer's next look.
  {
    std::lock_guard lock(n.mutex);
    if (n.ros_name == b.name) asked(n.life, LTransition::TRANSITION_ACTIVATE, runtime::steadyNs());
  }
  if (lifecycle_.request(n.plan->name, b.name, LTransition::TRANSITION_ACTIVATE) != LifecycleLink::Asked::Written) {
    std::lock_guard lock(n.mutex);  // the timer's next look asks again
    if (n.ros_name == b.name) unasked(n.life, LTransition::TRANSITION_ACTIVATE);
  }
  nlohmann::json rec = log::schema::node(n.plan->name, b.name, b.pid, "promoted");
  rec[log::schema::field::kDetail] = old != 0 ? fmt::format("in place of pid {} ({}), {}", old, old_name, fenced)
                                              : fenced;
  rec[log::schema::field::kAfterMs] = static_cast<double>(runtime::steadyNs() - t0) / 1e6;
  rec[log::schema::field::kTime] = log_.sinceStart(t0);
  log_.write(std::move(rec));
  pokeTimer();  // a standby started behind it
  return true;
}

// The serving process `pid` made unable to publish before a standby is activated: deactivated
// (confirmed) and then ended, or killed when it does not answer within its transition timeout.
// What was done, for the log.
std::string NodeSupervisor::fence(Node& n, pid_t pid, const std::string& name) {
  // Its transition timeout, at most a second: the standby waits meanwhile.
  const double timeout_ms = std::min(1000.0,
                                     n.serving.load(std::memory_order_acquire)->lifecycle->transition_timeout_ms);
  const auto until = Clock::now() + std::chrono::microseconds(static_cast<std::int64_t>(timeout_ms * 1e3));
  bool answers = false;
  {
    std::lock_guard lock(n.mutex);
    n.stopping = true;  // its silence and its exit from here on are keel's doing
    n.life.steps.clear();
    n.life.asked = -1;
    answers = !n.life.unresponsive && n.life.state == LState::PRIMARY_STATE_ACTIVE;
  }
  bool deactivated = false;
  const std::int64_t asked_ns = runtime::steadyNs();
  if (answers &&
      lifecycle_.request(n.plan->name, name, LTransition::TRANSITION_DEACTIVATE) == LifecycleLink::Asked::Written) {
    std::unique_lock lock(n.mutex);
    deactivated = n.changed.wait_until(lock, until, [&] {
      return n.pid != pid || n.life.state == LState::PRIMARY_STATE_INACTIVE;
    }) && n.pid == pid;
  }
  std::unique_lock lock(n.mutex);
  if (n.pid != pid) return "it ended meanwhile";
  if (deactivated) {
    n.retired[pid] = name;  // it ends, its exit no fault
    n.pid = 0;
    lock.unlock();
    nlohmann::json record = log::schema::node(n.plan->name, name, pid, "deactivated");
    record[log::schema::field::kAfterMs] = static_cast<double>(runtime::steadyNs() - asked_ns) / 1e6;
    record[log::schema::field::kTime] = log_.now();
    log_.write(std::move(record));
    ::killpg(pid, SIGINT);  // the rest of its end is the watch's (exited): its group killed then
    return "deactivated, then ended";
  }
  ::killpg(pid, SIGKILL);
  // The kernel ends a killed process promptly; the bound is against a watch that stopped.
  if (!n.changed.wait_for(lock, std::chrono::seconds(5), [&] { return n.pid != pid; }))
    warn_(fmt::format("node '{}' (pid {}): no exit seen 5 s after SIGKILL", n.plan->name, pid));
  return answers ? "not deactivated in time: killed" : "killed (it was not Active, or did not answer)";
}

// The role ended (its stop, keel run's end): its standbys too, SIGINT then SIGKILL after `grace`.
void NodeSupervisor::endStandbys(Node& n, std::chrono::milliseconds grace) {
  std::vector<pid_t> pids;
  {
    std::lock_guard lock(n.mutex);
    n.standbys_end = true;
    for (Standby& b : n.standbys) {
      b.ending = true;
      pids.push_back(b.pid);
    }
  }
  for (pid_t pid : pids) ::killpg(pid, SIGINT);
  std::unique_lock lock(n.mutex);
  auto gone = [&] {
    return std::none_of(n.standbys.begin(), n.standbys.end(),
                        [&](const Standby& b) { return std::find(pids.begin(), pids.end(), b.pid) != pids.end(); });
  };
  if (n.changed.wait_for(lock, grace, gone)) return;
  for (pid_t pid : pids) ::killpg(pid, SIGKILL);
  if (!n.changed.wait_for(lock, std::chrono::seconds(5), gone))
    warn_(fmt::format("node '{}': a standby's exit not seen 5 s after SIGKILL", n.plan->name));
}

// A reset of a live managed node that answers: deactivate → cleanup → configure → activate (from
// where it is), its process kept. False: it is to be restarted (dead, unresponsive, or in a
// state no transition leads back from).
bool NodeSupervisor::resetByTransitions(Node& n) {
  if (!n.managed || !lifecycle_.request) return false;
  std::deque<std::uint8_t> steps;
  nlohmann::json record;
  {
    std::lock_guard lock(n.mutex);
    if (n.pid == 0 || n.stopping || n.life.unresponsive || !n.life.answered) return false;
    switch (n.life.state) {
      case LState::PRIMARY_STATE_ACTIVE:
        steps = {LTransition::TRANSITION_DEACTIVATE, LTransition::TRANSITION_CLEANUP, LTransition::TRANSITION_CONFIGURE,
                 LTransition::TRANSITION_ACTIVATE};
        break;
      case LState::PRIMARY_STATE_INACTIVE:
        steps = {LTransition::TRANSITION_CLEANUP, LTransition::TRANSITION_CONFIGURE, LTransition::TRANSITION_ACTIVATE};
        break;
      case LState::PRIMARY_STATE_UNCONFIGURED:
        steps = {LTransition::TRANSITION_CONFIGURE, LTransition::TRANSITION_ACTIVATE};
        break;
      default: return false;  // Finalized, or between states: only a new process comes back
    }
    n.life.steps = steps;
    n.life.asked = -1;
    n.resetting = true;
    recoversLater(n.proxy);
    record = log::schema::node(n.plan->name, n.ros_name, n.pid, "resetting");
    record[log::schema::field::kDetail] = fmt::format("{}, in the same process (it is {})", stepList(steps),
                                                      stateName(n.life.state));
  }
  record[log::schema::field::kTime] = log_.now();
  log_.write(std::move(record));
  pokeTimer();
  return true;
}

// Before a managed node is signalled to end: deactivated and shut down, each transition
// confirmed before the next, all by `until`. What is not done by then the signals do.
void NodeSupervisor::windDown(Node& n, Clock::time_point until) {
  if (!lifecycle_.request) return;
  std::deque<std::uint8_t> steps;
  std::string name;
  pid_t pid = 0;
  {
    std::lock_guard lock(n.mutex);
    n.life.steps.clear();
    n.life.asked = -1;
    name = n.ros_name;
    pid = n.pid;
    if (n.life.unresponsive || !n.life.answered) return;  // it did not answer: the signals speak to it
    switch (n.life.state) {
      case LState::PRIMARY_STATE_ACTIVE:
        steps = {LTransition::TRANSITION_DEACTIVATE, LTransition::TRANSITION_INACTIVE_SHUTDOWN};
        break;
      case LState::PRIMARY_STATE_INACTIVE: steps = {LTransition::TRANSITION_INACTIVE_SHUTDOWN}; break;
      case LState::PRIMARY_STATE_UNCONFIGURED: steps = {LTransition::TRANSITION_UNCONFIGURED_SHUTDOWN}; break;
      default: return;
    }
  }
  for (std::uint8_t t : steps) {
    const std::int64_t asked_ns = runtime::steadyNs();
    while (lifecycle_.request(n.plan->name, name, t) != LifecycleLink::Asked::Written) {
      if (Clock::now() + std::chrono::nanoseconds(kUnmatchedRetryNs) > until) return;
      std::this_thread::sleep_for(std::chrono::nanoseconds(kUnmatchedRetryNs));
    }
    std::unique_lock lock(n.mutex);
    auto done = [&] { return n.life.state == goalOf(t) || n.pid != pid; };
    while (!done()) {
      const auto slice = std::min(until, Clock::now() + std::chrono::nanoseconds(kProbeNs));
      if (n.changed.wait_until(lock, slice, done)) break;
      if (Clock::now() >= until) return;
      lock.unlock();  // no answer yet: its state, in case the event went missing
      if (lifecycle_.ask_state) (void)lifecycle_.ask_state(n.plan->name, name);
      lock.lock();
    }
    if (n.pid != pid) return;
    nlohmann::json record = log::schema::node(n.plan->name, name, pid, confirmedPhase(t));
    record[log::schema::field::kAfterMs] = static_cast<double>(runtime::steadyNs() - asked_ns) / 1e6;
    lock.unlock();
    record[log::schema::field::kTime] = log_.now();
    log_.write(std::move(record));
  }
}

}  // namespace keel::supervision
