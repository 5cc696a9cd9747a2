// How a run starts: every component is started (onStart) before any runs its first cycle, so a
// first onExecute that calls another component's service finds it Active, whichever executor
// was started first.
#include <gtest/gtest.h>

#include <filesystem>

#include "log/schema.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"
#include "support/temp_log.hpp"

namespace keel {
namespace {

TEST(Start, AFirstCycleFindsEveryOtherComponentStarted) {
  ::setenv("KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS, 1);
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

}  // namespace
}  // namespace keel
