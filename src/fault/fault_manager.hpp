// The fault manager (paper §3.2, §5.2–5.3): every detected fault reaches it, whichever detector
// found it — the guard, a port, the watchdog, a monitor or voter, raiseFault, or a FaultEvent
// sent to its `faults` port. It gives the fault its id (the injection's, when keel injected
// it), applies the component's compiled rules (fault/rules.hpp) and escalates along
// reset → replace → stop → emergency.
//
// How a fault flows (ARCHITECTURE.md): local recoveries — reset with the checkpoint restored,
// the switch to a preloaded alternative — run at once on the thread that caught the fault when
// that is the component's own executor thread, and the manager's thread is told afterwards
// (no wake-up on the recovery path). Anything else is handed over: to the component's thread
// (posted between its callbacks, or its hung callback interrupted by a signal), or to the
// manager's own thread, which does what needs the whole picture: loading an alternative cold,
// fault stop over the dependency graph, emergency stop, and the log (`injected`, `detected`,
// `diagnosed`, `action`, `recovered`, `state`).
// Thread-safety: onFault, runPending, recovered, emergencyStop, clearEmergency and the readers
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

#include "fault/dependency_graph.hpp"
#include "fault/fault_log.hpp"
#include "fault/report.hpp"
#include "keel/component.hpp"
#include "keel/fault_event.hpp"
#include "keel/result.hpp"
#include "runtime/wake_signal.hpp"

namespace keel::fault {

struct FaultCount {
  std::string component;
  std::string kind;
  std::string detail;  // the first one
  std::uint64_t count = 0;
};

/// One detection, as kept for summaries and tests.
struct Detection {
  std::uint64_t fault_id = 0;
  std::string component;
  FaultKind kind = FaultKind::User;
  std::int64_t detected_ns = 0;  // steady clock
  std::int64_t injected_ns = 0;  // 0: not injected
};

/// One fault's handling, as kept for the run's summary and the benchmarks.
struct Handling {
  std::uint64_t fault_id = 0;
  std::string component;
  FaultKind kind = FaultKind::User;
  std::string severity;
  std::string actions;           // "reset", "escalate reset→replace, replace", ...
  bool failed = false;           // an action failed (the last word is then the outcome)
  std::int64_t detected_ns = 0;
  std::int64_t injected_ns = 0;  // 0: not injected
  std::int64_t recovered_ns = 0; // 0: not (yet) recovered
};

/// What the manager needs from the runtime that runs the components (the engine).
class HandlingHost {
 public:
  virtual ~HandlingHost() = default;
  virtual Component* find(std::string_view instance) const = 0;
  /// Every running component (replacements in place of what they replaced).
  virtual std::vector<Component*> components() const = 0;
  /// Cold replacement, on the manager's thread: loads, creates, initializes and wires the
  /// alternative of `failed` (outputs attached, not started, not yet receiving).
  virtual Result<Component*> createAlternative(ComponentHandling& h, Component& failed) = 0;
  /// On `failed`'s own thread: `alternative` takes its place — inputs retargeted, provided
  /// services rebound, executor member swapped, lookups by name answer the alternative.
  virtual void switchTo(Component& failed, Component& alternative) = 0;
  /// `hung`'s executor thread is stuck in its callback and cannot be interrupted: the executor
  /// is abandoned and a new one (same configuration) takes its other members, and
  /// `replacement` (may be null) in `hung`'s place, started on the calling thread before the
  /// new executor runs. Returns the new executor's name, or why it could not be done.
  virtual Result<std::string> abandonExecutor(Component& hung, Component* replacement) = 0;
};

class FaultManager {
 public:
  /// `find` maps an instance name to its component (null when unknown); used until attach().
  FaultManager(FaultLog& log, std::function<Component*(std::string_view)> find);
  ~FaultManager();
  FaultManager(const FaultManager&) = delete;
  FaultManager& operator=(const FaultManager&) = delete;

  /// Connects the manager to the runtime and the plan's dependency graph (may be null).
  void attach(HandlingHost* host, const DependencyGraph* graph);
  /// Starts the manager's thread. Without it, reports are handled on the reporting thread.
  void start();
  /// Handles what is queued, then ends the thread.
  void stop();
  /// Waits until everything reported so far has been handled and logged (tests, shutdown).
  void drain();

  /// A new fault id (the injector takes one per injection).
  std::uint64_t nextId() { return next_id_.fetch_add(1, std::memory_order_relaxed); }

