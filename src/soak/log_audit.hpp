// The soak's audit of one round of the fault log (docs/soak.md): every line whole JSON, the
// run's own records present, every injected fault that manifested detected, diagnosed and
// handled, every detected fault diagnosed and handled, every emergency stop reached, and no
// collision reported (the robot's referee reports them) in a round where keel stopped nothing.
// What it finds wrong is a violation, named with the line it concerns.
// Thread-safety: plain values and functions of their arguments.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace keel::soak {

/// What became of the faults of one kind.
struct KindCounts {
  int armed = 0;           // injected by the scenario (hardware faults: sent to their driver)
  int handled = 0;         // manifested, then detected, diagnosed and acted upon
  int not_manifested = 0;  // armed, but its component never ran again in that round (stopped,
                           // replaced, its process still being replaced, the round over)
  int overtaken = 0;       // manifested, but before a detector could see it its component was
                           // stopped (another fault's handling, an emergency) or the round ended
};

/// An injected fault that manifested this close to the round's end may still be undetected:
/// a hang is seen a heartbeat timeout later.
inline constexpr std::int64_t kGraceNs = 1'000'000'000;

struct RoundAudit {
  std::map<std::string, KindCounts> by_kind;
  std::size_t lines = 0;
  int detected = 0;                       // faults detected, injected or not
  int emergencies = 0;                    // emergency latches
  int emergencies_reached = 0;            // ... whose emergency_stop action ran in every component
  int stops = 0;                          // stop and emergency_stop actions: keel reporting the robot unsafe
  std::optional<int> collisions;          // from a component's end-of-run record, if it reports them
  std::optional<std::string> neutral_by;  // the robot: what held the motors first (command, deadman)
  std::vector<std::string> violations;
};

/// Audits `text`, the lines one run wrote (from its engine `load` record on); `first_line` is
/// the number of its first line in the whole log, for the violations' messages.
RoundAudit auditRound(std::string_view text, std::size_t first_line);

}  // namespace keel::soak
