#include "monitor/port_tap.hpp"

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include <keel/component.hpp>

namespace keel::monitor {
namespace {

struct Pose {
  double x, y;
};

class Source : public Component {
 public:
  OutputDataPort<double> range{this, "range"};
  OutputDataPort<std::array<double, 2>> wheels{this, "wheels"};
  OutputDataPort<bool> bumper{this, "bumper"};
  OutputDataPort<Pose> pose{this, "pose"};
  OutputDataPort<std::string> label{this, "label"};
  OutputDataPort<std::array<double, PortTap::kMaxWords - 1>> largest{this, "largest"};
  OutputDataPort<std::array<double, PortTap::kMaxWords>> too_large{this, "too_large"};
};

std::vector<std::string> drained(PortTap& tap) {
  std::vector<std::string> out;
  tap.drain([&](std::int64_t t, const std::string& json) {
    EXPECT_GT(t, 0);
    out.push_back(json);
  });
  return out;
}

TEST(PortTap, TakesEveryValueWhileActiveAsJsonInOrder) {
  Source s;
  PortTap tap(s.range, 8);
  ASSERT_TRUE(tap.attach());
  tap.setActive(true);
  s.range.push(1.5);
  s.range.push(-2.0);
  s.range.push(3.25e10);  // the shortest form that reads back the same
  EXPECT_EQ(drained(tap), (std::vector<std::string>{"1.5", "-2", "3.25e+10"}));
  EXPECT_TRUE(drained(tap).empty()) << "each value once";
  EXPECT_EQ(tap.taken(), 3U);
}

TEST(PortTap, ArraysBooleansAndNonFiniteNumbersHaveTheirJsonForms) {
  Source s;
  PortTap wheels(s.wheels, 4), bumper(s.bumper, 4);
  ASSERT_TRUE(wheels.attach());
  ASSERT_TRUE(bumper.attach());
  wheels.setActive(true);
  bumper.setActive(true);
  s.wheels.push({0.5, std::numeric_limits<double>::quiet_NaN()});
  s.bumper.push(true);
  EXPECT_EQ(drained(wheels), (std::vector<std::string>{"[0.5,null]"}));
  EXPECT_EQ(drained(bumper), (std::vector<std::string>{"true"}));
}

TEST(PortTap, PortsWithoutAJsonFormAreNotTapped) {
  Source s;
  PortTap pose(s.pose, 4), label(s.label, 4);
  EXPECT_FALSE(pose.attach()) << "a struct has bytes but no JSON form";
  EXPECT_FALSE(label.attach()) << "a std::string is not trivially copyable";
}

TEST(PortTap, TakesValuesUpToItsLargestInASmallerRing) {
  Source s;
  PortTap largest(s.largest, 1 << 20), too_large(s.too_large, 4), range(s.range, 1000);
  ASSERT_TRUE(largest.attach()) << "with its time, 64 words";
  EXPECT_FALSE(too_large.attach());
  EXPECT_EQ(range.capacity(), 1024U) << "rounded up to a power of two";
  EXPECT_EQ(largest.capacity(), 4096U) << "2 MiB of 512-byte slots";
  largest.setActive(true);
  std::array<double, PortTap::kMaxWords - 1> v{};
  v.back() = 7.5;
  s.largest.push(v);
  const auto got = drained(largest);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_TRUE(got[0].ends_with(",0,7.5]")) << got[0];
}

TEST(PortTap, InactiveItKeepsOnlyTheNewestValue) {
  Source s;
  PortTap tap(s.range, 8);
  ASSERT_TRUE(tap.attach());
  std::string newest;
  EXPECT_FALSE(tap.newest([&](std::int64_t, const std::string& j) { newest = j; })) << "nothing sent yet";
  s.range.push(1.0);
  s.range.push(2.0);
  EXPECT_TRUE(drained(tap).empty()) << "nothing queued while inactive";
  EXPECT_TRUE(tap.newest([&](std::int64_t, const std::string& j) { newest = j; }));
  EXPECT_EQ(newest, "2");
}

TEST(PortTap, AFullRingDropsAndCountsAndNeverBlocksTheSender) {
  Source s;
  PortTap tap(s.range, 4);
  ASSERT_TRUE(tap.attach());
  tap.setActive(true);
  for (int i = 0; i < 10; ++i) s.range.push(i);
  EXPECT_EQ(drained(tap), (std::vector<std::string>{"0", "1", "2", "3"})) << "the oldest kept, the rest dropped";
  EXPECT_EQ(tap.dropped(), 6U);
  s.range.push(42);
  EXPECT_EQ(drained(tap), (std::vector<std::string>{"42"})) << "room again once drained";
}

}  // namespace
}  // namespace keel::monitor
