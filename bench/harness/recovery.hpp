// keel's recovery latency (recovered − detected) per handling mechanism, on the real engine:
// one victim component on a 1 ms periodic task, with the fault policy of the mechanism measured
// (packages in share/keel/bench/profiles). Each trial injects a segfault into the victim's next
// onExecute (runtime::arm), waits for the fault manager's Handling of that fault to carry a
// `recovered` time, and goes on after a few normal cycles.
//   reset              one engine; the victim is reset in place, trial after trial
//   replace_preloaded  a fresh engine per trial (a role is replaced once); the alternative was
//                      created at start
//   replace_cold       a fresh engine per trial; the alternative's library (used by nothing
//                      else) is dlopened at fault time — checked before every fault
//   reset_hang         one engine; a hung onExecute is found by the watchdog (20 ms heartbeat)
//                      and interrupted by a signal, then reset (detected → recovered)
// `recovered` is the end of the first good onExecute after the recovery. For the replacements
// the log also gives "in place": detected → the `replace` action (the alternative Active in the
// failed one's executor slot).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "paths.hpp"

namespace keel::bench {

struct RecoveryCell {
  std::vector<std::int64_t> latencies_ns;  // recovered − detected, one per recovered fault
  std::vector<std::int64_t> in_place_ns;   // replacements: detected → the `replace` action
  std::vector<std::int64_t> to_client_ns;  // _monitored: detected → a monitor client has the record
  std::size_t failed = 0;                  // trials without a `recovered` within the bound
  std::size_t unexpected = 0;              // trials whose actions were not the mechanism's
  std::size_t already_mapped = 0;          // replace_cold: the library was mapped before the fault
  std::string error;                       // non-empty: the cell could not run (profile, engine)
  std::string warnings;                    // the engine's warnings (e.g. a policy it could not set)
};

/// `n` faults of `mechanism` under SCHED_FIFO 50 (`fifo`) or SCHED_OTHER; the fault log goes
/// to `log_path` (rewritten by each fresh engine).
RecoveryCell measureRecovery(const Paths& paths, const std::string& mechanism, bool fifo, int n,
                             const std::string& log_path);

}  // namespace keel::bench
