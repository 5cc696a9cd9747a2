// The fault manager as a component (paper §3.2: "the fault manager is itself a component, a
// so-called system component"): instance `fault_manager`, with an input event port `faults`
// (keel::FaultEvent) that any component may connect an output event port to. Created by the
// engine when a profile connects to it; runs on its own aperiodic executor.
// Thread-safety: as any component; forwards to FaultManager::onFault.
#pragma once

#include "fault/fault_manager.hpp"
#include "keel/component.hpp"
#include "profile/model.hpp"

namespace keel::fault {

inline constexpr const char* kFaultManagerInstance = "fault_manager";

class FaultManagerComponent final : public Component {
 public:
  InputEventPort<FaultEvent> faults{this, "faults"};

  explicit FaultManagerComponent(FaultManager& manager) : manager_(manager) {}
  ReturnCode onEvent(InputEventPortBase& port) override;

  /// The component profile the plan uses for it (aperiodic; the `faults` port).
  static const profile::ComponentProfile& profile();

 private:
  FaultManager& manager_;
};

}  // namespace keel::fault
