#include "keel/detail/port_queue.hpp"

#include <gtest/gtest.h>

namespace keel::detail {
namespace {

TEST(PortQueue, FifoReturnsOldestFirstAndDropsOldestWhenFull) {
  PortQueue<int> q(3, QueuePolicy::Fifo);
  for (int i = 1; i <= 5; ++i) q.push(i);
  EXPECT_EQ(q.size(), 3u);
  EXPECT_EQ(q.dropped(), 2u);
  EXPECT_EQ(q.pop(), 3);
  EXPECT_EQ(q.pop(), 4);
  EXPECT_EQ(q.pop(), 5);
  EXPECT_EQ(q.pop(), std::nullopt);
}

TEST(PortQueue, LifoReturnsNewestFirstAndDropsOldestWhenFull) {
  PortQueue<int> q(3, QueuePolicy::Lifo);
  for (int i = 1; i <= 4; ++i) q.push(i);
  EXPECT_EQ(q.peek(), 4);
  EXPECT_EQ(q.pop(), 4);
  EXPECT_EQ(q.pop(), 3);
  EXPECT_EQ(q.pop(), 2);  // 1 was dropped
  EXPECT_EQ(q.pop(), std::nullopt);
  EXPECT_EQ(q.dropped(), 1u);
}

TEST(PortQueue, LastKeepsOnlyTheLatestValue) {
  PortQueue<double> q(10, QueuePolicy::Last);
  q.push(1.0);
  q.push(2.0);
  q.push(3.0);
  EXPECT_EQ(q.capacity(), 1u);
  EXPECT_EQ(q.pop(), 3.0);
  EXPECT_EQ(q.pop(), std::nullopt);
}

TEST(PortQueue, UnboundedFifoGrowsAndLosesNothing) {
  PortQueue<int> q(2, QueuePolicy::UFifo);
  for (int i = 0; i < 100; ++i) q.push(i);
  EXPECT_EQ(q.dropped(), 0u);
  EXPECT_EQ(q.size(), 100u);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(q.pop(), i);
}

TEST(PortQueue, WrapsAroundWithoutLosingOrder) {
  PortQueue<int> q(4, QueuePolicy::Fifo);
  int next_in = 0, next_out = 0;
  for (int round = 0; round < 50; ++round) {
    q.push(next_in++);
    q.push(next_in++);
    EXPECT_EQ(q.pop(), next_out++);
    EXPECT_EQ(q.pop(), next_out++);
  }
  EXPECT_EQ(q.dropped(), 0u);
}

TEST(PortQueue, ClearEmptiesTheQueue) {
  PortQueue<std::string> q(4, QueuePolicy::Fifo);
  q.push("a");
  q.push("b");
  q.clear();
  EXPECT_EQ(q.size(), 0u);
  EXPECT_EQ(q.pop(), std::nullopt);
}

}  // namespace
}  // namespace keel::detail
