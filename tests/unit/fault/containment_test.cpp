// Containment (src/fault/containment.hpp): the emergency stop — every component's
// onEmergencyStop, on its own thread or under its lock, the latch and its log records — its
// clearing, and the fault stop of a component alone when there is no dependency graph.
#include "fault/containment.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "log/schema.hpp"
#include "plan/fault_manager_profile.hpp"
#include "runtime/clock.hpp"
#include "runtime/component_core.hpp"
#include "runtime/executor.hpp"
#include "runtime/invoke.hpp"
#include "support/fake_recovery_actions.hpp"
#include "support/log_reader.hpp"
#include "support/temp_log.hpp"

namespace keel::fault {
namespace {

namespace ev = log::schema::event;
namespace fd = log::schema::field;
using namespace std::chrono_literals;
using nlohmann::json;
using runtime::coreOf;

/// Notes where and how its onEmergencyStop ran.
class Actuator : public Component {
 public:
  explicit Actuator(const std::string& name) { coreOf(*this).instance_name = name; }
  ReturnCode onEmergencyStop() override {
    thread = std::this_thread::get_id();
    auto& core = coreOf(*this);
    if (runtime::Executor* ex = core.executor.load()) on_executor = ex->onThisThread();
    // Whether this thread holds the passive lock: another thread cannot take it then.
    bool taken = false;
    std::thread([&] {
      if (core.passive_mutex.try_lock()) {
        taken = true;
        core.passive_mutex.unlock();
      }
    }).join();
    under_lock = !taken;
    stops.fetch_add(1);
    return ReturnCode::Ok;
  }
  std::atomic<int> stops{0};
  std::thread::id thread;
  bool on_executor = false;
  bool under_lock = false;
};

/// Containment as the fault manager has it: its records in a fault log on a temporary file,
/// the host's components, no dependency graph.
struct Rig {
  Rig() { containment.attach(&host, nullptr); }
  std::vector<json> read() const { return file.read(); }

  test::TempLog file{"keel_containment"};
  FaultRecords records{file.log};
  test::FakeRecoveryActions host;
  Containment containment{records, host.lookup()};
};

TEST(Containment, AnEmergencyStopRunsEveryComponentsOnEmergencyStopAndLatches) {
  Rig rig;
  Actuator left("left"), right("right"), manager(plan::kFaultManagerInstance);
  rig.host.all = {&left, &right, &manager};

  const auto ran = rig.containment.emergencyStop("operator");

  EXPECT_EQ(ran, (std::vector<std::string>{"left", "right"}));
  EXPECT_EQ(left.stops.load(), 1);
  EXPECT_EQ(right.stops.load(), 1);
  EXPECT_EQ(manager.stops.load(), 0) << "the fault manager is not an actuator";
  EXPECT_TRUE(rig.containment.emergencyLatched());
  EXPECT_TRUE(left.emergencyLatched());
  EXPECT_TRUE(right.emergencyLatched());
  const auto log = rig.read();
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0][fd::kEvent], ev::kEmergency);
  EXPECT_EQ(log[0][fd::kPhase], "latched");
  EXPECT_EQ(log[0][fd::kBy], "operator");
  EXPECT_EQ(log[1][fd::kEvent], ev::kAction);
  EXPECT_EQ(log[1][fd::kAction], "emergency_stop");
  EXPECT_EQ(log[1][fd::kOutcome], log::schema::kOk);
  EXPECT_EQ(log[1][fd::kBy], "operator");
  EXPECT_EQ(log[1][fd::kComponents], json::array({"left", "right"}));
  EXPECT_FALSE(log[1].contains(fd::kFaultId)) << "no fault caused it";
  EXPECT_FALSE(log[1].contains(fd::kOnFaultManagerThread)) << "every component answered on its own thread";
}

