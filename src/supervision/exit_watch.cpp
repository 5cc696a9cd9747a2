#include "supervision/exit_watch.hpp"

#include <fmt/format.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "runtime/clock.hpp"
#include "supervision/spawner.hpp"

namespace keel::supervision {
namespace {

// waitid's id type for a pidfd (Linux 5.4): <linux/wait.h>'s P_PIDFD, which glibc 2.36's idtype_t
// does not name.
constexpr int kIdPidfd = 3;

// pidfd_open(2) by its system call: glibc 2.36's <sys/pidfd.h> declares it without C linkage.
int pidfdOpen(pid_t pid) { return static_cast<int>(::syscall(SYS_pidfd_open, pid, 0U)); }

}  // namespace

std::string describe(const Exit& exit) {
  if (exit.status < 0) return "exited (its status is its parent's, not keel's)";
  return describeExit(exit.status);
}

ExitWatch::ExitWatch()
    : epoll_(::epoll_create1(EPOLL_CLOEXEC)), wake_(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)),
      thread_([this] { run(); }) {}

ExitWatch::~ExitWatch() {
  stop();
  for (const auto& [pidfd, w] : watched_) ::close(pidfd);
  if (wake_ >= 0) ::close(wake_);
  if (epoll_ >= 0) ::close(epoll_);
}

Result<void> ExitWatch::watch(pid_t pid, OnExit on_exit) {
  if (epoll_ < 0 || wake_ < 0) return fail("cannot watch processes: no epoll or eventfd");
  const int pidfd = pidfdOpen(pid);
  if (pidfd < 0) return fail(fmt::format("cannot watch process {}: {}", pid, std::generic_category().message(errno)));
  std::lock_guard lock(mutex_);
  if (stopped_) {
    ::close(pidfd);
    return fail(fmt::format("cannot watch process {}: the watch has stopped", pid));
  }
  watched_.emplace(pidfd, Watched{pid, std::move(on_exit)});
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.fd = pidfd;
  if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, pidfd, &ev) != 0) {
    const int err = errno;
    watched_.erase(pidfd);
    ::close(pidfd);
    return fail(fmt::format("cannot watch process {}: {}", pid, std::generic_category().message(err)));
  }
  return {};
}

void ExitWatch::stop() {
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
  }
  if (wake_ >= 0) {
    const std::uint64_t one = 1;
    (void)!::write(wake_, &one, sizeof one);
  }
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

void ExitWatch::run() {
  if (epoll_ < 0 || wake_ < 0) return;
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.fd = wake_;
  if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, wake_, &ev) != 0) return;
  std::array<epoll_event, 16> events{};
  for (;;) {
    const int n = ::epoll_wait(epoll_, events.data(), static_cast<int>(events.size()), -1);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return;
    for (int i = 0; i < n; ++i) {
      if (events[static_cast<std::size_t>(i)].data.fd == wake_) return;
      ended(events[static_cast<std::size_t>(i)].data.fd);
    }
  }
}

void ExitWatch::ended(int pidfd) {
  const std::int64_t at = runtime::steadyNs();
  Watched w;
  {
    std::lock_guard lock(mutex_);
    auto it = watched_.find(pidfd);
    if (it == watched_.end()) return;
    w = std::move(it->second);
    watched_.erase(it);
    ::epoll_ctl(epoll_, EPOLL_CTL_DEL, pidfd, nullptr);
  }
  Exit exit{-1, at};
  siginfo_t info{};
  if (::waitid(static_cast<idtype_t>(kIdPidfd), static_cast<id_t>(pidfd), &info, WEXITED) == 0) {
    switch (info.si_code) {
      case CLD_EXITED: exit.status = W_EXITCODE(info.si_status, 0); break;
      case CLD_KILLED: exit.status = info.si_status; break;
      case CLD_DUMPED: exit.status = info.si_status | WCOREFLAG; break;
      default: break;
    }
  }  // ECHILD: not keel run's child, whose status is its parent's
  ::close(pidfd);
  w.on_exit(w.pid, exit);
}

}  // namespace keel::supervision
