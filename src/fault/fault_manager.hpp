// The fault manager (paper §3.2, §5.2–5.3): every detected fault reaches it, whichever detector
// found it — the guard, a port, the watchdog, a monitor or voter, raiseFault, or a FaultEvent
// sent to its `faults` port — and it carries the fault's handling through, step by step. It
// owns the parts of one job each and decides nothing itself:
//   diagnosis      who is at fault, the fault's id, what the rules call for (fault/diagnosis)
//   escalation     which step follows which outcome — pure (fault/escalation)
//   recovery       reset, replacement, abandoning a hung executor (fault/recovery)
//   containment    fault stop over the dependency graph, emergency stop (fault/containment)
//   the thread     its own thread and queue (fault/handling_queue)
//   the records    the fault log's records and the summaries (fault/fault_records)
//
// How a fault flows (docs/architecture.md): local recoveries — reset with the checkpoint
// restored, the switch to a preloaded alternative — run at once on the thread that caught the
// fault when that is the component's own executor thread, and the manager's thread is told
// afterwards (no wake-up on the recovery path). Anything else is handed over: to the
// component's thread (posted between its callbacks, or its hung callback interrupted by a
// signal), or to the manager's own thread, which does what needs the whole picture.
// Thread-safety: report, runPending, recovered, emergencyStop, clearEmergency and the readers
// may be called from any thread; attach/start/stop from the engine's thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "fault/containment.hpp"
#include "fault/dependency_graph.hpp"
#include "fault/diagnosis.hpp"
#include "fault/escalation.hpp"
#include "fault/fault_records.hpp"
#include "fault/handling_queue.hpp"
#include "fault/recovery.hpp"
#include "fault/recovery_actions.hpp"
#include "fault/report.hpp"
#include "keel/component.hpp"
#include "keel/fault_event.hpp"
#include "log/fault_log.hpp"
#include "runtime/component_core.hpp"

namespace keel::fault {

class FaultManager final : public runtime::FaultSink {
 public:
  /// `find` maps an instance name to its component (null when unknown); used until attach().
  FaultManager(log::FaultLog& log, std::function<Component*(std::string_view)> find);
  ~FaultManager() override;
  FaultManager(const FaultManager&) = delete;
  FaultManager& operator=(const FaultManager&) = delete;

  /// Connects the manager to the runtime and the plan's dependency graph (may be null).
  void attach(RecoveryActions* actions, const DependencyGraph* graph);
  /// `changed` is called after each fault report or recovery is logged (FaultRecords::onChange).
  void onChange(std::function<void()> changed) { records_.onChange(std::move(changed)); }
  /// Starts the manager's thread. Without it, reports are handled on the reporting thread.
  void start();
  /// The components run: the manager's thread from now on also wakes by itself now and then,
  /// for a recovery's report that nothing wakes it for (HandlingQueue::armSafetyNet).
  void armSafetyNet() { queue_.armSafetyNet(); }
  /// Handles what is queued, then ends the thread.
  void stop();
  /// Waits until everything reported so far has been handled and logged (tests, shutdown).
  void drain();

  /// A new fault id (the injector takes one per injection).
  std::uint64_t nextId() { return ids_.next(); }
  /// Fault ids come from `shared` (the run's processes share one counter); before start.
  void shareIds(std::atomic<std::uint64_t>* shared) { ids_.share(shared); }

  /// `reporter` detected `fault`; `fault.component` names the faulty component (empty: the
  /// reporter itself). `detector` names who found it in the log (empty: the reporter).
  /// Not `recoverable` (a failed lifecycle transition): logged and diagnosed, never handled.
  /// Returns the fault's id.
  /// `caught`: what the guard caught, when `fault`'s detail is still to be written from it.
  std::uint64_t report(Component& reporter, const FaultEvent& fault, std::string_view detector, bool recoverable = true,
                       const FaultReport::Caught* caught = nullptr);

  // runtime::FaultSink: what the runtime reports, straight from the thread that noticed it.
  void report(Component& c, const FaultEvent& fault) override { (void)report(c, fault, {}); }
  void reportFailedTransition(Component& c, const FaultEvent& fault) override { report(c, fault, {}, false); }
  /// Keeps `caught` in the report: its text is written with the fault's records.
  void reportCaught(Component& c, const FaultEvent& fault, const runtime::GuardOutcome& caught, const char* callback,
                    const char* (*code_name)(int)) override {
    const FaultReport::Caught what{caught, callback, code_name};
    (void)report(c, fault, {}, true, &what);
  }
  /// On `c`'s own thread: carries on the handling that waits for it.
  void runPending(Component& c) override;
  /// `c` executed normally after a recovery.
  void recovered(Component& c, std::int64_t t_ns) override;
  /// What fault `id` of `c` lost came back (a DDS writer: src/dds): its `recovered`, unless the
  /// fault's handling logged one already (a reset component that ran again first).
  void peerBack(Component& c, std::uint64_t id, std::int64_t t_ns);

  /// Emergency stop (§5.3.3, fault/containment.hpp): latches the emergency and runs every
  /// component's onEmergencyStop. Returns the components whose onEmergencyStop ran. `by` is logged.
  std::vector<std::string> emergencyStop(std::string_view by) { return containment_.emergencyStop(by); }
  /// Clears the latch (an explicit operator action, logged). False if none was latched.
  bool clearEmergency(std::string_view by) { return containment_.clearEmergency(by); }
  bool emergencyLatched() const { return containment_.emergencyLatched(); }

  std::vector<FaultCount> counts() const { return records_.counts(); }
  std::vector<Detection> detections() const { return records_.detections(); }
  std::vector<Handling> handlings() const { return records_.handlings(); }
  /// The handling of fault `id`, if it was logged (no copy of the others).
  std::optional<Handling> handling(std::uint64_t id) const { return records_.handling(id); }
  /// How many `recovered` records were logged so far (cheap: for waiting on a recovery).
  std::size_t recoveredCount() const { return records_.recoveredCount(); }
  /// How many faults were detected so far (cheap: no copy, no lock).
  std::size_t detectionCount() const { return records_.detectionCount(); }
  /// The components and applications fault-stopped so far.
  std::set<std::string> stoppedComponents() const { return containment_.stoppedComponents(); }
  std::set<std::string> stoppedApplications() const { return containment_.stoppedApplications(); }
  /// Called at the end of a run: logs injections that manifested but were never detected.
  void flushUndetected(const std::vector<Component*>& components);

 private:
  // Where handling may act: on the component's own thread (between its callbacks or holding a
  // passive component's lock), on the manager's thread, or both.
  static constexpr unsigned kLocal = 1, kManager = 2;

  /// Carries `r` through its steps as far as it can from here (`where`).
  void advance(FaultReport& r, unsigned where);
  /// Records the decision after `step` ended with `outcome` and moves r.next on.
  void escalate(FaultReport& r, Step step, Outcome outcome, std::string_view detail = {});
  void handOverLocal(FaultReport& r, unsigned where);
  void handOverManager(FaultReport& r);
  void finish(FaultReport& r, unsigned where);
  void checkInterrupted(const FaultReport& handed);
  void process(HandlingItem& item);
  bool onManagerThread() const { return queue_.onThread(); }

  std::function<Component*(std::string_view)> find_;
  RecoveryActions* actions_ = nullptr;
  FaultIds ids_;
  FaultRecords records_;
  Recovery recovery_;
  Containment containment_;
  HandlingQueue queue_;
};

}  // namespace keel::fault
