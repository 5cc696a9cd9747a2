// The seqlock ring (runtime/ipc/ring.hpp) between real processes, each with its own mapping:
// order and no loss, lapped readers, fencing by epoch, wake-ups, and the layout checks.
#include "runtime/ipc/ring.hpp"

#include <gtest/gtest.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <vector>

#include "ipc_test_support.hpp"

namespace keel::runtime::ipc {
namespace {

using test::Child;
using test::must;
using Sample = test::Stamped<8>;
using namespace std::chrono_literals;

TEST(Ring, ValuesCrossProcessesInOrderAndWithoutLossWhenTheReaderKeepsUp) {
  constexpr std::uint64_t kCount = 20000;
  struct Control {
    std::atomic<std::uint64_t> consumed{0};
  };
  test::SharedBlock<Control> control;
  auto ring = must(Ring<Sample>::create("ring a", 64));
  auto reader = ring.reader();

  Child producer = Child::run([&] {
    auto own = test::attachOwnMapping<Sample>(ring);
    const auto writer = must(own.takeOver());
    for (std::uint64_t i = 0; i < kCount; ++i) {
      while (i - control->consumed.load() >= 32) ::sched_yield();  // the test's flow control
      auto pushed = own.push(writer.epoch, Sample::of(i));
      if (!pushed || *pushed != PushStatus::Written) return 3;
    }
    return 0;
  });

  std::vector<std::uint64_t> got;
  SampleInfo info;
  bool all_whole = true, indices_match = true;
  const auto end = std::chrono::steady_clock::now() + 10s;
  while (got.size() < kCount && std::chrono::steady_clock::now() < end) {
    if (auto s = reader.pop(&info)) {
      all_whole &= s->whole();
      indices_match &= info.index == s->value() && info.epoch == 1;
      got.push_back(s->value());
      control->consumed = got.size();
    } else {
      reader.wait(100ms);
    }
  }
  if (got.size() < kCount) producer.kill();  // stuck in the flow control: given up on
  EXPECT_TRUE(test::exitedWith(producer.wait(), 0));
  ASSERT_EQ(got.size(), kCount);
  for (std::uint64_t i = 0; i < kCount; ++i) ASSERT_EQ(got[i], i) << "out of order or lost at " << i;
  EXPECT_TRUE(all_whole);
  EXPECT_TRUE(indices_match) << "a sample came with another index or epoch than its writer's";
  EXPECT_EQ(reader.dropped(), 0u);
  EXPECT_FALSE(reader.pop()) << "nothing beyond what was pushed";
}

TEST(Ring, ALappedReaderSkipsToTheOldestSampleStillThereAndCountsTheRestAsDropped) {
  auto ring = must(Ring<std::uint64_t>::create("ring lapped", 4));
  auto reader = ring.reader();
  const auto writer = must(ring.takeOver());
  for (std::uint64_t v = 0; v < 10; ++v) ASSERT_EQ(ring.push(writer.epoch, v).value(), PushStatus::Written);

  SampleInfo info;
  EXPECT_EQ(reader.pop(&info), 6u) << "samples 6..9 are still in the ring's 4 slots";
  EXPECT_EQ(info.index, 6u);
  EXPECT_EQ(reader.dropped(), 6u);
  EXPECT_EQ(reader.pop(), 7u);
  EXPECT_EQ(reader.pop(), 8u);
  EXPECT_EQ(reader.pop(), 9u);
  EXPECT_FALSE(reader.pop());
  EXPECT_EQ(reader.dropped(), 6u);
}

TEST(Ring, LatestReadsTheNewestSampleOnceAndCountsWhatItSkippedAsDropped) {
  auto ring = must(Ring<std::uint64_t>::create("ring latest", 8));
  auto reader = ring.reader();
  EXPECT_FALSE(reader.latest()) << "nothing pushed yet";
  const auto writer = must(ring.takeOver());
  for (std::uint64_t v = 0; v < 5; ++v) ASSERT_TRUE(ring.push(writer.epoch, v));

  EXPECT_EQ(reader.latest(), 4u);
  EXPECT_EQ(reader.dropped(), 4u);
  EXPECT_FALSE(reader.latest()) << "read once";
  ASSERT_TRUE(ring.push(writer.epoch, 5));
  EXPECT_EQ(reader.pop(), 5u) << "FIFO goes on after it";
}

TEST(Ring, AReaderLappedByAWriterInAnotherProcessNeverGetsATornOrStaleSample) {
  struct Control {
    std::atomic<int> stop{0};
  };
  test::SharedBlock<Control> control;
  auto ring = must(Ring<Sample>::create("ring torn", 4));
  auto reader = ring.reader();
  Child writer = Child::run([&] {
    test::PinnedToCpu writer_cpu(1);  // the other CPU, when there is one: a real race
    auto own = test::attachOwnMapping<Sample>(ring);
    const auto me = must(own.takeOver());
    for (std::uint64_t v = 0; control->stop.load(std::memory_order_relaxed) == 0; ++v)
      if (!own.push(me.epoch, Sample::of(v))) return 3;
    return 0;
  });
  test::PinnedToCpu reader_cpu(0);  // after the fork: the writer may still choose the other CPU

  std::uint64_t received = 0, torn = 0, stale = 0, last = 0;
  SampleInfo info;
  const auto end = std::chrono::steady_clock::now() + 2s;
  while (received < 200000 && std::chrono::steady_clock::now() < end) {
    if (auto s = reader.pop(&info)) {
      torn += s->whole() ? 0 : 1;
      stale += (received > 0 && s->value() <= last) || s->value() != info.index ? 1 : 0;
      last = s->value();
      ++received;
    }
  }
  control->stop = 1;
  EXPECT_TRUE(test::exitedWith(writer.wait(), 0));
  ASSERT_GT(received, 0u);
  EXPECT_EQ(torn, 0u) << "of " << received;
  EXPECT_EQ(stale, 0u) << "a sample older than one already read, or not the one at its index";
  EXPECT_GT(reader.dropped(), 0u) << "the reader was never lapped: the test tested nothing";
  EXPECT_EQ(reader.dropped() + received, last + 1) << "every sample up to the last is read or counted dropped";
}

TEST(Ring, AfterATakeOverThePreviousWritersPushIsRefusedAndNeverSeen) {
  struct Control {
    std::atomic<int> step{0};
    std::atomic<int> late_push{-1};  // the old writer's push after the takeover: a PushStatus
  };
  test::SharedBlock<Control> control;
  auto ring = must(Ring<Sample>::create("ring fenced", 16));
  auto reader = ring.reader();
  Child old_writer = Child::run([&] {
    auto own = test::attachOwnMapping<Sample>(ring);
    const auto me = must(own.takeOver());
    for (std::uint64_t v = 0; v < 3; ++v)
      if (!own.push(me.epoch, Sample::of(v))) return 3;
    control->step = 1;
    while (control->step.load() != 2) ::sched_yield();
    auto late = own.push(me.epoch, Sample::of(3));
    control->late_push = late ? static_cast<int>(*late) : 100;
    return 0;
  });
  ASSERT_TRUE(test::eventually([&] { return control->step.load() == 1; }));

  const auto taken = must(ring.takeOver());
  EXPECT_EQ(taken.epoch, 2u);
  EXPECT_FALSE(taken.writer_died);
  control->step = 2;
  EXPECT_TRUE(test::exitedWith(old_writer.wait(), 0));
  EXPECT_EQ(control->late_push.load(), static_cast<int>(PushStatus::Fenced));
  ASSERT_EQ(ring.push(taken.epoch, Sample::of(100)).value(), PushStatus::Written);

  std::vector<std::pair<std::uint64_t, std::uint32_t>> seen;  // value, epoch
  SampleInfo info;
  while (auto s = reader.pop(&info)) seen.emplace_back(s->value(), info.epoch);
  using Seen = std::vector<std::pair<std::uint64_t, std::uint32_t>>;
  EXPECT_EQ(seen, (Seen{{0, 1}, {1, 1}, {2, 1}, {100, 2}}));
  EXPECT_EQ(ring.buffer().written(), 4u);
  EXPECT_EQ(ring.buffer().epoch(), 2u);
}

TEST(Ring, NobodyWritesBeforeTakingTheRingOverNorWithAnEpochTakenOver) {
  auto ring = must(Ring<std::uint64_t>::create("ring epochs", 4));
  auto reader = ring.reader();
  EXPECT_EQ(ring.buffer().epoch(), 0u);
  EXPECT_EQ(ring.push(0, 7).value(), PushStatus::Fenced) << "epoch 0 is no writer";
  EXPECT_EQ(must(ring.takeOver()).epoch, 1u);
  EXPECT_EQ(ring.push(1, 8).value(), PushStatus::Written);
  EXPECT_EQ(must(ring.takeOver()).epoch, 2u);
  EXPECT_EQ(ring.push(1, 9).value(), PushStatus::Fenced);
  EXPECT_EQ(reader.pop(), 8u);
  EXPECT_FALSE(reader.pop());
}

TEST(Ring, AReaderAsleepInWaitIsWokenByAPushFromAnotherProcess) {
  struct Control {
    std::atomic<int> woke{0};  // 1: woken with a sample; 2: wait() timed out
    std::atomic<std::uint64_t> value{0};
  };
  test::SharedBlock<Control> control;
  auto ring = must(Ring<std::uint64_t>::create("ring wake", 8));
  const auto writer = must(ring.takeOver());
  Child sleeper = Child::run([&] {
    auto own = test::attachOwnMapping<std::uint64_t>(ring);
    auto reader = own.reader();
    const bool woken = reader.wait(60s);  // far beyond the test's own bound
    const auto v = reader.pop();
    control->value = v.value_or(0);
    control->woke = woken && v ? 1 : 2;
    return 0;
  });
  ASSERT_TRUE(test::eventually([&] { return ring.buffer().sleepingReaders() == 1; })) << "the reader never slept";

  ASSERT_EQ(ring.push(writer.epoch, 42).value(), PushStatus::Written);

  ASSERT_TRUE(test::eventually([&] { return control->woke.load() != 0; })) << "the push did not wake the reader";
  EXPECT_EQ(control->woke.load(), 1);
  EXPECT_EQ(control->value.load(), 42u);
  EXPECT_TRUE(test::exitedWith(sleeper.wait(), 0));
  EXPECT_EQ(ring.buffer().sleepingReaders(), 0u);
}

TEST(Ring, AThreadAsleepOnTheRingAmongOtherWordsIsWokenByAPushFromAnotherProcess) {
  ASSERT_TRUE(futexWaitAnySupported()) << "this kernel has no futex_waitv (Linux 5.16)";
  struct Control {
    std::atomic<int> woke{0};  // 1: woken with a sample; 2: without one
    std::atomic<std::uint64_t> value{0};
  };
  test::SharedBlock<Control> control;
  auto ring = must(Ring<std::uint64_t>::create("ring wake any", 8));
  const auto writer = must(ring.takeOver());
  Child sleeper = Child::run([&] {
    auto own = test::attachOwnMapping<std::uint64_t>(ring);
    RingReader reader(own.buffer());
    std::atomic<std::uint32_t> own_word{0};                        // an executor's own wake word, never woken here
    const auto deadline = std::chrono::steady_clock::now() + 60s;  // far beyond the test's own bound
    const std::optional<FutexWaiter> on_ring = reader.announceSleep();
    if (!on_ring) return 3;
    const FutexWaiter words[] = {{&own_word, 0, FutexScope::Process}, *on_ring};
    while (!reader.available() && std::chrono::steady_clock::now() < deadline) futexWaitAny(words, &deadline);
    reader.endSleep();
    std::uint64_t v = 0;
    const bool got = reader.pop(&v).has_value();
    control->value = v;
    control->woke = got ? 1 : 2;
    return 0;
  });
  ASSERT_TRUE(test::eventually([&] { return ring.buffer().sleepingReaders() == 1; })) << "the reader never slept";

  ASSERT_EQ(ring.push(writer.epoch, 42).value(), PushStatus::Written);

  ASSERT_TRUE(test::eventually([&] { return control->woke.load() != 0; })) << "the push did not wake the reader";
  EXPECT_EQ(control->woke.load(), 1);
  EXPECT_EQ(control->value.load(), 42u);
  EXPECT_TRUE(test::exitedWith(sleeper.wait(), 0));
  EXPECT_EQ(ring.buffer().sleepingReaders(), 0u);

  // A sample there already: no sleep is announced, and the writer is not asked to wake anyone.
  RingReader late(ring.buffer());
  ASSERT_EQ(ring.push(writer.epoch, 43).value(), PushStatus::Written);
  EXPECT_FALSE(late.announceSleep());
  EXPECT_EQ(ring.buffer().sleepingReaders(), 0u);
}

TEST(Ring, WaitWithNothingPushedReturnsFalseAtItsTimeout) {
  auto ring = must(Ring<std::uint64_t>::create("ring idle", 2));
  auto reader = ring.reader();
  EXPECT_FALSE(reader.wait(1ms));
  EXPECT_EQ(ring.buffer().sleepingReaders(), 0u);
}

TEST(Ring, AttachingChecksTheLayoutAndTheSampleSizeWithClearErrors) {
  auto ring = must(Ring<Sample>::create("ring cam→det", 8));
  const int fd = ring.buffer().memory().fd();

  auto wrong_type = Ring<std::uint64_t>::attach(must(SharedMemory::adopt(::dup(fd), "ring cam→det")));
  ASSERT_FALSE(wrong_type);
  EXPECT_EQ(wrong_type.error().message, "ring 'ring cam→det' carries samples of 72 bytes, this side expects 8");

  auto not_a_ring = Ring<Sample>::attach(must(SharedMemory::create("zeros", 4096)));
  ASSERT_FALSE(not_a_ring);
  EXPECT_EQ(not_a_ring.error().message, "'zeros' is not a keel ring of version 1 (magic 0x0, version 0)");

  auto three = Ring<Sample>::create("ring odd", 3);
  ASSERT_FALSE(three);
  EXPECT_EQ(three.error().message, "ring 'ring odd': 3 slots; the count must be a power of two, 1..16777216");

  auto small = RingBuffer::create(must(SharedMemory::create("small", 100)), 8, 4);
  ASSERT_FALSE(small);
  EXPECT_EQ(small.error().message, "ring 'small': 4 slots of 8 bytes need " +
                                       std::to_string(RingBuffer::bytesFor(8, 4)) + " bytes, the region has 100");

  auto no_sample = RingBuffer::create("ring empty", 0, 4);
  ASSERT_FALSE(no_sample);
  EXPECT_EQ(no_sample.error().message, "ring 'ring empty': a sample of 0 bytes; it must be 1..16777216");
}

}  // namespace
}  // namespace keel::runtime::ipc
