// The escalation decision (src/fault/escalation.hpp): every row of docs/fault-handling.md's
// escalation rules as a table, the first step of a fault, the restart-intensity window, and
// that no sequence of outcomes makes handling loop.
#include "fault/escalation.hpp"

#include <gtest/gtest.h>

#include <set>
#include <tuple>

namespace keel::fault {
namespace {

using profile::Severity;

struct Row {
  const char* rule;  // the rule of docs/fault-handling.md this row checks
  Step step;
  Outcome outcome;
  RoleFacts role;
  Step next;
  bool escalates;
};

constexpr RoleFacts kNoAlternative{false, false, false, false};
constexpr RoleFacts kAlternative{true, false, false, false};
constexpr RoleFacts kReplaced{true, true, false, false};
constexpr RoleFacts kAlternativeReady{true, false, true, false};
constexpr RoleFacts kAfterEmergency{false, false, false, true};
constexpr RoleFacts kAlternativeAfterEmergency{true, false, false, true};

const Row kRows[] = {
    {"a reset that did is the end", Step::Reset, Outcome::Done, kAlternative, Step::Done, false},
    {"reset: intensity exceeded, alternative declared → replace", Step::Reset, Outcome::IntensityExceeded, kAlternative,
     Step::Replace, true},
    {"reset: intensity exceeded, no alternative → stop", Step::Reset, Outcome::IntensityExceeded, kNoAlternative,
     Step::Stop, true},
    {"reset: intensity exceeded, alternative already in place → stop", Step::Reset, Outcome::IntensityExceeded,
     kReplaced, Step::Stop, true},
    {"reset failed, alternative declared → replace", Step::Reset, Outcome::Failed, kAlternative, Step::Replace, true},
    {"reset failed, no alternative → stop", Step::Reset, Outcome::Failed, kNoAlternative, Step::Stop, true},
    {"reset failed, alternative already in place → stop", Step::Reset, Outcome::Failed, kReplaced, Step::Stop, true},
    {"a replacement that did is the end", Step::Replace, Outcome::Done, kAlternative, Step::Done, false},
    {"replace without an alternative → stop", Step::Replace, Outcome::Unavailable, kNoAlternative, Step::Stop, true},
    {"replace with the alternative already in place (a role is replaced once) → stop", Step::Replace,
     Outcome::Unavailable, kReplaced, Step::Stop, true},
    {"the alternative failing (load or onStart) → stop", Step::Replace, Outcome::Failed, kAlternative, Step::Stop,
     true},
    {"a stop that did is the end", Step::Stop, Outcome::Done, kNoAlternative, Step::Done, false},
    {"a stop that cannot be carried out → emergency", Step::Stop, Outcome::Failed, kNoAlternative, Step::Emergency,
     true},
    {"a stop that cannot be carried out after an emergency: nothing further", Step::Stop, Outcome::Failed,
     kAfterEmergency, Step::Done, false},
    {"a stop that cannot be carried out after an emergency, an alternative declared: nothing further", Step::Stop,
     Outcome::Failed, kAlternativeAfterEmergency, Step::Done, false},
    {"emergency, then as stop: the alternative replaces", Step::Emergency, Outcome::Done, kAlternative, Step::Replace,
     false},
    {"emergency, then as stop: no alternative → stop", Step::Emergency, Outcome::Done, kNoAlternative, Step::Stop,
     false},
    {"emergency, then as stop: the alternative already in place → stop", Step::Emergency, Outcome::Done, kReplaced,
     Step::Stop, false},
    {"hung callback, an alternative ready → replace", Step::Reset, Outcome::Hung, kAlternativeReady, Step::Replace,
     true},
    {"hung callback, no alternative → stop", Step::Reset, Outcome::Hung, kNoAlternative, Step::Stop, true},
    {"hung callback while replacing, none ready → stop", Step::Replace, Outcome::Hung, kAlternative, Step::Stop, true},
    {"a passive component that stays busy → stop", Step::Reset, Outcome::Busy, kAlternative, Step::Stop, true},
    {"a stop whose component is hung is a stop that cannot be carried out", Step::Stop, Outcome::Hung, kNoAlternative,
     Step::Emergency, true},
    {"an emergency goes on as a stop whatever held it up", Step::Emergency, Outcome::Busy, kNoAlternative, Step::Stop,
     false},
    {"ignore is the end", Step::Ignore, Outcome::Done, kAlternative, Step::Done, false},
};

TEST(Escalation, EveryRuleOfTheHandlingTableDecidesItsNextStep) {
  for (const Row& row : kRows) {
    const Decision d = decide(row.step, row.outcome, row.role);
    EXPECT_EQ(d.next, row.next) << row.rule << ": got " << toString(d.next);
    EXPECT_EQ(d.escalates, row.escalates) << row.rule;
    EXPECT_EQ(d.why.empty(), !row.escalates) << row.rule << ": an escalation says why, nothing else does";
  }
}

TEST(Escalation, TheReasonNamesWhatHappened) {
  EXPECT_EQ(decide(Step::Reset, Outcome::Failed, kAlternative).why, "the reset failed");
  EXPECT_EQ(decide(Step::Reset, Outcome::IntensityExceeded, kAlternative).why, "restart intensity exceeded");
  EXPECT_EQ(decide(Step::Replace, Outcome::Unavailable, kNoAlternative).why, "no alternative");
  EXPECT_EQ(decide(Step::Replace, Outcome::Unavailable, kReplaced).why, "the alternative is already in place");
  EXPECT_EQ(decide(Step::Reset, Outcome::Hung, kNoAlternative).why,
            "the hung callback did not return when interrupted");
}

struct FirstRow {
  Severity severity;
  bool alternative;
  Step first;
};

TEST(Escalation, TheFirstStepFollowsTheSeverity) {
  const FirstRow rows[] = {
      {Severity::Ignore, false, Step::Ignore},      {Severity::Reset, false, Step::Reset},
      {Severity::Reset, true, Step::Reset},         {Severity::Stop, false, Step::Stop},
      {Severity::Stop, true, Step::Replace},        {Severity::Emergency, false, Step::Emergency},
      {Severity::Emergency, true, Step::Emergency},
  };
  profile::ComponentProfile backup;
  for (const FirstRow& row : rows) {
    Rules rules;
    rules.has_policy = true;
    rules.severity.fill(row.severity);
    rules.alternative = row.alternative ? &backup : nullptr;
    const FirstStep f = firstStep(rules, FaultKind::Signal, false, false);
    EXPECT_EQ(f.severity, row.severity);
    EXPECT_EQ(f.step, row.first) << profile::toString(row.severity) << (row.alternative ? " with" : " without")
                                 << " an alternative";
  }
}

TEST(Escalation, AFaultOfARoleBeingHandledOrStoppedIsOnlyLogged) {
  Rules rules;
  rules.has_policy = true;
  rules.severity.fill(Severity::Reset);
  const FirstStep busy = firstStep(rules, FaultKind::Signal, true, false);
  EXPECT_EQ(busy.step, Step::Done);
  EXPECT_EQ(busy.why, "a fault of it is being handled");
  const FirstStep stopped = firstStep(rules, FaultKind::Signal, true, true);
  EXPECT_EQ(stopped.step, Step::Done);
  EXPECT_EQ(stopped.why, "the component is stopped");
  rules.severity.fill(Severity::Ignore);  // ignore stays ignore: it is logged as such
  EXPECT_EQ(firstStep(rules, FaultKind::Signal, true, true).step, Step::Ignore);
}

TEST(Escalation, WithoutAPolicyACrashIsContainedAndTheRestLogged) {
  const Rules none;
  EXPECT_EQ(firstStep(none, FaultKind::Signal, false, false).step, Step::Stop);
  EXPECT_EQ(firstStep(none, FaultKind::Range, false, false).step, Step::Ignore);
}

// Handling as the fault manager drives it: each step's worst outcome, the role's facts updated
// as the acting parts update them. Whatever the outcomes, it ends, and no (step, facts) state
// comes back.
TEST(Escalation, NoSequenceOfOutcomesLoops) {
  const Outcome outcomes[] = {Outcome::Done,        Outcome::Failed, Outcome::IntensityExceeded,
                              Outcome::Unavailable, Outcome::Hung,   Outcome::Busy};
  for (Step first : {Step::Reset, Step::Replace, Step::Stop, Step::Emergency}) {
    for (bool alternative : {false, true}) {
      for (std::size_t seed = 0; seed < std::size_t{6} * 6 * 6 * 6; ++seed) {
        RoleFacts role{alternative, false, false, false};
        Step step = first;
        std::set<std::tuple<Step, bool, bool>> seen;
        std::size_t pick = seed;
        int steps = 0;
        while (step != Step::Done) {
          ASSERT_TRUE(seen.insert({step, role.replaced, role.emergency_done}).second)
              << "handling came back to " << toString(step) << " (seed " << seed << ")";
          ASSERT_LT(++steps, 8);
          Outcome o = outcomes[pick % 6];
          pick /= 6;
          if (step == Step::Replace && role.replaced) o = Outcome::Unavailable;  // the manager's check
          if (step == Step::Replace && o != Outcome::Unavailable && o != Outcome::Busy) role.replaced = true;
          if (step == Step::Emergency) {
            o = Outcome::Done;
            role.emergency_done = true;
          }
          step = decide(step, o, role).next;
        }
      }
    }
  }
}

TEST(RestartWindow, MoreThanIntensityRecoveriesWithinThePeriodExceedIt) {
  constexpr std::int64_t ms = 1'000'000;
  RestartWindow w(3, 100 * ms);  // at most 3 recoveries in any 100 ms
  EXPECT_FALSE(w.exceededAt(0));
  w.note(0);
  w.note(10 * ms);
  EXPECT_FALSE(w.exceededAt(20 * ms));
  w.note(20 * ms);
  EXPECT_TRUE(w.exceededAt(30 * ms));  // a 4th within 100 ms of the 1st
  EXPECT_TRUE(w.exceededAt(99 * ms));
  EXPECT_FALSE(w.exceededAt(100 * ms));  // the 1st has left the window
  w.note(100 * ms);
  EXPECT_TRUE(w.exceededAt(109 * ms));  // 10, 20, 100 are within 100 ms of 109
  EXPECT_FALSE(w.exceededAt(110 * ms));
}

TEST(RestartWindow, IntensityZeroEscalatesTheFirstFault) {
  RestartWindow w(0, 1'000'000'000);
  EXPECT_TRUE(w.exceededAt(0));
  w.note(0);
  EXPECT_TRUE(w.exceededAt(0));
}

}  // namespace
}  // namespace keel::fault
