// The fault manager's place in a plan (paper §3.2: "the fault manager is itself a component"):
// its fixed instance name, which profiles connect to, and the component profile the plan gives
// it. The component itself (fault/fault_manager_component.hpp) sits above; the plan only
// needs to know that it exists and what its port is.
// Thread-safety: constants; the profile is built once, on first use.
#pragma once

#include "profile/model.hpp"

namespace keel::plan {

inline constexpr const char* kFaultManagerInstance = "fault_manager";

/// The component profile of the fault manager (aperiodic; the input event port `faults`).
const profile::ComponentProfile& faultManagerProfile();

}  // namespace keel::plan
