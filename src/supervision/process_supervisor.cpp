#include "supervision/process_supervisor.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <future>
#include <memory>
#include <system_error>
#include <utility>

#include "fault/rules.hpp"
#include "log/schema.hpp"
#include "runtime/clock.hpp"
#include "runtime/futex.hpp"
#include "runtime/injection.hpp"
#include "supervision/crossing.hpp"
#include "supervision/process_host.hpp"

namespace keel::supervision {
namespace {

namespace ipc = runtime::ipc;
using ipc::HostState;
using Clock = std::chrono::steady_clock;

constexpr auto kTakeoverWait = std::chrono::seconds(2);  // for a standby that is taking over
constexpr auto kRespawnWait = std::chrono::seconds(10);  // for a respawned host to run
constexpr auto kFirstRunWait = std::chrono::seconds(1);  // for the new active's first cycle
constexpr auto kEmergencyWait = std::chrono::seconds(1);
constexpr int kFirstChildFd = 3;  // the session; the rings follow

HostState stateOf(const ipc::HostSlot& s) { return static_cast<HostState>(s.state.load(std::memory_order_acquire)); }

std::string describeStatus(int status) {
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* abbrev = sigabbrev_np(sig);
    return fmt::format("killed by signal {} (SIG{}{})", sig, abbrev ? abbrev : "?",
                       WCOREDUMP(status) ? ", core dumped" : "");
  }
  if (WIFEXITED(status)) return fmt::format("exited with status {}", WEXITSTATUS(status));
  return fmt::format("ended (wait status {:#x})", status);
}

/// Waits until `done()` or `deadline`, waking at each change in `block` (every host state,
/// first cycle, emergency done and slot freed bumps `changes`); what `done()` said last.
template <class Done>
bool waitFor(ipc::ProcessBlock& block, Clock::time_point deadline, Done done) {
  for (;;) {
    const std::uint32_t seen = block.changes.load(std::memory_order_acquire);
    if (done()) return true;
    if (Clock::now() >= deadline) return false;
    runtime::futexWait(block.changes, seen, &deadline, runtime::FutexScope::Shared);
  }
}

pid_t activePid(const ipc::ProcessBlock& block) {
  for (const auto& s : block.slots)
    if (stateOf(s) == HostState::Active) return s.pid.load(std::memory_order_acquire);
  return 0;
}

}  // namespace

std::string defaultHostExecutable() {
  if (const char* env = std::getenv("KEEL_HOST"); env && *env) return env;
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return "keel-host";
  return (self.parent_path() / "keel-host").string();
}

struct ProcessSupervisor::Group {
  const plan::PlannedProcess* plan = nullptr;
  std::size_t index = 0;
  ipc::ProcessBlock* block = nullptr;
  std::vector<std::size_t> rings;  // ring indices its hosts read or write
  std::vector<Proxy*> proxies;
  bool takes_over = false;  // every member's `process` faults are reset: standbys take over by themselves
  int standby = 0;          // standbys to keep ready

  mutable std::mutex mutex;       // guards the slots' bookkeeping below
  std::int64_t heartbeat_ns = 0;  // the process's (processHeartbeatNs); 0: not watched
  std::array<pid_t, ipc::kHostSlots> pids{};
  std::array<std::string, ipc::kHostSlots> hung{};  // why a host was killed as hung
  std::array<bool, ipc::kHostSlots> used{};
  struct Watcher {
    std::thread thread;
    std::shared_ptr<std::atomic<bool>> done;  // its host died and it reported it
  };
  std::vector<Watcher> watchers;  // finished ones are joined when the next host starts
  std::mutex recover_mutex;       // one recovery at a time
  std::atomic<bool> stopped{false};
};

struct ProcessSupervisor::Proxy final : Component, runtime::ProcessTarget {
  Proxy(ProcessSupervisor& s, Group& g) : sup(s), group(g) {}
  ReturnCode onReset() override {
    auto r = sup.recover(group);
    if (r) {
      runtime::coreOf(*this).fault.recovered_at_ns.store(*r, std::memory_order_release);
      return ReturnCode::Ok;
    }
    sup.warn_(fmt::format("process '{}': {}", group.plan->name, r.error().message));
    return ReturnCode::InternalFault;
  }
  ReturnCode onStop() override {
    sup.stopGroup(group, std::chrono::seconds(2));
    return ReturnCode::Ok;
  }
  ReturnCode onEmergencyStop() override {
    sup.emergency(group);
    return ReturnCode::Ok;
  }
  bool signalProcess(int signal) override {
    const pid_t pid = activePid(*group.block);
    return pid > 0 && ::kill(pid, signal) == 0;
  }
  ProcessSupervisor& sup;
  Group& group;
};

