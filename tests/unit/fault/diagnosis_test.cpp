// Diagnosis of one detected fault (src/fault/diagnosis.hpp): who is accused, which fault id it
// gets (the injection's, else a new one), who detected it, what the accused's rules call for,
// and that it claims the role — a fault of a role already handled or stopped is only logged.
#include "fault/diagnosis.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <string>

#include "runtime/clock.hpp"
#include "runtime/component_core.hpp"

namespace keel::fault {
namespace {

using profile::Severity;
using runtime::coreOf;

class Named : public Component {
 public:
  explicit Named(const std::string& name) { coreOf(*this).instance_name = name; }
};

/// Components by instance name, as the engine's lookup answers.
class Registry {
 public:
  void add(Component& c) { by_name_[c.instanceName()] = &c; }
  std::function<Component*(std::string_view)> find() {
    return [this](std::string_view n) -> Component* {
      auto it = by_name_.find(std::string(n));
      return it == by_name_.end() ? nullptr : it->second;
    };
  }

 private:
  std::map<std::string, Component*> by_name_;
};

/// Handling whose policy gives every kind `severity` (no alternative).
void handle(Component& c, ComponentHandling& h, Severity severity) {
  h.rules.has_policy = true;
  h.rules.severity.fill(severity);
  h.name = c.instanceName();
  coreOf(c).fault.handling = &h;
}

TEST(Diagnosis, TheComponentTheEventNamesIsAccusedAndTheReporterIsTheDetector) {
  Named monitor("monitor"), sonar("sonar");
  Registry all;
  all.add(monitor);
  all.add(sonar);
  FaultIds ids;

  const FaultReport r = diagnose(monitor, FaultEvent(FaultKind::Model, "sonar", "stuck at 0.2 m"), {}, all.find(), ids);

  EXPECT_EQ(r.accused, &sonar);
  EXPECT_EQ(r.event.componentName(), "sonar");
  EXPECT_EQ(r.event.kind, FaultKind::Model);
  EXPECT_EQ(r.event.detailText(), "stuck at 0.2 m");
  EXPECT_STREQ(r.detector.data(), "monitor");
  EXPECT_EQ(coreOf(sonar).faults.load(), 1u) << "the fault is counted for the accused";
  EXPECT_EQ(coreOf(monitor).faults.load(), 0u);
}

TEST(Diagnosis, AnEventNamingNoComponentAccusesTheReporterAndNamesIt) {
  Named arm("arm");
  Registry all;
  all.add(arm);
  FaultIds ids;

  const FaultReport r = diagnose(arm, FaultEvent(FaultKind::User, "", "gripper jammed"), {}, all.find(), ids);

  EXPECT_EQ(r.accused, &arm);
  EXPECT_EQ(r.event.componentName(), "arm");
  EXPECT_EQ(coreOf(arm).faults.load(), 1u);
}

TEST(Diagnosis, AnEventNamingAnUnknownComponentAccusesTheReporter) {
  Named monitor("monitor");
  Registry all;
  all.add(monitor);
  FaultIds ids;

  const FaultReport r = diagnose(monitor, FaultEvent(FaultKind::Model, "ghost", "?"), {}, all.find(), ids);

  EXPECT_EQ(r.accused, &monitor);
  EXPECT_EQ(coreOf(monitor).faults.load(), 1u);
  EXPECT_EQ(r.event.componentName(), "monitor") << "the records name whom the fault is handled for";
}

TEST(Diagnosis, AGivenDetectorNameIsLoggedInsteadOfTheReporter) {
  Named arm("arm");
  Registry all;
  all.add(arm);
  FaultIds ids;

  const FaultReport r = diagnose(arm, FaultEvent(FaultKind::Heartbeat, "", "silent"), "watchdog", all.find(), ids);

  EXPECT_STREQ(r.detector.data(), "watchdog");
}

TEST(Diagnosis, EachFaultNotInjectedGetsANewNonZeroId) {
  Named arm("arm");
  Registry all;
  all.add(arm);
  FaultIds ids;

  const FaultReport first = diagnose(arm, FaultEvent(FaultKind::User, "", "a"), {}, all.find(), ids);
  const FaultReport second = diagnose(arm, FaultEvent(FaultKind::User, "", "b"), {}, all.find(), ids);

  EXPECT_NE(first.id, 0u);
  EXPECT_NE(second.id, 0u);
  EXPECT_NE(first.id, second.id);
  EXPECT_EQ(first.injected_ns, 0) << "not injected";
}

TEST(Diagnosis, AnInjectedFaultKeepsTheInjectionsIdAndTimeOnce) {
  Named arm("arm");
  Registry all;
  all.add(arm);
  FaultIds ids;
  coreOf(arm).injection.injected_id.store(77);
  coreOf(arm).injection.injected_t_ns.store(123'456);

  const FaultReport injected = diagnose(arm, FaultEvent(FaultKind::Signal, "", "SIGSEGV"), {}, all.find(), ids);
  const FaultReport later = diagnose(arm, FaultEvent(FaultKind::Signal, "", "SIGSEGV"), {}, all.find(), ids);

  EXPECT_EQ(injected.id, 77u) << "`injected` and `detected` share the injection's id";
  EXPECT_EQ(injected.injected_ns, 123'456);
  EXPECT_EQ(coreOf(arm).injection.injected_id.load(), 0u) << "the injection is answered by this detection";
  EXPECT_NE(later.id, 77u) << "a later fault is not the injection's";
  EXPECT_EQ(later.injected_ns, 0);
}

TEST(Diagnosis, TheInjectionOfTheAccusedNotOfTheReporterIsAttributed) {
  Named monitor("monitor"), sonar("sonar");
  Registry all;
  all.add(monitor);
  all.add(sonar);
  FaultIds ids;
  coreOf(sonar).injection.injected_id.store(9);
  coreOf(sonar).injection.injected_t_ns.store(1000);

  const FaultReport r = diagnose(monitor, FaultEvent(FaultKind::Model, "sonar", "stuck"), {}, all.find(), ids);

  EXPECT_EQ(r.id, 9u);
  EXPECT_EQ(r.injected_ns, 1000);
}

TEST(Diagnosis, TheDetectionTimeIsTheEventsOrElseNow) {
  Named arm("arm");
  Registry all;
  all.add(arm);
  FaultIds ids;
  FaultEvent timed(FaultKind::User, "", "a");
  timed.t_ns = 42;

  const std::int64_t before = runtime::steadyNs();
  const FaultReport untimed = diagnose(arm, FaultEvent(FaultKind::User, "", "b"), {}, all.find(), ids);
  const std::int64_t after = runtime::steadyNs();
  const FaultReport kept = diagnose(arm, timed, {}, all.find(), ids);

  EXPECT_GE(untimed.event.t_ns, before);
  EXPECT_LE(untimed.event.t_ns, after);
  EXPECT_EQ(kept.event.t_ns, 42);
}

TEST(Diagnosis, TheAccusedsRulesChooseSeverityScopeAndFirstStepAndClaimTheRole) {
  Named arm("arm");
  Registry all;
  all.add(arm);
  FaultIds ids;
  ComponentHandling h;
  handle(arm, h, Severity::Stop);
  h.rules.severity[static_cast<std::size_t>(FaultKind::Signal)] = Severity::Reset;
  h.rules.scope = profile::Scope::Executor;

  const FaultReport r = diagnose(arm, FaultEvent(FaultKind::Signal, "", "SIGSEGV"), {}, all.find(), ids);

  EXPECT_TRUE(r.has_policy);
  EXPECT_EQ(r.severity, Severity::Reset);
  EXPECT_EQ(r.scope, profile::Scope::Executor);
  EXPECT_EQ(r.first, Step::Reset);
  EXPECT_EQ(r.next, Step::Reset);
  EXPECT_EQ(r.n_actions, 0) << "nothing done yet";
  std::lock_guard lock(h.mutex);
  EXPECT_TRUE(h.busy) << "this fault's handling owns the role now";
}

TEST(Diagnosis, AStopSeverityStartsWithTheAlternativeWhenThereIsOne) {
  Named arm("arm");
  Registry all;
  all.add(arm);
  FaultIds ids;
  ComponentHandling h;
  handle(arm, h, Severity::Stop);
  const profile::ComponentProfile backup;
  h.rules.alternative = &backup;

  const FaultReport r = diagnose(arm, FaultEvent(FaultKind::Exception, "", "boom"), {}, all.find(), ids);

  EXPECT_EQ(r.severity, Severity::Stop);
  EXPECT_EQ(r.first, Step::Replace);
}

TEST(Diagnosis, AFaultOfARoleBeingHandledIsOnlyLoggedWithWhy) {
  Named arm("arm");
  Registry all;
  all.add(arm);
  FaultIds ids;
  ComponentHandling h;
  handle(arm, h, Severity::Reset);
  (void)diagnose(arm, FaultEvent(FaultKind::Signal, "", "first"), {}, all.find(), ids);  // claims the role

  const FaultReport r = diagnose(arm, FaultEvent(FaultKind::Signal, "", "second"), {}, all.find(), ids);

  EXPECT_EQ(r.first, Step::Done);
  EXPECT_EQ(r.next, Step::Done);
  ASSERT_EQ(r.n_actions, 1);
  EXPECT_EQ(r.actions[0].kind, ActionKind::Ignore);
  EXPECT_TRUE(r.actions[0].ok);
  EXPECT_STREQ(r.actions[0].detail.data(), "a fault of it is being handled");
  EXPECT_EQ(r.severity, Severity::Reset) << "the severity is still the rules'";
}

TEST(Diagnosis, AFaultOfAStoppedRoleIsOnlyLoggedWithWhy) {
  Named arm("arm");
  Registry all;
  all.add(arm);
  FaultIds ids;
  ComponentHandling h;
  handle(arm, h, Severity::Reset);
  h.stopped = true;

  const FaultReport r = diagnose(arm, FaultEvent(FaultKind::Signal, "", "again"), {}, all.find(), ids);

  EXPECT_EQ(r.first, Step::Done);
  ASSERT_EQ(r.n_actions, 1);
  EXPECT_EQ(r.actions[0].kind, ActionKind::Ignore);
  EXPECT_STREQ(r.actions[0].detail.data(), "the component is stopped");
  std::lock_guard lock(h.mutex);
  EXPECT_FALSE(h.busy) << "a fault only logged does not claim the role";
}

TEST(Diagnosis, AnIgnoredFaultDoesNotClaimTheRole) {
  Named arm("arm");
  Registry all;
  all.add(arm);
  FaultIds ids;
  ComponentHandling h;
  handle(arm, h, Severity::Ignore);

  const FaultReport r = diagnose(arm, FaultEvent(FaultKind::Range, "", "NaN"), {}, all.find(), ids);

  EXPECT_EQ(r.first, Step::Ignore);
  EXPECT_EQ(r.n_actions, 0) << "the ignore action is the manager's to add";
  std::lock_guard lock(h.mutex);
  EXPECT_FALSE(h.busy);
}

TEST(Diagnosis, WithoutHandlingACrashIsStoppedAndARangeFaultIgnored) {
  Named arm("arm");  // no core.fault.handling: not managed by a runtime
  Registry all;
  all.add(arm);
  FaultIds ids;

  const FaultReport crash = diagnose(arm, FaultEvent(FaultKind::Signal, "", "SIGSEGV"), {}, all.find(), ids);
  const FaultReport range = diagnose(arm, FaultEvent(FaultKind::Range, "", "NaN"), {}, all.find(), ids);

  EXPECT_FALSE(crash.has_policy);
  EXPECT_EQ(crash.severity, Severity::Stop);
  EXPECT_EQ(crash.first, Step::Stop);
  EXPECT_EQ(range.severity, Severity::Ignore);
  EXPECT_EQ(range.first, Step::Ignore);
}

}  // namespace
}  // namespace keel::fault
