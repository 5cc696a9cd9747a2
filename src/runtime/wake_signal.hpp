// WakeSignal: lets one thread sleep until another wakes it or an absolute deadline passes
// (CLOCK_MONOTONIC, the clock of std::chrono::steady_clock). A futex word: notify() costs one
// atomic exchange when the sleeper is awake, one futex wake syscall when it sleeps. The sleeper
// may sleep on other futex words in the same sleep (sleepAlso).
// Thread-safety: any number of notifiers, one waiter.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <span>

#include "runtime/futex.hpp"

namespace keel::runtime {

class WakeSignal {
 public:
  using Clock = std::chrono::steady_clock;

  void notify() {
    if (pending_.exchange(1, std::memory_order_seq_cst) == 0 && sleeping_.load(std::memory_order_seq_cst) != 0) {
      futexWake(pending_, 1, FutexScope::Process);
    }
  }

  /// Sleeps until notified or `deadline`. Returns true when notified (and consumes it).
  bool waitUntil(Clock::time_point deadline) { return wait(&deadline); }
  /// Sleeps until notified.
  void wait() { wait(nullptr); }
  /// Sleeps until notified (not consumed), `deadline` (null: for ever) or until a sleeper on any
  /// of `also[1..]` is woken: futexWaitAny over this signal's word, which goes in `also[0]`.
  /// Spurious returns are possible.
  void sleepAlso(std::span<FutexWaiter> also, const Clock::time_point* deadline) {
    sleeping_.store(1, std::memory_order_seq_cst);
    if (pending_.load(std::memory_order_seq_cst) == 0) {
      also[0] = FutexWaiter{&pending_, 0, FutexScope::Process};
      futexWaitAny(also, deadline);
    }
    sleeping_.store(0, std::memory_order_relaxed);
  }
  /// Consumes a pending notification without sleeping.
  bool consume() { return pending_.exchange(0, std::memory_order_acquire) != 0; }

 private:
  bool wait(const Clock::time_point* deadline) {
    for (;;) {
      if (consume()) return true;
      if (deadline && *deadline <= Clock::now()) return consume();
      sleeping_.store(1, std::memory_order_seq_cst);
      if (pending_.load(std::memory_order_seq_cst) == 0) futexWait(pending_, 0, deadline, FutexScope::Process);
      sleeping_.store(0, std::memory_order_relaxed);
    }
  }

  std::atomic<std::uint32_t> pending_{0};
  std::atomic<std::uint32_t> sleeping_{0};
};

}  // namespace keel::runtime
