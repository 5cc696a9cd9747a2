#include "supervision/node_supervisor.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
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
  const profile::NodeProfile* profile = nullptr;
  std::string output;  // its output file

  mutable std::mutex mutex;
  std::condition_variable changed;
  Proxy* proxy = nullptr;  // null once the engine destroyed it
  pid_t pid = 0;           // its running process; 0: none
  bool stopping = false;   // keel asked it to end: its exit is no fault
  std::uint64_t exits = 0;
  std::mutex restart_mutex;  // one restart or stop at a time
};

struct NodeSupervisor::Proxy final : Component, runtime::ProcessTarget {
  Proxy(NodeSupervisor& s, std::shared_ptr<Node> n) : sup(s), held(std::move(n)), node(*held) {}
  ~Proxy() override {  // may come after the supervisor's end: the engine closes its side first
    std::lock_guard lock(node.mutex);
    node.proxy = nullptr;
  }
  Proxy(const Proxy&) = delete;
  Proxy& operator=(const Proxy&) = delete;
  Proxy(Proxy&&) = delete;
  Proxy& operator=(Proxy&&) = delete;
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
  ReturnCode onEmergencyStop() override {
    if (node.profile->emergency && node.profile->emergency->stop) sup.stopNode(node, graceOf(node));
    return ReturnCode::Ok;
  }
  bool signalProcess(int signal) override {
    std::lock_guard lock(node.mutex);
    return node.pid > 0 && ::kill(node.pid, signal) == 0;
  }
  static std::chrono::milliseconds graceOf(const Node& n) {
    return std::chrono::milliseconds(static_cast<std::int64_t>(n.profile->stop_grace_ms));
  }
  NodeSupervisor& sup;  // not used once the engine shut down: only the destructor runs then
  std::shared_ptr<Node> held;
  Node& node;
};

NodeSupervisor::NodeSupervisor(const plan::Plan& plan, NodeLaunch launch, runtime::Warn warn, log::FaultLog& log,
                               Spawner& spawner)
    : launch_(std::move(launch)), warn_(std::move(warn)), log_(log), spawner_(spawner) {
  for (const auto& pi : plan.instances) {
    if (!pi.node) continue;
    auto n = std::make_shared<Node>();
    n->plan = &pi;
    n->profile = pi.node;
    if (!pi.attached)
      n->output = (fs::path(launch_.output_dir) / fmt::format("{}.{}.out", launch_.output_stem, pi.name)).string();
    nodes_.push_back(std::move(n));
  }
  warnNotYet(plan);
}

// What a node profile or its subcomponent may say that this keel reads but does not act on yet,
// each a warning at its line: the run goes on without it, and the integrator knows.
void NodeSupervisor::warnNotYet(const plan::Plan& plan) const {
  auto note = [this](const profile::Where& where, const std::string& what) {
    warn_(fmt::format("{}: {} is accepted, not acted on yet: {}", where.str(), what,
                      "this keel starts, watches the death of, restarts and stops nodes (docs/ros2-nodes.md)"));
  };
  for (const auto& n : nodes_) {
    const plan::PlannedInstance& pi = *n->plan;
    const profile::NodeProfile& p = *n->profile;
    if (pi.attached) note(pi.where, fmt::format("<attach/> of node '{}' (nothing watches it)", pi.name));
    if (pi.policy && pi.policy->alternative)
      note(pi.policy->alternative->where, fmt::format("the <alternative> of node '{}'", pi.name));
    for (const auto& t : p.topics)
      if (t.deadline_ms || t.liveliness_ms) note(t.where, fmt::format("the deadline or liveliness of {}", t.topic));
    for (const auto& port : p.component.data_ports)
      for (const auto& v : port.field_validity)
        note(v.where, fmt::format("<validity field=\"{}\"> on the values of a node (its path is checked)", v.field));
    if (p.emergency)
      for (const auto& c : p.emergency->publish) note(c.where, fmt::format("<publish topic=\"{}\">", c.topic));
    if (!p.diagnostics_name.empty()) note(p.where, fmt::format("<diagnostics name=\"{}\">", p.diagnostics_name));
    for (const auto& c : plan.connections)
      if (c.source.component == pi.name || c.target.component == pi.name)
        note(c.where,
             fmt::format("a connection to node '{}'s port (keel reads and writes no node topic yet)", pi.name));
  }
}

NodeSupervisor::~NodeSupervisor() {
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

std::unique_ptr<Component> NodeSupervisor::makeProxy(const plan::PlannedInstance& instance) {
  for (auto& n : nodes_) {
    if (n->plan != &instance) continue;
    auto proxy = std::make_unique<Proxy>(*this, n);
    std::lock_guard lock(n->mutex);
    n->proxy = proxy.get();
    return proxy;
  }
  return nullptr;
}

ChildSpec NodeSupervisor::childOf(const Node& n) const {
  const profile::NodeProfile& p = *n.profile;
  ChildSpec child{p.executable, {}, {}};
  child.args.assign(p.command.begin() + (p.command.empty() ? 0 : 1), p.command.end());
  // ROS 2's own section last, as launch_ros writes it: rcl reads what follows --ros-args.
  child.args.insert(child.args.end(),
                    {"--ros-args", "-r", "__node:=" + p.node_name, "-r", "__ns:=" + p.node_namespace});
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

Result<pid_t> NodeSupervisor::start(Node& n, std::string_view phase) {
  auto pid = spawner_.start(childOf(n));
  if (!pid) return fail(fmt::format("node '{}': {}", n.plan->name, pid.error().message));
  tellGuard('+', *pid);  // its process group's id is its pid
  {
    std::lock_guard lock(n.mutex);
    n.pid = *pid;
    n.stopping = false;
  }
  nlohmann::json rec = log::schema::node(n.plan->name, n.profile->fullName(), *pid, phase);
  rec[log::schema::field::kOutput] = n.output;
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
  if (asked || !proxy || !report_) return;
  std::string detail = fmt::format("node '{}' (pid {}) {}", n.profile->fullName(), pid, how);
  if (!last.empty()) detail += ": " + last.back();
  FaultEvent ev(FaultKind::Process, n.plan->name, detail);
  ev.t_ns = exit.at_ns;
  report_(*proxy, ev);
}

Result<void> NodeSupervisor::restart(Node& n) {
  if (n.plan->attached) return fail("an attached node is not keel's to restart");
  std::lock_guard one(n.restart_mutex);
  stopNode(n, Proxy::graceOf(n));  // alive when its fault came from its topics
  auto pid = start(n, "restarted");
  if (!pid) return pid.error();
  std::lock_guard lock(n.mutex);
  if (n.proxy) runtime::coreOf(*n.proxy).fault.recovered_at_ns.store(runtime::steadyNs(), std::memory_order_release);
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
  std::string errors;
  for (auto& n : nodes_) {
    if (n->plan->attached) continue;
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

}  // namespace keel::supervision
