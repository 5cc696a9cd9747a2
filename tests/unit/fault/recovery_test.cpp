// Local recoveries (src/fault/recovery.hpp): a reset — callbacks in order, checkpoint restored,
// Active again, counted by the restart window — a replacement by the ready alternative with the
// failed one's checkpoint, loading the alternative, and abandoning the executor of a hung one.
#include "fault/recovery.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "runtime/checkpoint.hpp"
#include "runtime/clock.hpp"
#include "runtime/component_core.hpp"
#include "runtime/invoke.hpp"

namespace keel::fault {
namespace {

using runtime::coreOf;

struct Pose {
  int count = 0;
  double x = 0.0;
};

/// Its critical memory is `pose`; its recovery callbacks and onStart note themselves in `trace`.
class Worker : public Component {
 public:
  Worker(const std::string& name, std::vector<std::string>& trace) : trace_(trace) {
    coreOf(*this).instance_name = name;
    critical(pose);
  }
  ReturnCode onError() override {
    state_at_error = state();
    return note("onError", ReturnCode::Ok);
  }
  ReturnCode onReset() override { return note("onReset", reset_rc); }
  ReturnCode onRecover() override {
    count_at_recover = pose.count;
    return note("onRecover", ReturnCode::Ok);
  }
  ReturnCode onStart() override {
    count_at_start = pose.count;
    note("onStart", ReturnCode::Ok);
    if (start_throws) throw std::runtime_error("no motor power");
    return ReturnCode::Ok;
  }

  Pose pose;
  ReturnCode reset_rc = ReturnCode::Ok;
  bool start_throws = false;
  State state_at_error = State::Created;
  int count_at_recover = -1;
  int count_at_start = -1;

 private:
  ReturnCode note(const char* what, ReturnCode rc) {
    trace_.push_back(instanceName() + "." + what);
    return rc;
  }
  std::vector<std::string>& trace_;
};

/// The runtime side, faked: records what recovery asks of it.
class Host : public RecoveryActions {
 public:
  explicit Host(std::vector<std::string>& trace) : trace_(trace) {}
  Component* find(std::string_view) const override { return nullptr; }
  std::vector<Component*> components() const override { return {}; }
  Result<Component*> createAlternative(ComponentHandling&, Component&) override {
    ++creations;
    if (created == nullptr) return fail("libbackup.so: cannot open shared object file");
    return created;
  }
  void switchTo(Component& failed, Component& alt) override {
    trace_.emplace_back("switchTo");
    switched_from = &failed;
    switched_to = &alt;
  }
  Result<std::string> abandonExecutor(Component& hung, Component* alternative) override {
    abandoned = &hung;
    abandoned_with = alternative;
    if (alternative && start_alternative) runtime::setStateQuiet(*alternative, State::Active);
    return std::string("arm_exec+");
  }

  Component* created = nullptr;   // what createAlternative answers (null: it fails)
  bool start_alternative = true;  // abandonExecutor starts the alternative, as the engine does
  int creations = 0;
  Component* switched_from = nullptr;
  Component* switched_to = nullptr;
  Component* abandoned = nullptr;
  Component* abandoned_with = nullptr;

