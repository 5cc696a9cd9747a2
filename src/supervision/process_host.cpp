#include "supervision/process_host.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <mutex>

#include "runtime/clock.hpp"
#include "runtime/futex.hpp"
#include "supervision/crossing.hpp"

namespace keel::supervision {
namespace {

namespace ipc = runtime::ipc;

std::uint64_t fnv1a(std::string_view text, std::uint64_t h = 0xcbf29ce484222325ULL) {
  for (char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

}  // namespace

ipc::SessionShape sessionShape(const plan::Plan& plan) {
  ipc::SessionShape s;
  s.processes = plan.processes.size();
  std::uint64_t h = fnv1a(plan.name);
  for (const auto& p : plan.processes) h = fnv1a(p.name + '\n', h);
  for (const auto& i : plan.instances) {
    h = fnv1a(i.name + '@' + i.process + '\n', h);
    s.checkpoints += !i.process.empty();
  }
  const auto crossing = crossingConnections(plan);
  s.rings = crossing.size();
  for (std::size_t k : crossing) {
    const auto& c = plan.connections[k];
    h = fnv1a(fmt::format("{}.{}>{}.{}\n", c.source.component, c.source.port, c.target.component, c.target.port), h);
  }
  s.plan_hash = h;
  return s;
}

std::int64_t processHeartbeatNs(const plan::Plan& plan, std::string_view process) {
  std::int64_t shortest = 0;
  for (const auto& i : plan.instances) {
    if (i.process != process || !i.policy || !i.policy->heartbeat_timeout_ms) continue;
    const auto ns = static_cast<std::int64_t>(*i.policy->heartbeat_timeout_ms * 1e6);
    if (shortest == 0 || ns < shortest) shortest = ns;
  }
  return shortest;
}

std::optional<std::size_t> checkpointIndex(const plan::Plan& plan, std::string_view instance) {
  std::size_t n = 0;
  for (const auto& i : plan.instances) {
    if (i.process.empty()) continue;
    if (i.name == instance) return n;
    ++n;
  }
  return std::nullopt;
}

ProcessHost::ProcessHost(ipc::Session session, HostRole role, std::size_t index)
    : session_(std::move(session)), role_(std::move(role)), index_(index) {}

Result<std::unique_ptr<ProcessHost>> ProcessHost::open(const plan::Plan& plan, HostRole role) {
  std::size_t index = plan.processes.size();
  for (std::size_t i = 0; i < plan.processes.size(); ++i)
    if (plan.processes[i].name == role.process) index = i;
  const int fd = role.session_fd;
  if (index == plan.processes.size()) {
    ::close(fd);
    return fail(fmt::format("the profile has no <process name=\"{}\">", role.process));
  }
  if (role.slot >= ipc::kHostSlots) {
    ::close(fd);
    return fail(fmt::format("host slot {} is out of range", role.slot));
  }
  auto session = ipc::Session::adopt(fd, sessionShape(plan));
  if (!session) return session.error();
  return std::unique_ptr<ProcessHost>(new ProcessHost(std::move(*session), std::move(role), index));
}

ProcessHost::~ProcessHost() {
  // The watchers sleep for the life of the process; the process ends with _exit (leave()).
  if (supervisor_watcher_.joinable()) supervisor_watcher_.detach();
  if (beat_.joinable()) beat_.detach();
  if (signal_watcher_.joinable()) signal_watcher_.detach();
}

Result<void> ProcessHost::enter(std::function<void()> supervisor_lost) {
  // Orphan backstop: SIGUSR2 when the thread that started this process ends. That thread lives
  // as long as keel run's supervisor, so the signal means keel run is dying (it comes as its
  // threads die, while getppid() may still name it). If keel run died before this line,
  // getppid() says so now.
  ::prctl(PR_SET_PDEATHSIG, SIGUSR2);
  if (role_.parent != 0 && ::getppid() != role_.parent) return fail("keel run ended before this host started");
  // A core dump of a host would delay every death notice by its writing (decision 0011).
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGTERM);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGUSR2);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);  // for every thread from here: the signal watcher takes them

  auto life = slot().life.lock();
  if (!life) return fail("life lock: " + life.error().message);
  has_life_ = true;
  slot().pid.store(::getpid(), std::memory_order_release);
  ipc::publishState(block(), slot(), ipc::HostState::Loading);

  supervisor_lost_ = std::move(supervisor_lost);
  supervisor_watcher_ = std::thread([this] {
    auto locked = session_.supervisor().lock();  // held by keel run's main thread while it lives
    (void)locked;  // whatever it says, keel run is gone (or broke its lock): stop the actuators
    supervisorLost();
  });
  signal_watcher_ = std::thread([this, stop] {
    for (;;) {
      int sig = 0;
      if (sigwait(&stop, &sig) != 0) continue;
      if (sig == SIGUSR2 || (role_.parent != 0 && ::getppid() != role_.parent)) supervisorLost();
      if (!active_.load(std::memory_order_acquire)) exitLeavingLogWhole(0);  // a standby has nothing running
      signalled_.store(true, std::memory_order_release);
      block().command.fetch_add(0, std::memory_order_acq_rel);
      runtime::futexWakeAll(block().command, runtime::FutexScope::Shared);
    }
  });
  return {};
}

void ProcessHost::setLog(log::FaultLog* log) {
  std::lock_guard lock(log_mutex_);
  log_ = log;
}

