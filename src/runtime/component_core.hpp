// The runtime's side of a component instance: its name, state, ports, properties, critical
// memory, the executor that runs it and the hooks that report what happens to it, in cells by
// owner (the executor's, the watchdog's, fault injection's, the checkpoints', the fault
// manager's). Allocated by Component's constructor (so ports can register while the derived
// class is built) and owned by the Component. Included by the runtime and the layers above.
// Thread-safety: per cell, as stated there; the configuration is set before start.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "keel/component.hpp"
#include "keel/fault_event.hpp"

namespace keel::runtime {
class Executor;
class ExecutionGate;
struct GuardOutcome;
namespace ipc {
struct CheckpointArea;
}

/// Where the runtime reports faults: the runtime's own interface to the fault layer, which
/// implements it (fault::FaultManager). Called on executor threads and detectors' threads.
class FaultSink {
 public:
  virtual ~FaultSink() = default;
  /// A fault was detected in `c` (or raised by it). Called on the thread that noticed it.
  virtual void report(Component& c, const FaultEvent& fault) = 0;
  /// A running callback of `c` (`callback`: its name) failed as the guard `caught` it; `fault`
  /// has the kind, time and component, and no detail yet: `caught.describe(fault, callback,
  /// code_name)` writes it. A sink may do that off the thread that noticed it, where the text
  /// is needed; by default it is written here and the fault reported as any other.
  virtual void reportCaught(Component& c, const FaultEvent& fault, const GuardOutcome& caught, const char* callback,
                            const char* (*code_name)(int));
  /// A lifecycle callback of `c` (onInitialize, onStart, onStop, onDestroy) failed with
  /// `fault`. Reported like any fault, but no rule recovers a transition that did not happen:
  /// the component stays in Error until it is destroyed. Called on the thread of the call.
  virtual void reportFailedTransition(Component& c, const FaultEvent& fault) { report(c, fault); }
  /// Handling of a fault of `c` waits for `c`'s own thread (the fault cell's `pending` was
  /// set): called there, between callbacks or after its hung callback was interrupted.
  virtual void runPending(Component& c) = 0;
  /// `c` completed an onExecute after a recovery (the fault cell's `recovering_id` was set).
  virtual void recovered(Component& c, std::int64_t t_ns) = 0;
};

/// What else the runtime tells the owner of a run about a component. Implemented by the engine.
class RunHooks {
 public:
  virtual ~RunHooks() = default;
  virtual void stateChanged(Component& c, State from, State to) = 0;
  /// `c` asked to end the run (keel::RunControl::endRun); the first request wins.
  virtual void endRun(Component& c, std::string_view summary, std::string_view event, std::string_view fields) {
    (void)c, (void)summary, (void)event, (void)fields;
  }
};

struct CriticalRegion {
  void* addr;
  std::size_t len;
};

/// What the fault layer keeps per component (fault::ComponentHandling derives from it). The
/// runtime only carries it; it never looks inside.
class FaultSlot {
 public:
  virtual ~FaultSlot() = default;
};

/// Fault injection's cell (runtime/injection): armed by the injector, fired inside the guard.
struct InjectionCell {
  std::atomic<std::uint8_t> kind{0};              // runtime::InjectKind; 0: none armed
  std::atomic<std::uint64_t> id{0};               // fault_id of the armed injection
  std::atomic<std::uint64_t> injected_id{0};      // manifested and not yet detected
  std::atomic<std::int64_t> injected_t_ns{0};     // steady ns of the manifestation
  std::atomic<std::int64_t> stalled_until_ns{0};  // stall_heartbeat: not executed until then
  std::atomic<bool> release_hang{false};          // ends an injected hang (at shutdown)
};

/// The watchdog's cell (fault/watchdog reads it): written by the executor when the component
/// has a heartbeat.
struct WatchCell {
  std::int64_t heartbeat_ns = 0;                   // <heartbeat timeout> of its policy; 0: none
  std::atomic<std::int64_t> callback_since_ns{0};  // start of the running callback; 0: none
  std::atomic<std::int64_t> last_beat_ns{0};       // start of its latest onExecute
};

/// Checkpoints of the critical() memory (runtime/checkpoint): taken on the component's own
/// thread at cycle boundaries, read by recovery (same thread) or an alternative (any thread).
struct CheckpointStore {
  std::int64_t period_ns = 0;                  // <checkpoint period>; 0: only at start
  ipc::CheckpointArea* shared = nullptr;       // in a component process: also published there
  std::int64_t next_ns = 0;                    // its executor's thread only
  std::mutex mutex;                            // guards the three below
  std::vector<std::vector<std::byte>> copies;  // one copy per critical region
  std::int64_t t_ns = 0;                       // when the copy was taken; 0: none yet
  std::uint64_t count = 0;
};

/// The fault manager's cell (fault/fault_manager): its per-component state, and the handshake
/// with the component's own thread.
struct FaultCell {
  FaultSlot* handling = nullptr;                // fault::ComponentHandling; null: unmanaged
  std::atomic<bool> pending{false};             // a fault's handling waits for this thread
  std::atomic<bool> interrupt{false};           // interrupt the running (hung) callback
  std::atomic<std::uint64_t> recovering_id{0};  // recovered: after the next good onExecute
  std::atomic<bool> emergency{false};           // the emergency is latched (containment)
  // A passive stand-in for a component running in another process (keel run's proxy): when
  // that component ran again after its reset (steady ns), the `recovered` moment; 0: on return.
  std::atomic<std::int64_t> recovered_at_ns{0};
  // A passive stand-in whose recovery comes after its handling ends (a lifecycle node reset
  // through its transitions: recovered once Active): its handling's end logs no `recovered`;
  // the stand-in's owner reports it (FaultSink::recovered) when it happens.
  std::atomic<bool> recovers_later{false};
  // The newest fault accusing this component, as diagnosed (before its records are written on
  // the fault manager's thread): stored before `ComponentCore::faults` counts it.
  std::atomic<std::uint64_t> last_id{0};
  std::atomic<std::uint8_t> last_kind{0};  // a FaultKind
  std::atomic<std::int64_t> last_ns{0};    // its detection, steady ns
};
}  // namespace keel::runtime