  /// `reporter` detected `fault`; `fault.component` names the faulty component (empty: the
  /// reporter itself). `detector` names who found it in the log (default: the reporter).
  void onFault(Component& reporter, const FaultEvent& fault, std::string_view detector = {});
  /// On `c`'s own thread: carries on the handling that waits for it (runtime hook).
  void runPending(Component& c);
  /// `c` executed normally after a recovery (runtime hook).
  void recovered(Component& c, std::int64_t t_ns);

  /// Emergency stop (§5.3.3): latches the emergency and runs every component's onEmergencyStop,
  /// on its executor when that answers within `bound`, else on the calling thread. Returns the
  /// components whose onEmergencyStop ran. `by` is logged.
  std::vector<std::string> emergencyStop(std::string_view by);
  /// Clears the latch (an explicit operator action, logged). False if none was latched.
  bool clearEmergency(std::string_view by);
  bool emergencyLatched() const { return emergency_.load(std::memory_order_acquire); }

  std::vector<FaultCount> counts() const;
  std::vector<Detection> detections() const;
  std::vector<Handling> handlings() const;
  /// The handling of fault `id`, if it was logged (no copy of the others).
  std::optional<Handling> handling(std::uint64_t id) const;
  /// How many `recovered` records were logged so far (cheap: for waiting on a recovery).
  std::size_t recoveredCount() const { return recovered_count_.load(std::memory_order_acquire); }
  /// How many faults were detected so far (cheap: no copy, no lock).
  std::size_t detectionCount() const { return detection_count_.load(std::memory_order_acquire); }
  /// The components and applications fault-stopped so far.
  std::set<std::string> stoppedComponents() const;
  std::set<std::string> stoppedApplications() const;
  /// Called at the end of a run: logs injections that manifested but were never detected.
  void flushUndetected(const std::vector<Component*>& components);

 private:
  // Where handling may act: on the component's own thread (between its callbacks or holding a
  // passive component's lock), on the manager's thread, or both.
  static constexpr unsigned kLocal = 1, kManager = 2;

  void advance(FaultReport& r, unsigned where);
  void handOverLocal(FaultReport& r, unsigned where);
  void handOverManager(FaultReport& r);
  void finish(FaultReport& r, unsigned where);
  bool reset(FaultReport& r, ComponentHandling& h);
  bool replace(FaultReport& r, ComponentHandling& h);
  void stopScope(FaultReport& r, ComponentHandling& h);
  void markRecovering(FaultReport& r, Component& c);
  void checkInterrupted(const FaultReport& handed);
  /// The hung callback of `r.accused` did not come back: its executor is abandoned, the
  /// alternative (if any) takes its place on the new executor, else it stays stopped.
  void abandonHung(FaultReport& r, ComponentHandling& h);
  Step afterReset(ComponentHandling& h);

  // the manager's thread and its queue
  struct Item {
    // Report: carry on handling; Recovered: log it; CheckInterrupted: verify that a hung
    // callback came back when interrupted, else abandon its executor.
    enum class Type : std::uint8_t { Report, Recovered, CheckInterrupted } type = Type::Report;
    FaultReport report;
  };
  /// Hands `report` to the manager's thread (written straight into the queue: one copy), or
  /// handles it here when the thread does not run.
  void enqueue(Item::Type type, const FaultReport& report, bool wake);
  void run();
  void process(Item& item);
  void logReport(FaultReport& r);
  void logRecovered(const FaultReport& r);  // r: id, component, event.t_ns = the recovery
  bool onManagerThread() const { return std::this_thread::get_id() == thread_id_.load(); }

  FaultLog& log_;
  std::function<Component*(std::string_view)> find_;
  HandlingHost* host_ = nullptr;
  const DependencyGraph* graph_ = nullptr;
  std::atomic<std::uint64_t> next_id_{1};

  std::thread thread_;
  std::atomic<std::thread::id> thread_id_{};
  runtime::WakeSignal signal_;
  std::atomic<bool> stop_{false};
  std::mutex queue_mutex_;
  std::vector<Item> ring_;  // fixed capacity: enqueue never allocates
  std::size_t head_ = 0, size_ = 0;
  bool accepting_ = false;  // the thread runs and takes reports (guarded by queue_mutex_)
  std::atomic<std::uint64_t> enqueued_{0}, processed_{0};

  std::atomic<bool> emergency_{false};
  std::mutex emergency_mutex_;  // one emergency stop at a time

  mutable std::mutex mutex_;  // guards the records below
  std::vector<FaultCount> counts_;
  std::vector<Detection> detections_;
  std::vector<Handling> handlings_;
  std::set<std::string> stopped_components_;
  std::set<std::string> stopped_applications_;
  std::atomic<std::size_t> detection_count_{0};
  std::atomic<std::size_t> recovered_count_{0};
};

}  // namespace keel::fault
