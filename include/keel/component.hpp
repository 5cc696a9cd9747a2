// keel::Component: the base class of every component (OPRoS's Component). An author derives
// from it, declares ports as members, overrides the callbacks it needs and registers the class
// with KEEL_REGISTER_COMPONENT. The runtime owns instances and calls the callbacks; all
// callbacks of one component are serialised (never two at once), so authors write no locks.
// Two abilities are opt-in, by adding a base: keel::HardwareDriver (keel/hardware_driver.hpp)
// to receive a fault scenario's hardware faults, keel::RunControl (keel/run_control.hpp) to
// end the run.
// Thread-safety: callbacks run on the component's executor; the protected services
// (critical, raiseFault, reportFault, property) may be called from any callback.
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

 private:
  friend struct detail::ComponentAccess;
  const PropertyValue* findProperty(std::string_view name) const;
  std::unique_ptr<detail::ComponentCore> core_;
};

}  // namespace keel
