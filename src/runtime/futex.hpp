// The futex calls keel makes, in one place: a thread sleeps on a 32-bit word until another
// wakes it or an absolute CLOCK_MONOTONIC deadline (std::chrono::steady_clock's clock) passes.
// Private futexes serve threads of one process (WakeSignal); shared ones a word in memory that
// several processes map (runtime/ipc's ring). futexWaitAny sleeps on several words at once, of
// either scope (futex_waitv, Linux 5.16): how an executor waits for its own wake-ups and for the
// rings of its inputs from other processes in one sleep.
// Thread-safety: the kernel's; the callers own the protocol around the word.
#pragma once

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdint>
#include <ctime>
#include <span>

namespace keel::runtime {

enum class FutexScope { Process, Shared };

/// An absolute CLOCK_MONOTONIC time as the futex calls take it.
inline timespec toTimespec(std::chrono::steady_clock::time_point t) {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
  return {static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
}

/// Sleeps while `word` holds `expected`, until woken or `deadline` (null: for ever). Spurious
/// returns are possible: callers re-check their condition.
inline void futexWait(std::atomic<std::uint32_t>& word, std::uint32_t expected,
                      const std::chrono::steady_clock::time_point* deadline, FutexScope scope) {
  static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t), "a futex word is 32 bits");
  const timespec ts = deadline ? toTimespec(*deadline) : timespec{};
  // FUTEX_WAIT_BITSET without FUTEX_CLOCK_REALTIME: an absolute CLOCK_MONOTONIC timeout.
  const int op = scope == FutexScope::Process ? FUTEX_WAIT_BITSET_PRIVATE : FUTEX_WAIT_BITSET;
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), op, expected, deadline ? &ts : nullptr, nullptr,
          FUTEX_BITSET_MATCH_ANY);
}

/// One word of a futexWaitAny: sleep while `*word` holds `expected`.
struct FutexWaiter {
  std::atomic<std::uint32_t>* word = nullptr;
  std::uint32_t expected = 0;
  FutexScope scope = FutexScope::Process;
};

/// The most words one futexWaitAny sleeps on (the kernel's FUTEX_WAITV_MAX).
inline constexpr std::size_t kFutexWaitAnyMax = FUTEX_WAITV_MAX;

/// Sleeps while every word holds its expected value, until one of them is woken or `deadline`
/// (null: for ever) passes; at most kFutexWaitAnyMax words. Spurious returns are possible. False
/// only when the kernel has no futex_waitv (before Linux 5.16): then it returned at once.
inline bool futexWaitAny(std::span<const FutexWaiter> waiters, const std::chrono::steady_clock::time_point* deadline) {
  futex_waitv vec[kFutexWaitAnyMax] = {};
  const std::size_t n = std::min(waiters.size(), kFutexWaitAnyMax);
  for (std::size_t i = 0; i < n; ++i) {
    vec[i].val = waiters[i].expected;
    vec[i].uaddr = reinterpret_cast<std::uintptr_t>(waiters[i].word);
    vec[i].flags = FUTEX_32 | (waiters[i].scope == FutexScope::Process ? FUTEX_PRIVATE_FLAG : 0);
  }
  const timespec ts = deadline ? toTimespec(*deadline) : timespec{};
  const long r = syscall(SYS_futex_waitv, vec, static_cast<unsigned>(n), 0U, deadline ? &ts : nullptr, CLOCK_MONOTONIC);
  return !(r < 0 && errno == ENOSYS);
}

/// Whether this kernel has futex_waitv (asked once).
inline bool futexWaitAnySupported() {
  static const bool supported = [] {
    const long r = syscall(SYS_futex_waitv, nullptr, 0U, 0U, nullptr, CLOCK_MONOTONIC);
    return !(r < 0 && errno == ENOSYS);
  }();
  return supported;
}

/// Wakes up to `count` sleepers on `word`.
inline void futexWake(std::atomic<std::uint32_t>& word, int count, FutexScope scope) {
  const int op = scope == FutexScope::Process ? FUTEX_WAKE_PRIVATE : FUTEX_WAKE;
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), op, count, nullptr, nullptr, 0);
}

/// Wakes every sleeper on `word`.
inline void futexWakeAll(std::atomic<std::uint32_t>& word, FutexScope scope) { futexWake(word, INT_MAX, scope); }

}  // namespace keel::runtime
