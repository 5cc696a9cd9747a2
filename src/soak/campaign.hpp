// keel soak's campaign (docs/soak.md): the application run again and again, each run (a round)
// with a random fault scenario of its own drawn from its fault menu (soak/fault_menu.hpp) and,
// now and then, an operator's emergency stop, until the soak's time is up. Each round is
// audited from the fault log as soon as it has ended (soak/log_audit.hpp), and what it started
// must be gone; the process's memory and descriptors, sampled between rounds, are compared with
// their level after the warm-up. The first round with a violation is the last.
// Thread-safety: runSoak runs the whole campaign on the calling thread.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "keel/result.hpp"
#include "soak/log_audit.hpp"
#include "soak/resources.hpp"

namespace keel::soak {

struct SoakOptions {
  std::string profile;
  double minutes = 10;
  double fault_every_ms = 500;
  std::uint64_t seed = 1;
  std::string log;                // the fault log of every round, appended; empty: a temporary file
  double warmup_s = 60;           // resources are compared with their level after this
  double round_s = 60;            // a round's longest run (it ends sooner when a component ends the run)
  std::vector<std::string> sets;  // keel run's --set, for every round
  std::string host_executable;    // keel-host for <process>es; empty: beside this program
};

/// The allowed growth of memory and descriptors after the warm-up.
inline constexpr double kMaxGrowth = 0.05;
/// The heap in use between runs is a few hundred KB that varies by tens of KB (buffers kept at
/// the capacity they reached): under ASan, where it is judged, growth counts beyond this too.
inline constexpr std::uint64_t kHeapSlackBytes = std::uint64_t{256} * 1024;

/// Where the campaign is, after each round and while one runs.
struct SoakProgress {
  int round = 0;
  double elapsed_s = 0;
  double total_s = 0;
  int armed = 0;    // faults injected so far (rounds audited)
  int handled = 0;  // ... of which detected, diagnosed and handled
  std::size_t violations = 0;
  Usage usage;
};

struct SoakResult {
  int rounds = 0;
  double seconds = 0;
  std::map<std::string, KindCounts> by_kind;
  int detected = 0;
  int emergencies = 0;
  int emergencies_reached = 0;
  int operator_emergencies = 0;  // pressed by the soak
  int collisions = 0;
  std::size_t lines = 0;
  Usage start;                    // after the first round
  std::optional<Usage> baseline;  // the first sample after the warm-up
  Usage last;
  std::vector<std::string> violations;
};

/// Runs the campaign. An error (a profile that does not load, a run that cannot start the first
/// time) is a failure; what goes wrong once it runs is a violation in the result.
Result<SoakResult> runSoak(const SoakOptions& options, const std::function<void(const SoakProgress&)>& progress);

}  // namespace keel::soak
