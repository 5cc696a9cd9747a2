// The fault manager's queue and thread (src/fault/handling_queue.hpp): processed at once on the
// caller's thread without a thread, in order on its own thread once started, none lost when the
// ring is full, what is queued processed at stop, and onThread() true only on that thread; an
// item queued without a wake-up left alone until the safety net is armed, then taken by it.
#include "fault/handling_queue.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

namespace keel::fault {
namespace {

using namespace std::chrono_literals;

/// One processed item: which report, on which thread, and whether onThread() said so.
struct Seen {
  std::uint64_t id;
  std::thread::id thread;
  bool on_thread;
};

FaultReport numbered(std::uint64_t id) {
  FaultReport r;
  r.id = id;
  return r;
}

/// A queue whose process() notes every item (optionally taking `work` over each).
class Recorder {
 public:
  explicit Recorder(std::size_t capacity = HandlingQueue::kCapacity, std::chrono::microseconds work = {})
      : work_(work), queue_([this](HandlingItem& item) { note(item); }, capacity) {}

  HandlingQueue& queue() { return queue_; }
  std::vector<Seen> seen() {
    std::lock_guard lock(mutex_);
    return seen_;
  }
  std::vector<std::uint64_t> ids() {
    std::vector<std::uint64_t> out;
    for (const Seen& s : seen()) out.push_back(s.id);
    return out;
  }
  std::function<void(HandlingItem&)> before;  // runs first in process(), when set

 private:
  void note(HandlingItem& item) {
    if (before) before(item);
    if (work_.count() != 0) std::this_thread::sleep_for(work_);
    std::lock_guard lock(mutex_);
    seen_.push_back({item.report.id, std::this_thread::get_id(), queue_.onThread()});
  }

  std::chrono::microseconds work_;
  std::mutex mutex_;
  std::vector<Seen> seen_;
  HandlingQueue queue_;  // last: stopped (its thread joined) before the rest is destroyed
};

TEST(HandlingQueue, WithoutStartAnItemIsProcessedAtOnceOnTheCallersThread) {
  Recorder rec;

  rec.queue().enqueue(HandlingItem::Type::Report, numbered(1), true);

  const auto seen = rec.seen();
  ASSERT_EQ(seen.size(), 1u) << "processed before enqueue returned";
  EXPECT_EQ(seen[0].id, 1u);
  EXPECT_EQ(seen[0].thread, std::this_thread::get_id());
  EXPECT_FALSE(seen[0].on_thread) << "the caller's thread is not the queue's";
  EXPECT_FALSE(rec.queue().running());
}

TEST(HandlingQueue, TheItemsTypeAndReportReachProcess) {
  HandlingItem::Type got = HandlingItem::Type::Report;
  std::uint64_t id = 0;
  HandlingQueue queue([&](HandlingItem& item) {
    got = item.type;
    id = item.report.id;
  });

  queue.enqueue(HandlingItem::Type::Recovered, numbered(33), true);

  EXPECT_EQ(got, HandlingItem::Type::Recovered);
  EXPECT_EQ(id, 33u);
}

TEST(HandlingQueue, AfterStartItemsAreProcessedOnItsThreadInOrderAndDrainWaitsForAll) {
  Recorder rec(HandlingQueue::kCapacity, 500us);
  rec.queue().start();

  for (std::uint64_t i = 0; i < 50; ++i) rec.queue().enqueue(HandlingItem::Type::Report, numbered(i), true);
  rec.queue().drain();

  const auto seen = rec.seen();
  ASSERT_EQ(seen.size(), 50u) << "drain returned before everything was processed";
  for (std::uint64_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i].id, i) << "first in, first out";
    EXPECT_NE(seen[i].thread, std::this_thread::get_id());
    EXPECT_EQ(seen[i].thread, seen[0].thread) << "one thread";
    EXPECT_TRUE(seen[i].on_thread);
  }
  EXPECT_TRUE(rec.queue().running());
  EXPECT_FALSE(rec.queue().onThread()) << "only inside process";
}

TEST(HandlingQueue, ItemsQueuedWithoutAWakeUpAreProcessedByDrain) {
  Recorder rec;
  rec.queue().start();

  for (std::uint64_t i = 0; i < 5; ++i) rec.queue().enqueue(HandlingItem::Type::Report, numbered(i), false);
  rec.queue().drain();

  EXPECT_EQ(rec.ids(), (std::vector<std::uint64_t>{0, 1, 2, 3, 4}));
}