ProcessSupervisor::ProcessSupervisor(const plan::Plan& plan, ipc::Session& session,
                                     std::vector<ipc::SharedMemory> rings, HostLaunch launch, Warn warn,
                                     log::FaultLog& log)
    : session_(session), rings_(std::move(rings)), launch_(std::move(launch)), warn_(std::move(warn)), log_(log) {
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
  spawner_.stop();
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

pid_t ProcessSupervisor::spawnNow(Group& g, std::size_t slot, bool standby, bool respawn) {
  // The child's descriptors: the session at 3, then the rings. Copies above every target first,
  // so that no dup2 overwrites a source another one still needs.
  std::vector<int> sources{session_.memory().fd()};
  sources.reserve(1 + g.rings.size());
  for (std::size_t k : g.rings) sources.push_back(rings_[k].fd());
  std::vector<int> high;
  high.reserve(sources.size());
  for (int fd : sources)
    high.push_back(::fcntl(fd, F_DUPFD_CLOEXEC, kFirstChildFd + 64 + static_cast<int>(sources.size())));
  std::vector<std::string> args;
  args.push_back(launch_.executable);
  args.insert(args.end(), launch_.args.begin(), launch_.args.end());
  args.insert(args.end(), {"--process", g.plan->name, "--slot", std::to_string(slot), "--session-fd",
                           std::to_string(kFirstChildFd), "--parent", std::to_string(::getpid())});
  for (std::size_t j = 0; j < g.rings.size(); ++j)
    args.insert(args.end(), {"--ring", fmt::format("{}={}", g.rings[j], kFirstChildFd + 1 + static_cast<int>(j))});
  if (standby) args.emplace_back("--standby");
  if (respawn) args.emplace_back("--respawn");
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  for (std::size_t j = 0; j < high.size(); ++j)
    posix_spawn_file_actions_adddup2(&actions, high[j], kFirstChildFd + static_cast<int>(j));
  // Nothing else of keel run's: not every descriptor it holds is close-on-exec (CycloneDDS's
  // sockets are not, nor what a component opens without O_CLOEXEC), and a host started after
  // keel run joined DDS would otherwise hold its participant's sockets for its whole life.
  posix_spawn_file_actions_addclosefrom_np(&actions, kFirstChildFd + static_cast<int>(high.size()));
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, defaults;
  sigemptyset(&none);
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGINT);
  sigaddset(&defaults, SIGTERM);
  sigaddset(&defaults, SIGPIPE);
  sigaddset(&defaults, SIGUSR2);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
  pid_t pid = 0;
  const int rc = ::posix_spawn(&pid, launch_.executable.c_str(), &actions, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  for (int fd : high)
    if (fd >= 0) ::close(fd);
  if (rc != 0) {
    ipc::HostSlot& s = g.block->slots[slot];
    ipc::setMessage(s, fmt::format("cannot start '{}': {}", launch_.executable, std::generic_category().message(rc)));
    ipc::publishState(*g.block, s, HostState::Failed);
    return 0;
  }
  return pid;
}

pid_t ProcessSupervisor::spawn(Group& g, std::size_t slot, bool standby, bool respawn) {
  if (spawner_.isCurrent()) return spawnNow(g, slot, standby, respawn);
  std::promise<pid_t> started;
  auto result = started.get_future();
  spawner_.post([&] { started.set_value(spawnNow(g, slot, standby, respawn)); });
  return result.get();
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
    const std::string why = "ended before it was ready: " + describeStatus(status);
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
  std::string why = describeStatus(status);
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

void ProcessSupervisor::watchBeats(Group& g) {
  const auto period = std::chrono::nanoseconds(g.heartbeat_ns / 4);
  std::unique_lock lock(beat_mutex_);
  while (!beat_cv_.wait_for(lock, period, [this] { return stopping_.load(std::memory_order_acquire); })) {
    if (g.stopped.load(std::memory_order_acquire)) continue;
    const std::int64_t now = runtime::steadyNs();
    std::lock_guard slots(g.mutex);
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i) {
      const ipc::HostSlot& s = g.block->slots[i];
      if (!g.used[i] || g.pids[i] <= 0 || stateOf(s) != HostState::Active || !g.hung[i].empty()) continue;
      const std::int64_t silent = now - s.beat_ns.load(std::memory_order_acquire);
      if (silent <= g.heartbeat_ns) continue;
      // Killed before anyone else writes its ports: its standby takes over from a dead writer.
      g.hung[i] = fmt::format("hung: no heartbeat for {:.1f} ms (heartbeat timeout {:.1f} ms), killed", silent / 1e6,
                              g.heartbeat_ns / 1e6);
      ::kill(g.pids[i], SIGKILL);
    }
  }
}

std::map<std::size_t, int> ProcessSupervisor::ringDescriptors() const {
  std::map<std::size_t, int> out;
  for (std::size_t k = 0; k < rings_.size(); ++k) out[k] = ::fcntl(rings_[k].fd(), F_DUPFD_CLOEXEC, 0);
  return out;
}

void ProcessSupervisor::topUpStandbys(Group& g) {
  if (stopping_.load(std::memory_order_acquire) || g.stopped.load(std::memory_order_acquire)) return;
  int have = 0;
  {
    std::lock_guard lock(g.mutex);
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i) {
      if (!g.used[i]) continue;
      const HostState st = stateOf(g.block->slots[i]);
      have += st == HostState::Starting || st == HostState::Loading || st == HostState::Standby;
    }
  }
  for (; have < g.standby; ++have)
    if (auto r = launchHost(g, true, false); !r) warn_(r.error().message);
}

