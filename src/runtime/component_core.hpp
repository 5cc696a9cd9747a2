// The runtime's side of a component instance: its name, state, ports, properties, critical
// memory, the executor that runs it and the hooks that report what happens to it. Allocated by
// Component's constructor (so ports can register while the derived class is built) and owned
// by the Component. Only src/runtime and src/fault include this header.
// Thread-safety: `state` and the counters are atomic; everything else is set before start.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "keel/component.hpp"
#include "keel/fault_event.hpp"

namespace keel::runtime {
class Executor;

/// What the runtime is told about a component. Implemented by the engine.
class RuntimeHooks {
 public:
  virtual ~RuntimeHooks() = default;
  virtual void stateChanged(Component& c, State from, State to) = 0;
  /// A fault was detected in `c` (or raised by it). Called on the thread that noticed it.
  virtual void faultDetected(Component& c, const FaultEvent& fault) = 0;
  /// Handling of a fault of `c` waits for `c`'s own thread (core.pending was set): called
  /// there, between callbacks or after its hung callback was interrupted.
  virtual void runPending(Component& c) = 0;
  /// `c` completed an onExecute after a recovery (core.recovering_id was set).
  virtual void recovered(Component& c, std::int64_t t_ns) = 0;
  /// `c` asked to end the run (Component::endRun); the first request wins.
  virtual void endRun(Component& c, std::string_view summary, std::string_view event, std::string_view fields) {
    (void)c, (void)summary, (void)event, (void)fields;
  }
};

struct CriticalRegion {
  void* addr;
  std::size_t len;
};
}  // namespace keel::runtime

namespace keel::detail {

class ComponentCore {
 public:
  std::string instance_name;
  std::string class_name;
  std::atomic<State> state{State::Created};
  std::atomic<bool> emergency{false};
  std::vector<PortBase*> ports;
  std::map<std::string, PropertyValue, std::less<>> properties;
  std::vector<runtime::CriticalRegion> critical;
  // null: passive. Atomic: an executor abandoned with a hung thread hands its components to a
  // new one while other threads wake them (notifyInput) or post to them.
  std::atomic<runtime::Executor*> executor{nullptr};
  runtime::RuntimeHooks* hooks = nullptr;     // null: not yet managed by a runtime
  // Serialises callbacks of passive components. Not a timed mutex: TSan does not see
  // pthread_mutex_clocklock, which try_lock_for uses (timeouts poll try_lock instead).
  std::recursive_mutex passive_mutex;
  std::atomic<bool> event_pending{false};     // an input event port has something queued
  std::atomic<bool> input_pending{false};     // an input data port received a value

  std::int64_t deadline_ns = 0;               // <deadline> of its fault policy; 0: none
  std::int64_t heartbeat_ns = 0;              // <heartbeat timeout> of its policy; 0: none

  // watchdog (src/fault/watchdog): written by the executor when heartbeat_ns != 0
  std::atomic<std::int64_t> callback_since_ns{0};  // start of the running callback; 0: none
  std::atomic<std::int64_t> last_beat_ns{0};       // start of its latest onExecute

  // fault injection (src/runtime/injection): armed by the injector, fired inside the guard
  std::atomic<std::uint8_t> inject_kind{0};        // runtime::InjectKind; 0: none armed
  std::atomic<std::uint64_t> inject_id{0};         // fault_id of the armed injection
  std::atomic<std::uint64_t> injected_id{0};       // manifested and not yet detected
  std::atomic<std::int64_t> injected_t_ns{0};      // steady ns of the manifestation
  std::atomic<std::int64_t> stalled_until_ns{0};   // stall_heartbeat: not executed until then
  std::atomic<bool> release_hang{false};           // ends an injected hang (at shutdown)

  // checkpoints of the critical() memory (runtime/checkpoint): taken on the component's own
  // thread at cycle boundaries, read by recovery (same thread) or a replacement (any thread)
  std::int64_t checkpoint_period_ns = 0;           // <checkpoint period>; 0: only at start
  std::int64_t next_checkpoint_ns = 0;             // its executor's thread only
  std::mutex checkpoint_mutex;                     // guards the three below
  std::vector<std::vector<std::byte>> checkpoint;  // one copy per critical region
  std::int64_t checkpoint_t_ns = 0;                // when the copy was taken; 0: none yet
  std::uint64_t checkpoint_count = 0;

  // fault handling (src/fault/fault_manager): rules and state owned by the fault manager
  void* handling = nullptr;                        // fault::ComponentHandling*
  std::atomic<bool> pending{false};                // a fault's handling waits for this thread
  std::atomic<bool> interrupt{false};              // interrupt the running (hung) callback
  std::atomic<std::uint64_t> recovering_id{0};     // recovered: after the next good onExecute

  // counters, read by the engine's summary and the watchdog
  std::atomic<std::uint64_t> executions{0};
  std::atomic<std::uint64_t> faults{0};  // counted by the fault manager, for the accused
  std::atomic<std::uint64_t> deadline_overruns{0};

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
inline const detail::ComponentCore& coreOf(const Component& c) {
  return detail::ComponentAccess::core(c);
}
}  // namespace keel::runtime
