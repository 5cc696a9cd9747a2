// Child processes of the harness — the peers (peers.cpp), the background load (load.cpp), the
// plot script (main.cpp): a descriptor that closes itself, a close-on-exec pipe, a line reader
// bounded by a deadline, a spawned process that is reaped on every path (a pidfd makes its end
// pollable), run-and-capture for a whole command, a poll of another process's progress, a
// program looked up in $PATH, and a temporary directory removed with everything in it.
// Not thread-safe: each object belongs to the one thread that uses it.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "keel/result.hpp"

namespace keel::bench {

using Deadline = std::chrono::steady_clock::time_point;

inline constexpr int kFifoPriority = 50;  // the SCHED_FIFO priority of every `fifo` run

/// Owns a file descriptor; -1 when empty.
class Fd {
 public:
  Fd() = default;
  explicit Fd(int fd) : fd_(fd) {}
  Fd(Fd&& other) noexcept : fd_(other.release()) {}
  Fd& operator=(Fd&& other) noexcept;
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() { reset(); }

  int get() const { return fd_; }
  int release();
  void reset(int fd = -1);

 private:
  int fd_ = -1;
};

/// Both ends close on exec: a spawned process gets one only through its stdio.
struct Pipe {
  Fd read, write;
  /// (Re)opens the pipe, closing any previous ends; false with errno set.
  bool open();
};

/// Lines read from a descriptor, each without its '\n'.
class LineReader {
 public:
  explicit LineReader(int fd) : fd_(fd) {}
  /// The next line; nullopt at the deadline, at end of file (a last unterminated line is
  /// returned first) or on a read error.
  std::optional<std::string> next(Deadline deadline);
  bool atEnd() const { return end_; }

 private:
  int fd_;
  std::string buf_;
  bool end_ = false;
};

/// The descriptors a spawned process gets as its stdin, stdout, stderr; -1: /dev/null for
/// stdin, the harness's own for stdout and stderr.
struct Stdio {
  int in = -1, out = -1, err = -1;
};

/// A variable of a spawned process's environment that differs from the harness's own: set to
/// `value`, or removed when it has none. The harness's environment itself is not changed.
struct EnvChange {
  std::string name;
  std::optional<std::string> value;
};

/// A spawned child process. Destroying it kills (SIGKILL) and reaps it if it is still there.
class Process {
 public:
  /// posix_spawn of argv[0] (a path): empty signal mask, default dispositions; `fifo`: under
  /// SCHED_FIFO kFifoPriority; `ownGroup`: in a process group of its own, killed as a whole;
  /// the harness's environment with `env`'s changes.
  static Result<Process> spawn(const std::vector<std::string>& argv, Stdio io, bool fifo, bool ownGroup,
                               const std::vector<EnvChange>& env = {});

  Process(Process&& other) noexcept;
  Process& operator=(Process&&) = delete;
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;
  ~Process();

  /// Its wait status once it has ended (it is reaped); past the deadline it is killed, reaped
  /// and this returns nullopt.
  std::optional<int> waitUntil(Deadline deadline);
  /// Sends `sig` to it (to its whole group when it has one of its own), while it is there.
  void signal(int sig) const;
  pid_t pid() const { return pid_; }

 private:
  Process(pid_t pid, Fd pidfd, bool group) : pid_(pid), pidfd_(std::move(pidfd)), group_(group) {}
  void killAndReap();

  pid_t pid_ = -1;  // -1 once reaped
  Fd pidfd_;
  bool group_ = false;
};

/// Polls `done` every `every` until it is true (then true) or `bound` passed (false). For
/// another process's progress: what it measures it times itself; the poll only decides when
/// the harness looks (and what the harness's looking costs the CPU the measured share).
template <class F>
bool pollUntil(F done, std::chrono::steady_clock::duration bound,
               std::chrono::steady_clock::duration every = std::chrono::microseconds(200)) {
  const auto until = std::chrono::steady_clock::now() + bound;
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(every);
  }
  return true;
}

/// Puts the calling thread under SCHED_FIFO kFifoPriority: empty, or why not.
std::string becomeFifo();

/// `name` found in $PATH (an executable file), or empty.
std::string findInPath(const std::string& name);

/// What a command printed (stdout and stderr, merged) and how it ended.
struct Captured {
  int status = -1;                 // exit code, or 128 + the signal that ended it
  std::vector<std::string> lines;  // its output
  std::string error;               // non-empty: it could not run, or passed the deadline
};

/// Runs argv to its end (killed, with its process group, at the deadline).
Captured runCaptured(const std::vector<std::string>& argv, bool fifo, Deadline deadline);

/// A directory of its own under the temporary directory (mkdtemp, named `prefix`XXXXXX),
/// removed with everything in it when this goes; path() is empty when it could not be made
/// (errno says why).
class TempDir {
 public:
  explicit TempDir(const std::string& prefix);
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace keel::bench
