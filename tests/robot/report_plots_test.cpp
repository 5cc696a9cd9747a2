// keel report --plots on a recorded run of the test robot (Fig. 6's experiment): the timeline, Fig.
// 6 from the recording's wheel ports and the trajectory from its referee's truth and world ports;
// with the referee's trace, both on simulated time.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "support/paths.hpp"
#include "support/process.hpp"

namespace keel::test {
namespace {

namespace fs = std::filesystem;

class RobotReport : public ::testing::Test {
 protected:
  void SetUp() override {
    if (test::runProcess({"/usr/bin/python3", "-c", "import matplotlib"}).status != 0)
      GTEST_SKIP() << "no matplotlib for /usr/bin/python3 (scripts/deps.sh installs it)";
    dir_ = fs::temp_directory_path() / ("keel_robot_report_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);  // kept for a look when something failed
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(RobotReport, PlotsTheTrajectoryAndFig6FromTheRecordingAlone) {
  const Ran run = runProcess({KEEL_CLI, "run", std::string(KEEL_ROBOT) + "/navigation.xml", "--duration", "5",
                              "--inject", std::string(KEEL_ROBOT) + "/scenarios/fig6_left_motor_off.xml", "--record",
                              path("run.mcap"), "--set", "referee.trace=" + path("trace.csv")});
  ASSERT_EQ(run.status, 0) << run.err;

  const Ran plots = runProcess({KEEL_CLI, "report", path("run.mcap"), "--plots", path("plots")});
  ASSERT_EQ(plots.status, 0) << plots.err;
  EXPECT_TRUE(plots.out.starts_with(run.out)) << plots.out;
  EXPECT_EQ(plots.err.find("no trajectory.svg"), std::string::npos) << plots.err;
  const std::string trajectory = slurp(path("plots/trajectory.svg"));
  EXPECT_NE(trajectory.find("model@actuator"), std::string::npos) << "the detection, where the robot was";
  EXPECT_NE(trajectory.find(">target<"), std::string::npos) << "the world, from the referee's world port";
  const std::string fig6 = slurp(path("plots/fig6.svg"));
  EXPECT_NE(fig6.find("time since the run started (ms)"), std::string::npos);
  EXPECT_NE(fig6.find("model@actuator"), std::string::npos) << "the detection, with its delay";
  EXPECT_NE(slurp(path("plots/timeline.svg")).find("actuator"), std::string::npos);

  const Ran traced = runProcess(
      {KEEL_CLI, "report", path("run.mcap"), "--plots", path("traced"), "--trace", path("trace.csv")});
  ASSERT_EQ(traced.status, 0) << traced.err;
  for (const char* svg : {"timeline.svg", "trajectory.svg", "fig6.svg"})
    EXPECT_NE(slurp(path(std::string("traced/") + svg)).find("</svg>"), std::string::npos) << svg;
  EXPECT_NE(slurp(path("traced/fig6.svg")).find("simulated time (ms)"), std::string::npos);
}

}  // namespace
}  // namespace keel::test
