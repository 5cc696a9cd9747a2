#include "supervision/process_supervisor.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <system_error>
#include <utility>

#include "fault/rules.hpp"
#include "log/schema.hpp"
#include "runtime/clock.hpp"
#include "runtime/futex.hpp"
#include "runtime/injection.hpp"
#include "supervision/crossing.hpp"
#include "supervision/process_group.hpp"
#include "supervision/process_host.hpp"

namespace keel::supervision {
namespace {

namespace ipc = runtime::ipc;
using ipc::HostState;
using Clock = std::chrono::steady_clock;

}  // namespace

std::string defaultHostExecutable() {
  if (const char* env = std::getenv("KEEL_HOST"); env && *env) return env;
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return "keel-host";
  return (self.parent_path() / "keel-host").string();
}

ProcessSupervisor::ProcessSupervisor(const plan::Plan& plan, ipc::Session& session,
                                     std::vector<ipc::SharedMemory> rings, HostLaunch launch, runtime::Warn warn,
                                     log::FaultLog& log, Spawner& spawner)
    : session_(session), rings_(std::move(rings)), launch_(std::move(launch)), warn_(std::move(warn)), log_(log),
      spawner_(spawner) {
  const std::vector<std::size_t> crossing = crossingConnections(plan);
  for (std::size_t i = 0; i < plan.processes.size(); ++i) {
    auto g = std::make_unique<Group>();
    g->plan = &plan.processes[i];
    g->index = i;
    g->block = &session.process(i);
    for (std::size_t k = 0; k < crossing.size(); ++k) {
      const auto& c = plan.connections[crossing[k]];
      if (plan.processOf(c.source.component) == g->plan->name || plan.processOf(c.target.component) == g->plan->name)
        g->rings.push_back(k);
    }
    g->takes_over = true;
    for (const auto& m : g->plan->members) {
      const plan::PlannedInstance* pi = plan.find(m);
      const fault::Rules rules = fault::compileRules(pi && pi->policy ? &*pi->policy : nullptr, {});
      g->takes_over &= rules.severityOf(FaultKind::Process) == profile::Severity::Reset;
    }
    g->standby = g->takes_over ? g->plan->standby : 0;
    g->heartbeat_ns = processHeartbeatNs(plan, g->plan->name);
    if (g->plan->standby > 0 && !g->takes_over)
      warn_(
          fmt::format("{}:{}: process '{}': standby=\"{}\" has no effect: a standby takes over when the "
                      "fault policy of every component in the process resets `process` faults",
                      g->plan->where.file, g->plan->where.line, g->plan->name, g->plan->standby));
    groups_.push_back(std::move(g));
  }
}

ProcessSupervisor::~ProcessSupervisor() {
  stop(std::chrono::seconds(2));
  spawner_.drain();  // a standby's top-up it posted, which refers to it
}

std::unique_ptr<Component> ProcessSupervisor::makeProxy(const plan::PlannedInstance& instance) {
  for (auto& g : groups_) {
    if (g->plan->name != instance.process) continue;
    auto proxy = std::make_unique<Proxy>(*this, *g);
    g->proxies.push_back(proxy.get());
    return proxy;
  }
  return nullptr;
}

pid_t ProcessSupervisor::spawn(Group& g, std::size_t slot, bool standby, bool respawn) {
  ChildSpec child{launch_.executable, launch_.args, {session_.memory().fd()}};  // the session at 3
  child.args.insert(child.args.end(), {"--process", g.plan->name, "--slot", std::to_string(slot), "--session-fd",
                                       std::to_string(kFirstChildFd), "--parent", std::to_string(::getpid())});
  for (std::size_t j = 0; j < g.rings.size(); ++j) {  // the rings after it
    child.fds.push_back(rings_[g.rings[j]].fd());
    child.args.insert(child.args.end(),
                      {"--ring", fmt::format("{}={}", g.rings[j], kFirstChildFd + 1 + static_cast<int>(j))});
  }
  if (standby) child.args.emplace_back("--standby");
  if (respawn) child.args.emplace_back("--respawn");
  auto pid = spawner_.start(child);
  if (pid) return *pid;
  ipc::HostSlot& s = g.block->slots[slot];
  ipc::setMessage(s, pid.error().message);
  ipc::publishState(*g.block, s, HostState::Failed);
  return 0;
}

Result<std::size_t> ProcessSupervisor::launchHost(Group& g, bool standby, bool respawn) {
  std::size_t slot = ipc::kHostSlots;
  {
    std::lock_guard lock(g.mutex);
    for (std::size_t i = 0; i < ipc::kHostSlots && slot == ipc::kHostSlots; ++i)
      if (!g.used[i]) slot = i;
    if (slot == ipc::kHostSlots) return fail(fmt::format("process '{}': no free host slot", g.plan->name));
    g.used[slot] = true;
  }
  ipc::HostSlot& s = g.block->slots[slot];
  s.pid.store(0, std::memory_order_relaxed);
  s.active_ns.store(0, std::memory_order_relaxed);
  s.woke_ns.store(0, std::memory_order_relaxed);
  s.first_run_ns.store(0, std::memory_order_relaxed);
  s.message_len.store(0, std::memory_order_relaxed);
  ipc::publishState(*g.block, s, HostState::Starting);
  const pid_t pid = spawn(g, slot, standby, respawn);
  if (pid == 0) {
    std::lock_guard lock(g.mutex);
    g.used[slot] = false;
    return fail(ipc::messageOf(s));
  }
  s.pid.store(pid, std::memory_order_release);
  std::lock_guard lock(g.mutex);
  g.pids[slot] = pid;
  // A campaign of kills starts thousands of hosts: join the watchers whose host is gone.
  std::erase_if(g.watchers, [](Group::Watcher& w) {
    if (!w.done->load(std::memory_order_acquire)) return false;
    w.thread.join();
    return true;
  });
  auto done = std::make_shared<std::atomic<bool>>(false);
  g.watchers.push_back({std::thread([this, &g, slot, pid, done] {
                          watch(g, slot, pid);
                          done->store(true, std::memory_order_release);
                        }),
                        done});
  return slot;
}

void ProcessSupervisor::watch(Group& g, std::size_t slot, pid_t pid) {
  ipc::HostSlot& s = g.block->slots[slot];
  int status = 0;
  // Until the host holds its life lock (Loading), its death shows only as an exit: looked at
  // every 50 ms while it starts (it may fail to exec, or die loading a library).
  while (!waitFor(*g.block, Clock::now() + std::chrono::milliseconds(50),
                  [&] { return stateOf(s) != HostState::Starting; })) {
    if (::waitpid(pid, &status, WNOHANG) != pid) continue;
    const std::string why = "ended before it was ready: " + describeExit(status);
    ipc::setMessage(s, why);
    ipc::publishState(*g.block, s, HostState::Failed);
    died(g, slot, HostState::Starting, runtime::steadyNs(), why);
    return;
  }
  auto locked = s.life.lock();  // sleeps while the host lives
  const std::int64_t t = runtime::steadyNs();
  const HostState was = stateOf(s);
  ::waitpid(pid, &status, 0);
  if (locked) (void)s.life.unlock();
  std::string why = describeExit(status);
  {
    std::lock_guard lock(g.mutex);
    if (!g.hung[slot].empty()) why = std::exchange(g.hung[slot], {});
  }
  died(g, slot, was, t, why);
}

void ProcessSupervisor::died(Group& g, std::size_t slot, HostState was, std::int64_t t_ns, const std::string& detail) {
  ipc::HostSlot& s = g.block->slots[slot];
  const pid_t pid = s.pid.load(std::memory_order_acquire);
  const bool clean = was == HostState::Exited;
  log_.repair(ipc::logParticipant(g.index, slot));  // a line it had not finished writing
  nlohmann::json rec = log::schema::host(g.plan->name, pid,
                                         clean                      ? "exited"
                                         : was == HostState::Failed ? "failed"
                                                                    : "died");
  rec[log::schema::field::kDetail] = was == HostState::Failed ? ipc::messageOf(s) : detail;
  rec[log::schema::field::kTime] = log_.sinceStart(t_ns);
  log_.write(std::move(rec));
  if (!clean && was != HostState::Failed) ipc::publishState(*g.block, s, HostState::Failed);
  {
    std::lock_guard lock(g.mutex);
    g.used[slot] = false;
    g.pids[slot] = 0;
  }
  g.block->changes.fetch_add(1, std::memory_order_acq_rel);  // the slot is free: stopGroup waits for that
  runtime::futexWakeAll(g.block->changes, runtime::FutexScope::Shared);
  if (stopping_.load(std::memory_order_acquire) || g.stopped.load(std::memory_order_acquire)) return;
  if (was == HostState::Active) {
    if (!report_) return;
    // Detected by whoever saw it first: this watcher, or the standby that woke to take over.
    const std::int64_t alive_since = s.active_ns.load(std::memory_order_acquire);
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i) {
      const std::int64_t woke = g.block->slots[i].woke_ns.load(std::memory_order_acquire);
      if (i != slot && woke != 0 && woke >= alive_since && woke < t_ns) t_ns = woke;
    }
    for (Proxy* p : g.proxies) {
      FaultEvent ev(FaultKind::Process, p->instanceName(),
                    fmt::format("process '{}' (pid {}) {}", g.plan->name, pid, detail));
      ev.t_ns = t_ns;
      report_(*p, ev);
    }
  } else if (was == HostState::Standby || was == HostState::Loading) {
    warn_(fmt::format("process '{}': a standby host (pid {}) {}; starting another", g.plan->name, pid, detail));
    queueTopUp(g);  // this watcher must not wait for a spawn
  }
}

