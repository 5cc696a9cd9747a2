// Composites under keel: OPRoS gives a composite no state of its own; keel run logs one derived
// from its members' (`state` records with `composite`), and a fault policy can stop a composite
// whole (`<dependency>composite</dependency>`). docs/opros.md, docs/profiles.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

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

std::vector<std::string> compositeStates(const std::vector<nlohmann::json>& log, const std::string& composite) {
  std::vector<std::string> out;
  for (const auto& r : test::eventsOf(log, ev::kState))
    if (r.value(fd::kComposite, "") == composite) out.push_back(r.value(fd::kTo, ""));
  return out;
}

class Composites : public ::testing::Test {
 protected:
  keel::test::ScopedEnv component_path_{"KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS};
  void TearDown() override { std::filesystem::remove(log_); }
  std::string log_ = test::tempPath("keel_composite_test");
};

// Each state once all its members are in it: the composite's lifecycle, as OPRoS's engine
// walked its children through one.
TEST_F(Composites, ACompositeHasTheLifecycleItsMembersShare) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("with_composite.xml"), "--duration", "0.3", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  auto log = test::readLog(log_);
  EXPECT_EQ(compositeStates(log, "pair"), (std::vector<std::string>{"Ready", "Active", "Inactive", "Destroyed"}));
  // Each transition comes after the last member's.
  std::size_t last_member_active = 0, composite_active = 0;
  for (std::size_t i = 0; i < log.size(); ++i) {
    if (log[i].value(fd::kEvent, "") != ev::kState || log[i].value(fd::kTo, "") != "Active") continue;
    if (log[i].value(fd::kComposite, "") == "pair") composite_active = i;
    if (log[i].value(fd::kComponent, "").rfind("pair.", 0) == 0) last_member_active = i;
  }
  EXPECT_GT(composite_active, last_member_active);
}

// The crasher's fault stops its composite: both members, and only them.
TEST_F(Composites, AFaultStopOfScopeCompositeStopsTheWholeCompositeAndNothingElse) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("composite_stop.xml"), "--duration", "0.4", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  auto log = test::readLog(log_);
  auto stops = test::eventsOf(log, ev::kAction);
  auto stop = std::find_if(stops.begin(), stops.end(),
                           [](const auto& a) { return a.value(fd::kAction, "") == "stop"; });
  ASSERT_NE(stop, stops.end()) << r.out;
  EXPECT_EQ((*stop)[fd::kComponents].template get<std::vector<std::string>>(),
            (std::vector<std::string>{"pair.crasher", "pair.counter"}));
  EXPECT_EQ((*stop).value(fd::kScope, ""), "composite");
  EXPECT_EQ(test::statesOf(log, "pair.counter"),
            (std::vector<std::string>{"Ready", "Active", "Inactive", "Destroyed"}));
  EXPECT_EQ(test::statesOf(log, "outside"), (std::vector<std::string>{"Ready", "Active", "Inactive", "Destroyed"}));
  const auto pair = compositeStates(log, "pair");
  ASSERT_GE(pair.size(), 3u);
  EXPECT_EQ(pair[2], "Error") << "a member in Error puts its composite in Error";
}

}  // namespace
}  // namespace keel