TEST(Containment, APassiveComponentsOnEmergencyStopRunsUnderItsLock) {
  Rig rig;
  Actuator passive("passive");
  rig.host.all = {&passive};

  rig.containment.emergencyStop("operator");

  ASSERT_EQ(passive.stops.load(), 1);
  EXPECT_TRUE(passive.under_lock) << "its callbacks are serialised by its lock";
  EXPECT_EQ(passive.thread, std::this_thread::get_id());
}

TEST(Containment, AComponentOnAnExecutorStopsOnItsExecutorsThread) {
  Rig rig;
  Actuator driven("driven");
  ASSERT_TRUE(runtime::transition(driven, Transition::Initialize));
  runtime::Executor ex({"drive", runtime::ExecutorKind::Aperiodic, 10ms, 0, SchedPolicy::Other});
  ex.add(driven);
  ex.start();
  rig.host.all = {&driven};
  // An idle executor's wake can take more than 20 ms on a loaded machine under a sanitizer:
  // this test is about whose thread runs it, not how soon.
  rig.containment.setEmergencyBound(10s);

  const auto ran = rig.containment.emergencyStop("operator");

  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  EXPECT_EQ(ran, std::vector<std::string>{"driven"});
  EXPECT_EQ(driven.stops.load(), 1);
  EXPECT_TRUE(driven.on_executor);
  EXPECT_NE(driven.thread, std::this_thread::get_id());
}

TEST(Containment, APassiveComponentHeldBusyIsStoppedFromTheCallersThreadAndSaidSo) {
  Rig rig;
  Actuator stuck("stuck");
  rig.host.all = {&stuck};
  std::atomic<bool> holding{false}, release{false};
  std::thread holder([&] {  // a callback of it that does not return
    std::lock_guard lock(coreOf(stuck).passive_mutex);
    holding = true;
    while (!release) std::this_thread::sleep_for(1ms);
  });
  while (!holding) std::this_thread::yield();

  const auto ran = rig.containment.emergencyStop("operator");

  release = true;
  holder.join();
  EXPECT_EQ(ran, std::vector<std::string>{"stuck"});
  EXPECT_EQ(stuck.stops.load(), 1) << "a hung component's actuator is still made safe";
  EXPECT_EQ(stuck.thread, std::this_thread::get_id());
  const auto actions = test::eventsOf(rig.read(), ev::kAction);
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0][fd::kOnFaultManagerThread], json::array({"stuck"}));
}

TEST(Containment, ClearingTheEmergencyUnlatchesEveryComponentAndIsLogged) {
  Rig rig;
  Actuator left("left");
  rig.host.all = {&left};
  rig.containment.emergencyStop("fault 3 of left");

  const bool cleared = rig.containment.clearEmergency("operator");
  const bool again = rig.containment.clearEmergency("operator");

  EXPECT_TRUE(cleared);
  EXPECT_FALSE(again) << "nothing latched any more";
  EXPECT_FALSE(rig.containment.emergencyLatched());
  EXPECT_FALSE(left.emergencyLatched());
  const auto emergencies = test::eventsOf(rig.read(), ev::kEmergency);
  ASSERT_EQ(emergencies.size(), 2u) << "latched, cleared once";
  EXPECT_EQ(emergencies[1][fd::kPhase], "cleared");
  EXPECT_EQ(emergencies[1][fd::kBy], "operator");
  const auto actions = test::eventsOf(rig.read(), ev::kAction);
  ASSERT_EQ(actions.size(), 2u) << "the emergency stop, then the clear";
  EXPECT_EQ(actions[1][fd::kAction], "clear");
  EXPECT_EQ(actions[1][fd::kBy], "operator");
  EXPECT_EQ(actions[1][fd::kOutcome], "ok");
}

TEST(Containment, ClearingWhenNoEmergencyIsLatchedIsRefusedAndNotLogged) {
  Rig rig;
  const bool cleared = rig.containment.clearEmergency("operator");

  EXPECT_FALSE(cleared);
  EXPECT_TRUE(rig.read().empty());
}

