// The fault log's schema (docs/fault-log.md): every event name and field name of the JSONL log,
// defined once, and a builder per record so that a record of one kind is always shaped the
// same, whoever writes it. Used by the writers (the fault manager's parts, the injector, the
// engine, `keel run`), by the readers (`keel` reports, the tests' log reader) and the tests.
// Times passed to the builders are already relative to the log's start (FaultLog::sinceStart).
// Thread-safety: constants and functions of their arguments.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace keel::log::schema {

/// The `event` of a record.
namespace event {
inline constexpr char kInjected[] = "injected";           // keel injected a fault (its manifestation time)
inline constexpr char kArmed[] = "armed";                 // an injection waits for its moment in the component
inline constexpr char kDetected[] = "detected";           // a detector found a fault
inline constexpr char kDiagnosed[] = "diagnosed";         // the rules chose the handling
inline constexpr char kAction[] = "action";               // one step of the handling, with its outcome
inline constexpr char kRecovered[] = "recovered";         // the component (or its replacement) runs normally again
inline constexpr char kState[] = "state";                 // a component's or an application's state changed
inline constexpr char kEmergency[] = "emergency";         // the emergency latch was set or cleared
inline constexpr char kEngine[] = "engine";               // the run's phases: load, started, stopping, stopped
inline constexpr char kWarning[] = "warning";             // something the run goes on without
inline constexpr char kEndRequested[] = "end_requested";  // a component asked to end the run
inline constexpr char kHost[] = "host";                   // a component process (<process>) changed state
inline constexpr char kNode[] = "node";                   // a ROS 2 node keel runs was started, exited or stopped
inline constexpr char kCounts[] = "counts";               // a component's or an executor's totals, at its engine's end
}  // namespace event

/// Field names.
namespace field {
inline constexpr char kEvent[] = "event";
inline constexpr char kTime[] = "t_ns";  // ns since the engine started (steady clock)
inline constexpr char kFaultId[] = "fault_id";
inline constexpr char kComponent[] = "component";
inline constexpr char kApplication[] = "application";
inline constexpr char kComposite[] = "composite";  // `state`: a composite's derived state
inline constexpr char kKind[] = "kind";
inline constexpr char kDetail[] = "detail";
inline constexpr char kDetector[] = "detector";
inline constexpr char kMeasurement[] = "measurement";  // detected: the inconsistent measurement (a state estimator's)
inline constexpr char kDetected[] = "detected";        // on `injected`: false when never detected
inline constexpr char kSeverity[] = "severity";
inline constexpr char kRules[] = "rules";
inline constexpr char kScope[] = "scope";
inline constexpr char kHandling[] = "handling";
inline constexpr char kAction[] = "action";
inline constexpr char kOutcome[] = "outcome";
inline constexpr char kReplacement[] = "replacement";
inline constexpr char kAlternative[] = "alternative";  // `state`: true, of an instance's alternative
inline constexpr char kServing[] = "serving";          // `state`: false, of an object not standing for its name then
inline constexpr char kComponents[] = "components";
inline constexpr char kApplications[] = "applications";
inline constexpr char kFrom[] = "from";
inline constexpr char kTo[] = "to";
inline constexpr char kLatencyUs[] = "latency_us";
inline constexpr char kPhase[] = "phase";
inline constexpr char kBy[] = "by";
inline constexpr char kMessage[] = "message";
inline constexpr char kReason[] = "reason";
inline constexpr char kSummary[] = "summary";
inline constexpr char kOnFaultManagerThread[] = "on_fault_manager_thread";
inline constexpr char kNotFinished[] = "not_finished";
inline constexpr char kHardware[] = "hardware";                   // on `injected`: a hardware fault
inline constexpr char kFieldsError[] = "fields_error";            // on a component's end-of-run record
inline constexpr char kProfile[] = "profile";                     // engine `load`
inline constexpr char kInstances[] = "instances";                 // engine `load`
inline constexpr char kSet[] = "set";                             // engine `load`: keel run --set
inline constexpr char kEpochNs[] = "epoch_ns";                    // engine `load`: t_ns 0, CLOCK_MONOTONIC
inline constexpr char kExecutors[] = "executors";                 // engine `started`
inline constexpr char kCpuDmaLatencyUs[] = "cpu_dma_latency_us";  // engine `started`
inline constexpr char kProcess[] = "process";                     // `host`: the <process> name
inline constexpr char kPid[] = "pid";                             // `host`, `node`: its OS process id
inline constexpr char kNodeName[] = "node";                       // `node`: its name in the ROS 2 graph
inline constexpr char kLastLines[] = "last_lines";                // `node` `exited`: its output's last lines
inline constexpr char kOutput[] = "output";                       // `node` `started`: its output file
inline constexpr char kParams[] = "params";                       // `node` `restarted`: its params file
inline constexpr char kAfterMs[] = "after_ms";                    // `node` `up`: since its (re)start
inline constexpr char kName[] = "name";                           // engine `load`: the run's (root profile's) name
inline constexpr char kClass[] = "class";                         // `counts`, `state`: the component's class
inline constexpr char kExecutor[] = "executor";                   // `counts`: the executor's name, or "passive"
inline constexpr char kExecutions[] = "executions";               // `counts`: onExecute calls
inline constexpr char kDeadlineMisses[] = "deadline_misses";      // `counts`: onExecute calls over <deadline>
inline constexpr char kPeriodMs[] = "period_ms";                  // `counts`: a periodic executor's period
inline constexpr char kCycles[] = "cycles";                       // `counts`: an executor's cycles
inline constexpr char kLateCycles[] = "late_cycles";              // `counts`: cycles that ended after the next release
}  // namespace field

