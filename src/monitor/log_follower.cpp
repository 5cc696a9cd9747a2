#include "monitor/log_follower.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <system_error>
#include <thread>
#include <utility>

namespace keel::monitor {

Result<LogFollower> LogFollower::open(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return Error{"monitor: cannot read the log '" + path + "': " + std::generic_category().message(errno)};
  int in = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (in >= 0 && ::inotify_add_watch(in, path.c_str(), IN_MODIFY) < 0) {
    ::close(in);
    in = -1;
  }
  return LogFollower(fd, in);
}

LogFollower::LogFollower(LogFollower&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), inotify_fd_(std::exchange(other.inotify_fd_, -1)), offset_(other.offset_),
      pending_(std::move(other.pending_)), gap_since_(other.gap_since_), in_gap_(other.in_gap_) {}

LogFollower::~LogFollower() {
  if (fd_ >= 0) ::close(fd_);
  if (inotify_fd_ >= 0) ::close(inotify_fd_);
}

void LogFollower::read(std::vector<std::string>& lines) {
  char buf[64 * 1024];
  for (;;) {
    const ssize_t n = ::pread(fd_, buf, sizeof buf, static_cast<off_t>(offset_ + pending_.size()));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    pending_.append(buf, static_cast<std::size_t>(n));
  }
  std::size_t at = 0;
  std::size_t hole = pending_.find('\0');
  while (at < pending_.size()) {
    const auto nl = pending_.find('\n', at);
    if (hole != std::string::npos && (nl == std::string::npos || hole < nl)) {
      // A gap: another process reserved these bytes and has not written them yet. The line
      // it cuts waits, whole, until it is filled or given up for.
      const auto now = std::chrono::steady_clock::now();
      if (!in_gap_) {
        in_gap_ = true;
        gap_since_ = now;
      }
      if (now - gap_since_ < kGapPatience) break;
      const auto end = pending_.find_first_not_of('\0', hole);
      if (end == std::string::npos) break;  // nothing written after it yet
      at = end;
      hole = pending_.find('\0', at);
      in_gap_ = false;
      continue;
    }
    in_gap_ = false;
    if (nl == std::string::npos) break;
    lines.emplace_back(pending_, at, nl - at);
    at = nl + 1;
  }
  offset_ += at;
  pending_.erase(0, at);
  // Bytes of a gap were read as NULs: read again from there, once they may have been written.
  if (const auto gap = pending_.find('\0'); gap != std::string::npos) pending_.resize(gap);
}

void LogFollower::wait(std::chrono::milliseconds timeout) {
  if (inotify_fd_ < 0) {
    std::this_thread::sleep_for(std::min(timeout, std::chrono::milliseconds(2)));
    return;
  }
  pollfd pfd{inotify_fd_, POLLIN, 0};
  if (::poll(&pfd, 1, static_cast<int>(timeout.count())) > 0) {
    char events[4096];
    while (::read(inotify_fd_, events, sizeof events) > 0) {}
  }
}

}  // namespace keel::monitor