TEST(Containment, WithoutADependencyGraphAFaultStopStopsTheFaultyComponentAlone) {
  Rig rig;
  Actuator arm("arm"), leg("leg");
  ASSERT_TRUE(runtime::transition(leg, Transition::Initialize));
  ASSERT_TRUE(runtime::transition(leg, Transition::Start));
  runtime::setStateQuiet(arm, State::Error);
  rig.host.all = {&arm, &leg};
  ComponentHandling arm_handling, leg_handling;
  coreOf(arm).fault.handling = &arm_handling;
  coreOf(leg).fault.handling = &leg_handling;
  FaultReport r;
  r.event = FaultEvent(FaultKind::Signal, "arm", "SIGSEGV");
  r.event.t_ns = runtime::steadyNs();
  r.id = 9;
  r.accused = &arm;
  r.first = r.next = Step::Stop;
  r.add(ActionKind::Escalate, true, runtime::steadyNs(), "reset → stop: the reset failed");

  const Outcome outcome = rig.containment.stopScope(r, arm_handling);

  EXPECT_EQ(outcome, Outcome::Done);
  EXPECT_EQ(rig.containment.stoppedComponents(), std::set<std::string>{"arm"});
  EXPECT_TRUE(rig.containment.stoppedApplications().empty());
  EXPECT_TRUE(arm_handling.stopped) << "further faults of it are only logged";
  EXPECT_FALSE(leg_handling.stopped);
  EXPECT_EQ(leg.state(), State::Active) << "nothing depends on it without a graph";
  EXPECT_EQ(arm.state(), State::Error) << "the faulty component stays in Error";
  ASSERT_EQ(r.n_actions, 2);
  EXPECT_EQ(r.actions[1].kind, ActionKind::Stop);
  EXPECT_TRUE(r.actions[1].ok);
  EXPECT_EQ(r.logged_actions, r.n_actions) << "the stop record is written here";
  const auto log = rig.read();
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log.front()[fd::kEvent], ev::kDetected) << "what happened so far goes first";
  const auto actions = test::eventsOf(log, ev::kAction);
  ASSERT_EQ(actions.size(), 2u) << "the escalation, then the stop";
  EXPECT_EQ(actions[0][fd::kAction], "escalate");
  EXPECT_EQ(actions[1][fd::kAction], "stop");
  EXPECT_EQ(actions[1][fd::kOutcome], log::schema::kOk);
  EXPECT_EQ(actions[1][fd::kFaultId], 9u);
  EXPECT_EQ(actions[1][fd::kComponent], "arm");
  EXPECT_EQ(actions[1][fd::kScope], "component");
  EXPECT_EQ(actions[1][fd::kComponents], json::array({"arm"}));
  EXPECT_EQ(actions[1][fd::kApplications], json::array());
}

TEST(Containment, AComponentAlreadyStoppedIsNotListedAgain) {
  Rig rig;
  Actuator arm("arm");
  runtime::setStateQuiet(arm, State::Error);
  rig.host.all = {&arm};
  ComponentHandling h;
  coreOf(arm).fault.handling = &h;
  FaultReport first, second;
  for (FaultReport* r : {&first, &second}) {
    r->event = FaultEvent(FaultKind::Signal, "arm", "SIGSEGV");
    r->event.t_ns = runtime::steadyNs();
    r->accused = &arm;
  }
  first.id = 1;
  second.id = 2;
  rig.containment.stopScope(first, h);

  rig.containment.stopScope(second, h);

  const auto actions = test::eventsOf(rig.read(), ev::kAction);
  ASSERT_EQ(actions.size(), 2u);
  EXPECT_EQ(actions[1][fd::kFaultId], 2u);
  EXPECT_EQ(actions[1][fd::kComponents], json::array());
  EXPECT_EQ(rig.containment.stoppedComponents(), std::set<std::string>{"arm"});
}

}  // namespace
}  // namespace keel::fault
