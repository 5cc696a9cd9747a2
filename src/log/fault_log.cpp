#include "log/fault_log.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <system_error>
#include <thread>

namespace keel::log {

FaultLog::FaultLog() : epoch_ns_(runtime::steadyNs()) {}

FaultLog::~FaultLog() {
  if (fd_ >= 0) ::close(fd_);
  if (tee_fd_ >= 0) ::close(tee_fd_);
}

Result<void> FaultLog::open(const std::string& path, bool append) {
  int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | (append ? 0 : O_TRUNC) | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return fail(fmt::format("cannot open log '{}': {}", path, std::generic_category().message(errno)));
  fd_ = fd;
  return {};
}

Result<void> FaultLog::join(const std::string& path, std::int64_t epoch_ns) {
  int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);  // at reserved offsets (share): not O_APPEND
  if (fd < 0) return fail(fmt::format("cannot open log '{}': {}", path, std::generic_category().message(errno)));
  fd_ = fd;
  epoch_ns_ = epoch_ns;
  return {};
}

void FaultLog::tag(std::string key, nlohmann::json value) { tags_[std::move(key)] = std::move(value); }

void FaultLog::share(runtime::ipc::LogArena& arena, std::size_t participant, std::size_t participants) {
  std::lock_guard lock(mutex_);
  if (fd_ >= 0 && participant == 0) {
    // pwrite ignores the offset on an O_APPEND descriptor: write at offsets from here on.
    ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_APPEND);
    arena.tail.store(static_cast<std::uint64_t>(::lseek(fd_, 0, SEEK_END)), std::memory_order_release);
  }
  arena_ = &arena;
  participant_ = participant;
  participants_ = participants;
}

Result<void> FaultLog::openTee(const std::string& path) {
  // Non-blocking open: a FIFO's open would otherwise wait for its reader. O_APPEND and O_CREAT
  // are for a file; a pipe ignores the first, and the second creates nothing that exists.
  const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int err = errno;
    return fail(fmt::format("cannot open the log's tee '{}': {}", path,
                            err == ENXIO ? "no process reads that FIFO (start its reader first)"
                                         : std::generic_category().message(err)));
  }
  struct stat st {};
  struct stat log {};
  const bool known = ::fstat(fd, &st) == 0;
  if (known && fd_ >= 0 && ::fstat(fd_, &log) == 0 && st.st_dev == log.st_dev && st.st_ino == log.st_ino) {
    ::close(fd);  // appended to as it is written at offsets: both copies would be torn
    return fail(fmt::format("cannot open the log's tee '{}': it is the log itself", path));
  }
  const bool pipe = known && S_ISFIFO(st.st_mode);
  if (!pipe) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);  // a file, a terminal: whole lines
  std::lock_guard lock(mutex_);
  if (tee_fd_ >= 0) ::close(tee_fd_);
  tee_fd_ = fd;
  tee_is_pipe_ = pipe;
  return {};
}

std::uint64_t FaultLog::teeDropped() const {
  std::lock_guard lock(mutex_);
  return tee_dropped_;
}

std::uint64_t FaultLog::teeLines() const {
  std::lock_guard lock(mutex_);
  return tee_lines_;
}

namespace {
bool writeAll(int fd, const std::string& line) {
  const char* p = line.data();
  std::size_t left = line.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;  // disk full or closed: the run goes on, the log stops
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return true;
}

bool pwriteAll(int fd, const char* p, std::size_t n, std::uint64_t offset) {
  while (n > 0) {
    const ssize_t w = ::pwrite(fd, p, n, static_cast<off_t>(offset));
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;  // disk full or closed: the run goes on, the log stops
    p += w;
    n -= static_cast<std::size_t>(w);
    offset += static_cast<std::uint64_t>(w);
  }
  return true;
}
}  // namespace

