// The keel command as a user runs it: run, validate, inspect, graph, --version.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

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
using namespace std::chrono_literals;

std::string profile(const std::string& name) { return std::string(KEEL_TEST_PROFILES) + "/" + name; }

class Cli : public ::testing::Test {
 protected:
  // The CLI finds the test component library the way a user's installation would: through
  // KEEL_COMPONENT_PATH.
  keel::test::ScopedEnv component_path_{"KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS};
  void TearDown() override { std::filesystem::remove(log_); }
  std::string log_ = test::tempPath("keel_cli_test");
};

TEST_F(Cli, RunStopsAtTheEndOfTheDurationAndExitsZero) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("pipeline.xml"), "--duration", "0.5", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("keel: 'pipeline' ran"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("summer"), std::string::npos);
  auto log = test::readLog(log_);
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(test::statesOf(log, "counter"), (std::vector<std::string>{"Ready", "Active", "Inactive", "Destroyed"}));
  for (const auto& rec : log) {
    EXPECT_TRUE(rec.contains(fd::kTime));
    EXPECT_TRUE(rec.contains(fd::kEvent));
  }
  auto stopping = test::eventsOf(log, ev::kEngine);
  ASSERT_FALSE(stopping.empty());
}

// A property a component refuses is said where its value was written: the override's line in
// the package profile, in the component's own words, whole (not cut to a fault's length).
TEST_F(Cli, APropertyAComponentRefusesIsSaidAtTheLineThatWroteIt) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("estimator_refused.xml"), "--duration", "0.3", "--log", log_});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find(profile("estimator_refused.xml") +
                       ":16: component 'estimator': property 'R' is not a covariance: it must be symmetric and "
                       "positive definite"),
            std::string::npos)
      << r.err;
  // Given on the command line instead, it has no line of its own: the subcomponent's.
  r = test::runProcess({KEEL_CLI, "run", profile("estimator_refused.xml"), "--duration", "0.3", "--log", log_, "--set",
                        "estimator.R=1 1", "--set", "estimator.Q=-1"});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find(profile("estimator_refused.xml") +
                       ":9: component 'estimator' failed to initialize: component 'estimator': property 'Q' is not "
                       "a covariance: it must be symmetric and positive semi-definite"),
            std::string::npos)
      << r.err;
}

// OPRoS's lifecycle: a component whose onInitialize failed never started, so it is not stopped
// (its onStop would use what it never set up) nor reset by its rules (contained instead); it is
// destroyed. One never initialized gets no callback. The run fails, saying why once.
TEST_F(Cli, AComponentThatFailsToInitializeIsOnlyDestroyedAndTheRunSaysWhy) {
  const std::string trace = test::tempPath("keel_cli_refuser"), late = test::tempPath("keel_cli_late");
  auto r = test::runProcess({KEEL_CLI, "run", profile("refused.xml"), "--duration", "0.3", "--log", log_, "--set",
                             "refuser.trace=" + trace, "--set", "late.trace=" + late});
  const std::string callbacks = test::slurp(trace);
  EXPECT_FALSE(std::filesystem::exists(late)) << test::slurp(late);
  std::filesystem::remove(trace);
  std::filesystem::remove(late);
  EXPECT_EQ(r.status, 1) << r.err;
  const std::string why =
      "refused.xml:10: component 'refuser' failed to initialize: exception in onInitialize: no device at /dev/nothing";
  const auto at = r.err.find(why);
  EXPECT_NE(at, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("failed to initialize", at + why.size()), std::string::npos) << "said once\n" << r.err;
  EXPECT_EQ(callbacks, "onInitialize\nonDestroy\n");
  auto log = test::readLog(log_);
  EXPECT_EQ(test::statesOf(log, "refuser"), (std::vector<std::string>{"Error", "Destroyed"}));
  EXPECT_EQ(test::statesOf(log, "counter"), (std::vector<std::string>{"Ready", "Destroyed"}));
  EXPECT_EQ(test::statesOf(log, "late"), (std::vector<std::string>{"Destroyed"}));
  ASSERT_EQ(test::eventsOf(log, ev::kDetected).size(), 1u);
  const auto actions = test::eventsOf(log, ev::kAction);
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0].value(fd::kAction, ""), "stop") << actions[0].dump();
}

