// Convenience header: everything a component author uses.
#pragma once

#include "keel/component.hpp"
#include "keel/fault_event.hpp"
#include "keel/hardware_driver.hpp"
#include "keel/run_control.hpp"
