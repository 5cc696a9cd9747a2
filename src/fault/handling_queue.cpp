#include "fault/handling_queue.hpp"

#include <pthread.h>
#include <sched.h>

#include <chrono>
#include <memory>

#include "fault/on_thread.hpp"

namespace keel::fault {

using namespace std::chrono_literals;

HandlingQueue::HandlingQueue(Process process, std::size_t capacity) : process_(std::move(process)), ring_(capacity) {}

HandlingQueue::~HandlingQueue() { stop(); }

void HandlingQueue::start() {
  if (thread_.joinable()) return;
  stop_.store(false, std::memory_order_release);
  thread_ = std::thread([this] { run(); });
  while (thread_id_.load() == std::thread::id{}) std::this_thread::yield();
  std::lock_guard lock(mutex_);
  accepting_ = true;
}

void HandlingQueue::stop() {
  if (!thread_.joinable()) return;
  {
    // From now on callers process their items themselves; what is queued is the thread's.
    std::lock_guard lock(mutex_);
    accepting_ = false;
  }
  stop_.store(true, std::memory_order_release);
  signal_.notify();
  thread_.join();
  thread_id_.store(std::thread::id{});
}

void HandlingQueue::drain() {
  if (!running()) return;
  const std::uint64_t target = enqueued_.load(std::memory_order_acquire);
  signal_.notify();
  waitFor(10s, [&] { return processed_.load(std::memory_order_acquire) >= target; });
}

void HandlingQueue::enqueue(HandlingItem::Type type, const FaultReport& report, bool wake) {
  std::unique_lock lock(mutex_);
  // Full: let the thread catch up (never drops a fault). The thread may stop meanwhile, and
  // what it has not taken by then would never be processed: check again each time.
  while (accepting_ && !onThread() && size_ == ring_.size()) {
    lock.unlock();
    signal_.notify();
    std::this_thread::yield();
    lock.lock();
  }
  if (!accepting_ || onThread()) {  // no thread (not started, or stopping): process it here
    lock.unlock();
    HandlingItem item{type, report};
    process_(item);
    return;
  }
  HandlingItem& slot = ring_[(head_ + size_) % ring_.size()];  // one copy, straight into its slot
  slot.type = type;
  slot.report = report;
  ++size_;
  enqueued_.fetch_add(1, std::memory_order_release);
  lock.unlock();
  if (wake) signal_.notify();
}

void HandlingQueue::armSafetyNet() {
  if (!safety_net_armed_.exchange(true, std::memory_order_acq_rel)) signal_.notify();
}

void HandlingQueue::run() {
  pthread_setname_np(pthread_self(), "keel-faults");
  // Real-time when permitted (as the watchdog, one step below it): a cold replacement or a
  // fault stop must not queue behind the load it protects. Refused: normal priority, silently
  // (the watchdog already warned about the same limit).
  sched_param sp{};
  sp.sched_priority = sched_get_priority_max(SCHED_FIFO) - 1;
  (void)pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
  thread_id_.store(std::this_thread::get_id());
  auto item = std::make_unique<HandlingItem>();
  for (;;) {
    bool got = false;
    {
      std::lock_guard lock(mutex_);
      if (size_ != 0) {
        *item = ring_[head_];
        head_ = (head_ + 1) % ring_.size();
        --size_;
        got = true;
      }
    }
    if (got) {
      process_(*item);
      processed_.fetch_add(1, std::memory_order_release);
      continue;
    }
    if (stop_.load(std::memory_order_acquire)) break;
    // A recovery queues its report without a wake-up; its `recovered` record, or the next
    // step, wakes this thread. The timeout is only a safety net: waking more often would put
    // this real-time thread in the executors' way.
    if (safety_net_armed_.load(std::memory_order_acquire)) signal_.waitUntil(runtime::WakeSignal::Clock::now() + 100ms);
    else signal_.wait();
  }
}

}  // namespace keel::fault