// A failed onStop is not reset either, but the rules' emergency stop still runs: an actuator
// whose stop command failed must still reach its safe state.
TEST_F(Cli, AFailedOnStopIsNotResetButItsEmergencyStopRuns) {
  const std::string trace = test::tempPath("keel_cli_driver");
  auto r = test::runProcess({KEEL_CLI, "run", profile("unacknowledged_stop.xml"), "--duration", "0.3", "--log", log_,
                             "--set", "driver.trace=" + trace});
  const std::string callbacks = test::slurp(trace);
  std::filesystem::remove(trace);
  EXPECT_EQ(callbacks, "onInitialize\nonStart\nonStop\nonEmergencyStop\nonDestroy\n") << r.err;
  auto log = test::readLog(log_);
  const auto detected = test::eventsOf(log, ev::kDetected);
  ASSERT_EQ(detected.size(), 1u) << r.err;
  EXPECT_NE(detected[0].value(fd::kDetail, "").find("in onStop"), std::string::npos) << detected[0].dump();
  EXPECT_EQ(test::eventsOf(log, ev::kRecovered).size(), 0u);
  bool latched = false;
  for (const auto& e : test::eventsOf(log, ev::kEmergency)) latched |= e.value(fd::kPhase, "") == "latched";
  EXPECT_TRUE(latched) << r.err;
  EXPECT_EQ(test::statesOf(log, "driver"), (std::vector<std::string>{"Ready", "Active", "Error", "Destroyed"}));
}

// A reset ends in Active directly, as OPRoS's reset() does, through the paper's callbacks: no
// Ready between, no second onInitialize or onStart (docs/decisions/0012).
TEST_F(Cli, AResetRunsOnErrorOnResetOnRecoverAndNeverStartsTheComponentAgain) {
  const std::string trace = test::tempPath("keel_cli_reset_trace");
  std::filesystem::remove(trace);
  auto r = test::runProcess({KEEL_CLI, "run", profile("reset_trace.xml"), "--duration", "0.5", "--log", log_, "--set",
                             "driver.trace=" + trace});
  const std::string callbacks = test::slurp(trace);
  std::filesystem::remove(trace);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(callbacks, "onInitialize\nonStart\nonError\nonReset\nonRecover\nonStop\nonDestroy\n");
  const auto log = test::readLog(log_);
  EXPECT_EQ(test::statesOf(log, "driver"),
            (std::vector<std::string>{"Ready", "Active", "Error", "Active", "Inactive", "Destroyed"}));
  EXPECT_EQ(test::eventsOf(log, ev::kRecovered).size(), 1u);
}

// An alternative whose onInitialize fails is destroyed as any such component is (onDestroy, no
// onStart or onStop), and the failed replacement says why.
TEST_F(Cli, AnAlternativeThatFailsToInitializeIsDestroyedAndTheReplacementSaysWhy) {
  const std::string trace = test::tempPath("keel_cli_unplugged_trace");
  std::filesystem::remove(trace);
  auto r = test::runProcess({KEEL_CLI, "run", profile("unplugged_alternative.xml"), "--duration", "0.5", "--log", log_,
                             "--set", "driver.trace=" + trace});
  const std::string callbacks = test::slurp(trace);
  std::filesystem::remove(trace);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(callbacks.find("Unplugged.onInitialize\nUnplugged.onDestroy\n"), std::string::npos) << callbacks;
  EXPECT_EQ(callbacks.find("Unplugged.onStart"), std::string::npos) << callbacks;
  EXPECT_EQ(callbacks.find("Unplugged.onStop"), std::string::npos) << callbacks;
  bool failed_with_reason = false;
  for (const auto& a : test::eventsOf(test::readLog(log_), ev::kAction))
    if (a[fd::kAction] == "replace")
      failed_with_reason = a[fd::kOutcome] == log::schema::kFailed &&
                           a.value(fd::kDetail, "") ==
                               "loading the alternative failed: Unplugged: exception in onInitialize: no device at "
                               "/dev/spare";
  EXPECT_TRUE(failed_with_reason) << r.out;
}

