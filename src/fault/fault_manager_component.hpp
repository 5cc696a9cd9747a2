// The fault manager as a component (paper §3.2: "the fault manager is itself a component, a
// so-called system component"): instance `fault_manager`, with an input event port `faults`
// (keel::FaultEvent) that any component may connect an output event port to. Created by the
// engine when a profile connects to it; runs on its own aperiodic executor.
// Thread-safety: as any component; forwards to FaultManager::report.
#pragma once

#include "fault/fault_manager.hpp"
#include "keel/component.hpp"
#include "plan/fault_manager_profile.hpp"

namespace keel::fault {

using plan::kFaultManagerInstance;

class FaultManagerComponent final : public Component {
 public:
  InputEventPort<FaultEvent> faults{this, "faults"};

  explicit FaultManagerComponent(FaultManager& manager) : manager_(manager) {}
  ReturnCode onEvent(InputEventPortBase& port) override;

 private:
  FaultManager& manager_;
};

}  // namespace keel::fault
