// Test support: a pipe that a process the test starts writes to (keel run --log-tee), by the
// /proc path of the test's write end (opening it gives the same pipe), read all along by a
// thread of the test: a second channel, to hold what the process wrote against its files.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace keel::test {

/// The lines of `text` that end with '\n' (a last one without is not a line yet).
inline std::vector<std::string> linesOf(const std::string& text) {
  std::vector<std::string> out;
  for (std::size_t at = 0, nl; (nl = text.find('\n', at)) != std::string::npos; at = nl + 1)
    out.push_back(text.substr(at, nl - at));
  return out;
}

class PipeReader {
 public:
  PipeReader() {
    int fds[2] = {-1, -1};
    if (::pipe2(fds, O_CLOEXEC) != 0) return;
    read_end_ = fds[0];
    write_end_ = fds[1];
    thread_ = std::thread([this] { readUntilEnd(); });
  }
  ~PipeReader() { (void)finish(std::chrono::milliseconds(0)); }
  PipeReader(const PipeReader&) = delete;
  PipeReader& operator=(const PipeReader&) = delete;

  bool ok() const { return read_end_ >= 0; }
  /// The write end, as another process opens it.
  std::string path() const { return "/proc/" + std::to_string(::getpid()) + "/fd/" + std::to_string(write_end_); }

  /// Whether `needle` came through the pipe, waiting up to `within` for it.
  bool waitFor(const std::string& needle, std::chrono::milliseconds within) {
    std::unique_lock lock(mutex_);
    return cv_.wait_for(lock, within, [&] { return text_.find(needle) != std::string::npos || ended_; }) &&
           text_.find(needle) != std::string::npos;
  }

  /// Closes the test's write end and waits up to `within` for the end of the pipe: every
  /// process that opened it has closed it (they are gone). Whether it ended; text() then has
  /// everything that came through.
  bool finish(std::chrono::milliseconds within) {
    if (write_end_ >= 0) ::close(std::exchange(write_end_, -1));
    bool ended = false;
    {
      std::unique_lock lock(mutex_);
      ended = cv_.wait_for(lock, within, [this] { return ended_; });
    }
    quit_.store(true);
    if (thread_.joinable()) thread_.join();
    if (read_end_ >= 0) ::close(std::exchange(read_end_, -1));
    return ended;
  }

  std::string text() const {
    std::lock_guard lock(mutex_);
    return text_;
  }

 private:
  void readUntilEnd() {
    char buf[65536];
    while (!quit_.load()) {
      pollfd pfd{read_end_, POLLIN, 0};
      if (::poll(&pfd, 1, 20) <= 0) continue;
      const ssize_t n = ::read(read_end_, buf, sizeof buf);
      std::lock_guard lock(mutex_);
      if (n > 0) text_.append(buf, static_cast<std::size_t>(n));
      if (n == 0) ended_ = true;  // no writer left
      cv_.notify_all();
      if (n == 0) return;
    }
  }

  int read_end_ = -1;
  int write_end_ = -1;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::string text_;
  bool ended_ = false;
  std::atomic<bool> quit_{false};
  std::thread thread_;
};

}  // namespace keel::test