void ProcessHost::supervisorLost() {
  // Both watchers may get here (the robust wake and PDEATHSIG): the first runs the emergency
  // stop, the other waits for it; then the process ends.
  block().supervisor_lost.store(1, std::memory_order_release);  // before the role can pass on
  std::call_once(lost_once_, [this] {
    {
      // Any host, standby or loading too: a line of its own may follow keel run's in the file.
      std::lock_guard lock(log_mutex_);
      if (log_) log_->repair(ipc::logParticipant(std::nullopt, 0));
    }
    if (active_.load(std::memory_order_acquire) && supervisor_lost_) supervisor_lost_();
  });
  exitLeavingLogWhole(kExitSupervisorLost);
}

void ProcessHost::exitLeavingLogWhole(int status) {
  // Another of this process's threads may be between its line's place and its pwrite: the
  // exit would cut it off there, leaving NUL bytes before what the other hosts write next.
  log_mutex_.lock();  // held until the process ends: the log outlives the wait
  if (log_) log_->quiesce(std::chrono::seconds(1));
  ::_exit(status);
}

void ProcessHost::failed(const std::string& message) {
  ipc::setMessage(slot(), message);
  ipc::publishState(block(), slot(), ipc::HostState::Failed);
}

Result<bool> ProcessHost::takeRole() {
  if (role_.standby) ipc::publishState(block(), slot(), ipc::HostState::Standby);
  auto locked = block().role.lock();  // a standby sleeps here until the active dies or leaves
  if (locked && *locked == ipc::LockStatus::OwnerDied) slot().woke_ns.store(runtime::steadyNs());
  if (!locked) return fail("role lock: " + locked.error().message);
  role_tid_.store(::gettid(), std::memory_order_release);
  return *locked == ipc::LockStatus::OwnerDied;
}

bool ProcessHost::holdsRole() const { return role_tid_.load(std::memory_order_acquire) == ::gettid(); }

void ProcessHost::releaseRole() {
  if (!holdsRole()) return;
  role_tid_.store(0, std::memory_order_release);
  (void)block().role.unlock();  // the next standby wakes (and sees a stop, if it is one)
}

bool ProcessHost::stopRequested() {
  return signalled_.load(std::memory_order_acquire) ||
         session_.process(index_).command.load(std::memory_order_acquire) ==
             static_cast<std::uint32_t>(ipc::Command::Stop);
}

void ProcessHost::becameActive() {
  const std::int64_t now = runtime::steadyNs();
  slot().beat_ns.store(now, std::memory_order_release);
  slot().active_ns.store(now, std::memory_order_release);
  active_.store(true, std::memory_order_release);
  ipc::publishState(block(), slot(), ipc::HostState::Active);
  if (beat_period_ns_ > 0 && !beat_.joinable()) {
    // A thread of its own: it stops only when the whole process does (SIGSTOP, a freeze);
    // a hung component callback is the host's own watchdog's business.
    beat_ = std::thread([this] {
      for (;;) {
        std::this_thread::sleep_for(std::chrono::nanoseconds(beat_period_ns_));
        slot().beat_ns.store(runtime::steadyNs(), std::memory_order_release);
      }
    });
  }
}

void ProcessHost::ranOnce(std::int64_t t_ns) {
  std::int64_t none = 0;
  if (!slot().first_run_ns.compare_exchange_strong(none, t_ns, std::memory_order_acq_rel)) return;
  block().changes.fetch_add(1, std::memory_order_acq_rel);
  runtime::futexWakeAll(block().changes, runtime::FutexScope::Shared);
}

void ProcessHost::serve(const std::function<void()>& emergency, const std::function<void()>& clear) {
  auto command = [this] { return static_cast<ipc::Command>(block().command.load(std::memory_order_acquire)); };
  ipc::Command last = ipc::Command::Run;
  for (;;) {
    if (signalled_.load(std::memory_order_acquire)) return;
    const std::uint32_t word = block().command.load(std::memory_order_acquire);
    const ipc::Command now = command();
    if (now == ipc::Command::Stop) return;
    if (now != last) {
      if (now == ipc::Command::Emergency) {
        emergency();
        block().emergencies_done.fetch_add(1, std::memory_order_acq_rel);
        block().changes.fetch_add(1, std::memory_order_acq_rel);
        runtime::futexWakeAll(block().changes, runtime::FutexScope::Shared);
      } else if (last == ipc::Command::Emergency) {
        clear();
      }
      last = now;
      continue;
    }
    runtime::futexWait(block().command, word, nullptr, runtime::FutexScope::Shared);
  }
}

void HostFaultSink::recovered(Component& c, std::int64_t t_ns) {
  std::uint64_t first = kFirstRun;
  if (runtime::coreOf(c).fault.recovering_id.compare_exchange_strong(first, 0, std::memory_order_acq_rel)) {
    host_.ranOnce(t_ns);
    return;
  }
  manager_.recovered(c, t_ns);
}

void ProcessHost::leave() {
  active_.store(false, std::memory_order_release);
  releaseRole();  // if the main thread holds it: the next standby wakes, sees the stop and leaves
  ipc::publishState(block(), slot(), ipc::HostState::Exited);
  if (has_life_) (void)slot().life.unlock();
  has_life_ = false;
}

}  // namespace keel::supervision