void FaultLog::writeTee(const std::string& line) {
  if (tee_fd_ < 0) return;
  ++tee_lines_;
  if (!tee_is_pipe_) {
    if (!writeAll(tee_fd_, line)) ++tee_dropped_;
    return;
  }
  // Whole or not at all: a write of at most PIPE_BUF bytes is atomic, and a non-blocking one
  // fails (EAGAIN) rather than wait for a reader that is behind. The fault path never waits.
  if (tee_reader_gone_ || line.size() > PIPE_BUF) {
    ++tee_dropped_;
    return;
  }
  // A reader that closed its end raises SIGPIPE, whose default action kills: held off on this
  // thread for the write, and taken back if the write raised it.
  sigset_t pipe_signal;
  sigset_t old;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_signal, &old);
  ssize_t n = 0;
  do {
    n = ::write(tee_fd_, line.data(), line.size());
  } while (n < 0 && errno == EINTR);
  if (n < 0 && errno == EPIPE) {
    tee_reader_gone_ = true;
    const timespec zero{0, 0};
    (void)sigtimedwait(&pipe_signal, nullptr, &zero);
  }
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  if (n != static_cast<ssize_t>(line.size())) ++tee_dropped_;
}

bool FaultLog::writeShared(const std::string& line) {
  runtime::ipc::LogStage& stage = runtime::ipc::logStage(*arena_, participant_);
  const bool staged = line.size() <= runtime::ipc::kLogStageBytes;
  if (staged) {
    std::memcpy(stage.line, line.data(), line.size());
    stage.length.store(static_cast<std::uint32_t>(line.size()), std::memory_order_release);
  }
  auto locked = arena_->lock.lock();
  if (!locked) return false;
  if (*locked == runtime::ipc::LockStatus::OwnerDied) {
    // Its holder died reserving: the stage that names the tail was reserved, the tail not moved
    // yet. Move it past that line (the survivor that repairs the dead writer writes it there).
    const std::uint64_t tail = arena_->tail.load(std::memory_order_acquire);
    for (std::size_t i = 0; i < participants_; ++i) {
      const runtime::ipc::LogStage& s = runtime::ipc::logStage(*arena_, i);
      if (s.offset.load(std::memory_order_acquire) == tail)
        arena_->tail.store(tail + s.length.load(std::memory_order_acquire), std::memory_order_release);
    }
  }
  const std::uint64_t at = arena_->tail.load(std::memory_order_acquire);
  if (staged) stage.offset.store(at, std::memory_order_release);  // before the tail moves
  arena_->tail.store(at + line.size(), std::memory_order_release);
  (void)arena_->lock.unlock();
  const bool written = pwriteAll(fd_, line.data(), line.size(), at);
  if (staged) stage.offset.store(runtime::ipc::kNoOffset, std::memory_order_release);
  return written;
}

void FaultLog::repair(std::size_t participant) {
  if (!arena_ || fd_ < 0 || participant >= participants_) return;
  runtime::ipc::LogStage& stage = runtime::ipc::logStage(*arena_, participant);
  const std::uint64_t at = stage.offset.load(std::memory_order_acquire);
  if (at == runtime::ipc::kNoOffset) return;
  const std::size_t n = std::min<std::size_t>(stage.length.load(std::memory_order_acquire),
                                              runtime::ipc::kLogStageBytes);
  (void)pwriteAll(fd_, stage.line, n, at);
  stage.offset.store(runtime::ipc::kNoOffset, std::memory_order_release);
}

void FaultLog::quiesce(std::chrono::milliseconds within) {
  const auto until = std::chrono::steady_clock::now() + within;
  while (!mutex_.try_lock()) {                              // never unlocked: the process ends with it held
    if (std::chrono::steady_clock::now() >= until) return;  // a writer stuck on another's lock: leave anyway
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
}

std::int64_t FaultLog::now() const { return runtime::steadyNs() - epoch_ns_; }

void FaultLog::write(nlohmann::json record) {
  if (fd_ < 0) return;
  if (!record.contains("t_ns")) record["t_ns"] = now();
  for (const auto& [key, value] : tags_.items())
    if (!record.contains(key)) record[key] = value;
  std::string line = record.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  line += '\n';
  std::lock_guard lock(mutex_);
  const bool written = arena_ ? writeShared(line) : writeAll(fd_, line);
  if (written) writeTee(line);  // after the log: what the tee shows, the log has
}

}  // namespace keel::log