 private:
  std::vector<std::string>& trace_;
};

/// The rules of a role with at most `intensity` recoveries per 10 s, and its alternative if any.
Rules rulesOf(int intensity, const profile::ComponentProfile* alternative = nullptr) {
  Rules r;
  r.has_policy = true;
  r.severity.fill(profile::Severity::Reset);
  r.intensity = intensity;
  r.period_ns = 10'000'000'000;
  r.alternative = alternative;
  r.preload = true;
  return r;
}

/// A fault of `c` detected now, being handled by `step`.
FaultReport faultOf(Component& c, std::uint64_t id, Step step) {
  FaultReport r;
  r.event = FaultEvent(FaultKind::Signal, c.instanceName(), "SIGSEGV in onExecute");
  r.event.t_ns = runtime::steadyNs();
  r.id = id;
  r.accused = &c;
  r.first = r.next = step;
  return r;
}

TEST(Recovery, AResetRunsTheRecoveryCallbacksInOrderRestoresTheCheckpointAndMakesItActive) {
  std::vector<std::string> trace;
  Worker arm("arm", trace);
  arm.pose = {7, 1.5};
  runtime::takeCheckpoint(coreOf(arm), runtime::steadyNs());
  arm.pose = {99, -1.0};  // corrupted by the fault
  runtime::setStateQuiet(arm, State::Error);
  ComponentHandling h(rulesOf(3), "arm");
  FaultReport r = faultOf(arm, 5, Step::Reset);
  Recovery recovery;

  const Outcome outcome = recovery.reset(r, h);

  EXPECT_EQ(outcome, Outcome::Done);
  EXPECT_EQ(trace, (std::vector<std::string>{"arm.onError", "arm.onReset", "arm.onRecover"}));
  EXPECT_EQ(arm.pose.count, 7);
  EXPECT_EQ(arm.pose.x, 1.5);
  EXPECT_EQ(arm.count_at_recover, 7) << "onRecover sees the restored memory";
  EXPECT_EQ(arm.state(), State::Active);
  ASSERT_EQ(r.n_actions, 2);
  EXPECT_EQ(r.actions[0].kind, ActionKind::Reset);
  EXPECT_TRUE(r.actions[0].ok);
  EXPECT_EQ(r.actions[1].kind, ActionKind::Restore);
  EXPECT_TRUE(r.actions[1].ok);
  EXPECT_EQ(coreOf(arm).fault.recovering_id.load(), 5u) << "recovered after its next good onExecute";
}

TEST(Recovery, AResetOfAComponentNotYetInErrorEntersErrorFirst) {
  std::vector<std::string> trace;
  Worker arm("arm", trace);
  runtime::setStateQuiet(arm, State::Active);
  ComponentHandling h(rulesOf(3), "arm");
  FaultReport r = faultOf(arm, 1, Step::Reset);
  Recovery recovery;

  const Outcome outcome = recovery.reset(r, h);

  EXPECT_EQ(outcome, Outcome::Done);
  EXPECT_EQ(arm.state_at_error, State::Error) << "onError runs in Error";
  EXPECT_EQ(arm.state(), State::Active);
}

TEST(Recovery, AResetBeforeAnyCheckpointLeavesTheMemoryAndSaysSo) {
  std::vector<std::string> trace;
  Worker arm("arm", trace);
  arm.pose.count = 42;
  runtime::setStateQuiet(arm, State::Error);
  ComponentHandling h(rulesOf(3), "arm");
  FaultReport r = faultOf(arm, 1, Step::Reset);
  Recovery recovery;

  const Outcome outcome = recovery.reset(r, h);

  EXPECT_EQ(outcome, Outcome::Done);
  EXPECT_EQ(arm.pose.count, 42);
  ASSERT_EQ(r.n_actions, 2);
  EXPECT_EQ(r.actions[1].kind, ActionKind::Restore);
  EXPECT_FALSE(r.actions[1].ok);
  EXPECT_STREQ(r.actions[1].detail.data(), "no checkpoint yet: critical memory left as it was");
}

TEST(Recovery, TheRestartWindowNotesEachResetUntilTheIntensityIsExceeded) {
  std::vector<std::string> trace;
  Worker arm("arm", trace);
  ComponentHandling h(rulesOf(2), "arm");
  Recovery recovery;
  EXPECT_EQ(recovery.intensityAt(h, runtime::steadyNs()), Outcome::Done);

  FaultReport first = faultOf(arm, 1, Step::Reset);
  ASSERT_EQ(recovery.reset(first, h), Outcome::Done);
  EXPECT_EQ(recovery.intensityAt(h, runtime::steadyNs()), Outcome::Done) << "one reset of two allowed";
  FaultReport second = faultOf(arm, 2, Step::Reset);
  ASSERT_EQ(recovery.reset(second, h), Outcome::Done);

  EXPECT_EQ(recovery.intensityAt(h, runtime::steadyNs()), Outcome::IntensityExceeded);
  EXPECT_EQ(recovery.intensityAt(h, runtime::steadyNs() + 11'000'000'000), Outcome::Done) << "after the period";
}

TEST(Recovery, AComponentWhoseOnResetFailsIsNotRecovered) {
  std::vector<std::string> trace;
  Worker arm("arm", trace);
  arm.reset_rc = ReturnCode::InternalFault;
  runtime::setStateQuiet(arm, State::Error);
  ComponentHandling h(rulesOf(1), "arm");
  FaultReport r = faultOf(arm, 3, Step::Reset);
  Recovery recovery;

  const Outcome outcome = recovery.reset(r, h);

  EXPECT_EQ(outcome, Outcome::Failed);
  EXPECT_EQ(trace, (std::vector<std::string>{"arm.onError", "arm.onReset"})) << "no onRecover";
  EXPECT_EQ(arm.state(), State::Error);
  ASSERT_EQ(r.n_actions, 1);
  EXPECT_EQ(r.actions[0].kind, ActionKind::Reset);
  EXPECT_FALSE(r.actions[0].ok);
  EXPECT_NE(std::string(r.actions[0].detail.data()).find("internal fault"), std::string::npos)
      << r.actions[0].detail.data();
  EXPECT_EQ(recovery.intensityAt(h, runtime::steadyNs()), Outcome::Done) << "a failed reset is no recovery";
  EXPECT_EQ(coreOf(arm).fault.recovering_id.load(), 0u);
}

/// A failed `arm` (checkpoint taken, then its memory torn) and its preloaded alternative, of class
/// BackupArm (created and initialized, not started), with a recovery attached to a fake host.
struct Replacement {
  Replacement() {
    failed.pose = {7, 2.5};
    runtime::takeCheckpoint(coreOf(failed), runtime::steadyNs());
    failed.pose = {-1, 0.0};  // torn by the fault: not what the alternative gets
    runtime::setStateQuiet(failed, State::Error);
    coreOf(alternative).class_name = "BackupArm";
    runtime::setStateQuiet(alternative, State::Ready);
    h.ready_alternative = &alternative;
    recovery.attach(&host);
  }

  std::vector<std::string> trace;
  Worker failed{"arm", trace};
  Worker alternative{"arm", trace};
  profile::ComponentProfile backup;
  ComponentHandling h{rulesOf(1, &backup), "arm"};
  Host host{trace};
  Recovery recovery;
};

TEST(Recovery, TheReadyAlternativeGetsTheCheckpointTakesTheRoleAndStarts) {
  Replacement role;
  FaultReport r = faultOf(role.failed, 11, Step::Replace);

  const Outcome outcome = role.recovery.replace(r, role.h);

  EXPECT_EQ(outcome, Outcome::Done);
  EXPECT_EQ(role.alternative.pose.count, 7);
  EXPECT_EQ(role.alternative.pose.x, 2.5);
  EXPECT_EQ(role.alternative.count_at_start, 7) << "it starts from the checkpointed state";
  EXPECT_EQ(role.trace, (std::vector<std::string>{"switchTo", "arm.onStart"}));
  EXPECT_EQ(role.host.switched_from, &role.failed);
  EXPECT_EQ(role.host.switched_to, &role.alternative);
  EXPECT_EQ(role.alternative.state(), State::Active);
  EXPECT_EQ(role.failed.state(), State::Error);
  EXPECT_TRUE(role.h.replaced);
  EXPECT_EQ(role.h.ready_alternative, nullptr);
  EXPECT_EQ(r.alternative, &role.alternative);
  ASSERT_EQ(r.n_actions, 1);
  EXPECT_EQ(r.actions[0].kind, ActionKind::Replace);
  EXPECT_TRUE(r.actions[0].ok);
  EXPECT_STREQ(r.actions[0].detail.data(), "alternative BackupArm (preloaded) took over with the checkpointed state");
  EXPECT_EQ(coreOf(role.alternative).fault.recovering_id.load(), 11u);
  EXPECT_GE(coreOf(role.alternative).checkpoints.count, 1u) << "its own first checkpoint, for a later reset";
  EXPECT_EQ(role.recovery.intensityAt(role.h, runtime::steadyNs()), Outcome::IntensityExceeded)
      << "a replacement counts";
}

TEST(Recovery, AnAlternativeWhoseOnStartThrowsFailsTheReplacement) {
  Replacement role;
  role.alternative.start_throws = true;
  FaultReport r = faultOf(role.failed, 12, Step::Replace);

  const Outcome outcome = role.recovery.replace(r, role.h);

  EXPECT_EQ(outcome, Outcome::Failed);
  EXPECT_EQ(role.alternative.state(), State::Error);
  EXPECT_TRUE(role.h.replaced) << "a role is replaced once";
  ASSERT_EQ(r.n_actions, 1);
  EXPECT_EQ(r.actions[0].kind, ActionKind::Replace);
  EXPECT_FALSE(r.actions[0].ok);
  EXPECT_NE(std::string(r.actions[0].detail.data()).find("no motor power"), std::string::npos)
      << r.actions[0].detail.data();
  EXPECT_EQ(coreOf(role.alternative).fault.recovering_id.load(), 0u);
}

TEST(Recovery, LoadingTheAlternativeMakesItReady) {
  Replacement role;
  role.h.ready_alternative = nullptr;
  role.host.created = &role.alternative;
  FaultReport r = faultOf(role.failed, 13, Step::Replace);

  const Outcome outcome = role.recovery.load(r, role.h);

  EXPECT_EQ(outcome, Outcome::Done);
  EXPECT_EQ(role.h.ready_alternative, &role.alternative);
  EXPECT_EQ(role.host.creations, 1);
  EXPECT_EQ(r.n_actions, 0);
}

TEST(Recovery, AnAlternativeThatDoesNotLoadFailsWithTheReason) {
  Replacement role;
  role.h.ready_alternative = nullptr;
  FaultReport r = faultOf(role.failed, 14, Step::Replace);

  const Outcome outcome = role.recovery.load(r, role.h);

  EXPECT_EQ(outcome, Outcome::Failed);
  EXPECT_EQ(role.h.ready_alternative, nullptr);
  ASSERT_EQ(r.n_actions, 1);
  EXPECT_EQ(r.actions[0].kind, ActionKind::Replace);
  EXPECT_FALSE(r.actions[0].ok);
  EXPECT_STREQ(r.actions[0].detail.data(),
               "loading the alternative failed: libbackup.so: cannot open shared object file");
}

TEST(Recovery, AHungComponentIsReplacedByItsReadyAlternativeOnANewExecutor) {
  Replacement role;
  FaultReport r = faultOf(role.failed, 15, Step::Reset);

  role.recovery.abandon(r, role.h);

  EXPECT_EQ(role.host.abandoned, &role.failed);
  EXPECT_EQ(role.host.abandoned_with, &role.alternative);
  EXPECT_EQ(role.alternative.pose.count, 7) << "it takes over with the checkpoint";
  EXPECT_EQ(r.next, Step::Done);
  EXPECT_EQ(r.alternative, &role.alternative);
  EXPECT_TRUE(role.h.replaced);
  EXPECT_EQ(role.h.ready_alternative, nullptr);
  ASSERT_EQ(r.n_actions, 2);
  EXPECT_EQ(r.actions[0].kind, ActionKind::Escalate);
  EXPECT_STREQ(r.actions[0].detail.data(), "reset → replace: the hung callback did not return when interrupted");
  EXPECT_EQ(r.actions[1].kind, ActionKind::Replace);
  EXPECT_TRUE(r.actions[1].ok);
  EXPECT_EQ(coreOf(role.alternative).fault.recovering_id.load(), 15u);
}

TEST(Recovery, AHungComponentWithoutAnAlternativeStaysStoppedOnAnAbandonedExecutor) {
  Replacement role;
  ComponentHandling alone(rulesOf(1), "arm");
  FaultReport r = faultOf(role.failed, 16, Step::Reset);

  role.recovery.abandon(r, alone);

  EXPECT_EQ(role.host.abandoned, &role.failed);
  EXPECT_EQ(role.host.abandoned_with, nullptr);
  EXPECT_EQ(role.host.creations, 0) << "nothing to load";
  EXPECT_EQ(r.next, Step::Stop);
  ASSERT_EQ(r.n_actions, 2);
  EXPECT_EQ(r.actions[0].kind, ActionKind::Escalate);
  EXPECT_STREQ(r.actions[0].detail.data(), "reset → stop: the hung callback did not return when interrupted");
  EXPECT_EQ(r.actions[1].kind, ActionKind::Stop);
  EXPECT_TRUE(r.actions[1].ok);
  EXPECT_STREQ(r.actions[1].detail.data(), "executor abandoned; its other components now run on arm_exec+");
}

TEST(Recovery, AHungComponentsAlternativeThatDoesNotStartOnTheNewExecutorLeavesItStopped) {
  Replacement role;
  role.host.start_alternative = false;
  FaultReport r = faultOf(role.failed, 17, Step::Reset);

  role.recovery.abandon(r, role.h);

  EXPECT_EQ(r.next, Step::Stop);
  ASSERT_EQ(r.n_actions, 2);
  EXPECT_EQ(r.actions[1].kind, ActionKind::Replace);
  EXPECT_FALSE(r.actions[1].ok);
  EXPECT_EQ(coreOf(role.alternative).fault.recovering_id.load(), 0u) << "nothing to wait for";
}

}  // namespace
}  // namespace keel::fault
