// The fault manager as a whole (src/fault/fault_manager.hpp): one fault of a passive component
// carried from detection to recovery, with or without the manager's thread, as the fault log
// shows it; a further fault while one is handled only logged; ignore, containment, emergency.
#include "fault/fault_manager.hpp"

#include <gtest/gtest.h>
#include <signal.h>

#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "log/schema.hpp"
#include "runtime/component_core.hpp"
#include "runtime/guard.hpp"
#include "runtime/invoke.hpp"
#include "support/fake_recovery_actions.hpp"
#include "support/log_reader.hpp"
#include "support/temp_log.hpp"

namespace keel::fault {
namespace {

namespace ev = log::schema::event;
namespace fd = log::schema::field;
using nlohmann::json;
using profile::Severity;
using runtime::coreOf;

/// A passive component (no executor): notes its recovery callbacks, the thread they ran on and
/// whether they held its lock.
class Joint : public Component {
 public:
  explicit Joint(const std::string& name) { coreOf(*this).instance_name = name; }
  ReturnCode onError() override { return note("onError"); }
  ReturnCode onReset() override {
    if (during_reset) during_reset();
    return note("onReset");
  }
  ReturnCode onRecover() override { return note("onRecover"); }
  ReturnCode onEmergencyStop() override { return note("onEmergencyStop"); }
  ReturnCode onExecute() override {
    if (during_execute) during_execute();
    return note("onExecute");
  }

  std::vector<std::string> trace() {
    std::lock_guard lock(mutex_);
    return trace_;
  }
  std::function<void()> during_reset;
  std::function<void()> during_execute;
  std::thread::id thread;
  bool under_lock = false;

 private:
  ReturnCode note(const char* what) {
    thread = std::this_thread::get_id();
    bool taken = false;  // by another thread: only if this one does not hold the passive lock
    std::thread([&] {
      if (coreOf(*this).passive_mutex.try_lock()) {
        taken = true;
        coreOf(*this).passive_mutex.unlock();
      }
    }).join();
    under_lock = !taken;
    std::lock_guard lock(mutex_);
    trace_.emplace_back(what);
    return ReturnCode::Ok;
  }
  std::mutex mutex_;
  std::vector<std::string> trace_;
};

/// A record in short: its event ("detected"), with the state it went to ("state Error") or
/// the action it took ("action reset").
std::string shortly(const json& r) {
  std::string event = r.value(fd::kEvent, "");
  if (event == ev::kState) return event + " " + r.value(fd::kTo, "");
  if (event == ev::kAction) return event + " " + r.value(fd::kAction, "");
  return event;
}

/// A `state` record to `to`, in short.
std::string state(const std::string& to) { return std::string(ev::kState) + " " + to; }
/// An `action` record of `what`, in short.
std::string action(const std::string& what) { return std::string(ev::kAction) + " " + what; }
/// The records of a fault reset and recovered, in short.
std::vector<std::string> resetAndRecovered() {
  return {ev::kDetected, state("Error"), ev::kDiagnosed, action("reset"), state("Active"), ev::kRecovered};
}

/// The records of fault `id`, in short, in the order they were written.
std::vector<std::string> recordsOf(const std::vector<json>& log, std::uint64_t id) {
  std::vector<std::string> out;
  for (const json& r : log)
    if (r.value(fd::kFaultId, std::uint64_t{0}) == id) out.push_back(shortly(r));
  return out;
}

/// The fault id of the detection with `detail` (0: none).
std::uint64_t idOf(const std::vector<json>& log, std::string_view detail) {
  for (const json& r : test::eventsOf(log, ev::kDetected))
    if (r.value(fd::kDetail, "") == detail) return r.value(fd::kFaultId, std::uint64_t{0});
  return 0;
}

/// The detail of fault `id`'s first `action` record of that action ("" when there is none).
std::string detailOf(const std::vector<json>& log, std::uint64_t id, std::string_view action) {
  for (const json& r : test::eventsOf(log, ev::kAction))
    if (r.value(fd::kFaultId, std::uint64_t{0}) == id && r.value(fd::kAction, "") == action)
      return r.value(fd::kDetail, "");
  return "";
}

/// A fault manager without a thread, logging to a temporary file, and one passive component
/// `arm`, Active, whose role it handles (ComponentHandling set as the engine sets it).
struct Rig {
  Rig() {
    runtime::setStateQuiet(arm, State::Active);
    host.all = {&arm};
    coreOf(arm).fault.handling = &handling;
  }

