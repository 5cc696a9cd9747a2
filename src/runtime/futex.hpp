// The futex calls keel makes, in one place: a thread sleeps on a 32-bit word until another
// wakes it or an absolute CLOCK_MONOTONIC deadline (std::chrono::steady_clock's clock) passes.
// Private futexes serve threads of one process (WakeSignal); shared ones a word in memory that
// several processes map (runtime/ipc's ring).
// Thread-safety: the kernel's; the callers own the protocol around the word.
#pragma once

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <climits>
#include <cstdint>
#include <ctime>

namespace keel::runtime {

enum class FutexScope { Process, Shared };

/// Sleeps while `word` holds `expected`, until woken or `deadline` (null: for ever). Spurious
/// returns are possible: callers re-check their condition.
inline void futexWait(std::atomic<std::uint32_t>& word, std::uint32_t expected,
                      const std::chrono::steady_clock::time_point* deadline, FutexScope scope) {
  static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t), "a futex word is 32 bits");
  timespec ts{};
  if (deadline) {
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(deadline->time_since_epoch()).count();
    ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
  }
  // FUTEX_WAIT_BITSET without FUTEX_CLOCK_REALTIME: an absolute CLOCK_MONOTONIC timeout.
  const int op = scope == FutexScope::Process ? FUTEX_WAIT_BITSET_PRIVATE : FUTEX_WAIT_BITSET;
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), op, expected, deadline ? &ts : nullptr, nullptr,
          FUTEX_BITSET_MATCH_ANY);
}

/// Wakes up to `count` sleepers on `word`.
inline void futexWake(std::atomic<std::uint32_t>& word, int count, FutexScope scope) {
  const int op = scope == FutexScope::Process ? FUTEX_WAKE_PRIVATE : FUTEX_WAKE;
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), op, count, nullptr, nullptr, 0);
}

/// Wakes every sleeper on `word`.
inline void futexWakeAll(std::atomic<std::uint32_t>& word, FutexScope scope) { futexWake(word, INT_MAX, scope); }

}  // namespace keel::runtime
