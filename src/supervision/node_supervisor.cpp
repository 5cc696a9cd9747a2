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
  // A managed node (<lifecycle/>): its state as keel last knew it, and the transitions keel has
  // yet to make it go through (requested one at a time, each confirmed before the next).
  bool managed = false;
  std::uint8_t state = 0;          // lifecycle_msgs/msg/State id; 0: unknown
  std::deque<std::uint8_t> steps;  // transitions to request, in order
  int asked = -1;                  // the transition requested and not confirmed yet; -1: none
  std::uint8_t asked_from = 0;     // its state when it was requested
  std::int64_t asked_ns = 0;       // when it was first requested: its timeout counts from then
  std::int64_t sent_ns = 0;        // when the request was last written
  std::int64_t probed_ns = 0;      // when its state was last asked
  bool unresponsive = false;       // a transition of this life timed out: a reset restarts it
  bool resetting = false;          // the steps are a reset's: recovered once Active
  std::int64_t active_ns = 0;      // when it became Active in this life; 0: not Active
  std::vector<const Node*> needs;  // the managed nodes it needs (<needs>, through any component)
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
  void endProcess() override { sup.stopNode(node, graceOf(node)); }
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

ChildSpec NodeSupervisor::childOf(const Node& n, const std::string& params_file) const {
  const profile::NodeProfile& p = *n.serving.load(std::memory_order_acquire);
  ChildSpec child{p.executable, {}, {}};
  child.args.assign(p.command.begin() + (p.command.empty() ? 0 : 1), p.command.end());
  // ROS 2's own section last, as launch_ros writes it: rcl reads what follows --ros-args.
  child.args.insert(child.args.end(),
                    {"--ros-args", "-r", "__node:=" + p.node_name, "-r", "__ns:=" + p.node_namespace});
  // A restart's values are all in its params file: a `-p` would win over the file in rcl.
  if (!params_file.empty()) child.args.insert(child.args.end(), {"--params-file", params_file});
  else
    for (const auto& param : p.parameters) child.args.insert(child.args.end(), {"-p", param.name + ":=" + param.value});
  // Defaults first, the profile's over them; the domain is keel's, always.
  child.environment = {"RCUTILS_COLORIZED_OUTPUT=0", "PYTHONUNBUFFERED=1"};
  for (const auto& v : p.environment) child.environment.push_back(v.name + "=" + v.value);
  child.environment.push_back(fmt::format("ROS_DOMAIN_ID={}", launch_.domain));
  child.directory = fs::path(p.file).parent_path().string();
  child.output = n.output;
  child.shim = launch_.node_exec;
  return child;
}