// A recovery queues its report without a wake-up and runs the recovered component's first step
// at once: the queue's real-time thread must not wake in between (it would preempt that step for
// the whole logging of the fault). Before the safety net is armed nothing wakes it.
TEST(HandlingQueue, AnItemQueuedWithoutAWakeUpDoesNotWakeTheThreadBeforeTheSafetyNetIsArmed) {
  Recorder rec;
  rec.queue().start();
  rec.queue().enqueue(HandlingItem::Type::Report, numbered(0), true);  // the thread is up and has
  rec.queue().drain();                                                 // looked at the ring:
  std::this_thread::sleep_for(200ms);  // it sleeps (an item queued before that would be taken)

  rec.queue().enqueue(HandlingItem::Type::Report, numbered(1), false);
  std::this_thread::sleep_for(300ms);

  EXPECT_EQ(rec.ids(), (std::vector<std::uint64_t>{0})) << "the thread woke for an item queued without a wake-up";
  rec.queue().enqueue(HandlingItem::Type::Recovered, numbered(2), true);
  rec.queue().drain();
  EXPECT_EQ(rec.ids(), (std::vector<std::uint64_t>{0, 1, 2})) << "the woken thread takes both, in order";
}

// Once armed (the components run), an item queued without a wake-up is still taken by the
// thread on its own, within its safety-net timeout (100 ms; bounded generously here).
TEST(HandlingQueue, OnceArmedTheSafetyNetTakesAnItemNothingWokeTheThreadFor) {
  Recorder rec;
  rec.queue().start();
  rec.queue().armSafetyNet();
  std::this_thread::sleep_for(200ms);  // the arming's own wake has passed: the thread sleeps again

  rec.queue().enqueue(HandlingItem::Type::Report, numbered(7), false);
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (rec.ids().empty() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(5ms);

  EXPECT_EQ(rec.ids(), (std::vector<std::uint64_t>{7})) << "no drain, no wake-up: the safety net's timeout";
}

TEST(HandlingQueue, ARingSmallerThanTheItemsFromSeveralThreadsLosesNone) {
  Recorder rec(4, 20us);
  rec.queue().start();
  constexpr std::uint64_t kEach = 500;

  std::vector<std::thread> producers;
  for (std::uint64_t p = 0; p < 2; ++p)
    producers.emplace_back([&rec, p] {
      for (std::uint64_t i = 0; i < kEach; ++i)
        rec.queue().enqueue(HandlingItem::Type::Report, numbered(p * 1'000'000 + i), true);
    });
  for (auto& t : producers) t.join();
  rec.queue().drain();

  const auto ids = rec.ids();
  ASSERT_EQ(ids.size(), 2 * kEach);
  EXPECT_EQ(std::set<std::uint64_t>(ids.begin(), ids.end()).size(), 2 * kEach) << "each exactly once";
  std::uint64_t next[2] = {0, 0};
  for (std::uint64_t id : ids) {  // each producer's items in the order it enqueued them
    const std::uint64_t p = id / 1'000'000;
    ASSERT_LT(p, 2u);
    EXPECT_EQ(id % 1'000'000, next[p]++) << "producer " << p;
  }
}

TEST(HandlingQueue, StopProcessesWhatWasQueuedThenCallersProcessTheirOwn) {
  Recorder rec;
  std::atomic<bool> release{false};
  rec.before = [&](HandlingItem& item) {  // the first item holds the thread up while more queue
    if (item.report.id == 0)
      while (!release) std::this_thread::sleep_for(1ms);
  };
  rec.queue().start();
  for (std::uint64_t i = 0; i < 10; ++i) rec.queue().enqueue(HandlingItem::Type::Report, numbered(i), false);
  std::thread releaser([&] {  // after stop() has begun: the other nine are still queued then
    std::this_thread::sleep_for(50ms);
    release = true;
  });

  rec.queue().stop();
  releaser.join();
  const auto at_stop = rec.seen();
  rec.queue().enqueue(HandlingItem::Type::Report, numbered(10), true);

  ASSERT_EQ(at_stop.size(), 10u) << "stop() lost what was queued";
  for (const Seen& s : at_stop) EXPECT_NE(s.thread, std::this_thread::get_id());
  EXPECT_FALSE(rec.queue().running());
  const auto after = rec.seen();
  ASSERT_EQ(after.size(), 11u) << "after stop(), an item is processed before enqueue returns";
  EXPECT_EQ(after.back().id, 10u);
  EXPECT_EQ(after.back().thread, std::this_thread::get_id());
  EXPECT_FALSE(after.back().on_thread);
}

TEST(HandlingQueue, AnItemEnqueuedByProcessItselfIsProcessedThereAndThen) {
  Recorder rec;
  rec.before = [&](HandlingItem& item) {
    if (item.report.id == 1) rec.queue().enqueue(HandlingItem::Type::Report, numbered(100), true);
  };
  rec.queue().start();

  for (std::uint64_t i = 0; i < 3; ++i) rec.queue().enqueue(HandlingItem::Type::Report, numbered(i), true);
  rec.queue().drain();

  EXPECT_EQ(rec.ids(), (std::vector<std::uint64_t>{0, 100, 1, 2}))
      << "the manager's own thread hands itself nothing: it carries on at once";
}

}  // namespace
}  // namespace keel::fault
