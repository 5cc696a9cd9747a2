#include "runtime/alarm.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace keel::runtime {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

TEST(Alarm, ASleeperWakesWhenAnotherThreadSetsItForNow) {
  auto alarm = Alarm::create();
  ASSERT_TRUE(alarm) << alarm.error().message;
  std::atomic<bool> woke{false};
  std::thread sleeper([&] {
    alarm->wait();
    woke = true;
  });
  std::this_thread::sleep_for(50ms);
  EXPECT_FALSE(woke.load());  // not set: it sleeps
  alarm->setIn(0ns);
  sleeper.join();  // would hang if the setting did not wake it
  EXPECT_TRUE(woke.load());
}

TEST(Alarm, ItFiresNoSoonerThanSetAndALaterSettingReplacesAnEarlierOne) {
  auto alarm = Alarm::create();
  ASSERT_TRUE(alarm) << alarm.error().message;
  const auto t0 = Clock::now();
  alarm->setIn(10s);  // replaced: the test would take 10 s
  alarm->setIn(40ms);
  alarm->wait();
  EXPECT_GE(Clock::now() - t0, 40ms);
  EXPECT_LT(Clock::now() - t0, 5s);
}

}  // namespace
}  // namespace keel::runtime