// A cold alternative's library is looked for at start, not first at the fault (where the search
// would cost the recovery its time): a missing one is said, with the rule's file and line, by a
// run in which no fault happens; when the fault comes, the replacement fails and says why.
TEST_F(Cli, AColdAlternativeWhoseLibraryIsMissingIsSaidAtStartAndTheReplacementFails) {
  const std::string warning =
      "unloadable_alternative.xml:11: alternative 'Unloadable' of 'driver', loaded at a fault, will not load: "
      "library 'keel_test_not_installed' not found";
  auto quiet = test::runProcess({KEEL_CLI, "run", profile("unloadable_alternative.xml"), "--duration", "0.3", "--log",
                                 log_, "--set", "driver.throw_at=0"});
  ASSERT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_NE(quiet.err.find(warning), std::string::npos) << quiet.err;
  EXPECT_TRUE(test::eventsOf(test::readLog(log_), ev::kAction).empty());

  auto r = test::runProcess(
      {KEEL_CLI, "run", profile("unloadable_alternative.xml"), "--duration", "0.5", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.err;
  bool failed_with_reason = false;
  for (const auto& a : test::eventsOf(test::readLog(log_), ev::kAction))
    if (a[fd::kAction] == "replace")
      failed_with_reason = a[fd::kOutcome] == log::schema::kFailed &&
                           a.value(fd::kDetail, "").find("library 'keel_test_not_installed' not found") !=
                               std::string::npos;
  EXPECT_TRUE(failed_with_reason) << r.out;
}

// The summary is printed after shutdown, from the run's log (an anonymous one without --log): a
// fault in onStop and the emergency stop it causes are in it, as they are in the log.
TEST_F(Cli, TheSummaryIsPrintedAfterShutdownAndHasWhatTheStopDid) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("unacknowledged_stop.xml"), "--duration", "0.5"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto faults = r.out.find("\nfaults:\n  driver ");
  ASSERT_NE(faults, std::string::npos) << r.out;
  EXPECT_NE(r.out.find("in onStop", faults), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("EMERGENCY STOP LATCHED", faults), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("no faults"), std::string::npos) << r.out;
  // Each column says what it counts; the counts are the engine's, as its `counts` records say.
  EXPECT_NE(r.out.find("at stop   executions deadline misses  faults  executor"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("period_ms     cycles  late cycles"), std::string::npos) << r.out;
  std::smatch counter;
  ASSERT_TRUE(std::regex_search(r.out, counter, std::regex(R"(\ncounter +Active +(\d+) +0 +0  )"))) << r.out;
  EXPECT_GT(std::stoul(counter[1]), 0u) << r.out;
  EXPECT_NE(r.out.find("(stopped: duration)"), std::string::npos) << r.out;
}

// The summary's counts are those of the log's `counts` records, a record per component and
// executor at the engine's end.
TEST_F(Cli, TheLogCountsEachComponentsExecutionsAndEachExecutorsCyclesAtTheEnd) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("unacknowledged_stop.xml"), "--duration", "0.5", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto log = test::readLog(log_);
  std::map<std::string, nlohmann::json> components, executors;
  for (const auto& c : test::eventsOf(log, ev::kCounts))
    (c.contains(fd::kComponent) ? components[c[fd::kComponent]] : executors[c[fd::kExecutor]]) = c;
  ASSERT_EQ(components.size(), 2u) << r.out;
  ASSERT_EQ(executors.size(), 2u) << r.out;  // a task per periodic component without <executor>
  const auto& counter = components["counter"];
  ASSERT_EQ(executors.count(counter[fd::kExecutor]), 1u) << counter.dump();
  const auto& ex = executors[counter[fd::kExecutor]];
  EXPECT_EQ(ex[fd::kPeriodMs], 5.0);
  EXPECT_GT(counter[fd::kExecutions].get<std::uint64_t>(), 0u);
  EXPECT_LE(counter[fd::kExecutions].get<std::uint64_t>(), ex[fd::kCycles].get<std::uint64_t>());
  EXPECT_EQ(counter[fd::kDeadlineMisses], 0);
  EXPECT_EQ(counter[fd::kClass], "Counter");
  std::smatch line;
  ASSERT_TRUE(std::regex_search(r.out, line, std::regex(R"(\ncounter +Active +(\d+) )"))) << r.out;
  EXPECT_EQ(std::stoul(line[1]), counter[fd::kExecutions].get<std::uint64_t>()) << r.out;
  const auto load = test::eventsOf(log, ev::kEngine).front();
  EXPECT_EQ(load[fd::kName], "unacknowledged_stop");
  EXPECT_EQ(load[fd::kComponents], (nlohmann::json{"driver", "counter"}));
}

// --cpu-dma-latency: the engine holds the request while it runs and says so in its log; a
// machine that refuses it gets a warning and the run goes on.
TEST_F(Cli, RunHoldsTheCpusWakeUpLatencyWhileRunning) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("pipeline.xml"), "--duration", "0.3", "--log", log_,
                             "--cpu-dma-latency", "50"});  // above the unit test's 7 µs
  ASSERT_EQ(r.status, 0) << r.err;
  auto log = test::readLog(log_);
  const bool permitted = ::geteuid() == 0 && std::filesystem::exists("/dev/cpu_dma_latency");
  bool started = false;
  for (const auto& e : test::eventsOf(log, ev::kEngine)) {
    if (e.value(fd::kPhase, "") != "started") continue;
    started = true;
    if (permitted) EXPECT_EQ(e.value(fd::kCpuDmaLatencyUs, -1), 50) << e.dump();
    else EXPECT_FALSE(e.contains(fd::kCpuDmaLatencyUs)) << e.dump();
  }
  EXPECT_TRUE(started);
  const bool warned = r.err.find("wake-up latency at 50 µs") != std::string::npos;
  EXPECT_EQ(warned, !permitted) << r.err;
  EXPECT_EQ(test::statesOf(log, "summer").back(), "Destroyed");
}

