// Test support for the inter-process primitives (runtime/ipc/): real child processes made by
// fork(), killed and reaped when a test ends however it ends; a control block in shared memory
// through which they report; self-checking samples. A child never returns into GoogleTest: it
// reports through the control block and its exit status, and leaves with _exit.
#pragma once

#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <new>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

#include "runtime/ipc/ring.hpp"
#include "runtime/ipc/shared_memory.hpp"

namespace keel::runtime::ipc::test {

/// A forked child running `body` (returns its exit status). Killed with SIGKILL and reaped
/// when destroyed, unless waited for.
class Child {
 public:
  template <class Body>
  static Child run(Body&& body) {
    std::fflush(nullptr);  // nothing buffered is written twice
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
      int status = 99;
      try {
        status = body();
      } catch (...) {}
      ::_exit(status);
    }
    return Child(pid);
  }

  Child(Child&& other) noexcept : pid_(std::exchange(other.pid_, -1)) {}
  Child& operator=(Child&&) = delete;
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  ~Child() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      wait();
    }
  }

  pid_t pid() const { return pid_; }
  void kill(int signal = SIGKILL) const { ::kill(pid_, signal); }
  /// Reaps it; its raw wait status.
  int wait() {
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {}
    pid_ = -1;
    return status;
  }
  /// The state letter of /proc/<pid>/stat: 'S' while it sleeps (on a futex, in these tests).
  char state() const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/stat");
    std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto paren = all.rfind(')');
    return paren == std::string::npos || paren + 2 >= all.size() ? '?' : all[paren + 2];
  }

 private:
  explicit Child(pid_t pid) : pid_(pid) {}
  pid_t pid_;
};

inline bool exitedWith(int status, int code) { return WIFEXITED(status) && WEXITSTATUS(status) == code; }
inline bool killedBy(int status, int signal) { return WIFSIGNALED(status) && WTERMSIG(status) == signal; }

/// Runs the calling thread on the `nth` CPU it may use (0, 1, ...) until destroyed, when there
/// is one: a writer and a reader pinned apart really race, even on a busy machine.
class PinnedToCpu {
 public:
  explicit PinnedToCpu(int nth) {
    if (::sched_getaffinity(0, sizeof before_, &before_) != 0) return;
    for (int cpu = 0, seen = 0; cpu < CPU_SETSIZE; ++cpu) {
      if (!CPU_ISSET(cpu, &before_) || seen++ != nth) continue;
      cpu_set_t one;
      CPU_ZERO(&one);
      CPU_SET(cpu, &one);
      pinned_ = ::sched_setaffinity(0, sizeof one, &one) == 0;
      return;
    }
  }
  ~PinnedToCpu() {
    if (pinned_) ::sched_setaffinity(0, sizeof before_, &before_);
  }
  PinnedToCpu(const PinnedToCpu&) = delete;
  PinnedToCpu& operator=(const PinnedToCpu&) = delete;

 private:
  cpu_set_t before_{};
  bool pinned_ = false;
};

/// The value of `r`, or an exception (which fails the test, or exits a child with 99).
template <class T>
T must(Result<T> r) {
  if (!r) throw std::runtime_error(r.error().message);
  return std::move(r.value());
}

/// A T (of atomics, for children to report through) in a shared region of its own.
template <class T>
class SharedBlock {
 public:
  SharedBlock()
      : memory_(must(SharedMemory::create("ipc test control", sizeof(T)))), value_(new (memory_.data()) T()) {}
  T* operator->() const { return value_; }
  T& operator*() const { return *value_; }
  const SharedMemory& memory() const { return memory_; }

 private:
  SharedMemory memory_;
  T* value_;
};

/// Polls `pred` until true or `timeout` (generous: for behaviour, not for timing).
template <class Pred>
bool eventually(Pred pred, std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
  return pred();
}

/// This process's own mapping of `ring`'s region (a dup of its fd adopted, as a process that
/// inherited the fd would), attached as a Ring<T>.
template <class T, class U>
Ring<T> attachOwnMapping(const Ring<U>& ring) {
  return must(Ring<T>::attach(must(SharedMemory::adopt(::dup(ring.buffer().memory().fd()), "attached"))));
}

/// A sample that checks itself: N copies of a value and a checksum of it. A sample torn
/// between two writes has copies of two values, or a sum that does not match.
template <std::size_t N>
struct Stamped {
  std::uint64_t copies[N];
  std::uint64_t sum;

  static std::uint64_t mix(std::uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    return x ^ (x >> 33);
  }
  static Stamped of(std::uint64_t value) {
    Stamped s{};
    for (auto& c : s.copies) c = value;
    s.sum = mix(value);
    return s;
  }
  std::uint64_t value() const { return copies[0]; }
  bool whole() const {
    for (auto c : copies)
      if (c != copies[0]) return false;
    return sum == mix(copies[0]);
  }
};

}  // namespace keel::runtime::ipc::test
