// `keel run --set INSTANCE.PROPERTY=VALUE`: the value reaches the component (after the
// profile's own overrides, in a package or in a system), and each bad setting is one line and
// exit 2 before anything runs.
#include <gtest/gtest.h>

#include <filesystem>

#include "log/schema.hpp"
#include "support/env.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"

namespace keel {
namespace {

std::string profile(const std::string& name) { return std::string(KEEL_TEST_PROFILES) + "/" + name; }

class SetOption : public ::testing::Test {
 protected:
  keel::test::ScopedEnv component_path_{"KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS};
  void TearDown() override { std::filesystem::remove(log_); }
  test::Ran run(const std::string& name, std::vector<std::string> sets, const std::string& duration = "30") {
    std::vector<std::string> argv = {KEEL_CLI, "run", profile(name), "--duration", duration, "--log", log_};
    for (auto& s : sets) {
      argv.emplace_back("--set");
      argv.push_back(std::move(s));
    }
    return test::runProcess(argv);
  }
  std::string log_ = (std::filesystem::temp_directory_path() /
                      ("keel_set_option_test_" + std::to_string(::getpid()) + ".jsonl"))
                         .string();
};

TEST_F(SetOption, TheValueReachesTheComponentAfterTheProfilesOverride) {
  // finish/mission.xml makes the finisher end the run after 20 executions
  auto r = run("finish/mission.xml", {"finisher.end_after=30", "finisher.end_after=7"});

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("ended by finisher: done after 7 executions"), std::string::npos) << r.out;
  const auto log = test::readLog(log_);
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log.back()["executions"], 7);
  EXPECT_EQ(log.front()["phase"], "load");
  EXPECT_EQ(log.front()[log::schema::field::kSet], nlohmann::json({"finisher.end_after=30", "finisher.end_after=7"}));
}

TEST_F(SetOption, NamesAnInstanceOfAnApplicationInASystem) {
  auto r = run("linked/system.xml", {"consumer.summer.label=relayed"}, "1");

  ASSERT_EQ(r.status, 0) << r.err;
  const auto detected = test::eventsOf(test::readLog(log_), "detected");
  ASSERT_FALSE(detected.empty()) << r.out;
  EXPECT_EQ(detected[0]["component"], "consumer.events");
  EXPECT_EQ(detected[0]["detail"], "milestone 30 reached: relayed");
}

TEST_F(SetOption, RejectsAnUnknownInstanceListingTheInstances) {
  auto r = run("finish/mission.xml", {"finsher.end_after=7"});

  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "keel run: --set 'finsher.end_after=7': no instance 'finsher' (instances: counter, finisher)\n");
  EXPECT_FALSE(std::filesystem::exists(log_));  // nothing ran
}

TEST_F(SetOption, RejectsAPropertyTheComponentDoesNotDeclareListingItsProperties) {
  auto r = run("finish/mission.xml", {"finisher.end_at=7"});

  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err,
            "keel run: --set 'finisher.end_at=7': component 'Finisher' of instance 'finisher' has no "
            "property 'end_at' (properties: end_after, end_on_stop, event, fields)\n");
}

TEST_F(SetOption, RejectsAValueNotOfThePropertysTypeNamingTheType) {
  auto r = run("finish/mission.xml", {"finisher.end_on_stop=maybe", "finisher.end_after=soon"});

  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err,
            "keel run: --set 'finisher.end_on_stop=maybe': property 'end_on_stop' of instance 'finisher' is of type "
            "bool: the value must be a bool (true, false, 1 or 0), got 'maybe'\n"
            "keel run: --set 'finisher.end_after=soon': property 'end_after' of instance 'finisher' is of type int: "
            "the value must be an int, got 'soon'\n");
}

TEST_F(SetOption, RejectsTextThatIsNotInstancePropertyEqualsValue) {
  auto r = run("finish/mission.xml", {"end_after=7"});

  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "keel run: --set 'end_after=7': expected INSTANCE.PROPERTY=VALUE (e.g. actuator.seed=7)\n");
}

}  // namespace
}  // namespace keel
