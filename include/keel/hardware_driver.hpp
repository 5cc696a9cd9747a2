// keel::HardwareDriver: what a component that drives hardware adds to its bases to receive a
// fault scenario's hardware faults (`keel run --inject`): how a hardware-in-the-loop or
// simulated driver gets the harness's faults and forwards them to its board. Opt-in: a
// component without it never receives them, and the injection's outcome says so.
//
//   class ActuatorControl : public keel::Component, public keel::HardwareDriver {
//     keel::ReturnCode onHardwareFault(std::string_view command) override;
//   };
//
// Thread-safety: onHardwareFault runs on the injector's thread, concurrently with the
// component's callbacks and whatever its state: it must be thread-safe, and return soon.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "keel/return_code.hpp"

namespace keel {

class HardwareDriver {
 public:
  virtual ~HardwareDriver() = default;
  /// A hardware fault at its time in the scenario. `command` is the kind, then a space and
  /// the scenario's `args` if any: "motor_power_off left", "sensor_stuck 1 250", "noise".
  /// Return Ok when the fault was applied; anything else, or an exception, is logged as the
  /// injection's outcome, with a warning.
  virtual ReturnCode onHardwareFault(std::string_view command) = 0;
  /// The hardware faults this driver can simulate, each a command onHardwareFault takes: what
  /// `keel soak` picks from at random. Offer only faults the application is meant to tolerate
  /// or stop safely from, one at a time. Default: none.
  virtual std::vector<std::string> simulatedFaults() const { return {}; }
};

}  // namespace keel