  /// The role's policy: every kind of fault has `severity`; no alternative.
  void policy(Severity severity) {
    handling.rules.has_policy = true;
    handling.rules.severity.fill(severity);
  }
  std::vector<json> read() const { return file.read(); }

  test::TempLog file{"keel_fault_manager"};
  Joint arm{"arm"};
  ComponentHandling handling{Rules{}, "arm"};
  test::FakeRecoveryActions host;
  FaultManager manager{file.log, host.lookup()};
};

FaultEvent segfault(const char* detail = "SIGSEGV in onExecute") { return {FaultKind::Signal, "", detail}; }

TEST(FaultManager, APassiveComponentFaultingInsideItsOwnCallbackIsResetAfterTheCallbackReturns) {
  Rig rig;
  rig.policy(Severity::Reset);
  coreOf(rig.arm).fault_sink = &rig.manager;  // the runtime's fault sink, as the engine wires it
  rig.arm.during_execute = [&] { runtime::reportFault(rig.arm, FaultEvent(FaultKind::User, "", "noticed")); };

  (void)runtime::invoke(rig.arm, runtime::Callback::Execute);

  // Not nested inside onExecute (its lock is recursive): the reset follows the callback.
  EXPECT_EQ(rig.arm.trace(), (std::vector<std::string>{"onExecute", "onError", "onReset", "onRecover"}));
  EXPECT_EQ(rig.arm.state(), State::Active);
}

// What the guard catches in a running callback reaches the fault manager as it was caught; its
// text is written with the fault's records, and says what was caught and where.
TEST(FaultManager, AFaultTheGuardCaughtIsDescribedInItsDetectedRecord) {
  runtime::installSignalHandlers();
  Rig rig;
  rig.policy(Severity::Reset);
  coreOf(rig.arm).fault_sink = &rig.manager;
  rig.arm.during_execute = [] { ::raise(SIGSEGV); };

  EXPECT_FALSE(runtime::invoke(rig.arm, runtime::Callback::Execute));

  EXPECT_EQ(rig.arm.trace(), (std::vector<std::string>{"onError", "onReset", "onRecover"}));
  const auto detected = test::eventsOf(rig.read(), ev::kDetected);
  ASSERT_EQ(detected.size(), 1u);
  EXPECT_EQ(detected[0][fd::kKind], "signal");
  EXPECT_EQ(detected[0][fd::kDetail], "SIGSEGV in onExecute (raised by its own process: abort(), raise() or kill)");
}

TEST(FaultManager, WithoutAThreadAResetFaultIsLoggedFromDetectionToRecoveryUnderOneFaultId) {
  Rig rig;
  rig.policy(Severity::Reset);

  rig.manager.report(rig.arm, segfault());

  EXPECT_EQ(rig.arm.trace(), (std::vector<std::string>{"onError", "onReset", "onRecover"}));
  EXPECT_EQ(rig.arm.thread, std::this_thread::get_id()) << "no thread: handled on the reporting one";
  EXPECT_TRUE(rig.arm.under_lock) << "a passive component is reset holding its lock";
  EXPECT_EQ(rig.arm.state(), State::Active);
  const auto log = rig.read();
  const auto detected = test::eventsOf(log, ev::kDetected);
  ASSERT_EQ(detected.size(), 1u);
  const auto id = detected[0][fd::kFaultId].get<std::uint64_t>();
  EXPECT_EQ(recordsOf(log, id), resetAndRecovered());
  EXPECT_EQ(log.size(), 6u) << "every record of it carries its fault_id";
  EXPECT_EQ(rig.manager.recoveredCount(), 1u);
  ASSERT_TRUE(rig.manager.handling(id));
  EXPECT_EQ(rig.manager.handling(id)->actions, "reset");
  std::lock_guard lock(rig.handling.mutex);
  EXPECT_FALSE(rig.handling.busy) << "the role is free for the next fault";
}

TEST(FaultManager, WithItsThreadAPassiveComponentIsResetThereAndLoggedTheSame) {
  Rig rig;
  rig.policy(Severity::Reset);
  rig.manager.start();

  rig.manager.report(rig.arm, segfault());
  rig.manager.drain();

  EXPECT_EQ(rig.arm.trace(), (std::vector<std::string>{"onError", "onReset", "onRecover"}));
  EXPECT_NE(rig.arm.thread, std::this_thread::get_id()) << "handed over to the manager's thread";
  EXPECT_TRUE(rig.arm.under_lock);
  EXPECT_EQ(rig.arm.state(), State::Active);
  const auto log = rig.read();
  ASSERT_FALSE(log.empty());
  const auto id = log.front()[fd::kFaultId].get<std::uint64_t>();
  EXPECT_EQ(recordsOf(log, id), resetAndRecovered());
}

TEST(FaultManager, ASecondFaultWhileTheFirstIsBeingHandledIsOnlyLogged) {
  Rig rig;
  rig.policy(Severity::Reset);
  rig.arm.during_reset = [&rig, reported = false]() mutable {
    if (reported) return;
    reported = true;
    rig.manager.report(rig.arm, segfault("second, during onReset"));
  };

  rig.manager.report(rig.arm, segfault("first"));

  EXPECT_EQ(rig.arm.trace(), (std::vector<std::string>{"onError", "onReset", "onRecover"})) << "reset once";
  EXPECT_EQ(rig.arm.state(), State::Active);
  const auto log = rig.read();
  const std::uint64_t first = idOf(log, "first"), second = idOf(log, "second, during onReset");
  ASSERT_NE(first, 0u);
  ASSERT_NE(second, 0u);
  EXPECT_NE(first, second);
  EXPECT_EQ(recordsOf(log, second), (std::vector<std::string>{ev::kDetected, ev::kDiagnosed, action("ignore")}));
  EXPECT_EQ(detailOf(log, second, "ignore"), "a fault of it is being handled");
  EXPECT_EQ(recordsOf(log, first), resetAndRecovered());
  EXPECT_EQ(rig.manager.detectionCount(), 2u);
}

TEST(FaultManager, OnceAFaultIsHandledTheNextOneIsHandledAgain) {
  Rig rig;
  rig.policy(Severity::Reset);
  rig.manager.report(rig.arm, segfault("first"));

  rig.manager.report(rig.arm, segfault("second"));

  EXPECT_EQ(rig.arm.trace(),
            (std::vector<std::string>{"onError", "onReset", "onRecover", "onError", "onReset", "onRecover"}));
  const auto log = rig.read();
  EXPECT_EQ(test::eventsOf(log, ev::kRecovered).size(), 2u);
  EXPECT_EQ(rig.manager.recoveredCount(), 2u);
}

TEST(FaultManager, AResetBeyondTheRestartIntensityEscalatesToAStop) {
  Rig rig;
  rig.policy(Severity::Reset);
  rig.handling.rules.intensity = 1;
  rig.handling.window = RestartWindow(1, 10'000'000'000);
  rig.manager.report(rig.arm, segfault("first"));

  rig.manager.report(rig.arm, segfault("second"));

  EXPECT_EQ(rig.arm.trace(), (std::vector<std::string>{"onError", "onReset", "onRecover"})) << "not reset twice";
  EXPECT_EQ(rig.arm.state(), State::Error);
  EXPECT_EQ(rig.manager.stoppedComponents(), std::set<std::string>{"arm"});
  const auto log = rig.read();
  EXPECT_EQ(recordsOf(log, idOf(log, "second")),
            (std::vector<std::string>{ev::kDetected, state("Error"), ev::kDiagnosed, action("escalate"),
                                      action("stop")}));
}

TEST(FaultManager, AnIgnoredFaultIsOnlyLoggedAndLeavesTheComponentActive) {
  Rig rig;
  rig.policy(Severity::Ignore);

  rig.manager.report(rig.arm, FaultEvent(FaultKind::Range, "", "NaN on distance"));

  EXPECT_TRUE(rig.arm.trace().empty());
  EXPECT_EQ(rig.arm.state(), State::Active);
  const auto log = rig.read();
  ASSERT_FALSE(log.empty());
  const auto id = log.front()[fd::kFaultId].get<std::uint64_t>();
  EXPECT_EQ(recordsOf(log, id), (std::vector<std::string>{ev::kDetected, ev::kDiagnosed, action("ignore")}));
  EXPECT_EQ(detailOf(log, id, "ignore"), "severity ignore: logged only");
}

TEST(FaultManager, AComponentWithoutHandlingIsContainedInError) {
  Rig rig;
  coreOf(rig.arm).fault.handling = nullptr;  // not managed by a runtime

  rig.manager.report(rig.arm, segfault());

  EXPECT_TRUE(rig.arm.trace().empty()) << "no recovery without rules";
  EXPECT_EQ(rig.arm.state(), State::Error);
  const auto log = rig.read();
  ASSERT_FALSE(log.empty());
  const auto id = log.front()[fd::kFaultId].get<std::uint64_t>();
  EXPECT_EQ(recordsOf(log, id),
            (std::vector<std::string>{ev::kDetected, state("Error"), ev::kDiagnosed, action("stop")}));
  EXPECT_EQ(detailOf(log, id, "stop"), "contained: the component stays in Error");
}

TEST(FaultManager, AStopSeverityFaultStopsTheComponentAndItsLaterFaultsAreOnlyLogged) {
  Rig rig;
  rig.policy(Severity::Stop);
  rig.manager.report(rig.arm, segfault("first"));

  rig.manager.report(rig.arm, segfault("later"));

  EXPECT_TRUE(rig.arm.trace().empty());
  EXPECT_EQ(rig.arm.state(), State::Error);
  EXPECT_EQ(rig.manager.stoppedComponents(), std::set<std::string>{"arm"});
  const auto log = rig.read();
  EXPECT_EQ(recordsOf(log, idOf(log, "first")),
            (std::vector<std::string>{ev::kDetected, state("Error"), ev::kDiagnosed, action("stop")}));
  EXPECT_EQ(recordsOf(log, idOf(log, "later")),
            (std::vector<std::string>{ev::kDetected, ev::kDiagnosed, action("ignore")}));
  EXPECT_EQ(detailOf(log, idOf(log, "later"), "ignore"), "the component is stopped");
}

TEST(FaultManager, AnEmergencyFaultRunsEveryOnEmergencyStopThenStopsTheFaultyComponent) {
  Rig rig;
  rig.policy(Severity::Emergency);
  Joint leg("leg");
  rig.host.all.push_back(&leg);
  rig.manager.attach(&rig.host, nullptr);

  rig.manager.report(rig.arm, segfault());

  EXPECT_EQ(rig.arm.trace(), std::vector<std::string>{"onEmergencyStop"});
  EXPECT_EQ(leg.trace(), std::vector<std::string>{"onEmergencyStop"});
  EXPECT_TRUE(rig.manager.emergencyLatched());
  EXPECT_EQ(rig.manager.stoppedComponents(), std::set<std::string>{"arm"}) << "an emergency goes on as a stop";
  const auto log = rig.read();
  const auto id = log.front()[fd::kFaultId].get<std::uint64_t>();
  EXPECT_EQ(recordsOf(log, id), (std::vector<std::string>{ev::kDetected, state("Error"), ev::kDiagnosed,
                                                          action("emergency_stop"), action("stop")}))
      << "the emergency stop is one of this fault's actions";
  const auto emergency = test::eventsOf(log, ev::kEmergency);
  ASSERT_EQ(emergency.size(), 1u);
  EXPECT_EQ(emergency[0][fd::kBy], "fault " + std::to_string(id) + " of arm");
}

}  // namespace
}  // namespace keel::fault