TEST_F(Cli, RunStopsCleanlyOnSigterm) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("pipeline.xml"), "--log", log_}, 500ms);
  ASSERT_EQ(r.status, 0) << r.err;
  auto log = test::readLog(log_);
  bool saw_reason = false;
  for (const auto& e : test::eventsOf(log, ev::kEngine))
    if (e.value(fd::kPhase, "") == "stopping")
      saw_reason = e.value(fd::kReason, "").find("Terminated") != std::string::npos;
  EXPECT_TRUE(saw_reason);
  EXPECT_EQ(test::statesOf(log, "summer").back(), "Destroyed");
}

TEST_F(Cli, RunReportsFaultsInItsSummary) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("crash.xml"), "--duration", "0.5", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("faults:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("crasher"), std::string::npos);
  EXPECT_NE(r.out.find("signal"), std::string::npos);
}

TEST_F(Cli, RunRejectsABadProfileWithFileAndLine) {
  auto r = test::runProcess({KEEL_CLI, "run", profile("wrong_type.xml"), "--duration", "0.1"});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("CounterDouble.xml:9: component 'counter': port 'count' carries 'double'"), std::string::npos)
      << r.err;
}

TEST_F(Cli, ValidateAcceptsGoodProfilesAndNamesEveryProblemInBadOnes) {
  auto good = test::runProcess({KEEL_CLI, "validate", profile("pipeline.xml"), profile("crash.xml")});
  EXPECT_EQ(good.status, 0) << good.err;
  auto bad = test::runProcess({KEEL_CLI, "validate", "--load", profile("wrong_type.xml")});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("CounterDouble.xml:9:"), std::string::npos) << bad.err;
  auto missing = test::runProcess({KEEL_CLI, "validate", profile("no_such_file.xml")});
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("no_such_file.xml"), std::string::npos) << missing.err;
  // A field a connection carries, looked up in the message's fields without loading anything.
  const std::string fields = std::string(KEEL_PROFILE_TEST_DATA) + "/errors/node/field_path.xml";
  auto field = test::runProcess({KEEL_CLI, "validate", fields});
  EXPECT_EQ(field.status, 2);
  EXPECT_EQ(field.err, fields +
                           ":10: port_connection wander.cmd field 'linear.q' -> nav.range: geometry_msgs/msg/Vector3 "
                           "(the type of 'linear') has no field 'q': its fields are x, y, z\n");
}

