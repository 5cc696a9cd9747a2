// <fault_policy> of a subcomponent (docs/profiles.md): every rule tag read with its value, the
// documented defaults, and each error message with its exact diagnostic.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;
using ::testing::Pair;

const Subcomponent& subcomponent(const ProfileSet& set, const std::string& name) {
  for (const Subcomponent& s : set.rootPackage()->subcomponents) {
    if (s.name == name) return s;
  }
  throw std::runtime_error("no subcomponent " + name);
}

TEST(FaultPolicy, ReadsEveryRuleTag) {
  const auto result = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const Subcomponent& sonar = subcomponent(*result, "sonar");

  ASSERT_TRUE(sonar.fault_policy.has_value());
  const FaultPolicy& p = *sonar.fault_policy;
  EXPECT_EQ(p.severity, Severity::Stop);
  EXPECT_THAT(p.severity_by_kind,  // kinds are normalised to lower case ("Signal")
              ElementsAre(Pair("range", Severity::Ignore), Pair("signal", Severity::Emergency)));
  EXPECT_EQ(p.dependency, Scope::Executor);
  EXPECT_EQ(p.heartbeat_timeout_ms, 100.0);
  EXPECT_EQ(p.deadline_ms, 20.0);
  EXPECT_EQ(p.checkpoint_period_ms, 100.0);
  ASSERT_TRUE(p.alternative.has_value());
  EXPECT_EQ(p.alternative->reference, keyOf("valid/SonarBackup.xml"));
  EXPECT_TRUE(p.alternative->preload);
  EXPECT_EQ(p.alternative->where.line, 22);
  EXPECT_EQ(p.restart.intensity, 5);
  EXPECT_DOUBLE_EQ(p.restart.period_ms, 2000.0);
  EXPECT_EQ(p.where.line, 14);
}

TEST(FaultPolicy, AppliesTheDocumentedDefaultsToAnEmptyPolicy) {
  const auto result = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const Subcomponent& nav = subcomponent(*result, "nav");

  ASSERT_TRUE(nav.fault_policy.has_value());
  const FaultPolicy& p = *nav.fault_policy;
  EXPECT_EQ(p.severity, Severity::Reset);
  EXPECT_TRUE(p.severity_by_kind.empty());
  EXPECT_EQ(p.dependency, Scope::Component);
  EXPECT_FALSE(p.heartbeat_timeout_ms.has_value());
  EXPECT_FALSE(p.deadline_ms.has_value());
  EXPECT_FALSE(p.checkpoint_period_ms.has_value());
  EXPECT_FALSE(p.alternative.has_value());
  EXPECT_EQ(p.restart.intensity, 3);
  EXPECT_DOUBLE_EQ(p.restart.period_ms, 10000.0);
}

TEST(FaultPolicy, IsAbsentWhenTheSubcomponentDeclaresNone) {
  const auto result = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  EXPECT_FALSE(subcomponent(*result, "map").fault_policy.has_value());
}

TEST(FaultPolicy, LoadsTheAlternativeComponentProfile) {
  const auto result = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  const auto it = result->components.find(keyOf("valid/SonarBackup.xml"));
  ASSERT_NE(it, result->components.end());
  EXPECT_EQ(it->second.name, "SonarBackup");
}

TEST(FaultPolicyErrors, RejectsAnUnknownSeverity) {
  EXPECT_THAT(problems("errors/fault/bad_severity.xml"),
              ElementsAre("errors/fault/bad_severity.xml:9: <severity> of fault_policy of subcomponent 'sonar' must be "
                          "one of ignore, reset, stop or emergency, got 'restart'"));
}

TEST(FaultPolicyErrors, RejectsAnUnknownFaultKind) {
  EXPECT_THAT(problems("errors/fault/bad_severity_kind.xml"),
              ElementsAre("errors/fault/bad_severity_kind.xml:9: kind of <severity> of fault_policy of subcomponent "
                          "'sonar' must be one of signal, exception, error_code, range, model, heartbeat, deadline, "
                          "vote, user, remote, process, start, reported or lifecycle, got 'timeout'"));
}

TEST(FaultPolicyErrors, RejectsTwoDefaultSeverities) {
  EXPECT_THAT(problems("errors/fault/duplicate_severity.xml"),
              ElementsAre("errors/fault/duplicate_severity.xml:10: duplicate <severity> in fault_policy of "
                          "subcomponent 'sonar' (first at line 9)"));
}

