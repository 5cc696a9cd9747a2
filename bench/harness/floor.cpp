#include "floor.hpp"

#include <time.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "process.hpp"
#include "runtime/injection.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;

std::int64_t nowNs() { return runtime::steadyNs(); }  // CLOCK_MONOTONIC, as clock_nanosleep below

}  // namespace

FloorResult measureWakeFloor(int n, bool fifo) {
  FloorResult r;
  r.latencies_ns.reserve(static_cast<std::size_t>(n));
  std::atomic<std::uint32_t> round{0};       // the waker bumps it; the waiter waits for a change
  std::atomic<std::int64_t> notified_ns{0};  // when the waker notified
  std::atomic<std::int64_t> woke_ns{0};      // when the waiter ran again (0: not yet)
  std::thread waiter([&] {
    if (fifo) r.warnings = becomeFifo();
    for (std::uint32_t seen = 0; seen < static_cast<std::uint32_t>(n); ++seen) {
      round.wait(seen, std::memory_order_acquire);
      woke_ns.store(nowNs(), std::memory_order_release);
    }
  });
  for (int i = 0; i < n; ++i) {
    std::this_thread::sleep_for(3ms);  // the waiter is asleep in the futex by now
    woke_ns.store(0, std::memory_order_relaxed);
    notified_ns.store(nowNs(), std::memory_order_relaxed);
    round.fetch_add(1, std::memory_order_release);
    round.notify_one();
    while (woke_ns.load(std::memory_order_acquire) == 0) std::this_thread::sleep_for(50us);
    r.latencies_ns.push_back(woke_ns.load(std::memory_order_relaxed) - notified_ns.load(std::memory_order_relaxed));
  }
  waiter.join();
  return r;
}

FloorResult measureTimerFloor(int n, bool fifo) {
  FloorResult r;
  r.latencies_ns.reserve(static_cast<std::size_t>(n));
  std::thread sleeper([&] {
    if (fifo) r.warnings = becomeFifo();
    std::int64_t next = nowNs();
    for (int i = 0; i < n; ++i) {
      next += 1'000'000;  // a 1 ms periodic cycle, as the benchmark's executors run
      const timespec at{static_cast<time_t>(next / 1'000'000'000), static_cast<long>(next % 1'000'000'000)};
      while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr) != 0) {
      }
      r.latencies_ns.push_back(nowNs() - next);
    }
  });
  sleeper.join();
  return r;
}

}  // namespace keel::bench
