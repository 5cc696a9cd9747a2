#include "injection/scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/temp_log.hpp"

namespace keel::injection {
namespace {

class ScenarioFile : public ::testing::Test {
 protected:
  std::string write(const std::string& body) {
    std::ofstream(path_) << body;
    return path_;
  }
  void TearDown() override { std::filesystem::remove(path_); }
  /// Every diagnostic of a scenario that failed to load, as `file:line: message`.
  static std::vector<std::string> problems(const Result<Scenario, profile::Diagnostics>& s) {
    std::vector<std::string> got;
    for (const auto& d : s.error()) got.push_back(d.str());
    return got;
  }
  std::string path_ = test::tempPath("keel_scenario", ".xml");
};

TEST_F(ScenarioFile, ReadsEveryAttributeAndSortsByTime) {
  auto s = loadScenario(write(R"(<fault_scenario>
  <fault at="300" component="b" kind="out_of_range" port="distance" value="0"/>
  <fault at="100" component="a" kind="segfault" repeat="3" every="50"/>
  <fault at="200" component="c" kind="stall_heartbeat" duration="80"/>
</fault_scenario>)"));
  ASSERT_TRUE(s) << s.error().front().str();
  ASSERT_EQ(s->faults.size(), 3u);
  EXPECT_EQ(s->faults[0].component, "a");
  EXPECT_EQ(s->faults[0].kind, runtime::InjectKind::Segfault);
  EXPECT_EQ(s->faults[0].repeat, 3);
  EXPECT_EQ(s->faults[0].every_ms, 50);
  EXPECT_EQ(s->faults[1].duration_ms, 80);
  EXPECT_EQ(s->faults[2].port, "distance");
  EXPECT_EQ(s->faults[2].value, 0.0);
  EXPECT_EQ(s->faults[2].where.line, 2);
}

TEST_F(ScenarioFile, OutOfRangeDefaultsToNaN) {
  auto s = loadScenario(write(R"(<fault_scenario><fault at="1" component="a" kind="out_of_range"/></fault_scenario>)"));
  ASSERT_TRUE(s);
  EXPECT_TRUE(std::isnan(s->faults[0].value));
}

TEST_F(ScenarioFile, ReportsEveryProblemWithFileAndLine) {
  auto s = loadScenario(write(R"(<fault_scenario>
  <fault at="-5" component="a" kind="segfault"/>
  <fault at="10" kind="explode"/>
  <fault at="10" component="a" kind="throw" speed="3"/>
  <oops/>
</fault_scenario>)"));
  ASSERT_FALSE(s);
  const std::string f = path_;
  EXPECT_EQ(problems(s),
            (std::vector<std::string>{
                f + ":2: <fault>: attribute 'at' must be a number >= 0 and <= 1000000000, got '-5'",
                f + ":3: <fault>: attribute 'component' is required",
                f + ":3: <fault>: unknown kind 'explode' (kinds: segfault, divide_by_zero, abort, "
                    "throw, error_code, hang, stall_heartbeat, out_of_range, kill; hardware: sensor_unplugged, "
                    "sensor_stuck, sensor_ok, motor_power_off, motor_power_on, noise, encoder_dead, encoder_ok, "
                    "gyro_dead, gyro_ok)",
                f + ":4: <fault>: unknown attribute 'speed' (known: at, component, kind, port, "
                    "value, duration, repeat, every, args)",
                f + ":5: unknown element <oops> in <fault_scenario> (expected <fault>)",
            }));
}

TEST_F(ScenarioFile, RejectsAnotherRootElement) {
  auto s = loadScenario(write("<package_profile/>"));
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().front().str(), path_ + ":1: root element must be <fault_scenario>, got <package_profile>");
}

TEST_F(ScenarioFile, RejectsRepeatWithoutEvery) {
  auto s = loadScenario(
      write(R"(<fault_scenario><fault at="1" component="a" kind="throw" repeat="2"/></fault_scenario>)"));
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().front().message, "<fault>: repeat needs every (ms) > 0");
}

// Found by the scenario fuzzer: repeat="6.6e56" was cast to int (undefined). Times and counts
// beyond what the injector can compute with are errors.
TEST_F(ScenarioFile, RejectsTimesAndCountsBeyondItsBounds) {
  auto s = loadScenario(write(R"(<fault_scenario>
  <fault at="1e300" component="a" kind="throw"/>
  <fault at="1" component="a" kind="throw" repeat="6.66667e+56" every="1"/>
  <fault at="1" component="a" kind="throw" repeat="2.5" every="1"/>
  <fault at="1" component="a" kind="hang" duration="1e10"/>
  <fault at="1" component="a" kind="throw" every="1e12"/>
</fault_scenario>)"));
  ASSERT_FALSE(s);
  EXPECT_EQ(problems(s), (std::vector<std::string>{
                             path_ + ":2: <fault>: attribute 'at' must be a number >= 0 and <= 1000000000, got '1e300'",
                             path_ + ":3: <fault>: attribute 'repeat' must be a number >= 1 and <= 1000000, got "
                                     "'6.66667e+56'",
                             path_ + ":4: <fault>: attribute 'repeat' must be a whole number, got '2.5'",
                             path_ + ":5: <fault>: attribute 'duration' must be a number >= 0 and <= 1000000000, got "
                                     "'1e10'",
                             path_ + ":6: <fault>: attribute 'every' must be a number >= 0 and <= 1000000000, got "
                                     "'1e12'",
                         }));
}

TEST_F(ScenarioFile, ReadsHardwareFaultsWithTheirArgs) {
  auto s = loadScenario(write(R"(<fault_scenario>
  <fault at="100" component="actuator" kind="motor_power_off" args="left"/>
  <fault at="200" component="sonars" kind="sensor_stuck" args=" 1 250 " repeat="2" every="10"/>
  <fault at="300" component="actuator" kind="motor_power_on"/>
  <fault at="400" component="sonars" kind="sensor_unplugged" args="3"/>
  <fault at="500" component="sonars" kind="sensor_ok" args="3"/>
  <fault at="600" component="camera" kind="noise" args="0.2"/>
</fault_scenario>)"));
  ASSERT_TRUE(s) << s.error().front().str();
  ASSERT_EQ(s->faults.size(), 6u);
  const ScheduledFault& off = s->faults[0];
  EXPECT_TRUE(off.hardware);
  EXPECT_EQ(off.kind, runtime::InjectKind::None);
  EXPECT_EQ(off.kind_name, "motor_power_off");
  EXPECT_EQ(off.args, "left");
  EXPECT_EQ(off.command(), "motor_power_off left");
  EXPECT_EQ(s->faults[1].command(), "sensor_stuck 1 250");  // args trimmed
  EXPECT_EQ(s->faults[1].repeat, 2);
  EXPECT_EQ(s->faults[2].command(), "motor_power_on");  // no args
  EXPECT_EQ(s->faults[5].command(), "noise 0.2");
  for (const char* kind :
       {"sensor_unplugged", "sensor_stuck", "sensor_ok", "motor_power_off", "motor_power_on", "noise"})
    EXPECT_TRUE(isHardwareKind(kind)) << kind;
  EXPECT_FALSE(isHardwareKind("segfault"));
}

TEST_F(ScenarioFile, SoftwareKindsTakeNoArgsAndHardwareKindsNothingElse) {
  auto s = loadScenario(write(R"(<fault_scenario>
  <fault at="1" component="a" kind="segfault" args="left"/>
  <fault at="1" component="a" kind="motor_power_off" port="distance" duration="5"/>
  <fault at="1" component="a" kind="noise" value="3"/>
</fault_scenario>)"));
  ASSERT_FALSE(s);
  const std::string f = path_;
  EXPECT_EQ(problems(s),
            (std::vector<std::string>{
                f + ":2: <fault>: attribute 'args' is for the hardware kinds; 'segfault' takes none",
                f + ":3: <fault>: attribute 'port' is not for hardware kind 'motor_power_off' (it takes args)",
                f + ":3: <fault>: attribute 'duration' is not for hardware kind 'motor_power_off' (it takes "
                    "args)",
                f + ":4: <fault>: attribute 'value' is not for hardware kind 'noise' (it takes args)",
            }));
}

}  // namespace
}  // namespace keel::injection
