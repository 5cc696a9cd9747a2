// Follows a fault log as it grows (monitor/hub.hpp reads the run's records from it): every
// process of a run — keel run and its component processes — writes its records to that one
// file, so following it sees them all, and costs the fault path nothing. Woken by inotify on
// each write; without inotify it looks every few milliseconds.
// Thread-safety: one owner thread.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "keel/result.hpp"

namespace keel::monitor {

class LogFollower {
 public:
  /// Follows `path` from its start.
  static Result<LogFollower> open(const std::string& path);
  LogFollower(LogFollower&& other) noexcept;
  LogFollower& operator=(LogFollower&&) = delete;
  LogFollower(const LogFollower&) = delete;
  LogFollower& operator=(const LogFollower&) = delete;
  ~LogFollower();

  /// Appends to `lines` every whole line written since the last call (without its newline).
  /// A line not yet whole — a record being written, or a gap another process reserved and has
  /// not filled yet — waits for the next call; a gap no one filled for `kGapPatience` is
  /// skipped (its writer died; keel run writes the line again elsewhere).
  void read(std::vector<std::string>& lines);
  /// Blocks until the file may have grown, or `timeout`.
  void wait(std::chrono::milliseconds timeout);
  /// Bytes of the file read and handed out so far.
  std::uint64_t offset() const { return offset_; }

  static constexpr std::chrono::milliseconds kGapPatience{2000};

 private:
  LogFollower(int fd, int inotify_fd) : fd_(fd), inotify_fd_(inotify_fd) {}
  int fd_ = -1;
  int inotify_fd_ = -1;  // -1: no inotify, wait() sleeps a little
  std::uint64_t offset_ = 0;
  std::string pending_;  // read past offset_, not yet a whole line
  std::chrono::steady_clock::time_point gap_since_{};
  bool in_gap_ = false;
};

}  // namespace keel::monitor
