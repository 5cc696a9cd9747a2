// WakeSignal: lets one thread sleep until another wakes it or an absolute deadline passes
// (CLOCK_MONOTONIC, the clock of std::chrono::steady_clock). A futex word: notify() costs one
// atomic exchange when the sleeper is awake, one futex wake syscall when it sleeps.
// Thread-safety: any number of notifiers, one waiter.
#pragma once

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <ctime>

namespace keel::runtime {

class WakeSignal {
 public:
  using Clock = std::chrono::steady_clock;

  void notify() {
    if (pending_.exchange(1, std::memory_order_seq_cst) == 0 && sleeping_.load(std::memory_order_seq_cst) != 0) {
      syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&pending_), FUTEX_WAKE_PRIVATE, 1, nullptr, nullptr, 0);
    }
  }

  /// Sleeps until notified or `deadline`. Returns true when notified (and consumes it).
  bool waitUntil(Clock::time_point deadline) { return wait(&deadline); }
  /// Sleeps until notified.
  void wait() { wait(nullptr); }
  /// Consumes a pending notification without sleeping.
  bool consume() { return pending_.exchange(0, std::memory_order_acquire) != 0; }

 private:
  bool wait(const Clock::time_point* deadline) {
    for (;;) {
      if (consume()) return true;
      timespec ts{};
      if (deadline) {
        auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(deadline->time_since_epoch());
        if (*deadline <= Clock::now()) return consume();
        ts.tv_sec = static_cast<time_t>(ns.count() / 1'000'000'000);
        ts.tv_nsec = static_cast<long>(ns.count() % 1'000'000'000);
      }
      sleeping_.store(1, std::memory_order_seq_cst);
      if (pending_.load(std::memory_order_seq_cst) == 0) {
        // Absolute CLOCK_MONOTONIC timeout (FUTEX_WAIT_BITSET without FUTEX_CLOCK_REALTIME).
        syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&pending_), FUTEX_WAIT_BITSET_PRIVATE, 0,
                deadline ? &ts : nullptr, nullptr, FUTEX_BITSET_MATCH_ANY);
      }
      sleeping_.store(0, std::memory_order_relaxed);
    }
  }

  static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));
  std::atomic<std::uint32_t> pending_{0};
  std::atomic<std::uint32_t> sleeping_{0};
};

}  // namespace keel::runtime
