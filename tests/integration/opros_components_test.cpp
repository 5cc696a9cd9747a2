// Components written for OPRoS, built from their sources unchanged (keel_add_opros_component)
// and run by `keel run` with their profiles: the real OPRoS samples of third_party/opros_samples,
// and keel's own OPRoS-API test component (components/opros_components.cpp), under keel's
// fault mechanisms. docs/opros.md, "OPRoS component sources".
#include <gtest/gtest.h>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

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

std::string profile(const std::string& name) { return std::string(KEEL_TEST_PROFILES) + "/opros/" + name; }
std::string sample(const std::string& path) { return std::string(KEEL_OPROS_SAMPLES) + "/" + path; }

struct Trace {
  long executions = 0, received = 0, events = 0;
};
Trace readTrace(const std::string& path) {
  Trace t;
  std::ifstream in(path);
  in >> t.executions >> t.received >> t.events;
  return t;
}

class OprosComponents : public ::testing::Test {
 protected:
  // The libraries are found as a user's would be: through KEEL_COMPONENT_PATH.
  keel::test::ScopedEnv component_path_{"KEEL_COMPONENT_PATH", KEEL_OPROS_COMPONENTS};
  void TearDown() override {
    std::filesystem::remove(log_);
    for (const auto& t : traces_) std::filesystem::remove(t);
  }
  std::string trace(const std::string& stem) {
    traces_.push_back(test::tempPath("keel_opros_" + stem, ".txt"));
    return traces_.back();
  }
  std::string log_ = test::tempPath("keel_opros_test");
  std::vector<std::string> traces_;
};

