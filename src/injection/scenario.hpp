// Fault scenarios (docs/faults.md): `<fault_scenario><fault at="1000" component="x" kind="segfault"
// .../></fault_scenario>`, read and checked whole, every problem as `file:line: message`.
// Attributes: at (ms after start), component, kind, and optionally port and value
// (out_of_range), duration (ms; stall_heartbeat, default: for ever), repeat and every (ms)
// to inject the same fault several times. Hardware faults (sensor_unplugged, sensor_stuck,
// sensor_ok, motor_power_off, motor_power_on, noise, encoder_dead, encoder_ok, gyro_dead,
// gyro_ok) take `args` and go to the named
// component's onHardwareFault as "kind args" (a keel::HardwareDriver: it drives that hardware).
// Thread-safety: plain values.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "keel/result.hpp"
#include "profile/loader.hpp"
#include "runtime/injection.hpp"

namespace keel::injection {

struct ScheduledFault {
  double at_ms = 0;
  std::string component;
  std::string kind_name;                                 // as written, for the log
  runtime::InjectKind kind = runtime::InjectKind::None;  // None for a hardware fault
  bool hardware = false;                                 // a hardware fault: sent to the component's onHardwareFault
  std::string args;                                      // hardware: its arguments ("left", "1 250")
  std::string port;                                      // out_of_range: the output port ("" = the first numeric one)
  double value = 0;                                      // out_of_range: the value pushed instead (default NaN)
  double duration_ms = 0;                                // stall_heartbeat: 0 = for ever
  int repeat = 1;
  double every_ms = 0;
  profile::Where where;

  /// What a hardware fault tells its component: "kind" or "kind args" ("motor_power_off left").
  std::string command() const { return args.empty() ? kind_name : kind_name + " " + args; }
};

/// Whether `kind` names a hardware fault.
bool isHardwareKind(std::string_view kind);

struct Scenario {
  std::string file;
  std::vector<ScheduledFault> faults;  // sorted by time
};

Result<Scenario, profile::Diagnostics> loadScenario(const std::string& path);

}  // namespace keel::injection
