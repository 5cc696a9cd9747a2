// keel's /diagnostics (src/dds/diagnostics): the DiagnosticArray made of the components'
// health, and the writer's rhythm: a snapshot at start, after each poke, and every period.
#include "dds/diagnostics.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

namespace keel::dds {
namespace {

using namespace std::chrono_literals;
using msg::diagnostic_msgs::DiagnosticArray;
using msg::diagnostic_msgs::DiagnosticStatus;

TEST(Diagnostics, EachComponentIsOneStatusWithItsLevelStateFaultsAndLastFault) {
  const std::vector<Health> health = {{"keel/nav/sonar", Health::Error, "in Error after a fault", "Error", 2,
                                       "exception (fault 7): stop"},
                                      {"keel/nav/planner", Health::Ok, "running", "Active", 0, ""}};
  const DiagnosticArray a = diagnosticArray(health, 1'700'000'000'123'456'789);
  EXPECT_EQ(a.header.stamp.sec, 1'700'000'000);
  EXPECT_EQ(a.header.stamp.nanosec, 123'456'789u);
  ASSERT_EQ(a.status.size(), 2u);
  const DiagnosticStatus& s = a.status[0];
  EXPECT_EQ(s.level, DiagnosticStatus::ERROR);
  EXPECT_EQ(s.name, "keel/nav/sonar");
  EXPECT_EQ(s.message, "in Error after a fault");
  EXPECT_EQ(s.hardware_id, "keel");
  ASSERT_EQ(s.values.size(), 3u);
  EXPECT_EQ(s.values[0].key, "state");
  EXPECT_EQ(s.values[0].value, "Error");
  EXPECT_EQ(s.values[1].key, "faults");
  EXPECT_EQ(s.values[1].value, "2");
  EXPECT_EQ(s.values[2].key, "last_fault");
  EXPECT_EQ(s.values[2].value, "exception (fault 7): stop");
  EXPECT_EQ(a.status[1].level, DiagnosticStatus::OK);
  EXPECT_EQ(Health::Warn, DiagnosticStatus::WARN);
  EXPECT_EQ(Health::Stale, DiagnosticStatus::STALE);
}

/// Counts what the writer publishes, and lets a test wait for the next.
struct Published {
  std::mutex mutex;
  std::vector<std::size_t> sizes;
  bool waitFor(std::size_t n, std::chrono::milliseconds within) {
    const auto end = std::chrono::steady_clock::now() + within;
    while (std::chrono::steady_clock::now() < end) {
      {
        std::lock_guard lock(mutex);
        if (sizes.size() >= n) return true;
      }
      std::this_thread::sleep_for(1ms);
    }
    std::lock_guard lock(mutex);
    return sizes.size() >= n;
  }
  std::size_t count() {
    std::lock_guard lock(mutex);
    return sizes.size();
  }
};

TEST(Diagnostics, TheWriterPublishesAtStartAfterEachPokeAndNotOtherwise) {
  Published out;
  std::atomic<int> components{1};
  // A period of an hour: every write within the test is the start's or a poke's.
  DiagnosticsWriter w([&] { return std::vector<Health>(components.load(), Health{}); },
                      [&](const DiagnosticArray& a) {
                        std::lock_guard lock(out.mutex);
                        out.sizes.push_back(a.status.size());
                      },
                      std::chrono::hours(1));
  ASSERT_TRUE(out.waitFor(1, 10s));
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(out.count(), 1u);  // nothing until poked
  components = 3;
  w.poke();
  ASSERT_TRUE(out.waitFor(2, 10s));  // a fresh snapshot, not the last one again
  std::lock_guard lock(out.mutex);
  EXPECT_EQ(out.sizes.back(), 3u);
}

TEST(Diagnostics, TheWriterPublishesEveryPeriodWithoutPokes) {
  Published out;
  DiagnosticsWriter w([] { return std::vector<Health>{}; },
                      [&](const DiagnosticArray&) {
                        std::lock_guard lock(out.mutex);
                        out.sizes.push_back(0);
                      },
                      20ms);
  EXPECT_TRUE(out.waitFor(4, 10s));
  w.stop();
  const std::size_t n = out.count();
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(out.count(), n);  // stopped: no more
}

}  // namespace
}  // namespace keel::dds