// ETRI's helloworld as published: HelloMaker calls MessagePrinter's print() through a required
// service port, pushes "Sample Msg" on a data port and a "messageid" event; MessagePrinter prints
// each. The profile asks FIFO/10 of DataIn, the code constructs LAST/1: the code's is used, with
// a warning naming the profile's line.
TEST_F(OprosComponents, TheHelloworldPairCallsSendsAndSignalsWithItsRealProfiles) {
  auto r = test::runProcess({KEEL_CLI, "run", sample("parasby/OPRoS/example/helloworld/app/abalone/hello.xml"),
                             "--duration", "1.5", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("Mes  message is Hello"), std::string::npos) << r.out;      // the service call
  EXPECT_NE(r.out.find("In Data is Sample Msg"), std::string::npos) << r.out;      // the data port
  EXPECT_NE(r.out.find("Event Data is hello world"), std::string::npos) << r.out;  // the event
  EXPECT_NE(r.err.find("port 'DataIn': the profile asks for fifo of 10, the code constructs last of 1"),
            std::string::npos)
      << r.err;
  auto log = test::readLog(log_);
  EXPECT_EQ(test::statesOf(log, "HelloMaker"), (std::vector<std::string>{"Ready", "Active", "Inactive", "Destroyed"}));
  EXPECT_EQ(test::statesOf(log, "MessagePrinter"),
            (std::vector<std::string>{"Ready", "Active", "Inactive", "Destroyed"}));
  EXPECT_TRUE(test::eventsOf(log, ev::kDetected).empty()) << r.out;
}

// GazeboSimpleArm's OneComp and TwoComp with their own application profile (OPRoSApp1): a user
// data type (PersonData, with opros::archive save/load and its own typeName) on a data port, an
// event to a SET_EVENT_CALLBACK callback, a service call, a property read every cycle.
TEST_F(OprosComponents, OneCompAndTwoCompExchangeAUserDataTypeWithTheirRealProfiles) {
  auto r = test::runProcess(
      {KEEL_CLI, "run", sample("opros-wiki/OPRoS_v2_Applications/GazeboSimpleArm/workspace/OPRoSApp1/OPRoSApp1.xml"),
       "--duration", "1", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("TwoComp::PrintStr opros"), std::string::npos) << r.out;     // the call, with OneComp's Msg
  EXPECT_NE(r.out.find("strEventInCallback : opros"), std::string::npos) << r.out;  // the event's callback
  EXPECT_NE(r.out.find("Person Name : opros"), std::string::npos) << r.out;         // PersonData arrived
  // The int port: TwoComp prints the value it got, "Two Component : 3". OneComp prints on another
  // thread into the same stdout, piece by piece as TwoComp does, so its line can fall inside
  // TwoComp's: "Two Component : One Component : 3\n3".
  const std::regex two_got(R"(Two Component : (?:One Component : (?:\d+\n)?)?(\d+))");
  bool got3 = false;
  for (std::sregex_iterator m(r.out.begin(), r.out.end(), two_got), end; m != end; ++m) got3 |= (*m)[1] == "3";
  EXPECT_TRUE(got3) << r.out;
  EXPECT_TRUE(test::eventsOf(test::readLog(log_), ev::kDetected).empty()) << r.out;
}

// The other samples with their own component profiles, each alone: FlightControl (two
// translation units) and the two KITECH components (2012's device types) run; the topological
// planner's code has a port its profile lacks: a warning naming it, and it loads.
// LaserScannerTestComp calls a laser scanner it is not connected to, as OPRoS would have
// thrown: an exception fault saying so.
TEST_F(OprosComponents, TheOtherSamplesRunAloneWithTheirRealProfiles) {
  const std::string kitech = "opros-wiki/OPRoS_v1.1_Components/Component/";
  for (const std::string& path :
       std::vector<std::string>{"parasby/OPRoS/example/droneTest/FlightControl/profile/FlightControl.xml",
                                kitech +
                                    "KITECH_TopologicalPathPlanningComp/profile/KITECH_TopologicalPathPlanningComp.xml",
                                kitech + "KitechLinearTrajectoryGenerationComp_V1.0_20120731/profile/"
                                         "KitechLinearTrajectoryGenerationComp.xml"}) {
    auto r = test::runProcess({KEEL_CLI, "run", sample(path), "--duration", "0.3", "--log", log_});
    ASSERT_EQ(r.status, 0) << path << r.out << r.err;
    EXPECT_TRUE(test::eventsOf(test::readLog(log_), ev::kDetected).empty()) << path << r.out;
    if (path.find("Topological") != std::string::npos) {
      EXPECT_NE(r.err.find("class 'KITECH_TopologicalPathPlanningComp' has required service port 'GlobalMapService' "
                           "that the profile does not declare (an OPRoS component: it loads)"),
                std::string::npos)
          << r.err;
    }
  }
  auto r = test::runProcess({KEEL_CLI, "run",
                             sample("idwn1203/OPRoS_SLAM/LaserScannerTestComp/profile/LaserScannerTestComp.xml"),
                             "--duration", "0.3", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  auto detected = test::eventsOf(test::readLog(log_), ev::kDetected);
  ASSERT_EQ(detected.size(), 1u) << r.out;
  EXPECT_EQ(detected[0].value(fd::kDetail, ""),
            "exception in onExecute: calling 'LaserScannerService.GetSensorValue': service port "
            "'LaserScannerService' is not connected");
}

// Data, event and service connections between two OPRoS components, each observed on the
// other side: `a` gets back what b.add returned (the call), b counted a's ticks (the event) and
// received more than a's calls of add(1) gave it (the data: a's counts).
TEST_F(OprosComponents, DataEventAndServicePortsConnectThroughKeel) {
  const std::string ta = trace("a"), tb = trace("b");
  auto r = test::runProcess({KEEL_CLI, "run", profile("pair.xml"), "--duration", "0.6", "--log", log_, "--set",
                             "a.trace=" + ta, "--set", "b.trace=" + tb});
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  const Trace a = readTrace(ta), b = readTrace(tb);
  EXPECT_GT(a.executions, 10);
  EXPECT_GT(a.received, 10) << "b's Counter.add answered a";
  EXPECT_GT(b.events, 10) << "a's ticks reached b's onEvent";
  EXPECT_GT(b.received, 2 * a.executions) << "a's counts reached b's input too";
  EXPECT_TRUE(test::eventsOf(test::readLog(log_), ev::kDetected).empty()) << r.err;
}

// A SIGSEGV inside an OPRoS component's onExecute is a `signal` fault; its policy resets it, and
// the memory it registered with critical() comes back from the checkpoint, undoing what it
// scribbled there before it crashed.
TEST_F(OprosComponents, ACrashIsResetAndTheCriticalStateRestored) {
  const std::string t = trace("crash");
  auto r = test::runProcess(
      {KEEL_CLI, "run", profile("crash_reset.xml"), "--duration", "0.8", "--log", log_, "--set", "counter.trace=" + t});
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  auto log = test::readLog(log_);
  auto detected = test::eventsOf(log, ev::kDetected);
  ASSERT_EQ(detected.size(), 1u) << r.out;
  EXPECT_EQ(detected[0].value(fd::kComponent, ""), "counter");
  EXPECT_EQ(detected[0].value(fd::kKind, ""), "signal");
  EXPECT_EQ(test::eventsOf(log, ev::kRecovered).size(), 1u);
  const Trace after = readTrace(t);
  EXPECT_GT(after.executions, 40) << "restored from the checkpoint, then counted on";
}

// Faults of other kinds in OPRoS code: an exception, a failing return code.
TEST_F(OprosComponents, AnExceptionAndAnErrorCodeAreFaultsOfTheirKinds) {
  for (const auto& [fault, kind] :
       std::vector<std::pair<std::string, std::string>>{{"throw", "exception"}, {"error", "error_code"}}) {
    auto r = test::runProcess({KEEL_CLI, "run", profile("crash_reset.xml"), "--duration", "0.5", "--log", log_, "--set",
                               "counter.fault=" + fault});
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    auto detected = test::eventsOf(test::readLog(log_), ev::kDetected);
    ASSERT_EQ(detected.size(), 1u) << fault << r.out;
    EXPECT_EQ(detected[0].value(fd::kKind, ""), kind);
    if (fault == "error") {
      EXPECT_EQ(detected[0].value(fd::kDetail, ""), "onExecute returned 502 (OPROS_INTERNAL_FAULT)");
    }
  }
}

// An OPRoS component in a process of its own with a preloaded standby: a kill -9 of that
// process is a `process` fault, the standby takes over with the checkpoint the dead one
// published (its count goes on from there, beyond what the standby counted alone), and its
// reader in keel run's process keeps receiving.
TEST_F(OprosComponents, InAProcessOfItsOwnItIsTakenOverAfterKill9WithItsCheckpoint) {
  const std::string tc = trace("isolated"), tr = trace("reader");
  auto r = test::runProcess({KEEL_CLI, "run", profile("isolated.xml"), "--duration", "1", "--log", log_, "--inject",
                             profile("kill_counter.xml"), "--set", "counter.trace=" + tc, "--set",
                             "reader.trace=" + tr});
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  auto log = test::readLog(log_);
  auto detected = test::eventsOf(log, ev::kDetected);
  ASSERT_EQ(detected.size(), 1u) << r.out;
  EXPECT_EQ(detected[0].value(fd::kKind, ""), "process");
  EXPECT_EQ(test::eventsOf(log, ev::kRecovered).size(), 1u) << r.out;
  // The standby's own executions (its `counts` record) against its count: it began from the
  // count of the process killed at 0.3 s (some 60 cycles of 5 ms), not from 0.
  long standby_executions = -1;
  for (const auto& c : test::eventsOf(log, ev::kCounts))
    if (c.value(fd::kComponent, "") == "counter") standby_executions = c.value(fd::kExecutions, -1L);
  ASSERT_GT(standby_executions, 0) << r.out;
  EXPECT_GT(readTrace(tc).executions, standby_executions + 20) << "the standby began from the checkpoint";
  EXPECT_GT(readTrace(tr).received, readTrace(tr).executions) << "the reader received counts";
}

// examples/03_opros_component as its README runs it: the OPRoS Odometer beside a keel wheel
// driver, a segfault and an out-of-range value injected into it, each detected by its detector
// and reset; its onError and onRecover run, and it goes on from its pose, not from 0.
TEST_F(OprosComponents, TheExampleRecoversItsOprosComponentFromInjectedFaults) {
  const std::string example = std::string(KEEL_EXAMPLES) + "/03_opros_component/";
  auto r = test::runProcess(
      {KEEL_CLI, "run", example + "app.xml", "--duration", "2.5", "--log", log_, "--inject", example + "scenario.xml"});
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  auto log = test::readLog(log_);
  auto detected = test::eventsOf(log, ev::kDetected);
  ASSERT_EQ(detected.size(), 2u) << r.out;
  EXPECT_EQ(detected[0].value(fd::kKind, ""), "signal");
  EXPECT_EQ(detected[1].value(fd::kKind, ""), "range");
  EXPECT_EQ(test::eventsOf(log, ev::kRecovered).size(), 2u) << r.out;
  // "odometer: recovered at X m, cycle N" (its onRecover) after each fault.
  std::size_t recovered = 0;
  for (std::size_t at = r.out.find("odometer: recovered at "); at != std::string::npos;
       at = r.out.find("odometer: recovered at ", at + 1)) {
    ++recovered;
    const std::size_t digits = r.out.find("cycle ", at) + 6;
    long cycle = -1;
    std::from_chars(r.out.data() + digits, r.out.data() + r.out.size(), cycle);
    EXPECT_GT(cycle, 10) << r.out.substr(at, 60);
  }
  EXPECT_EQ(recovered, 2u) << r.out;
}

// The rest of keel's handling, applied to OPRoS components by their integrator's rules: a hang
// found by the heartbeat and reset; a crash replaced by a preloaded alternative (the same OPRoS
// library); a failing return code, named as OPRoS names it, stopping what needs the component;
// an exception calling for the emergency stop, which every component gets.
TEST_F(OprosComponents, HeartbeatReplacementFaultStopAndEmergencyStopApply) {
  auto run = [&](const std::string& package) {
    auto r = test::runProcess({KEEL_CLI, "run", profile(package), "--duration", "0.5", "--log", log_});
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    return test::readLog(log_);
  };
  auto action = [](const std::vector<nlohmann::json>& log, const std::string& name) {
    for (const auto& a : test::eventsOf(log, ev::kAction))
      if (a.value(fd::kAction, "") == name) return a;
    return nlohmann::json();
  };
  {
    auto log = run("hang.xml");
    auto detected = test::eventsOf(log, ev::kDetected);
    ASSERT_EQ(detected.size(), 1u);
    EXPECT_EQ(detected[0].value(fd::kKind, ""), "heartbeat");
    EXPECT_EQ(test::eventsOf(log, ev::kRecovered).size(), 1u);
  }
  {
    auto log = run("replace.xml");
    const auto replaced = action(log, "replace");
    ASSERT_FALSE(replaced.is_null());
    EXPECT_EQ(replaced.value(fd::kOutcome, ""), "ok");
    EXPECT_NE(replaced.value(fd::kDetail, "").find("preloaded"), std::string::npos) << replaced;
    EXPECT_FALSE(test::eventsOf(log, ev::kRecovered).empty());
  }
  {
    auto log = run("stop.xml");
    auto detected = test::eventsOf(log, ev::kDetected);
    ASSERT_EQ(detected.size(), 1u);
    EXPECT_EQ(detected[0].value(fd::kDetail, ""), "onExecute returned 502 (OPROS_INTERNAL_FAULT)");
    const auto stopped = action(log, "stop");
    ASSERT_FALSE(stopped.is_null());
    EXPECT_EQ(stopped[fd::kComponents].get<std::vector<std::string>>(),
              (std::vector<std::string>{"counter", "reader"}));
  }
  {
    auto log = run("emergency.xml");
    const auto latched = test::eventsOf(log, ev::kEmergency);
    ASSERT_FALSE(latched.empty());
    const auto stop = action(log, "emergency_stop");
    ASSERT_FALSE(stop.is_null());
    EXPECT_EQ(stop[fd::kComponents].get<std::vector<std::string>>(), (std::vector<std::string>{"counter", "other"}));
  }
}

// keel validate --load finds what only the code can tell: a port of the code the profile lacks,
// a queue the code fixes otherwise. Warnings, as keel run prints them; problems with --strict.
TEST_F(OprosComponents, ValidateLoadWarnsOfCodeThatDisagreesWithItsProfileAndStrictRefusesIt) {
  auto r = test::runProcess({KEEL_CLI, "validate", "--load", profile("stale.xml")});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("stale.xml: ok, with 2 warning(s)"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("OprosCounterStale.xml:4: component 'counter': class 'OprosCounter' has input event port "
                       "'ticks' (string) that the profile does not declare (an OPRoS component: it loads)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("OprosCounterStale.xml:26: component 'counter': port 'in': the profile asks for fifo of 4, "
                       "the code constructs last of 1"),
            std::string::npos)
      << r.err;
  auto strict = test::runProcess({KEEL_CLI, "validate", "--load", "--strict", profile("stale.xml")});
  EXPECT_EQ(strict.status, 2) << strict.err;
  EXPECT_NE(strict.err.find("(an OPRoS component: it loads) (--strict)"), std::string::npos) << strict.err;
}

// A library exporting OPRoS's getComponent() but built against OPRoS's own headers cannot be
// hosted: the error says so and what to do.
TEST_F(OprosComponents, ALibraryBuiltWithoutKeelsOprosLayerIsAClearError) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("foreign.xml"), "--duration", "0.2"});
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("is an OPRoS component library (it exports getComponent) built without keel's OPRoS layer"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("keel_add_opros_component"), std::string::npos) << r.err;
}

// keel inspect lists an OPRoS library's one component and the ports its constructor registered.
TEST_F(OprosComponents, InspectListsTheComponentAndItsPorts) {
  auto r = test::runProcess({KEEL_CLI, "inspect", std::string(KEEL_OPROS_COMPONENTS) + "/libMessagePrinter.so"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("an OPRoS component library"), std::string::npos) << r.out;
  for (const char* port : {"MessagePrint", "DataIn", "DataOut", "EventIn", "EventOut"})
    EXPECT_NE(r.out.find(port), std::string::npos) << port << "\n" << r.out;
}

}  // namespace
}  // namespace keel
