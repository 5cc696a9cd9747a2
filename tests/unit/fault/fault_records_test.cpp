// The fault records (src/fault/fault_records.hpp): what each fault writes to the fault log, in
// which order, once — detection, state, diagnosis, each new action, recovery with its latency,
// an undetected injection — and the counts, detections and handlings kept for the summaries.
#include "fault/fault_records.hpp"

#include <gtest/gtest.h>
#include <signal.h>

#include <string>
#include <vector>

#include "log/schema.hpp"
#include "runtime/clock.hpp"
#include "runtime/component_core.hpp"
#include "support/log_reader.hpp"
#include "support/temp_log.hpp"

namespace keel::fault {
namespace {

namespace ev = log::schema::event;
namespace fd = log::schema::field;
using nlohmann::json;
using profile::Severity;

/// A fault of `who` detected at `t_ns` by the watchdog, diagnosed 1 ms later as `reset`.
FaultReport reportOf(std::uint64_t id, const char* who, FaultKind kind, const char* detail, std::int64_t t_ns) {
  FaultReport r;
  r.event = FaultEvent(kind, who, detail);
  r.event.t_ns = t_ns;
  FaultEvent::copyInto(r.detector, "watchdog");
  r.id = id;
  r.has_policy = true;
  r.severity = Severity::Reset;
  r.first = r.next = Step::Reset;
  r.diagnosed_ns = t_ns + 1'000'000;
  return r;
}

/// The component a report accuses, of class `Arm`.
struct Arm : Component {
  Arm() { runtime::coreOf(*this).class_name = "Arm"; }
};

/// The `event` of every record, in order.
std::vector<std::string> eventNames(const std::vector<json>& log) {
  std::vector<std::string> out;
  out.reserve(log.size());
  for (const json& r : log) out.push_back(r.value(fd::kEvent, ""));
  return out;
}

TEST(FaultRecords, ADetectionIsLoggedAsDetectedStateErrorAndDiagnosedSharingItsFaultId) {
  test::TempLog file;
  FaultRecords records(file.log);
  const std::int64_t t = runtime::steadyNs();
  FaultReport r = reportOf(7, "arm", FaultKind::Signal, "SIGSEGV in onExecute", t);
  Arm arm;
  r.noteState({State::Active, State::Error, t, &arm}, true);  // as the fault manager notes it

  records.logReport(r);

  const auto log = file.read();
  ASSERT_EQ(eventNames(log), (std::vector<std::string>{ev::kDetected, ev::kState, ev::kDiagnosed}));
  for (const json& rec : log) {
    EXPECT_EQ(rec.value(fd::kFaultId, 0u), 7u) << rec.dump();
    EXPECT_EQ(rec.value(fd::kComponent, ""), "arm") << rec.dump();
  }
  EXPECT_EQ(log[0][fd::kKind], "signal");
  EXPECT_EQ(log[0][fd::kDetail], "SIGSEGV in onExecute");
  EXPECT_EQ(log[0][fd::kDetector], "watchdog");
  EXPECT_EQ(log[0][fd::kTime], file.log.sinceStart(t)) << "the detection's time, from the log's start";
  EXPECT_EQ(log[1][fd::kFrom], "Active");
  EXPECT_EQ(log[1][fd::kTo], "Error");
  EXPECT_EQ(log[1][fd::kClass], "Arm") << "the class of the object that changed";
  EXPECT_FALSE(log[1].contains(fd::kAlternative)) << log[1];
  EXPECT_FALSE(log[1].contains(fd::kServing)) << "the fault path changes only the serving object: " << log[1];
  EXPECT_EQ(log[2][fd::kSeverity], "reset");
  EXPECT_EQ(log[2][fd::kRules], "fault_policy");
  EXPECT_EQ(log[2][fd::kScope], "component");
  EXPECT_EQ(log[2][fd::kHandling], "reset");
  EXPECT_EQ(log[2][fd::kTime], file.log.sinceStart(t + 1'000'000));
  EXPECT_TRUE(r.detection_logged);
  EXPECT_EQ(records.detectionCount(), 1u);
}

TEST(FaultRecords, AFaultThatDidNotMoveTheComponentToErrorHasNoStateRecord) {
  test::TempLog file;
  FaultRecords records(file.log);
  FaultReport r = reportOf(3, "sonar", FaultKind::Range, "NaN", runtime::steadyNs());
  r.has_policy = false;

  records.logReport(r);

  const auto log = file.read();
  EXPECT_EQ(eventNames(log), (std::vector<std::string>{ev::kDetected, ev::kDiagnosed}));
  EXPECT_EQ(log.back()[fd::kRules], "none (contained, not recovered)");
}

TEST(FaultRecords, AnInjectedFaultIsLoggedAsInjectedBeforeItsDetectionWithTheSameId) {
  test::TempLog file;
  FaultRecords records(file.log);
  const std::int64_t t = runtime::steadyNs();
  FaultReport r = reportOf(12, "arm", FaultKind::Signal, "SIGSEGV", t);
  r.injected_ns = t - 500'000;

  records.logReport(r);

  const auto log = file.read();
  ASSERT_GE(log.size(), 2u);
  EXPECT_EQ(log[0][fd::kEvent], ev::kInjected);
  EXPECT_EQ(log[0][fd::kFaultId], 12u);
  EXPECT_EQ(log[0][fd::kTime], file.log.sinceStart(t - 500'000));
  EXPECT_EQ(log[1][fd::kEvent], ev::kDetected);
  ASSERT_EQ(records.detections().size(), 1u);
  EXPECT_EQ(records.detections()[0].injected_ns, t - 500'000);
}

// A fault caught by the guard travels undescribed; its detail is written once, with its records.
TEST(FaultRecords, ACaughtFaultsDetailIsWrittenWithItsRecords) {
  test::TempLog file;
  FaultRecords records(file.log);
  const std::int64_t t = runtime::steadyNs();
  FaultReport r = reportOf(9, "arm", FaultKind::Signal, "", t);
  FaultReport::Caught caught;
  caught.outcome.kind = runtime::GuardOutcome::Kind::Signal;
  caught.outcome.signo = SIGFPE;
  caught.outcome.addr = reinterpret_cast<const void*>(0x42);
  caught.callback = "onExecute";
  r.caught = caught;
  EXPECT_EQ(r.event.detailText(), "") << "nothing formatted on the way to the recovery";

  records.logReport(r);

  EXPECT_FALSE(r.caught.has_value()) << "described once";
  EXPECT_EQ(r.event.detailText(), "SIGFPE in onExecute (instruction 0x42)");
  const auto detected = test::eventsOf(file.read(), ev::kDetected);
  ASSERT_EQ(detected.size(), 1u);
  EXPECT_EQ(detected[0][fd::kDetail], "SIGFPE in onExecute (instruction 0x42)");
}

TEST(FaultRecords, TheDetectionIsWrittenOnceAndEachCallWritesOnlyTheNewActions) {
  test::TempLog file;
  FaultRecords records(file.log);
  const std::int64_t t = runtime::steadyNs();
  FaultReport r = reportOf(5, "arm", FaultKind::Exception, "boom", t);
  Arm arm;
  r.noteState({State::Active, State::Error, t, &arm}, true);
  records.logReport(r);

  r.noteState({State::Error, State::Active, t + 9, &arm});  // as the reset notes it, before its action
  r.add(ActionKind::Reset, true, t + 10, "onError → onReset → onRecover");
  records.logReport(r);
  r.add(ActionKind::Restore, true, t + 20, "critical memory restored");
  records.logReport(r);
  records.logReport(r);  // nothing new

  const auto log = file.read();
  EXPECT_EQ(eventNames(log), (std::vector<std::string>{ev::kDetected, ev::kState, ev::kDiagnosed, ev::kAction,
                                                       ev::kState, ev::kAction}));
  const auto actions = test::eventsOf(log, ev::kAction);
  ASSERT_EQ(actions.size(), 2u);
  EXPECT_EQ(actions[0][fd::kAction], "reset");
  EXPECT_EQ(actions[0][fd::kOutcome], log::schema::kOk);
  EXPECT_EQ(actions[0][fd::kDetail], "onError → onReset → onRecover");
  EXPECT_EQ(actions[0][fd::kFaultId], 5u);
  EXPECT_EQ(actions[1][fd::kAction], "restore");
  const auto states = test::eventsOf(log, ev::kState);
  ASSERT_EQ(states.size(), 2u);
  EXPECT_EQ(states[1][fd::kFrom], "Error") << "a reset that did brings the component back";
  EXPECT_EQ(states[1][fd::kTo], "Active");
  EXPECT_EQ(r.logged_actions, r.n_actions);
  EXPECT_EQ(records.detectionCount(), 1u);
}

TEST(FaultRecords, AFailedResetLeavesTheComponentInError) {
  test::TempLog file;
  FaultRecords records(file.log);
  const std::int64_t t = runtime::steadyNs();
  FaultReport r = reportOf(6, "arm", FaultKind::Exception, "boom", t);
  r.add(ActionKind::Reset, false, t + 10, "exception in onReset: no");

  records.logReport(r);

  const auto log = file.read();
  EXPECT_TRUE(test::eventsOf(log, ev::kState).empty());
  const auto actions = test::eventsOf(log, ev::kAction);
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0][fd::kOutcome], log::schema::kFailed);
}

TEST(FaultRecords, ASuccessfulReplacementNamesTheAlternativesClass) {
  test::TempLog file;
  FaultRecords records(file.log);
  class Backup : public Component {};
  Backup backup;
  runtime::coreOf(backup).class_name = "BackupArm";
  runtime::coreOf(backup).alternative = true;
  const std::int64_t t = runtime::steadyNs();
  FaultReport r = reportOf(8, "arm", FaultKind::Signal, "SIGSEGV", t);
  r.alternative = &backup;
  r.noteState({State::Ready, State::Active, t + 9, &backup});  // the alternative's own change, as replace notes it
  r.add(ActionKind::Replace, true, t + 10, "alternative BackupArm took over");

  records.logReport(r);

  const auto log = file.read();
  const auto actions = test::eventsOf(log, ev::kAction);
  ASSERT_EQ(actions.size(), 1u);
  EXPECT_EQ(actions[0][fd::kReplacement], "BackupArm");
  ASSERT_FALSE(test::eventsOf(log, ev::kState).empty());
  const json took_over = test::eventsOf(log, ev::kState).back();
  EXPECT_EQ(took_over[fd::kTo], "Active");
  EXPECT_EQ(took_over[fd::kClass], "BackupArm") << "the alternative's record, under the instance's name";
  EXPECT_EQ(took_over[fd::kComponent], "arm");
  EXPECT_EQ(took_over.value(fd::kAlternative, false), true) << took_over;
}

TEST(FaultRecords, TheHandlingListsEveryActionAndFailsOnlyOnAFailedStep) {
  test::TempLog file;
  FaultRecords records(file.log);
  const std::int64_t t = runtime::steadyNs();
  FaultReport ok = reportOf(1, "arm", FaultKind::Signal, "SIGSEGV", t);
  ok.add(ActionKind::Reset, true, t, "");
  ok.add(ActionKind::Restore, false, t, "no checkpoint yet");  // a missing checkpoint is no failure
  FaultReport failed = reportOf(2, "leg", FaultKind::Signal, "SIGSEGV", t);
  failed.add(ActionKind::Reset, false, t, "");
  failed.add(ActionKind::Escalate, true, t, "reset → stop: the reset failed");
  failed.add(ActionKind::Stop, true, t, "");

  records.logReport(ok);
  records.logReport(failed);

  const auto a = records.handling(1);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->actions, "reset, restore (failed)");
  EXPECT_FALSE(a->failed);
  EXPECT_EQ(a->severity, "reset");
  EXPECT_EQ(a->detected_ns, t);
  const auto b = records.handling(2);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->actions, "reset (failed), escalate, stop");
  EXPECT_TRUE(b->failed);
  EXPECT_FALSE(records.handling(3));
  EXPECT_EQ(records.handlings().size(), 2u);
}

TEST(FaultRecords, RecoveredCarriesTheLatencyFromTheDetection) {
  test::TempLog file;
  FaultRecords records(file.log);
  const std::int64_t t = runtime::steadyNs();
  FaultReport r = reportOf(4, "arm", FaultKind::Signal, "SIGSEGV", t);
  records.logReport(r);

  records.logRecovered(4, "arm", t + 1'500'000);

  const auto recovered = test::eventsOf(file.read(), ev::kRecovered);
  ASSERT_EQ(recovered.size(), 1u);
  EXPECT_EQ(recovered[0][fd::kFaultId], 4u);
  EXPECT_EQ(recovered[0][fd::kComponent], "arm");
  EXPECT_DOUBLE_EQ(recovered[0][fd::kLatencyUs].get<double>(), 1500.0);
  EXPECT_EQ(recovered[0][fd::kTime], file.log.sinceStart(t + 1'500'000));
  EXPECT_EQ(records.recoveredCount(), 1u);
  EXPECT_EQ(records.handling(4)->recovered_ns, t + 1'500'000);
}

TEST(FaultRecords, AnInjectionNeverDetectedIsLoggedAsInjectedWithDetectedFalse) {
  test::TempLog file;
  FaultRecords records(file.log);
  const std::int64_t t = runtime::steadyNs();

  records.logUndetected(21, "arm", t);

  const auto log = file.read();
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(log[0][fd::kEvent], ev::kInjected);
  EXPECT_EQ(log[0][fd::kFaultId], 21u);
  EXPECT_EQ(log[0][fd::kComponent], "arm");
  EXPECT_EQ(log[0][fd::kDetected], false);
  EXPECT_EQ(log[0][fd::kTime], file.log.sinceStart(t));
  EXPECT_EQ(records.detectionCount(), 0u);
}

TEST(FaultRecords, CountsGroupFaultsByComponentAndKindKeepingTheFirstDetail) {
  test::TempLog file;
  FaultRecords records(file.log);
  const std::int64_t t = runtime::steadyNs();
  FaultReport a = reportOf(1, "arm", FaultKind::Signal, "first", t);
  FaultReport b = reportOf(2, "arm", FaultKind::Signal, "second", t);
  FaultReport c = reportOf(3, "arm", FaultKind::Range, "NaN", t);

  records.logReport(a);
  records.logReport(b);
  records.logReport(c);

  const auto counts = records.counts();
  ASSERT_EQ(counts.size(), 2u);
  EXPECT_EQ(counts[0].component, "arm");
  EXPECT_EQ(counts[0].kind, "signal");
  EXPECT_EQ(counts[0].count, 2u);
  EXPECT_EQ(counts[0].detail, "first");
  EXPECT_EQ(counts[1].kind, "range");
  EXPECT_EQ(counts[1].count, 1u);
  const auto detections = records.detections();
  ASSERT_EQ(detections.size(), 3u);
  EXPECT_EQ(detections[2].fault_id, 3u);
  EXPECT_EQ(detections[2].kind, FaultKind::Range);
  EXPECT_EQ(records.detectionCount(), 3u);
}

}  // namespace
}  // namespace keel::fault
