// keel's adapter of a component written for OPRoS: a keel component that owns one OPRoS Component
// object (made by its library's getComponent(), released by its releaseComponent()), gives each
// port the object registered with addPort a keel port of the same name, kind and type, and
// calls the object's OPRoS callbacks from its own keel callbacks. Everything keel does to a
// component — the guard, range checks, heartbeat, checkpoints, reset, replacement, fault stop,
// emergency stop, process isolation — thereby applies to the OPRoS component unchanged.
//
// The mapping (docs/opros.md): OPROS_SUCCESS (and OPROS_SUCCESS_SYNC) is keel's Ok; any other
// code is a keel ReturnCode carrying the same number, so a failing callback is a fault as in
// keel. getStatus() follows keel's state. Properties reach the object as text before its
// onInitialize; memory it registers with critical() is checkpointed.
// Thread-safety: as any keel component: the runtime calls one callback at a time.
#pragma once

#include <Component.h>

#include <vector>

#include "keel/component.hpp"

namespace keel::opros {

using Release = void (*)(::Component*);

class Adapter final : public keel::Component {
 public:
  /// Takes ownership of `object`, released with `release` (or deleted when null).
  Adapter(::Component* object, Release release);
  ~Adapter() override;
  Adapter(const Adapter&) = delete;
  Adapter& operator=(const Adapter&) = delete;

  ::Component& object() { return *object_; }

  ReturnCode onInitialize() override;
  ReturnCode onStart() override;
  ReturnCode onStop() override;
  ReturnCode onDestroy() override;
  ReturnCode onExecute() override;
  ReturnCode onUpdated() override;
  ReturnCode onEvent(InputEventPortBase& port) override;
  ReturnCode onError() override;
  ReturnCode onReset() override;
  ReturnCode onRecover() override;

 private:
  ReturnCode after(ReturnType r, LifecycleState on_success);

  ::Component* object_;
  Release release_;
  std::vector<std::pair<const detail::PortBase*, ::Port*>> event_inputs_;
};

}  // namespace keel::opros
