// Containment (paper §5.3.3): the fault stop of a component's scope and of what depends on it
// over the dependency graph, and the emergency stop of every component, latched until an
// operator clears it. Both run on the fault manager's thread (an emergency stop may also come
// from an operator's thread); they reach components on their own threads (fault/on_thread.hpp)
// and run an actuator's onEmergencyStop themselves when its executor is hung.
// Thread-safety: any thread; one emergency stop at a time.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "fault/dependency_graph.hpp"
#include "fault/escalation.hpp"
#include "fault/fault_records.hpp"
#include "fault/recovery_actions.hpp"
#include "fault/report.hpp"

namespace keel::fault {

class Containment {
 public:
  /// `find` maps an instance name to its serving component (null when unknown).
  Containment(FaultRecords& records, std::function<Component*(std::string_view)> find)
      : records_(records), find_(std::move(find)) {}

  void attach(RecoveryActions* actions, const DependencyGraph* graph) {
    actions_ = actions;
    graph_ = graph;
  }

  /// Stops r.accused, its scope and what depends on them; logs one `stop` action with the
  /// lists and a `state` record per stopped application. Done, or Failed when the faulty
  /// component's hung callback did not come back and its executor could not be abandoned.
  Outcome stopScope(FaultReport& r, ComponentHandling& h);

  /// Latches the emergency and runs every component's onEmergencyStop, on its executor when
  /// that answers within emergencyBound() (20 ms), else on the calling thread. Returns the
  /// components whose onEmergencyStop ran. `by` is logged; so are `fault_id` and `component`
  /// when a fault of that component called for it (0 and empty: an operator).
  std::vector<std::string> emergencyStop(std::string_view by, std::uint64_t fault_id = 0,
                                         std::string_view component = {});
  /// Clears the latch (an explicit operator action, logged). False if none was latched.
  bool clearEmergency(std::string_view by);
  bool emergencyLatched() const { return emergency_.load(std::memory_order_acquire); }
  /// How long the emergency stop waits for an executor before it takes it to be hung.
  std::chrono::nanoseconds emergencyBound() const { return emergency_bound_; }
  void setEmergencyBound(std::chrono::nanoseconds bound) { emergency_bound_ = bound; }

  std::set<std::string> stoppedComponents() const;
  std::set<std::string> stoppedApplications() const;

 private:
  /// Adds `targets` and what they take with them to the stopped sets; returns what is new.
  void markStopped(const std::set<std::string>& targets, std::vector<std::string>& components,
                   std::vector<std::string>& applications);
  /// Interrupts the faulty component's hung callback; false if it did not come back.
  bool interruptHung(Component* faulty);

  FaultRecords& records_;
  std::function<Component*(std::string_view)> find_;
  RecoveryActions* actions_ = nullptr;
  const DependencyGraph* graph_ = nullptr;

  std::atomic<bool> emergency_{false};
  std::chrono::nanoseconds emergency_bound_ = std::chrono::milliseconds(20);
  std::mutex emergency_mutex_;  // one emergency stop at a time

  mutable std::mutex mutex_;  // guards the two sets
  std::set<std::string> stopped_components_;
  std::set<std::string> stopped_applications_;
};

}  // namespace keel::fault
