// Bad input that only a run can find (docs/bad-input.md): a library without the component a
// profile names, a component whose constructor throws, a scenario naming a component the run
// does not have. Each is refused with its file:line before anything starts: exit 1, no
// component initialised (those constructed are destroyed), and the reason on stderr.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "log/schema.hpp"
#include "support/env.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"
#include "support/temp_log.hpp"

namespace keel {
namespace {

namespace ev = log::schema::event;
namespace fd = log::schema::field;

std::string profile(const std::string& name) { return std::string(KEEL_TEST_PROFILES) + "/" + name; }

class BadInput : public ::testing::Test {
 protected:
  keel::test::ScopedEnv component_path_{"KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS};
  void TearDown() override {
    std::filesystem::remove(log_);
    std::filesystem::remove(scenario_);
  }
  /// Runs `args` and checks that it was refused before anything started.
  test::Ran refused(const std::vector<std::string>& args) {
    std::vector<std::string> argv = {KEEL_CLI, "run"};
    argv.insert(argv.end(), args.begin(), args.end());
    argv.insert(argv.end(), {"--duration", "0.3", "--log", log_});
    test::Ran r = test::runProcess(argv);
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    for (const auto& state : test::statesOf(test::readLog(log_), "counter"))  // constructed, then destroyed
      EXPECT_TRUE(state == "Destroyed") << "the good component was initialised: " << state;
    for (const auto& e : test::eventsOf(test::readLog(log_), ev::kEngine))
      EXPECT_NE(e.value(fd::kPhase, ""), "started");
    return r;
  }
  std::string log_ = test::tempPath("keel_bad_input");
  std::string scenario_ = test::tempPath("keel_bad_input_scenario", ".xml");
};

TEST_F(BadInput, ALibraryWithoutTheComponentIsRefusedNamingWhatItHas) {
  const auto r = refused({profile("bad/missing_class.xml")});
  EXPECT_NE(r.err.find(profile("bad/Ghost.xml") + ":3: component 'missing_class': library '"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("libkeel_test_components.so' registers no component 'Ghost' (it has: "), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("Counter"), std::string::npos) << "the classes it has are listed\n" << r.err;
}

TEST_F(BadInput, AComponentWhoseConstructorThrowsIsRefusedWithItsMessage) {
  const auto r = refused({profile("bad/throws_in_constructor.xml")});
  EXPECT_NE(r.err.find(profile("bad/Fragile.xml") + ":3: component 'throws_in_constructor': constructing 'Fragile' "
                                                    "failed: no calibration file at /etc/fragile.yaml"),
            std::string::npos)
      << r.err;
}

TEST_F(BadInput, AScenarioNamingAComponentTheRunDoesNotHaveIsRefusedAtItsLine) {
  std::ofstream(scenario_) << "<?xml version=\"1.0\"?>\n<fault_scenario>\n"
                              "  <fault at=\"100\" component=\"counter\" kind=\"throw\"/>\n"
                              "  <fault at=\"100\" component=\"nobody\" kind=\"throw\"/>\n"
                              "</fault_scenario>\n";
  const auto r = refused({profile("pipeline.xml"), "--inject", scenario_});
  EXPECT_NE(r.err.find(scenario_ + ":4: fault: no component 'nobody' in this run"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(":3:"), std::string::npos) << "the good line is not reported\n" << r.err;
}

}  // namespace
}  // namespace keel
