// The soak's audit of a round of the fault log (src/soak/log_audit): each thing it must find
// wrong, in a log made to have it, and what it must not call wrong.
#include "soak/log_audit.hpp"

#include <gtest/gtest.h>

#include <string>

namespace keel::soak {
namespace {

const std::string kStart = R"({"event":"engine","phase":"load","t_ns":1})"
                           "\n"
                           R"({"event":"engine","phase":"started","t_ns":2})"
                           "\n";
const std::string kEnd = R"({"event":"engine","phase":"stopping","reason":"round over","t_ns":9000000000})"
                         "\n"
                         R"({"event":"engine","phase":"stopped","t_ns":9000000100})"
                         "\n";
const std::string kArmed = R"({"component":"a","event":"armed","fault_id":1,"kind":"segfault","t_ns":1000})"
                           "\n";
const std::string kInjected = R"({"component":"a","event":"injected","fault_id":1,"t_ns":2000})"
                              "\n";
const std::string kDetected =
    R"({"component":"a","event":"detected","fault_id":1,"kind":"signal","detail":"SIGSEGV","t_ns":2100})"
    "\n";
const std::string kDiagnosed =
    R"({"component":"a","event":"diagnosed","fault_id":1,"severity":"reset","scope":"component","t_ns":2200})"
    "\n";
const std::string kAction =
    R"({"component":"a","event":"action","fault_id":1,"action":"reset","outcome":"ok","t_ns":2300})"
    "\n";

std::string joinedViolations(const RoundAudit& a) {
  std::string s;
  for (const auto& v : a.violations) s += v + '\n';
  return s;
}

TEST(SoakAudit, AFaultDetectedDiagnosedAndHandledIsCountedAndNothingIsWrong) {
  const RoundAudit a = auditRound(kStart + kArmed + kInjected + kDetected + kDiagnosed + kAction + kEnd, 1);
  EXPECT_TRUE(a.violations.empty()) << joinedViolations(a);
  EXPECT_EQ(a.lines, 9u);
  EXPECT_EQ(a.detected, 1);
  ASSERT_TRUE(a.by_kind.contains("segfault"));
  EXPECT_EQ(a.by_kind.at("segfault").armed, 1);
  EXPECT_EQ(a.by_kind.at("segfault").handled, 1);
}

TEST(SoakAudit, ATornLineIsAViolationAtItsLineNumber) {
  const std::string torn = R"({"component":"a","event":"detec)"
                           "\n";
  const RoundAudit a = auditRound(kStart + kArmed + torn + kEnd, 101);
  ASSERT_EQ(a.violations.size(), 1u) << joinedViolations(a);
  EXPECT_NE(a.violations[0].find("line 104: not a whole record"), std::string::npos) << a.violations[0];
}

TEST(SoakAudit, ALogEndingInsideALineIsTorn) {
  const RoundAudit a = auditRound(kStart + kEnd + R"({"event":"engine")", 1);
  ASSERT_EQ(a.violations.size(), 1u) << joinedViolations(a);
  EXPECT_NE(a.violations[0].find("line 5: the log ends inside a line"), std::string::npos) << a.violations[0];
}

TEST(SoakAudit, NulBytesWhereALineShouldBeAreAHole) {
  const RoundAudit a = auditRound(kStart + std::string(12, '\0') + "\n" + kEnd, 1);
  ASSERT_EQ(a.violations.size(), 1u) << joinedViolations(a);
  EXPECT_NE(a.violations[0].find("line 3: NUL bytes"), std::string::npos) << a.violations[0];
}

TEST(SoakAudit, ARunWithoutItsEngineRecordsIsMissingThem) {
  const RoundAudit a = auditRound(kStart, 1);
  EXPECT_NE(joinedViolations(a).find("no engine 'stopping' record"), std::string::npos) << joinedViolations(a);
  EXPECT_NE(joinedViolations(a).find("no engine 'stopped' record"), std::string::npos) << joinedViolations(a);
}

TEST(SoakAudit, ADetectedFaultNeverDiagnosedOrNeverHandledIsAViolation) {
  const RoundAudit undiagnosed = auditRound(kStart + kArmed + kInjected + kDetected + kEnd, 1);
  ASSERT_EQ(undiagnosed.violations.size(), 1u) << joinedViolations(undiagnosed);
  EXPECT_NE(undiagnosed.violations[0].find("fault 1 (segfault of 'a'): detected, never diagnosed"), std::string::npos)
      << undiagnosed.violations[0];
  const RoundAudit unhandled = auditRound(kStart + kArmed + kInjected + kDetected + kDiagnosed + kEnd, 1);
  ASSERT_EQ(unhandled.violations.size(), 1u) << joinedViolations(unhandled);
  EXPECT_NE(unhandled.violations[0].find("diagnosed, no action taken"), std::string::npos) << unhandled.violations[0];
  // A fault nobody injected (a consequence: a voter's, a monitor's) must be handled too.
  const std::string own = R"({"component":"v","event":"detected","fault_id":7,"kind":"vote","t_ns":5})"
                          "\n";
  EXPECT_EQ(auditRound(kStart + own + kEnd, 1).violations.size(), 1u);
}

TEST(SoakAudit, AnInjectedFaultNoDetectorSawIsAViolation) {
  const std::string undetected = R"({"component":"a","event":"injected","fault_id":1,"detected":false,"t_ns":2000})"
                                 "\n";
  const RoundAudit a = auditRound(kStart + kArmed + kEnd + undetected, 1);
  ASSERT_EQ(a.violations.size(), 1u) << joinedViolations(a);
  EXPECT_NE(a.violations[0].find("fault 1 (segfault of 'a'): injected, never detected"), std::string::npos)
      << a.violations[0];
}

TEST(SoakAudit, AnUndetectedFaultOvertakenByItsComponentsStopOrTheRoundsEndIsNotAViolation) {
  const std::string late = R"({"component":"a","event":"injected","fault_id":1,"detected":false,"t_ns":8500000000})"
                           "\n";
  RoundAudit a = auditRound(kStart + kArmed + kEnd + late, 1);
  EXPECT_TRUE(a.violations.empty()) << joinedViolations(a);
  EXPECT_EQ(a.by_kind.at("segfault").overtaken, 1);

  const std::string undetected = R"({"component":"a","event":"injected","fault_id":1,"detected":false,"t_ns":2000})"
                                 "\n";
  const std::string stopped = R"({"component":"a","event":"state","from":"Active","to":"Inactive","t_ns":3000})"
                              "\n";
  a = auditRound(kStart + kArmed + stopped + kEnd + undetected, 1);
  EXPECT_TRUE(a.violations.empty()) << joinedViolations(a);
  EXPECT_EQ(a.by_kind.at("segfault").overtaken, 1);
  // Another component stopping overtakes nothing.
  const std::string other = R"({"component":"b","event":"state","from":"Active","to":"Inactive","t_ns":3000})"
                            "\n";
  EXPECT_EQ(auditRound(kStart + kArmed + other + kEnd + undetected, 1).violations.size(), 1u);
}

TEST(SoakAudit, AnArmedFaultThatNeverManifestedIsCountedNotAViolation) {
  const RoundAudit a = auditRound(kStart + kArmed + kEnd, 1);
  EXPECT_TRUE(a.violations.empty()) << joinedViolations(a);
  EXPECT_EQ(a.by_kind.at("segfault").not_manifested, 1);
  EXPECT_EQ(a.by_kind.at("segfault").handled, 0);
}

TEST(SoakAudit, AnEmergencyStopMustBeReachedInEveryComponent) {
  const std::string latched = R"({"event":"emergency","phase":"latched","by":"keel soak","t_ns":4000})"
                              "\n";
  const std::string reached =
      R"({"event":"action","action":"emergency_stop","outcome":"ok","components":["a"],"t_ns":4100})"
      "\n";
  const std::string late =
      R"({"event":"action","action":"emergency_stop","outcome":"failed","not_finished":["a"],"t_ns":4100})"
      "\n";
  RoundAudit a = auditRound(kStart + latched + reached + kEnd, 1);
  EXPECT_TRUE(a.violations.empty()) << joinedViolations(a);
  EXPECT_EQ(a.emergencies, 1);
  EXPECT_EQ(a.emergencies_reached, 1);
  a = auditRound(kStart + latched + late + kEnd, 1);
  ASSERT_EQ(a.violations.size(), 1u) << joinedViolations(a);
  EXPECT_NE(a.violations[0].find("emergency stop not reached: not finished in [\"a\"]"), std::string::npos)
      << a.violations[0];
  a = auditRound(kStart + latched + kEnd, 1);
  ASSERT_EQ(a.violations.size(), 1u) << joinedViolations(a);
  EXPECT_NE(a.violations[0].find("line 3: emergency latched, and no emergency_stop action followed"), std::string::npos)
      << a.violations[0];
}

TEST(SoakAudit, AHardwareFaultItsDriverRefusedIsAViolation) {
  const std::string taken =
      R"({"component":"act","event":"injected","fault_id":3,"hardware":true,"kind":"noise","detail":"noise 2","t_ns":10})"
      "\n";
  const std::string refused =
      R"({"component":"act","event":"injected","fault_id":4,"hardware":true,"kind":"noise","detail":"noise 2","outcome":"BadInput","t_ns":10})"
      "\n";
  RoundAudit a = auditRound(kStart + taken + kEnd, 1);
  EXPECT_TRUE(a.violations.empty()) << joinedViolations(a);
  EXPECT_EQ(a.by_kind.at("noise").armed, 1);
  a = auditRound(kStart + refused + kEnd, 1);
  ASSERT_EQ(a.violations.size(), 1u) << joinedViolations(a);
  EXPECT_NE(a.violations[0].find("hardware fault 'noise 2' not taken by 'act': BadInput"), std::string::npos)
      << a.violations[0];
}

TEST(SoakAudit, ACollisionInARoundWhereKeelStoppedNothingIsAViolation) {
  const std::string mission =
      R"({"component":"referee","event":"mission","collisions":2,"neutral_by":"command","t_ns":9000000200})"
      "\n";
  RoundAudit a = auditRound(kStart + kEnd + mission, 1);
  ASSERT_TRUE(a.collisions.has_value());
  EXPECT_EQ(*a.collisions, 2);
  ASSERT_EQ(a.violations.size(), 1u) << joinedViolations(a);
  EXPECT_NE(a.violations[0].find("2 collision(s) while keel stopped nothing"), std::string::npos) << a.violations[0];
  // A sonar stopped by keel: it said the robot was not whole.
  const std::string stop =
      R"({"component":"a","event":"action","fault_id":1,"action":"stop","outcome":"ok","t_ns":2300})"
      "\n";
  a = auditRound(kStart + kArmed + kInjected + kDetected + kDiagnosed + stop + kEnd + mission, 1);
  EXPECT_TRUE(a.violations.empty()) << joinedViolations(a);
}

}  // namespace
}  // namespace keel::soak
