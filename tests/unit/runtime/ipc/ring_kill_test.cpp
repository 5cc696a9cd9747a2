// The ring under kill -9 (runtime/ipc/ring.hpp, decision 0011's ring_torture as a test): a
// producer process killed at random moments mid-stream, again and again, each time replaced by a
// new one that takes the ring over; a consumer process checks every sample it gets.
#include <gtest/gtest.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <random>

#include "ipc_test_support.hpp"
#include "runtime/ipc/ring.hpp"

namespace keel::runtime::ipc {
namespace {

using test::Child;
using Sample = test::Stamped<8>;
using namespace std::chrono_literals;

constexpr int kKills = 200;
constexpr int kEpochShift = 40;  // a sample's value: its writer's epoch, then its count

struct Campaign {
  std::atomic<std::uint32_t> producing{0};     // the epoch of the producer that has pushed
  std::atomic<std::uint32_t> writers_died{0};  // takeovers that found the writer lock's holder dead
  std::atomic<std::uint32_t> producer_errors{0};
  std::atomic<int> stop{0};
  std::atomic<std::uint64_t> consumed{0}, torn{0}, out_of_order{0}, epochs_seen{0};
};

int produce(const Ring<Sample>& ring, Campaign& campaign) {
  auto own = test::attachOwnMapping<Sample>(ring);
  const auto me = test::must(own.takeOver());
  if (me.writer_died) ++campaign.writers_died;
  for (std::uint64_t n = 0;; ++n) {
    auto pushed = own.push(me.epoch, Sample::of(std::uint64_t{me.epoch} << kEpochShift | n));
    if (!pushed || *pushed != PushStatus::Written) {
      ++campaign.producer_errors;
      return 3;
    }
    if (n == 0) campaign.producing = me.epoch;
  }
}

int consume(const Ring<Sample>& ring, Campaign& campaign) {
  auto own = test::attachOwnMapping<Sample>(ring);
  auto reader = own.reader();
  std::uint64_t last_value = 0, last_index = 0, consumed = 0;
  SampleInfo info;
  while (campaign.stop.load() == 0) {
    const auto s = reader.pop(&info);
    if (!s) {
      ::sched_yield();  // not wait(): a sleeping reader would have the producer in FUTEX_WAKE, not in push
      continue;
    }
    if (!s->whole() || s->value() >> kEpochShift != info.epoch) ++campaign.torn;
    if (consumed > 0 && (s->value() <= last_value || info.index <= last_index)) ++campaign.out_of_order;
    if (consumed == 0 || s->value() >> kEpochShift != last_value >> kEpochShift) ++campaign.epochs_seen;
    last_value = s->value();
    last_index = info.index;
    campaign.consumed = ++consumed;
  }
  return 0;
}

TEST(RingKill, AProducerKilledAtRandomMomentsNeverLeavesATornOrOutOfOrderSample) {
  test::SharedBlock<Campaign> campaign;
  auto ring = test::must(Ring<Sample>::create("ring kill", 64));
  Child consumer = Child::run([&] { return consume(ring, *campaign); });

  std::mt19937 random(14);  // NOLINT(cert-msc51-cpp): fixed, so that a failure can be run again
  int killed = 0, never_started = 0;
  for (int k = 1; k <= kKills; ++k) {
    const std::uint32_t before = campaign->producing.load();
    Child producer = Child::run([&] { return produce(ring, *campaign); });
    if (!test::eventually([&] { return campaign->producing.load() != before; })) {
      ++never_started;
      break;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(random() % 2000));  // mid-stream
    producer.kill(SIGKILL);
    killed += test::killedBy(producer.wait(), SIGKILL) ? 1 : 0;
  }
  ASSERT_TRUE(test::eventually([&] { return campaign->consumed.load() > 0; }));
  campaign->stop = 1;
  EXPECT_TRUE(test::exitedWith(consumer.wait(), 0));

  EXPECT_EQ(never_started, 0) << "a new producer could not take the ring over after a kill";
  EXPECT_EQ(killed, kKills) << "a producer ended otherwise than by the kill";
  EXPECT_EQ(campaign->producer_errors.load(), 0u);
  EXPECT_EQ(campaign->torn.load(), 0u) << "of " << campaign->consumed.load() << " samples";
  EXPECT_EQ(campaign->out_of_order.load(), 0u);
  EXPECT_GT(campaign->writers_died.load(), 0u) << "no kill landed inside a push: the repair went untested";
  EXPECT_GT(campaign->epochs_seen.load(), 10u) << "the consumer hardly saw the takeovers";
  std::printf("[   info   ] %d kills, %u inside a push; %llu samples consumed from %llu writers\n", killed,
              campaign->writers_died.load(), static_cast<unsigned long long>(campaign->consumed.load()),
              static_cast<unsigned long long>(campaign->epochs_seen.load()));
}

}  // namespace
}  // namespace keel::runtime::ipc
