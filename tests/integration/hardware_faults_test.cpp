// Hardware faults of a fault scenario (`keel run --inject`): at its time each goes to the
// component that drives that hardware (keel::HardwareDriver::onHardwareFault, "kind args"), and the log
// gets an `injected` record with "hardware": true; a component that does not take it gives a
// warning and the record's outcome.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <set>

#include "log/schema.hpp"
#include "support/env.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"

namespace keel {
namespace {

std::string hardware(const std::string& name) { return std::string(KEEL_TEST_PROFILES) + "/hardware/" + name; }

struct Received {
  std::string command;
  double at_ms;
};

/// The "[driver] hardware fault '<command>' at <ms> ms" lines the Driver printed.
std::vector<Received> received(const std::string& out) {
  std::vector<Received> got;
  const std::regex line(R"(\[driver\] hardware fault '([^']*)' at (-?\d+) ms)");
  for (std::sregex_iterator it(out.begin(), out.end(), line), end; it != end; ++it)
    got.push_back({(*it)[1], std::stod((*it)[2])});
  return got;
}

class HardwareFaults : public ::testing::Test {
 protected:
  keel::test::ScopedEnv component_path_{"KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS};
  void TearDown() override { std::filesystem::remove(log_); }
  test::Ran run(const std::string& scenario) {
    return test::runProcess(
        {KEEL_CLI, "run", hardware("robot.xml"), "--duration", "0.6", "--inject", hardware(scenario), "--log", log_});
  }
  std::string log_ = (std::filesystem::temp_directory_path() /
                      ("keel_hardware_faults_test_" + std::to_string(::getpid()) + ".jsonl"))
                         .string();
};

TEST_F(HardwareFaults, ReachTheDriverInOrderWithTheirArgsAtTheirTimes) {
  auto r = run("taken.xml");

  ASSERT_EQ(r.status, 0) << r.err;
  const auto got = received(r.out);
  const std::vector<std::pair<std::string, double>> expected = {
      {"motor_power_off left", 100}, {"sensor_stuck 1 250", 150}, {"sensor_unplugged 2", 200},
      {"sensor_unplugged 2", 250},   {"sensor_unplugged 2", 300}, {"motor_power_on", 400}};
  ASSERT_EQ(got.size(), expected.size()) << r.out;
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].command, expected[i].first);
    EXPECT_GT(got[i].at_ms, expected[i].second - 30) << got[i].command;   // onStart is not the injector's t0
    EXPECT_LT(got[i].at_ms, expected[i].second + 300) << got[i].command;  // a loaded machine
  }
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}

TEST_F(HardwareFaults, AreLoggedAsInjectedHardwareFaults) {
  auto r = run("taken.xml");

  ASSERT_EQ(r.status, 0) << r.err;
  const auto injected = test::eventsOf(test::readLog(log_), "injected");
  ASSERT_EQ(injected.size(), 6u);
  std::set<std::uint64_t> ids;
  for (const auto& rec : injected) {
    EXPECT_EQ(rec["component"], "driver");
    EXPECT_EQ(rec[log::schema::field::kHardware], true);
    EXPECT_FALSE(rec.contains("outcome")) << rec.dump();
    ids.insert(rec["fault_id"].get<std::uint64_t>());
  }
  EXPECT_EQ(ids.size(), 6u);  // a fault_id each
  EXPECT_EQ(injected[0]["kind"], "motor_power_off");
  EXPECT_EQ(injected[0]["detail"], "motor_power_off left");
  EXPECT_EQ(injected[1]["detail"], "sensor_stuck 1 250");
  EXPECT_EQ(injected[5]["kind"], "motor_power_on");
  EXPECT_EQ(injected[5]["detail"], "motor_power_on");
  // times since the engine's start: each at or after its scenario time, in order
  const double first_ms = injected[0]["t_ns"].get<double>() / 1e6;
  const double last_ms = injected[5]["t_ns"].get<double>() / 1e6;
  EXPECT_GE(first_ms, 100);
  EXPECT_NEAR(last_ms - first_ms, 300, 200);  // either may be late on a loaded machine
}

TEST_F(HardwareFaults, NotTakenGiveAWarningAndTheOutcome) {
  auto r = run("not_taken.xml");

  ASSERT_EQ(r.status, 0) << r.err;
  const std::string at = hardware("not_taken.xml");
  EXPECT_NE(r.err.find("keel: warning: " + at +
                       ":3: hardware fault 'motor_power_off right' not taken by "
                       "'counter': unsupported\n"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("keel: warning: " + at +
                       ":4: hardware fault 'noise 0.5' not taken by 'driver': bad "
                       "input\n"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("keel: warning: " + at +
                       ":5: hardware fault 'sensor_ok explode' not taken by "
                       "'driver': exception: board unreachable\n"),
            std::string::npos)
      << r.err;
  const auto injected = test::eventsOf(test::readLog(log_), "injected");
  ASSERT_EQ(injected.size(), 3u);
  EXPECT_EQ(injected[0]["component"], "counter");
  EXPECT_EQ(injected[0]["outcome"], "unsupported");
  EXPECT_EQ(injected[1]["outcome"], "bad input");
  EXPECT_EQ(injected[2]["outcome"], "exception: board unreachable");
  for (const auto& rec : injected) EXPECT_EQ(rec[log::schema::field::kHardware], true);
  // the driver got the two it could not apply; the run went on
  ASSERT_EQ(received(r.out).size(), 2u) << r.out;
  EXPECT_TRUE(test::eventsOf(test::readLog(log_), "detected").empty());
}

}  // namespace
}  // namespace keel
