// keel::Component: the base class of every component (OPRoS's Component). An author derives
// from it, declares ports as members, overrides the callbacks it needs and registers the class
// with KEEL_REGISTER_COMPONENT. The runtime owns instances and calls the callbacks; all
// callbacks of one component are serialised (never two at once), so authors write no locks —
// except onHardwareFault, which a driver of hardware implements thread-safe.
// Thread-safety: callbacks run on the component's executor; the protected services
// (critical, raiseFault, reportFault, endRun, property) may be called from any callback.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "keel/data_port.hpp"
#include "keel/event_port.hpp"
#include "keel/fault_event.hpp"
#include "keel/lifecycle.hpp"
#include "keel/property.hpp"
#include "keel/registry.hpp"
#include "keel/return_code.hpp"
#include "keel/service_port.hpp"

namespace keel {

namespace detail {
class ComponentCore;
struct ComponentAccess;
}  // namespace detail

class Component {
 public:
  Component();
  virtual ~Component();
  Component(const Component&) = delete;
  Component& operator=(const Component&) = delete;

  // ---- lifecycle callbacks (each succeeds by default) ----
  virtual ReturnCode onInitialize() { return ReturnCode::Ok; }  // Created -> Ready
  virtual ReturnCode onStart() { return ReturnCode::Ok; }       // Ready/Inactive -> Active
  virtual ReturnCode onStop() { return ReturnCode::Ok; }        // Active -> Inactive
  virtual ReturnCode onDestroy() { return ReturnCode::Ok; }     // -> Destroyed
  // ---- execution callbacks ----
  virtual ReturnCode onExecute() { return ReturnCode::Ok; }  // once per cycle / per input
  virtual ReturnCode onUpdated() { return ReturnCode::Ok; }  // after the cycle's onExecutes
  /// An event arrived on `port`; read it with that port's `current()`.
  virtual ReturnCode onEvent(InputEventPortBase& port) {
    (void)port;
    return ReturnCode::Ok;
  }
  // ---- fault-tolerance callbacks (paper §5.3) ----
  virtual ReturnCode onError() { return ReturnCode::Ok; }    // entered Error
  virtual ReturnCode onReset() { return ReturnCode::Ok; }    // being reset
  virtual ReturnCode onRecover() { return ReturnCode::Ok; }  // recovered, about to run again
  /// Actuators: put outputs into the safe state ("stop in neutral") and keep them there until
  /// the emergency is cleared.
  virtual ReturnCode onEmergencyStop() { return ReturnCode::Ok; }
  /// A hardware fault from a fault scenario (`keel run --inject`, SPEC §6), for the component
  /// that drives that hardware: how a hardware-in-the-loop or simulated driver receives the
  /// harness's hardware faults (it forwards them to its board). `command` is the kind, then a
  /// space and the scenario's `args` if any: "motor_power_off left", "sensor_stuck 1 250",
  /// "noise". Called at the fault's time on the injector's thread, concurrently with this
  /// component's callbacks and whatever its state: it must be thread-safe, and return soon.
  /// Return Ok when the fault was applied; anything else (the default: Unsupported) or an
  /// exception is logged as the injection's outcome, with a warning.
  virtual ReturnCode onHardwareFault(std::string_view command) {
    (void)command;
    return ReturnCode::Unsupported;
  }

  /// Instance name from the package profile ("sonar_left"); empty before the runtime names it.
  const std::string& instanceName() const;
  /// Current lifecycle state.
  State state() const;
  /// True while an emergency stop is latched for this component.
  bool emergencyLatched() const;

  /// A typed property from the profile (after subcomponent overrides). Throws PropertyError
  /// when it is missing or cannot be represented as T; thrown from onInitialize this fails
  /// the load with the message.
  template <class T>
  T property(std::string_view name) const {
    return detail::propertyAs<T>(findProperty(name), instanceName(), name);
  }
  template <class T>
  T property(std::string_view name, T fallback) const {
    const PropertyValue* v = findProperty(name);
    return v ? detail::propertyAs<T>(v, instanceName(), name) : fallback;
  }
  bool hasProperty(std::string_view name) const { return findProperty(name) != nullptr; }

 protected:
  /// Registers memory to checkpoint (paper §5.3.1: critical(void* addr, int len)). The
  /// framework backs it up periodically at cycle boundaries and restores it on recovery.
  void critical(void* addr, std::size_t len);
  template <class T>
  void critical(T& value) {
    static_assert(std::is_trivially_copyable_v<T>, "critical(T&) needs a trivially copyable T");
    critical(static_cast<void*>(&value), sizeof(T));
  }
  /// Reports a fault this component noticed itself (kind `user`).
  void raiseFault(std::string_view why);
  /// Reports a fault of another kind this component detected, about itself or, when
  /// `fault.component` names one, about another component (monitors and voters do this).
  void reportFault(const FaultEvent& fault);
  /// Rejects a property value (from onInitialize): throws PropertyError "component '<instance>':
  /// property '<name>' <why>", which fails the load with that message.
  [[noreturn]] void rejectProperty(std::string_view name, std::string_view why) const;
  /// Ends the run, as the end of its duration would: `keel run` stops and destroys everything
  /// cleanly and exits 0. For a component that knows when the job is done (a mission referee).
  /// - Callable from any callback, onStop included (a run that ends for another reason, its
  ///   duration or a signal, still gets the record below); returns at once.
  /// - The first call of the run wins, from whichever component; later calls are ignored.
  /// - `summary` is printed by `keel run`: "ended by <instance>: <summary>".
  /// - With a non-empty `event`, once every component has stopped (their onStop ran) the fault
  ///   log's last record is {"t_ns":…, "event": event, "component": <instance>, <fields_json>},
  ///   where `fields_json` is the members of a JSON object without braces
  ///   (`"goal_reached":true,"collisions":0`). It is checked when the record is written; if it
  ///   is malformed the record has "fields_error" (why) instead of them. t_ns, event and
  ///   component are keel's: members of those names are dropped.
  /// Without a runtime (a component not run by keel) it does nothing.
  void endRun(std::string_view summary, std::string_view event = {}, std::string_view fields_json = {});

 private:
  friend struct detail::ComponentAccess;
  const PropertyValue* findProperty(std::string_view name) const;
  std::unique_ptr<detail::ComponentCore> core_;
};

}  // namespace keel