// A fault scenario is checked as keel run --inject reads it, before anything runs.
// A setting that loads but has no effect is a `file:line: warning:`: validate says the file is
// ok with it, run prints it, logs it, and runs.
TEST_F(Cli, ASettingWithoutEffectIsAWarningAtItsLineAndTheRunGoesOn) {
  const std::string file = profile("passive_heartbeat.xml");
  const std::string what = "<heartbeat> of subcomponent 'doubler' has no effect";
  const std::string warning = file + ":12: warning: " + what;
  auto checked = test::runProcess({KEEL_CLI, "validate", file});
  EXPECT_EQ(checked.status, 0) << checked.err;
  EXPECT_EQ(checked.err.rfind(warning, 0), 0u) << checked.err;
  EXPECT_EQ(checked.out, file + ": ok, with 1 warning(s)\n");
  auto ran = test::runProcess({KEEL_CLI, "run", file, "--duration", "0.3", "--log", log_});
  EXPECT_EQ(ran.status, 0) << ran.err;
  EXPECT_EQ(ran.err.rfind(warning, 0), 0u) << ran.err;
  const auto warnings = test::eventsOf(test::readLog(log_), ev::kWarning);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0][fd::kMessage].get<std::string>().rfind(file + ":12: " + what, 0), 0u) << warnings[0].dump();
  EXPECT_NE(ran.out.find("1 warning (in the log)"), std::string::npos) << ran.out;
}

// --strict: a warning is a problem; validate exits 2 and run does not start.
TEST_F(Cli, StrictMakesEveryWarningAnError) {
  const std::string file = profile("passive_heartbeat.xml");
  const std::string problem = file + ":12: <heartbeat> of subcomponent 'doubler' has no effect";
  auto checked = test::runProcess({KEEL_CLI, "validate", "--strict", file});
  EXPECT_EQ(checked.status, 2);
  EXPECT_EQ(checked.err.rfind(problem, 0), 0u) << checked.err;
  EXPECT_NE(checked.err.find("(--strict)\n"), std::string::npos) << checked.err;
  EXPECT_EQ(checked.out, "");
  auto ran = test::runProcess({KEEL_CLI, "run", "--strict", file, "--duration", "0.3", "--log", log_});
  EXPECT_EQ(ran.status, 2);
  EXPECT_EQ(ran.err.rfind(problem, 0), 0u) << ran.err;
  EXPECT_FALSE(std::filesystem::exists(log_)) << "nothing ran";
  // A real OPRoS profile: ok with warnings, refused with --strict.
  const std::string opros = std::string(KEEL_OPROS_SAMPLES) +
                            "/parasby/OPRoS/example/droneTest/FlightControl/profile/"
                            "FlightControl.xml";
  EXPECT_EQ(test::runProcess({KEEL_CLI, "validate", opros}).status, 0);
  EXPECT_EQ(test::runProcess({KEEL_CLI, "validate", "--strict", opros}).status, 2);
}