/// `outcome` values.
inline constexpr char kOk[] = "ok";
inline constexpr char kFailed[] = "failed";

// ---- builders: one per record shape --------------------------------------------------------

inline nlohmann::json injected(std::uint64_t id, std::string_view component, std::int64_t t) {
  return {{field::kEvent, event::kInjected}, {field::kFaultId, id}, {field::kComponent, component}, {field::kTime, t}};
}

inline nlohmann::json detected(std::uint64_t id, std::string_view component, std::string_view kind,
                               std::string_view detail, std::string_view detector, std::int64_t t) {
  return {{field::kEvent, event::kDetected},
          {field::kFaultId, id},
          {field::kComponent, component},
          {field::kKind, kind},
          {field::kDetail, detail},
          {field::kDetector, detector},
          {field::kTime, t}};
}

inline nlohmann::json diagnosed(std::uint64_t id, std::string_view component, std::string_view severity,
                                std::string_view rules, std::string_view scope, std::string_view handling,
                                std::int64_t t) {
  return {{field::kEvent, event::kDiagnosed}, {field::kFaultId, id},  {field::kComponent, component},
          {field::kSeverity, severity},       {field::kRules, rules}, {field::kScope, scope},
          {field::kHandling, handling},       {field::kTime, t}};
}

/// An `action` record; `id` 0 for an action no fault caused (an operator's emergency stop).
inline nlohmann::json action(std::uint64_t id, std::string_view component, std::string_view action, bool ok,
                             std::int64_t t) {
  nlohmann::json r = {{field::kEvent, event::kAction},
                      {field::kAction, action},
                      {field::kOutcome, ok ? kOk : kFailed},
                      {field::kTime, t}};
  if (id != 0) r[field::kFaultId] = id;
  if (!component.empty()) r[field::kComponent] = component;
  return r;
}

inline nlohmann::json recovered(std::uint64_t id, std::string_view component, std::int64_t t) {
  return {{field::kEvent, event::kRecovered}, {field::kFaultId, id}, {field::kComponent, component}, {field::kTime, t}};
}

