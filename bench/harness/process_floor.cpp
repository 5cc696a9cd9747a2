#include "process_floor.hpp"

#include <linux/futex.h>
#include <pthread.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <new>
#include <thread>

#include "process.hpp"
#include "runtime/clock.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;

/// Anonymous shared memory for a T, inherited by fork(); unmapped when this goes.
template <class T>
class SharedAnon {
 public:
  SharedAnon() {
    void* p = ::mmap(nullptr, sizeof(T), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    value_ = new (p) T;
  }
  ~SharedAnon() {
    value_->~T();
    ::munmap(value_, sizeof(T));
  }
  SharedAnon(const SharedAnon&) = delete;
  SharedAnon& operator=(const SharedAnon&) = delete;
  T* operator->() { return value_; }

 private:
  T* value_;
};

void reap(pid_t pid) {
  ::kill(pid, SIGKILL);
  while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {}
}

struct Death {
  pthread_mutex_t lock;
  std::atomic<std::uint32_t> owned{0};    // a process holds the lock (reset before each death)
  std::atomic<std::uint32_t> waiting{0};  // the next waiter is about to block on it
  std::atomic<std::int64_t> woke_ns{0};
  std::atomic<std::uint32_t> fifo_refused{0};
};

/// The forked process: blocks on the lock unless `first`, notes when it got it, then holds it
/// until killed.
[[noreturn]] void holder(Death& d, bool first, bool fifo, int threads) {
  if (fifo && !becomeFifo().empty()) d.fifo_refused.store(1);
  if (!first) d.waiting.store(1, std::memory_order_release);
  const int rc = pthread_mutex_lock(&d.lock);
  if (!first) d.woke_ns.store(runtime::steadyNs(), std::memory_order_release);
  if (rc == EOWNERDEAD) pthread_mutex_consistent(&d.lock);
  for (int t = 1; t < threads; ++t)
    std::thread([] {
      for (;;) ::pause();
    }).detach();
  d.owned.store(1, std::memory_order_release);
  for (;;) ::pause();
}

struct Wake {
  std::atomic<std::uint32_t> word{0};
  std::atomic<std::int64_t> woke_ns{0};
  std::atomic<std::uint32_t> fifo_refused{0};
};

long futex(std::atomic<std::uint32_t>& word, int op, std::uint32_t value) {
  return ::syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), op, value, nullptr, nullptr, 0);
}

}  // namespace

FloorResult measureRobustFloor(int n, bool fifo, int threads) {
  FloorResult r;
  SharedAnon<Death> d;
  pthread_mutexattr_t attr;
  pthread_mutexattr_init(&attr);
  pthread_mutexattr_setpshared(&attr, PTHREAD_PROCESS_SHARED);
  pthread_mutexattr_setrobust(&attr, PTHREAD_MUTEX_ROBUST);
  pthread_mutex_init(&d->lock, &attr);
  pthread_mutexattr_destroy(&attr);
  pid_t owner = ::fork();
  if (owner == 0) holder(*d.operator->(), true, fifo, threads);
  if (!pollUntil([&] { return d->owned.load() == 1; }, 2000ms)) {
    reap(owner);
    r.warnings = "the first holder did not take the lock";
    return r;
  }
  for (int i = 0; i <= n; ++i) {  // trial 0 warms up, uncounted
    d->waiting.store(0);
    d->woke_ns.store(0);
    const pid_t waiter = ::fork();
    if (waiter == 0) holder(*d.operator->(), false, fifo, threads);
    pollUntil([&] { return d->waiting.load(std::memory_order_acquire) == 1; }, 2000ms);
    std::this_thread::sleep_for(3ms);  // asleep on the lock by now
    d->owned.store(0);
    const std::int64_t killed = runtime::steadyNs();
    ::kill(owner, SIGKILL);
    while (::waitpid(owner, nullptr, 0) < 0 && errno == EINTR) {}
    const bool woke = pollUntil([&] { return d->owned.load(std::memory_order_acquire) == 1; }, 2000ms);
    owner = waiter;
    if (!woke) {
      r.warnings = "a waiter did not wake to its holder's death";
      break;
    }
    if (i > 0) r.latencies_ns.push_back(d->woke_ns.load() - killed);
  }
  reap(owner);
  if (d->fifo_refused.load()) r.warnings = "SCHED_FIFO refused";
  return r;
}

FloorResult measureProcessWakeFloor(int n, bool fifo) {
  FloorResult r;
  SharedAnon<Wake> w;
  const pid_t child = ::fork();
  if (child == 0) {
    if (fifo && !becomeFifo().empty()) w->fifo_refused.store(1);
    for (std::uint32_t seen = 0;;) {
      while (w->word.load(std::memory_order_acquire) == seen) futex(w->word, FUTEX_WAIT, seen);
      w->woke_ns.store(runtime::steadyNs(), std::memory_order_release);
      seen = w->word.load(std::memory_order_acquire);
    }
  }
  // The waker runs as keel's writer does: under SCHED_FIFO at the waiter's priority when `fifo`
  // (the waiter cannot preempt it, and wakes on the other CPU), sleeping after each wake.
  std::thread waker([&] {
    if (fifo && !becomeFifo().empty()) w->fifo_refused.store(1);
    for (int i = 0; i <= n; ++i) {  // trial 0 warms up, uncounted
      std::this_thread::sleep_for(1ms);
      w->woke_ns.store(0);
      const std::int64_t woken = runtime::steadyNs();
      w->word.fetch_add(1, std::memory_order_release);
      futex(w->word, FUTEX_WAKE, 1);
      if (!pollUntil([&] { return w->woke_ns.load(std::memory_order_acquire) != 0; }, 2000ms)) {
        r.warnings = "the waiter did not wake";
        break;
      }
      if (i > 0) r.latencies_ns.push_back(w->woke_ns.load() - woken);
    }
  });
  waker.join();
  reap(child);
  if (w->fifo_refused.load()) r.warnings = "SCHED_FIFO refused";
  return r;
}

}  // namespace keel::bench
