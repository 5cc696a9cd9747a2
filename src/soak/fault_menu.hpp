// What `keel soak` may inject into an application (docs/soak.md): every fault that applies to
// one of its components and that one of its detectors is configured to see, read from its plan
// and from what its hardware drivers offer (keel::HardwareDriver::simulatedFaults), and a random
// fault scenario drawn from them, written as a fault_scenario file (docs/faults.md) so that keel
// run's process and the component processes inject exactly the same faults.
// Thread-safety: plain values and functions of their arguments.
#pragma once

#include <map>
#include <random>
#include <string>
#include <vector>

#include "plan/plan.hpp"

namespace keel::soak {

/// One fault the campaign may inject: a fault_scenario `<fault>` without its time.
struct Offer {
  std::string component;
  std::string kind;        // a scenario kind: segfault, ..., kill, or a hardware kind
  std::string args;        // hardware faults: the rest of the driver's command
  std::string port;        // out_of_range: the output data port
  double duration_ms = 0;  // stall_heartbeat: how long
  bool hardware = false;
};

/// The hardware faults each component's driver offers: instance name → commands.
using HardwareOffers = std::map<std::string, std::vector<std::string>>;

/// Every fault of `plan` a detector must see:
/// - a component that is executed (a member of a task or its own executor): segfault,
///   divide_by_zero, abort, throw, error_code;
/// - with a <heartbeat>: hang, and stall_heartbeat for three timeouts;
/// - a numeric output data port with a <validity> range, on it or on an input it feeds:
///   out_of_range (NaN);
/// - a component in a <process> of its own: kill;
/// - the hardware faults its driver offers.
/// The fault manager's own instance is not a target.
std::vector<Offer> faultMenu(const plan::Plan& plan, const HardwareOffers& hardware);

/// A fault_scenario whose faults start at `first_ms` and follow each other every `every_ms`
/// on average (uniform in [every/2, every*3/2]) until `length_ms`; each picks a kind at random
/// (every kind of the menu as likely), then an offer of that kind.
std::string randomScenario(const std::vector<Offer>& menu, std::mt19937_64& rng, double first_ms, double every_ms,
                           double length_ms);

}  // namespace keel::soak