Result<void> ProcessSupervisor::waitState(Group& g, std::size_t slot, std::chrono::milliseconds within) {
  ipc::HostSlot& s = g.block->slots[slot];
  auto settled = [&] {
    const HostState st = stateOf(s);
    return st == HostState::Active || st == HostState::Standby || st == HostState::Failed || st == HostState::Exited;
  };
  if (!waitFor(*g.block, Clock::now() + within, settled))
    return fail(fmt::format("process '{}': its host was not ready within {} ms", g.plan->name, within.count()));
  const HostState st = stateOf(s);
  if (st == HostState::Active || st == HostState::Standby) return {};
  const std::string why = ipc::messageOf(s);
  return fail(why.empty() ? fmt::format("process '{}': its host ended while starting", g.plan->name) : why);
}

Result<void> ProcessSupervisor::launch() {
  std::string errors;
  for (auto& g : groups_) {
    auto slot = launchHost(*g, false, false);
    if (slot) launched_.emplace_back(g.get(), *slot);
    else errors += slot.error().message + '\n';
  }
  if (!errors.empty()) {
    errors.pop_back();
    return fail(errors);
  }
  return {};
}

Result<void> ProcessSupervisor::waitReady(std::chrono::milliseconds within) {
  std::string errors;
  for (auto [g, slot] : launched_) {
    if (auto r = waitState(*g, slot, within); !r) errors += r.error().message + '\n';
  }
  if (!errors.empty()) {
    errors.pop_back();
    return fail(errors);
  }
  for (auto& g : groups_) {
    topUpStandbys(*g);
    if (g->heartbeat_ns > 0) beat_watchers_.emplace_back([this, p = g.get()] { watchBeats(*p); });
  }
  return {};
}

std::map<std::size_t, int> ProcessSupervisor::ringDescriptors() const {
  std::map<std::size_t, int> out;
  for (std::size_t k = 0; k < rings_.size(); ++k) out[k] = ::fcntl(rings_[k].fd(), F_DUPFD_CLOEXEC, 0);
  return out;
}

void ProcessSupervisor::stop(std::chrono::milliseconds within) {
  {
    std::lock_guard lock(beat_mutex_);
    if (stopping_.exchange(true)) return;
  }
  beat_cv_.notify_all();
  for (auto& w : beat_watchers_) w.join();
  session_.abandonRings();  // a host waiting for a ring keel run never made (it failed to start)
  for (auto& g : groups_) stopGroup(*g, within);
  for (auto& g : groups_) {
    std::vector<Group::Watcher> watchers;
    {
      std::lock_guard lock(g->mutex);
      watchers.swap(g->watchers);
    }
    for (auto& w : watchers)
      if (w.thread.joinable()) w.thread.join();
  }
}

}  // namespace keel::supervision