Result<pid_t> NodeSupervisor::start(Node& n, std::string_view phase, const std::string& params_file) {
  auto pid = spawner_.start(childOf(n, params_file));
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
    if (n.managed) {  // a new process is Unconfigured: configured and activated once it is in the graph
      n.state = msg::lifecycle_msgs::State::PRIMARY_STATE_UNCONFIGURED;
      n.steps = {msg::lifecycle_msgs::Transition::TRANSITION_CONFIGURE,
                 msg::lifecycle_msgs::Transition::TRANSITION_ACTIVATE};
      n.asked = -1;
      n.unresponsive = false;
      n.active_ns = 0;
    }
  }
  pokeTimer();
  nlohmann::json rec = log::schema::node(n.plan->name, n.profile->fullName(), *pid, phase);
  rec[log::schema::field::kOutput] = n.output;
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
  bool asked = false;
  Proxy* proxy = nullptr;
  {
    std::lock_guard lock(n.mutex);
    if (n.pid == pid) n.pid = 0;
    n.up = false;
    n.left_ns = 0;
    asked = n.stopping;
    proxy = n.proxy;
    ++n.exits;
  }
  if (asked) ::killpg(pid, SIGKILL);  // whatever the node forked and left in its group
  tellGuard('-', pid);
  const std::string how = describe(exit);
  nlohmann::json rec = log::schema::node(n.plan->name, n.profile->fullName(), pid, asked ? "stopped" : "exited");
  rec[log::schema::field::kDetail] = how;
  std::vector<std::string> last;
  if (!asked && !n.output.empty()) {
    last = lastLines(n.output, 10);
    rec[log::schema::field::kLastLines] = last;
  }
  rec[log::schema::field::kTime] = log_.sinceStart(exit.at_ns);
  log_.write(std::move(rec));
  n.changed.notify_all();
  const std::string who = fmt::format("node '{}' (pid {}) {}", n.profile->fullName(), pid, how);
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
  if (resetByTransitions(n)) return {};
  stopNode(n, Proxy::graceOf(n));  // alive when its fault came from its topics
  auto pid = start(n, "restarted", writeParameters(n));
  if (!pid) return pid.error();
  std::lock_guard lock(n.mutex);
  if (n.managed) {  // recovered once configured and Active again, not at the handling's end
    n.resetting = true;
    if (n.proxy) runtime::coreOf(*n.proxy).fault.recovers_later.store(true, std::memory_order_release);
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
  const std::uint64_t exits = n.exits;
  auto gone = [&] { return n.exits != exits; };
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

// Its params file, written now: the file, or "" when it could not be (warned) or would hold no
// value (rcl refuses a params file whose node has no parameters): then the restart has the
// profile's `-p`s, as its first start had.
std::string NodeSupervisor::writeParameters(Node& n) {
  ParameterMap values;
  {
    std::lock_guard lock(n.mutex);
    values = n.parameters;
  }
  if (values.empty()) return {};
  if (auto written = writeParamsFile(n.params_file, n.profile->fullName(), values); !written) {
    warn_(
        fmt::format("node '{}': {}: it restarts with its profile's parameters", n.plan->name, written.error().message));
    return {};
  }
  return n.params_file;
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
/// managed node: listed (its topics come with its configuration, which keel asks for then).
bool completeWith(const GraphSighting& g, bool has_outputs, bool managed) {
  return managed ? g.listed : g.missing.empty() && (g.listed || has_outputs);
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
    return n->plan->attached ? !n->up : n->pid == 0 || n->stopping || (n->managed && n->active_ns == 0);
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
    if (n->managed) return n->active_ns == 0 ? 0 : n->active_ns + static_cast<std::int64_t>(timeout_ms * 1e6);
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

// What a managed node's transition event says: its state, and the transition keel asked for
// confirmed or failed; unasked, a fall into ErrorProcessing or Finalized is its fault.
void NodeSupervisor::lifecycleTransition(std::string_view instance, std::uint8_t start, std::uint8_t goal) {
  const auto it = std::find_if(nodes_.begin(), nodes_.end(), [&](const auto& n) { return n->plan->name == instance; });
  if (it == nodes_.end() || !(*it)->managed) return;
  Node& n = **it;
  const std::int64_t now = runtime::steadyNs();
  std::optional<nlohmann::json> record;
  std::string fault;
  Proxy* back = nullptr;  // the node is back after its reset: its recovery
  {
    std::lock_guard lock(n.mutex);
    if (n.pid == 0) return;  // a life that ended: its last words change nothing
    const std::uint8_t known = n.state;
    n.state = goal;
    if (goal != LState::PRIMARY_STATE_ACTIVE) n.active_ns = 0;
    const std::string name = n.profile->fullName();
    if (n.asked >= 0) {
      const auto t = static_cast<std::uint8_t>(n.asked);
      const bool ends = primary(goal) && (start == throughOf(t) || start == LState::TRANSITION_STATE_ERRORPROCESSING);
      if (ends && goal == goalOf(t)) {
        n.asked = -1;
        if (!n.steps.empty() && n.steps.front() == t) n.steps.pop_front();
        record = log::schema::node(n.plan->name, name, n.pid, confirmedPhase(t));
        (*record)[log::schema::field::kAfterMs] = static_cast<double>(now - n.asked_ns) / 1e6;
        if (goal == LState::PRIMARY_STATE_ACTIVE) n.active_ns = now;
        if (n.resetting && n.steps.empty() && goal == LState::PRIMARY_STATE_ACTIVE) {
          n.resetting = false;
          back = n.proxy;
        }
      } else if (ends && !n.stopping) {
        fault = fmt::format("node '{}': {} failed{}: it is {}", name, transitionName(t),
                            start == LState::TRANSITION_STATE_ERRORPROCESSING ? " with an error" : "", stateName(goal));
        n.asked = -1;
        n.steps.clear();
        n.resetting = false;
      }
    } else if (!n.stopping &&
               (goal == LState::TRANSITION_STATE_ERRORPROCESSING || goal == LState::PRIMARY_STATE_FINALIZED)) {
      fault = fmt::format("node '{}' went from {} to {} by itself", name, stateName(start), stateName(goal));
      n.steps.clear();
    } else if (!n.stopping && primary(goal) && !primary(start) && goal != known) {
      // Another client moved it (`ros2 lifecycle set`): said in the log, not a fault. (An event
      // of keel's own transition that its state confirmed first changes no state it knew.)
      record = log::schema::node(n.plan->name, name, n.pid, stateName(goal));
      (*record)[log::schema::field::kDetail] = fmt::format("{} → {}, not asked by keel", stateName(start),
                                                           stateName(goal));
    }
  }
  n.changed.notify_all();
  if (record) {
    (*record)[log::schema::field::kTime] = log_.sinceStart(now);
    log_.write(std::move(*record));
  }
  if (back) recoveredAt(*back, now);
  if (!fault.empty()) report(n, FaultKind::Lifecycle, fault, now);
  pokeTimer();
}

// A get_state reply: the confirmation of a transition whose event was lost, or the sign that a
// request was (its state still the one it had).
void NodeSupervisor::lifecycleState(std::string_view instance, std::uint8_t state) {
  const auto it = std::find_if(nodes_.begin(), nodes_.end(), [&](const auto& n) { return n->plan->name == instance; });
  if (it == nodes_.end() || !(*it)->managed) return;
  Node& n = **it;
  const std::int64_t now = runtime::steadyNs();
  std::optional<nlohmann::json> record;
  bool resend = false;
  std::uint8_t t = 0;
  Proxy* back = nullptr;
  {
    std::lock_guard lock(n.mutex);
    if (n.pid == 0) return;
    if (n.asked >= 0) {
      t = static_cast<std::uint8_t>(n.asked);
      if (state == goalOf(t)) {
        n.state = state;
        n.asked = -1;
        if (!n.steps.empty() && n.steps.front() == t) n.steps.pop_front();
        record = log::schema::node(n.plan->name, n.profile->fullName(), n.pid, confirmedPhase(t));
        (*record)[log::schema::field::kAfterMs] = static_cast<double>(now - n.asked_ns) / 1e6;
        (*record)[log::schema::field::kDetail] = "confirmed by its state (its transition event was not seen)";
        if (state == LState::PRIMARY_STATE_ACTIVE) n.active_ns = now;
        if (n.resetting && n.steps.empty() && state == LState::PRIMARY_STATE_ACTIVE) {
          n.resetting = false;
          back = n.proxy;
        }
      } else if (state == n.asked_from && now - n.sent_ns >= kResendNs) {
        resend = true;  // it never got the request
        n.sent_ns = now;
      }
    } else if (primary(state)) {
      n.state = state;
    }
  }
  n.changed.notify_all();
  if (record) {
    (*record)[log::schema::field::kTime] = log_.sinceStart(now);
    log_.write(std::move(*record));
  }
  if (back) recoveredAt(*back, now);
  if (resend && lifecycle_.request) (void)lifecycle_.request(n.plan->name, t);
  pokeTimer();
}

// A managed node's reset is over: it is Active again.
void NodeSupervisor::recoveredAt(Proxy& proxy, std::int64_t t_ns) {
  runtime::coreOf(proxy).fault.recovers_later.store(false, std::memory_order_release);
  if (recovered_) recovered_(proxy, t_ns);
}

std::uint8_t NodeSupervisor::lifecycleStateOf(std::string_view instance) const {
  for (const auto& n : nodes_) {
    if (n->plan->name != instance) continue;
    std::lock_guard lock(n->mutex);
    return n->state;
  }
  return 0;
}

// The next of a managed node's steps, once it is in the graph; an unconfirmed one probed, and
// late, its fault. Returns when next to look.
std::int64_t NodeSupervisor::driveLifecycle(Node& n, std::int64_t now) {
  constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();
  if (!n.managed || !lifecycle_.request) return kNever;
  std::optional<std::uint8_t> ask;
  bool probe = false;
  std::string fault;
  std::int64_t next = kNever;
  {
    std::lock_guard lock(n.mutex);
    if (n.pid == 0 || n.stopping || !n.up) return kNever;
    const double timeout_ms = n.serving.load(std::memory_order_acquire)->lifecycle->transition_timeout_ms;
    const auto timeout_ns = static_cast<std::int64_t>(timeout_ms * 1e6);
    if (n.asked >= 0) {
      const auto t = static_cast<std::uint8_t>(n.asked);
      if (now - n.asked_ns >= timeout_ns) {
        fault = fmt::format("node '{}': {} not done within {:g} ms: it is {}", n.profile->fullName(), transitionName(t),
                            timeout_ms, stateName(n.state));
        n.asked = -1;
        n.steps.clear();
        n.resetting = false;
        n.unresponsive = true;
      } else {
        if (now - n.probed_ns >= kProbeNs) {
          probe = true;
          n.probed_ns = now;
        }
        next = std::min(n.asked_ns + timeout_ns, n.probed_ns + kProbeNs);
      }
    } else if (!n.steps.empty()) {
      ask = n.steps.front();
    }
  }
  // Configured and activated once what it needs is Active (their transitions poke the timer).
  if (ask && (*ask == LTransition::TRANSITION_CONFIGURE || *ask == LTransition::TRANSITION_ACTIVATE))
    for (const Node* m : n.needs) {
      std::lock_guard lock(m->mutex);
      if (m->active_ns == 0) return kNever;
    }
  if (!fault.empty()) {
    report(n, FaultKind::Lifecycle, fault, now);
    return kNever;
  }
  if (probe && lifecycle_.ask_state) (void)lifecycle_.ask_state(n.plan->name);
  if (!ask) return next;
  const LifecycleLink::Asked sent = lifecycle_.request(n.plan->name, *ask);
  if (sent == LifecycleLink::Asked::NotYet) return now + kUnmatchedRetryNs;  // its reader not matched yet
  if (sent == LifecycleLink::Asked::Cyclone) {
    {
      std::lock_guard lock(n.mutex);
      n.steps.clear();
      n.unresponsive = true;  // it cannot be asked: a reset restarts it (and it says so again)
      n.resetting = false;
    }
    report(n, FaultKind::Lifecycle,
           fmt::format("node '{}' runs on rmw_cyclonedds (its participant's vendor id is CycloneDDS's), whose "
                       "service requests keel does not write: run it on rmw_fastrtps_cpp to have keel drive it",
                       n.profile->fullName()),
           now);
    return kNever;
  }
  std::lock_guard lock(n.mutex);
  if (n.asked < 0 && !n.steps.empty() && n.steps.front() == *ask && !n.stopping) {
    n.asked = *ask;
    n.asked_from = n.state;
    n.asked_ns = n.sent_ns = n.probed_ns = now;
  }
  const double timeout_ms = n.serving.load(std::memory_order_acquire)->lifecycle->transition_timeout_ms;
  return std::min(now + kProbeNs, now + static_cast<std::int64_t>(timeout_ms * 1e6));
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
    if (n.pid == 0 || n.stopping || n.unresponsive || !n.up) return false;
    switch (n.state) {
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
    n.steps = steps;
    n.asked = -1;
    n.resetting = true;  // recovered once Active again, not at the handling's end
    if (n.proxy) runtime::coreOf(*n.proxy).fault.recovers_later.store(true, std::memory_order_release);
    record = log::schema::node(n.plan->name, n.profile->fullName(), n.pid, "resetting");
    record[log::schema::field::kDetail] = fmt::format("{}, in the same process (it is {})", stepList(steps),
                                                      stateName(n.state));
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
  {
    std::lock_guard lock(n.mutex);
    n.steps.clear();
    n.asked = -1;
    if (n.unresponsive || !n.up) return;  // it did not answer before: the signals speak to it
    switch (n.state) {
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
    while (lifecycle_.request(n.plan->name, t) != LifecycleLink::Asked::Written) {
      if (Clock::now() + std::chrono::nanoseconds(kUnmatchedRetryNs) > until) return;
      std::this_thread::sleep_for(std::chrono::nanoseconds(kUnmatchedRetryNs));
    }
    std::unique_lock lock(n.mutex);
    const std::uint64_t exits = n.exits;
    auto done = [&] { return n.state == goalOf(t) || n.exits != exits || n.pid == 0; };
    while (!done()) {
      const auto slice = std::min(until, Clock::now() + std::chrono::nanoseconds(kProbeNs));
      if (n.changed.wait_until(lock, slice, done)) break;
      if (Clock::now() >= until) return;
      lock.unlock();  // no answer yet: its state, in case the event went missing
      if (lifecycle_.ask_state) (void)lifecycle_.ask_state(n.plan->name);
      lock.lock();
    }
    if (n.pid == 0 || n.exits != exits) return;
    nlohmann::json record = log::schema::node(n.plan->name, n.profile->fullName(), n.pid, confirmedPhase(t));
    record[log::schema::field::kAfterMs] = static_cast<double>(runtime::steadyNs() - asked_ns) / 1e6;
    lock.unlock();
    record[log::schema::field::kTime] = log_.now();
    log_.write(std::move(record));
  }
}

}  // namespace keel::supervision