/// Which object under an instance's name a `state` record is of: the name stands for one object
/// at a time (the component created for it, then the alternative that replaced it), and each
/// object's records chain from its `Created` to its `Destroyed`.
struct StateOf {
  std::string_view cls;      // its class
  bool alternative = false;  // the instance's alternative, not the component created for it
  bool serving = true;       // false: a preloaded alternative standing by, a replaced component
};

/// A component's lifecycle change; `id` 0 when no fault caused it.
inline nlohmann::json componentState(std::string_view component, const StateOf& of, std::string_view from,
                                     std::string_view to, std::uint64_t id, std::int64_t t) {
  nlohmann::json r = {{field::kEvent, event::kState},
                      {field::kComponent, component},
                      {field::kClass, of.cls},
                      {field::kFrom, from},
                      {field::kTo, to}};
  if (of.alternative) r[field::kAlternative] = true;
  if (!of.serving) r[field::kServing] = false;
  if (id != 0) r[field::kFaultId] = id;
  r[field::kTime] = t;
  return r;
}

inline nlohmann::json applicationState(std::string_view application, std::string_view from, std::string_view to,
                                       std::uint64_t id, std::int64_t t) {
  return {{field::kEvent, event::kState}, {field::kApplication, application},
          {field::kFrom, from},           {field::kTo, to},
          {field::kFaultId, id},          {field::kTime, t}};
}

/// A composite's state, derived from its members' (OPRoS's composites have none of their own).
inline nlohmann::json compositeState(std::string_view composite, std::string_view from, std::string_view to,
                                     std::int64_t t) {
  return {{field::kEvent, event::kState},
          {field::kComposite, composite},
          {field::kFrom, from},
          {field::kTo, to},
          {field::kTime, t}};
}

/// The emergency latch: `phase` latched or cleared.
inline nlohmann::json emergency(std::string_view phase, std::string_view by) {
  return {{field::kEvent, event::kEmergency}, {field::kPhase, phase}, {field::kBy, by}};
}

inline nlohmann::json engine(std::string_view phase) {
  return {{field::kEvent, event::kEngine}, {field::kPhase, phase}};
}

/// A host process of `process` changed state: loading, standby, active, exited, died, failed.
inline nlohmann::json host(std::string_view process, long pid, std::string_view state) {
  return {{field::kEvent, event::kHost}, {field::kProcess, process}, {field::kPid, pid}, {field::kPhase, state}};
}

/// A ROS 2 node of instance `component`, fully named `node`, changed phase: started, restarted,
/// exited (by itself), stopped (by keel).
inline nlohmann::json node(std::string_view component, std::string_view node, long pid, std::string_view phase) {
  return {{field::kEvent, event::kNode},
          {field::kComponent, component},
          {field::kNodeName, node},
          {field::kPid, pid},
          {field::kPhase, phase}};
}

/// A component's totals at the end of its engine: `executor` its executor's name or "passive".
inline nlohmann::json componentCounts(std::string_view component, std::string_view cls, std::string_view executor,
                                      std::uint64_t executions, std::uint64_t deadline_misses) {
  return {{field::kEvent, event::kCounts}, {field::kComponent, component},   {field::kClass, cls},
          {field::kExecutor, executor},    {field::kExecutions, executions}, {field::kDeadlineMisses, deadline_misses}};
}

/// An executor's totals at the end of its engine; `period_ms` 0 for an aperiodic one (left out).
inline nlohmann::json executorCounts(std::string_view executor, double period_ms, std::uint64_t cycles,
                                     std::uint64_t late_cycles) {
  nlohmann::json r = {{field::kEvent, event::kCounts},
                      {field::kExecutor, executor},
                      {field::kCycles, cycles},
                      {field::kLateCycles, late_cycles}};
  if (period_ms > 0) r[field::kPeriodMs] = period_ms;
  return r;
}

inline nlohmann::json warning(std::string_view message) {
  return {{field::kEvent, event::kWarning}, {field::kMessage, message}};
}

}  // namespace keel::log::schema