namespace keel::detail {

/// The runtime's side of one component, in cells by owner: each cell says who writes it.
class ComponentCore {
 public:
  // Identity and configuration: written by the engine while it builds the run, read-only
  // once the component has started.
  std::string instance_name;
  std::string class_name;
  std::vector<PortBase*> ports;
  std::map<std::string, PropertyValue, std::less<>> properties;
  std::vector<runtime::CriticalRegion> critical;  // registered in onInitialize
  std::int64_t deadline_ns = 0;                   // <deadline> of its fault policy; 0: none
  runtime::RunHooks* hooks = nullptr;             // null: not yet managed by a runtime
  runtime::FaultSink* fault_sink = nullptr;       // null: faults are not handled
  runtime::ExecutionGate* gate = nullptr;         // OPRoS's execution order (depends); null: none
  std::string profile_file;                       // the component profile it was made from
  // An alternative, created to take its instance's place on a fault (preloaded or at fault
  // time), not the component created for the instance: the log's `state` records say so.
  bool alternative = false;
  // A component written for OPRoS (src/opros): its ports are checked as OPRoS's engine did (a
  // port the profile and the code disagree on is a warning, not an error), and the queues its
  // code fixed in a port's constructor (policy, size) win over the profile's.
  bool opros = false;
  // Names the codes its callbacks return, when they are not keel's (OPRoS's OPROS_...); null:
  // keel's own (keel::toString(ReturnCode)).
  const char* (*code_name)(int) = nullptr;
  std::map<std::string, std::pair<QueuePolicy, std::size_t>, std::less<>> code_queues;

  // Lifecycle: written only by runtime/invoke (transition, setState, setStateQuiet).
  std::atomic<State> state{State::Created};
  // Why the last lifecycle callback failed (the fault's detail), for the caller of
  // transition() to report; written and read on the thread that called it.
  std::string transition_fault;
  // The property the last failed lifecycle callback refused (a PropertyError), and the error's
  // whole text, untruncated: the caller says where the value was set. Same thread as above.
  std::string refused_property;
  std::string refused_text;

  // Execution (runtime/executor, runtime/service). The executor is null for a passive
  // component; atomic because an abandoned executor's components move to a new one while
  // other threads wake them (notifyInput) or post to them.
  std::atomic<runtime::Executor*> executor{nullptr};
  // Serialises callbacks of passive components. Not a timed mutex: TSan does not see
  // pthread_mutex_clocklock, which try_lock_for uses (timeouts poll try_lock instead).
  std::recursive_mutex passive_mutex;
  std::atomic<bool> event_pending{false};  // an input event port has something queued
  std::atomic<bool> input_pending{false};  // an input data port received a value

  runtime::WatchCell watch;
  runtime::InjectionCell injection;
  runtime::CheckpointStore checkpoints;
  runtime::FaultCell fault;

  // Counters, read by the run's summary and the watchdog.
  std::atomic<std::uint64_t> executions{0};         // the executor's
  std::atomic<std::uint64_t> faults{0};             // diagnosed accusing it (fault.last_*: the newest)
  std::atomic<std::uint64_t> deadline_overruns{0};  // the executor's

  PortBase* findPort(std::string_view name) const {
    for (PortBase* p : ports)
      if (p->name() == name) return p;
    return nullptr;
  }
};

/// The runtime's way in to a Component's private core.
struct ComponentAccess {
  static ComponentCore& core(Component& c) { return *c.core_; }
  static const ComponentCore& core(const Component& c) { return *c.core_; }
};

}  // namespace keel::detail

namespace keel::runtime {
inline detail::ComponentCore& coreOf(Component& c) { return detail::ComponentAccess::core(c); }
inline const detail::ComponentCore& coreOf(const Component& c) { return detail::ComponentAccess::core(c); }
}  // namespace keel::runtime