Result<std::int64_t> ProcessSupervisor::recover(Group& g) {
  std::lock_guard recovering(g.recover_mutex);
  // The dead host's slot says Failed by now (died()), and only one host holds the role: a slot
  // that says Active is the standby that took over (perhaps before keel run saw the death).
  auto newActive = [&]() -> std::optional<std::size_t> {
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i)
      if (stateOf(g.block->slots[i]) == HostState::Active) return i;
    return std::nullopt;
  };
  auto standbyLeft = [&] {
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i)
      if (stateOf(g.block->slots[i]) == HostState::Standby) return true;
    return false;
  };
  std::optional<std::size_t> active = newActive();
  if (!active && g.takes_over)  // a standby is taking over by itself, unless it died too
    waitFor(*g.block, Clock::now() + kTakeoverWait, [&] { return (active = newActive()) || !standbyLeft(); });
  if (!active) {  // no standby: a new host, which restores the checkpoint too
    auto slot = launchHost(g, false, true);
    if (!slot) return slot.error();
    if (auto r = waitState(g, *slot, kRespawnWait); !r) return fail("respawn failed: " + r.error().message);
    active = *slot;
  }
  // Back once the new active's components ran a cycle (bounded: an aperiodic one may wait).
  const ipc::HostSlot& s = g.block->slots[*active];
  waitFor(*g.block, Clock::now() + kFirstRunWait, [&] { return s.first_run_ns.load(std::memory_order_acquire) != 0; });
  queueTopUp(g);
  return s.first_run_ns.load(std::memory_order_acquire);
}

void ProcessSupervisor::queueTopUp(Group& g) {
  spawner_.post([this, &g] { topUpStandbys(g); });
}

void ProcessSupervisor::emergency(Group& g) const {
  const std::uint32_t before = g.block->emergencies_done.load(std::memory_order_acquire);
  ipc::publishCommand(*g.block, ipc::Command::Emergency);
  waitFor(*g.block, Clock::now() + kEmergencyWait, [&] {
    return g.block->emergencies_done.load(std::memory_order_acquire) != before || activePid(*g.block) == 0;
  });
}

void ProcessSupervisor::clearEmergency() {
  for (auto& g : groups_)
    if (g->block->command.load(std::memory_order_acquire) == static_cast<std::uint32_t>(ipc::Command::Emergency))
      ipc::publishCommand(*g->block, ipc::Command::Run);
}

void ProcessSupervisor::stopGroup(Group& g, std::chrono::milliseconds within) {
  if (g.stopped.exchange(true)) return;
  ipc::publishCommand(*g.block, ipc::Command::Stop);
  auto alive = [&] {
    std::lock_guard lock(g.mutex);
    for (bool u : g.used)
      if (u) return true;
    return false;
  };
  waitFor(*g.block, Clock::now() + within, [&] { return !alive(); });
  {
    std::lock_guard lock(g.mutex);
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i)
      if (g.used[i] && g.pids[i] > 0) {
        warn_(fmt::format("process '{}': host {} did not stop within {} ms; killed", g.plan->name, g.pids[i],
                          within.count()));
        ::kill(g.pids[i], SIGKILL);
      }
  }
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
