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
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <optional>
#include <system_error>

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
}

NodeSupervisor::~NodeSupervisor() {
  {
    std::lock_guard lock(timer_mutex_);
    timer_ending_ = true;
    timer_changed_.notify_all();
  }
  if (timer_.joinable()) timer_.join();
  stop(std::chrono::seconds(2));
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
  stopNode(n, Proxy::graceOf(n));  // alive when its fault came from its topics
  auto pid = start(n, "restarted", writeParameters(n));
  if (!pid) return pid.error();
  std::lock_guard lock(n.mutex);
  if (n.proxy) runtime::coreOf(*n.proxy).fault.recovered_at_ns.store(runtime::steadyNs(), std::memory_order_release);
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

/// Whether `g` shows the node up: every output topic published (a node with none: listed).
bool completeWith(const GraphSighting& g, bool has_outputs) { return g.missing.empty() && (g.listed || has_outputs); }

/// The sighting that speaks for the node: its own that is complete, else any of its own.
const GraphSighting* ownSighting(bool attached, pid_t pid, const std::vector<GraphSighting>& seen, bool has_outputs) {
  const GraphSighting* own = nullptr;
  for (const GraphSighting& g : seen)
    if (owns(attached, pid, g) && (own == nullptr || completeWith(g, has_outputs))) own = &g;
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
    const GraphSighting* own = ownSighting(n.plan->attached, n.pid, n.seen, n.has_outputs);
    if (own != nullptr && own->pid == 0 && !n.plan->attached && !n.warned_unknown_pid)
      unknown_pid = n.warned_unknown_pid = true;
    const bool complete = own != nullptr && completeWith(*own, n.has_outputs);
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
    return n->plan->attached ? !n->up : n->pid == 0 || n->stopping;
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
    for (auto& n : nodes_) next = std::min(next, checkTimes(*n, now));
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
        const GraphSighting* own = ownSighting(n.plan->attached, n.pid, n.seen, n.has_outputs);
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
          const GraphSighting* own = ownSighting(n.plan->attached, n.pid, n.seen, n.has_outputs);
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

}  // namespace keel::supervision