TEST_F(Cli, ValidateChecksAFaultScenarioAndNamesItsProblemsLine) {
  const std::string dir = ::testing::TempDir();
  const std::string good = dir + "keel_validate_good_scenario.xml", bad = dir + "keel_validate_bad_scenario.xml";
  auto writeFile = [](const std::string& path, const char* text) { std::ofstream(path) << text; };
  writeFile(good,
            "<fault_scenario>\n  <fault at=\"100\" component=\"counter\" kind=\"segfault\"/>\n"
            "  <fault at=\"200\" component=\"counter\" kind=\"throw\" repeat=\"3\" every=\"10\"/>\n"
            "</fault_scenario>\n");
  writeFile(bad, "<fault_scenario>\n  <fault at=\"100\" component=\"counter\" kind=\"melt\"/>\n</fault_scenario>\n");
  auto ok = test::runProcess({KEEL_CLI, "validate", good});
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_EQ(ok.out, good + ": ok (a fault scenario: 4 injections)\n");
  auto wrong = test::runProcess({KEEL_CLI, "validate", bad});
  EXPECT_EQ(wrong.status, 2);
  EXPECT_NE(wrong.err.find(bad + ":2:"), std::string::npos) << wrong.err;
  EXPECT_NE(wrong.err.find("melt"), std::string::npos) << wrong.err;
}

TEST_F(Cli, InspectListsEveryComponentOfALibraryWithItsPorts) {
  auto r = test::runProcess({KEEL_CLI, "inspect", std::string(KEEL_TEST_COMPONENTS) + "/libkeel_test_components.so",
                             "--profiles", KEEL_TEST_PROFILES});
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* name : {"Counter", "Summer", "EventLogger", "Crasher", "Doubler", "Caller"})
    EXPECT_NE(r.out.find(std::string("\n") + name + "\n"), std::string::npos) << name << "\n" << r.out;
  EXPECT_NE(r.out.find("count"), std::string::npos);
  EXPECT_NE(r.out.find("property gain"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("twice"), std::string::npos);
}

