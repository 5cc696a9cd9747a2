// The compiled fault rules (src/fault/rules.hpp): severities per kind, the first handling step
// of each severity, defaults without a policy; a report's action list.
#include "fault/rules.hpp"

#include <gtest/gtest.h>

#include "fault/report.hpp"

namespace keel::fault {
namespace {

using profile::Severity;

TEST(Rules, WithoutAPolicyAFaultThatStopsTheComponentIsContainedAndTheOthersAreLogged) {
  const Rules r = compileRules(nullptr, {});
  EXPECT_FALSE(r.has_policy);
  for (FaultKind k : {FaultKind::Signal, FaultKind::Exception, FaultKind::ErrorCode, FaultKind::Heartbeat})
    EXPECT_EQ(r.severityOf(k), Severity::Stop) << toString(k);
  for (FaultKind k : {FaultKind::Range, FaultKind::Model, FaultKind::Deadline, FaultKind::Vote, FaultKind::User})
    EXPECT_EQ(r.severityOf(k), Severity::Ignore) << toString(k);
}

TEST(Rules, APolicySeverityAppliesToEveryKindExceptThoseGivenPerKind) {
  profile::FaultPolicy p;
  p.severity = Severity::Reset;
  p.severity_by_kind["range"] = Severity::Ignore;
  p.severity_by_kind["heartbeat"] = Severity::Emergency;
  const Rules r = compileRules(&p, {});
  EXPECT_EQ(r.severityOf(FaultKind::Signal), Severity::Reset);
  EXPECT_EQ(r.severityOf(FaultKind::User), Severity::Reset);
  EXPECT_EQ(r.severityOf(FaultKind::Range), Severity::Ignore);
  EXPECT_EQ(r.severityOf(FaultKind::Heartbeat), Severity::Emergency);
}

TEST(Rules, StopReplacesWhenAnAlternativeIsDeclaredAndStopsOtherwise) {
  profile::FaultPolicy p;
  Rules none = compileRules(&p, {});
  EXPECT_EQ(none.firstStep(Severity::Stop), Step::Stop);
  EXPECT_EQ(none.firstStep(Severity::Reset), Step::Reset);
  EXPECT_EQ(none.firstStep(Severity::Emergency), Step::Emergency);
  EXPECT_EQ(none.firstStep(Severity::Ignore), Step::Ignore);

  std::map<std::string, profile::ComponentProfile> components;
  components["/p/Backup.xml"].name = "Backup";
  p.alternative = profile::Alternative{"/p/Backup.xml", true, {}};
  const Rules with = compileRules(&p, components);
  ASSERT_NE(with.alternative, nullptr);
  EXPECT_EQ(with.alternative->name, "Backup");
  EXPECT_TRUE(with.preload);
  EXPECT_EQ(with.firstStep(Severity::Stop), Step::Replace);
}

TEST(Rules, ActionsAreRecordedInOrderAndTheListNeverOverflows) {
  FaultReport r;
  r.add(ActionKind::Reset, true, 5, "reset {}", 1);
  r.add(ActionKind::Escalate, true, 6, "reset → {}", "stop");
  ASSERT_EQ(r.n_actions, 2);
  EXPECT_STREQ(r.actions[1].detail.data(), "reset → stop");
  for (int i = 0; i < 100; ++i) r.add(ActionKind::Stop, false, 7, "x");
  EXPECT_EQ(r.n_actions, r.actions.size());
}

}  // namespace
}  // namespace keel::fault
