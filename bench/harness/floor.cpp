#include "floor.hpp"

#include <setjmp.h>
#include <signal.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <thread>

#include "process.hpp"
#include "runtime/guard.hpp"
#include "runtime/injection.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;

std::int64_t nowNs() { return runtime::steadyNs(); }  // CLOCK_MONOTONIC, as clock_nanosleep below

/// A thread on a 1 ms absolute-time cycle (SCHED_FIFO 50 when `fifo`) that runs `fault` right
/// after waking on every `every`-th cycle until it has `n` latencies (fault → caught, from
/// `fault`'s return).
FloorResult onCycles(int n, bool fifo, int every, const std::function<std::int64_t()>& fault) {
  FloorResult r;
  r.latencies_ns.reserve(static_cast<std::size_t>(n));
  std::thread t([&] {
    if (fifo) r.warnings = becomeFifo();
    std::int64_t next = nowNs();
    for (int cycle = 1; static_cast<int>(r.latencies_ns.size()) < n; ++cycle) {
      next += 1'000'000;
      const timespec at{static_cast<time_t>(next / 1'000'000'000), static_cast<long>(next % 1'000'000'000)};
      while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr) != 0) {}
      if (cycle % every == 0) r.latencies_ns.push_back(fault());
    }
  });
  t.join();
  return r;
}

// The bare signal floor's state: the time its handler ran, and where it jumps back to. Only the
// floor's thread faults while the bare handler is installed.
thread_local sigjmp_buf t_back;
thread_local volatile std::int64_t t_caught_ns = 0;
thread_local volatile bool t_armed = false;

void bareHandler(int signo, siginfo_t*, void*) {
  if (!t_armed) {  // not the floor's fault: do not swallow it
    ::signal(signo, SIG_DFL);
    ::raise(signo);
    return;
  }
  t_caught_ns = nowNs();
  siglongjmp(t_back, 1);
}

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
      while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr) != 0) {}
      r.latencies_ns.push_back(nowNs() - next);
    }
  });
  sleeper.join();
  return r;
}

void storeToPageZero() {
  volatile std::uintptr_t addr = 0x10;         // page 0 is never mapped
  *reinterpret_cast<volatile int*>(addr) = 1;  // NOLINT(performance-no-int-to-ptr): the fault measured
}

void throwRuntimeError() { throw std::runtime_error("floor"); }

BareSegvHandler::BareSegvHandler() {
  struct sigaction bare {};
  bare.sa_sigaction = bareHandler;
  sigemptyset(&bare.sa_mask);
  bare.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_NODEFER;  // as keel's guard installs its own
  ::sigaction(SIGSEGV, &bare, &saved_);
}

BareSegvHandler::~BareSegvHandler() { ::sigaction(SIGSEGV, &saved_, nullptr); }

std::int64_t bareSegfault() {
  volatile std::int64_t faulted = 0;
  t_armed = true;
  if (sigsetjmp(t_back, 0) == 0) {
    faulted = nowNs();
    storeToPageZero();
  }
  t_armed = false;
  return t_caught_ns - faulted;
}

std::int64_t bareThrow() {
  const std::int64_t thrown = nowNs();
  try {
    throwRuntimeError();
  } catch (const std::exception&) {
    return nowNs() - thrown;
  }
  return 0;
}

FloorResult measureSignalFloor(int n, bool fifo, int every) {
  const BareSegvHandler bare;
  return onCycles(n, fifo, every, [] {
    runtime::installAltStack();  // the floor thread's own, as an executor has one (once)
    return bareSegfault();
  });
}

FloorResult measureThrowFloor(int n, bool fifo, int every) { return onCycles(n, fifo, every, bareThrow); }

}  // namespace keel::bench