TEST(FaultPolicyErrors, RejectsTwoSeveritiesForOneKindIgnoringCase) {
  EXPECT_THAT(problems("errors/fault/duplicate_severity_kind.xml"),
              ElementsAre("errors/fault/duplicate_severity_kind.xml:10: duplicate <severity kind=\"range\"> in "
                          "fault_policy of subcomponent 'sonar' (first at line 9)"));
}

TEST(FaultPolicyErrors, RejectsAnUnknownDependencyScope) {
  EXPECT_THAT(problems("errors/fault/bad_dependency.xml"),
              ElementsAre("errors/fault/bad_dependency.xml:9: <dependency> of fault_policy of subcomponent 'sonar' "
                          "must be one of component, executor, composite or system, got 'task'"));
}

TEST(FaultPolicyErrors, RejectsTwoDependencies) {
  EXPECT_THAT(
      problems("errors/fault/duplicate_dependency.xml"),
      ElementsAre(
          "errors/fault/duplicate_dependency.xml:10: duplicate <dependency> in <fault_policy> (first at line 9)"));
}

TEST(FaultPolicyErrors, RejectsAHeartbeatWithoutTimeout) {
  EXPECT_THAT(problems("errors/fault/heartbeat_missing_timeout.xml"),
              ElementsAre("errors/fault/heartbeat_missing_timeout.xml:9: missing attribute 'timeout' of <heartbeat>"));
}

TEST(FaultPolicyErrors, RejectsAMisspeltHeartbeatAttribute) {
  EXPECT_THAT(problems("errors/fault/heartbeat_misspelt_timeout.xml"),
              ElementsAre("errors/fault/heartbeat_misspelt_timeout.xml:9: unknown attribute 'timout' of <heartbeat>",
                          "errors/fault/heartbeat_misspelt_timeout.xml:9: missing attribute 'timeout' of <heartbeat>"));
}

TEST(FaultPolicyErrors, RejectsAZeroHeartbeatTimeout) {
  EXPECT_THAT(problems("errors/fault/heartbeat_zero.xml"),
              ElementsAre("errors/fault/heartbeat_zero.xml:9: timeout of <heartbeat> of fault_policy of subcomponent "
                          "'sonar' must be a positive number, got '0'"));
}

TEST(FaultPolicyErrors, RejectsTextInAnEmptyElement) {
  EXPECT_THAT(problems("errors/fault/text_in_heartbeat.xml"),
              ElementsAre("errors/fault/text_in_heartbeat.xml:9: unexpected text 'fast' in <heartbeat>"));
}

TEST(FaultPolicyErrors, RejectsADeadlineWithUnits) {
  EXPECT_THAT(problems("errors/fault/deadline_not_number.xml"),
              ElementsAre("errors/fault/deadline_not_number.xml:9: <deadline> of fault_policy of subcomponent 'sonar' "
                          "must be a positive number, got '20 ms'"));
}

TEST(FaultPolicyErrors, RejectsANegativeCheckpointPeriod) {
  EXPECT_THAT(problems("errors/fault/checkpoint_negative.xml"),
              ElementsAre("errors/fault/checkpoint_negative.xml:9: period of <checkpoint> of fault_policy of "
                          "subcomponent 'sonar' must be a positive number, got '-100'"));
}

TEST(FaultPolicyErrors, RejectsAMissingAlternativeFile) {
  EXPECT_THAT(problems("errors/fault/alternative_missing_file.xml"),
              ElementsAre("errors/fault/alternative_missing_file.xml:9: <alternative> of subcomponent 'sonar': cannot "
                          "open 'SonarSpare.xml': No such file or directory"));
}

TEST(FaultPolicyErrors, RejectsACompositeAsAlternative) {
  EXPECT_THAT(problems("errors/fault/alternative_is_composite.xml"),
              ElementsAre(
                  "errors/fault/alternative_is_composite.xml:9: <alternative> of subcomponent 'sonar': "
                  "'../../valid/SonarArray.xml' is a <composite_component_profile>, expected <component_profile> "
                  "or <ros2_node_profile>"));
}

TEST(FaultPolicyErrors, RejectsAPreloadThatIsNotABool) {
  EXPECT_THAT(problems("errors/fault/alternative_bad_preload.xml"),
              ElementsAre("errors/fault/alternative_bad_preload.xml:9: preload of <alternative> of fault_policy of "
                          "subcomponent 'sonar' must be true or false, got 'yes'"));
}