TEST_F(Cli, GraphPrintsTheStructureAsDot) {
  auto r = test::runProcess({KEEL_CLI, "graph", profile("crash.xml")});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.rfind("digraph \"crash\" {", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("\"counter\" -> \"summer\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("together (5 ms)"), std::string::npos) << r.out;
}

// The version is project()'s in the root CMakeLists.txt, read here from the source as a user
// reads it, so that the test holds whatever generates the CLI's copy.
TEST_F(Cli, VersionPrintsKeelAndTheProjectsVersionAndExitsZero) {
  std::smatch project;
  const std::string cmake = test::slurp(std::string(KEEL_SOURCE_DIR) + "/CMakeLists.txt");
  ASSERT_TRUE(std::regex_search(cmake, project, std::regex(R"(project\(keel VERSION ([0-9.]+))")));
  auto r = test::runProcess({KEEL_CLI, "--version"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "keel " + project[1].str() + "\n");
  EXPECT_EQ(r.err, "");
}

TEST_F(Cli, TheHelloExampleRunsAndDeliversEvents) {
  auto r = test::runProcess({KEEL_CLI, "run", std::string(KEEL_EXAMPLES) + "/01_hello_component/app.xml", "--duration",
                             "0.6", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("[listener] milestone: 5"), std::string::npos) << r.out;
  EXPECT_TRUE(test::eventsOf(test::readLog(log_), ev::kDetected).empty());
}

TEST_F(Cli, TheFaultDetectionExampleCatchesEachFaultAndKeepsTheRestRunning) {
  // 4 s: the second sonar's fault comes at ~1.6 s, later on a loaded machine.
  auto r = test::runProcess(
      {KEEL_CLI, "run", std::string(KEEL_EXAMPLES) + "/02_fault_detection/app.xml", "--duration", "4", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.err;
  auto log = test::readLog(log_);
  auto detected = test::eventsOf(log, ev::kDetected);
  ASSERT_GE(detected.size(), 3u);
  EXPECT_EQ(test::statesOf(log, "sonar_left"), (std::vector<std::string>{"Ready", "Active", "Error", "Destroyed"}));
  std::vector<std::string> kinds_of_sonars;
  int user_faults = 0, avoider_faults = 0;
  for (const auto& d : detected) {
    if (d[fd::kComponent] == "avoider") {
      ++avoider_faults;  // its two `user` faults, and on a loaded machine maybe a late step
      user_faults += d[fd::kKind] == "user";
    } else kinds_of_sonars.push_back(d[fd::kComponent].get<std::string>() + " " + d[fd::kKind].get<std::string>());
  }
  EXPECT_EQ(kinds_of_sonars, (std::vector<std::string>{"sonar_left signal", "sonar_right exception"}));
  EXPECT_EQ(user_faults, 2);
  // its <fault_policy> has the default severity, reset: each of its faults resets it
  std::vector<std::string> expected{"Ready", "Active"};
  for (int i = 0; i < avoider_faults; ++i) expected.insert(expected.end(), {"Error", "Active"});
  expected.insert(expected.end(), {"Inactive", "Destroyed"});
  EXPECT_EQ(test::statesOf(log, "avoider"), expected);
  EXPECT_EQ(test::eventsOf(log, ev::kRecovered).size(), static_cast<std::size_t>(avoider_faults));
}

TEST_F(Cli, TheConsoleLatchesAnEmergencyStopUntilItIsCleared) {
  const std::string cmd = "(sleep 0.4; echo emergency; sleep 0.4; echo status; echo clear; echo clear) | " +
                          std::string(KEEL_CLI) + " run " + std::string(KEEL_EXAMPLES) +
                          "/02_fault_detection/app.xml --duration 1.5 --console --log " + log_;
  auto r = test::runProcess({"/bin/sh", "-c", cmd});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto latched = r.out.find("keel: emergency stop latched");
  const auto status = r.out.find("keel: emergency latched;");
  const auto cleared = r.out.find("keel: emergency cleared");
  ASSERT_NE(latched, std::string::npos) << r.out;
  ASSERT_NE(status, std::string::npos) << r.out;
  ASSERT_NE(cleared, std::string::npos) << r.out;
  EXPECT_LT(latched, status);
  EXPECT_LT(status, cleared);
  EXPECT_NE(r.out.find("keel: no emergency latched", cleared), std::string::npos) << r.out;  // second clear
  EXPECT_EQ(r.out.find("EMERGENCY STOP LATCHED"), std::string::npos) << r.out;               // summary: cleared

  auto log = test::readLog(log_);
  auto phases = test::eventsOf(log, ev::kEmergency);
  ASSERT_EQ(phases.size(), 2u);
  EXPECT_EQ(phases[0][fd::kPhase], "latched");
  EXPECT_EQ(phases[0][fd::kBy], "console");
  EXPECT_EQ(phases[1][fd::kPhase], "cleared");
  bool stopped_actuators = false;
  for (const auto& a : test::eventsOf(log, ev::kAction))
    if (a[fd::kAction] == "emergency_stop") stopped_actuators = a[fd::kComponents].size() == 3;  // all three
  EXPECT_TRUE(stopped_actuators);
}

TEST_F(Cli, TheSummaryShowsEachFaultsHandlingAndRecoveryLatency) {
  auto r = test::runProcess(
      {KEEL_CLI, "run", std::string(KEEL_EXAMPLES) + "/02_fault_detection/app.xml", "--duration", "4", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto at = r.out.find("handling:");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sonar_left           signal     stop      stop", at), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("avoider              user       reset     reset", at), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" us\n", at), std::string::npos) << r.out;  // a recovery latency
  // Both of the avoider's faults, and any late step's on a loaded machine: all reset.
  const auto recovered = test::eventsOf(test::readLog(log_), ev::kRecovered).size();
  EXPECT_GE(recovered, 2u);
  EXPECT_NE(r.out.find(fmt::format("recovered {} of", recovered), at), std::string::npos) << r.out;
}

}  // namespace
}  // namespace keel
