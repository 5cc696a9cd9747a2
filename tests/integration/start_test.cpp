// How a run starts and ends: every component is started (onStart) before any runs its first
// cycle, and every executor has ended its last cycle before any component is stopped (onStop),
// so a first or last onExecute that calls another component's service finds it Active,
// whichever executor was started or stopped first.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "log/schema.hpp"
#include "support/env.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"
#include "support/temp_log.hpp"

namespace keel {
namespace {

TEST(Start, AFirstCycleFindsEveryOtherComponentStarted) {
  const test::ScopedEnv components("KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS);
  const std::string log = test::tempPath("keel_start_test");
  // Several runs: without the hold, the caller's executor (started first) runs its first cycle
  // while the server's is still being started, and its call fails.
  for (int run = 0; run < 5; ++run) {
    auto r = test::runProcess(
        {KEEL_CLI, "run", std::string(KEEL_TEST_PROFILES) + "/first_cycle.xml", "--duration", "0.1", "--log", log});
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_TRUE(test::eventsOf(test::readLog(log), log::schema::event::kDetected).empty()) << "run " << run << r.out;
  }
  std::filesystem::remove(log);
}

TEST(Start, ALastCycleFindsEveryOtherComponentStillActive) {
  const test::ScopedEnv components("KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS);
  const std::string log = test::tempPath("keel_last_cycle_test");
  // Without the barrier at the end, the server's executor (5 ms cycles) stops it while the
  // caller is still 40 ms into its last cycle, whose call then fails: a fault in every run.
  for (int run = 0; run < 3; ++run) {
    auto r = test::runProcess(
        {KEEL_CLI, "run", std::string(KEEL_TEST_PROFILES) + "/last_cycle.xml", "--duration", "0.2", "--log", log});
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    const auto records = test::readLog(log);
    EXPECT_TRUE(test::eventsOf(records, log::schema::event::kDetected).empty()) << "run " << run << r.out;
    EXPECT_EQ(test::statesOf(records, "server"),
              (std::vector<std::string>{"Ready", "Active", "Inactive", "Destroyed"}));
  }
  std::filesystem::remove(log);
}

}  // namespace
}  // namespace keel