TEST(FaultPolicyErrors, RejectsAnAlternativeWithoutReference) {
  EXPECT_THAT(problems("errors/fault/alternative_without_reference.xml"),
              ElementsAre(
                  "errors/fault/alternative_without_reference.xml:9: missing attribute 'reference' of <alternative>"));
}

TEST(FaultPolicyErrors, NamesEveryPortMismatchOfAnAlternative) {
  EXPECT_THAT(
      problems("errors/fault/alternative_ports_differ.xml"),
      ElementsAre("errors/fault/alternative_ports_differ.xml:9: subcomponent 'sonar': alternative 'SonarWrongPorts': "
                  "port 'distance' is an input data port of data_type 'double', but in component 'Sonar' it is an "
                  "output data port of data_type 'double'",
                  "errors/fault/alternative_ports_differ.xml:9: subcomponent 'sonar': alternative 'SonarWrongPorts': "
                  "port 'threshold' is an input data port of data_type 'float', but in component 'Sonar' it is an "
                  "input data port of data_type 'double'",
                  "errors/fault/alternative_ports_differ.xml:9: subcomponent 'sonar': alternative 'SonarWrongPorts' "
                  "has no port 'alarm' (an output event port of data_type 'keel::Event' of component 'Sonar')",
                  "errors/fault/alternative_ports_differ.xml:9: subcomponent 'sonar': alternative 'SonarWrongPorts' "
                  "has port 'debug' that component 'Sonar' does not have"));
}

TEST(FaultPolicyErrors, RejectsANegativeRestartIntensity) {
  EXPECT_THAT(problems("errors/fault/restart_bad_intensity.xml"),
              ElementsAre("errors/fault/restart_bad_intensity.xml:9: intensity of <restart> of fault_policy of "
                          "subcomponent 'sonar' must be an integer from 0 to 1000000, got '-1'"));
}

TEST(FaultPolicyErrors, RejectsAZeroRestartPeriod) {
  EXPECT_THAT(problems("errors/fault/restart_bad_period.xml"),
              ElementsAre("errors/fault/restart_bad_period.xml:9: period of <restart> of fault_policy of subcomponent "
                          "'sonar' must be a positive number, got '0'"));
}

TEST(FaultPolicyErrors, RejectsAnUnknownPolicyElement) {
  EXPECT_THAT(problems("errors/fault/unknown_policy_element.xml"),
              ElementsAre("errors/fault/unknown_policy_element.xml:9: unknown element <watchdog> in <fault_policy>"));
}

// What loads but has no effect is a warning at its line: a passive component's <heartbeat> and
// <deadline> (only an executor times its callbacks) and the `remote` kind (nothing in this keel produces it). A
// passive component's <checkpoint> works (taken between its calls) and a periodic one's
// <deadline> works: no warning for them.
TEST(FaultPolicyWarnings, SettingsWithoutEffectAreWarningsAtTheirLine) {
  const auto set = load(dataPath("warnings/ineffective_policy.xml"));
  ASSERT_TRUE(set.ok()) << joined(set);
  std::vector<std::string> warnings;
  for (const Diagnostic& w : set->warnings) warnings.push_back(relative(w.warningStr()));
  EXPECT_THAT(
      warnings,
      ElementsAre("warnings/ineffective_policy.xml:8: warning: <heartbeat> of subcomponent 'map' has no effect: "
                  "'MapServer' is passive, and its calls run on their callers' threads, whose own heartbeat "
                  "sees a call that hangs",
                  "warnings/ineffective_policy.xml:9: warning: <deadline> of subcomponent 'map' has no effect: "
                  "'MapServer' is passive, and a deadline bounds onExecute, which only an executor calls",
                  "warnings/ineffective_policy.xml:15: warning: <severity kind=\"remote\"> of subcomponent "
                  "'sonar' has no effect: remote faults come from its DDS subscriptions, and this profile's "
                  "<dds> has no <subscribe> of it"));
}

TEST(FaultPolicyWarnings, AValidProfileHasNone) {
  const auto set = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(set.ok()) << joined(set);
  EXPECT_TRUE(set->warnings.empty());
}

}  // namespace
}  // namespace keel::profile::test
