// Local recoveries (paper §5.3.1–5.3.2): reset with the checkpointed critical memory restored,
// and replacement by the alternative — preloaded, or loaded now — and the last resort for a
// hung callback: abandoning its executor. Each runs on the component's own thread (between
// its callbacks, or holding a passive component's lock), except abandon(), which runs on the
// fault manager's thread because the component's own is lost. Each records its actions in the
// fault's report and says how it ended; what follows is the escalation decision's.
// Thread-safety: as stated per operation; ComponentHandling's fields under its mutex.
#pragma once

#include "fault/escalation.hpp"
#include "fault/recovery_actions.hpp"
#include "fault/report.hpp"
#include "keel/result.hpp"

namespace keel::fault {

class Recovery {
 public:
  void attach(RecoveryActions* actions) { actions_ = actions; }

  /// Whether a reset now is within the restart intensity (Outcome::Done) or not.
  Outcome intensityAt(ComponentHandling& h, std::int64_t now_ns) const;
  /// onError → onReset → checkpoint restored → onRecover → Active. Done, or Failed.
  Outcome reset(FaultReport& r, ComponentHandling& h);
  /// Loads, creates and initializes the alternative now (no preload): h.ready_alternative. Done, or
  /// Failed with the reason recorded.
  Outcome load(FaultReport& r, ComponentHandling& h);
  /// h.ready_alternative takes the role of r.accused, with its checkpoint: Done, or Failed (onStart).
  Outcome replace(FaultReport& r, ComponentHandling& h);
  /// r.accused's callback did not come back when interrupted: its executor is abandoned, the
  /// alternative (if any, loaded now if need be) takes its place on the new executor, else it
  /// stays stopped. Sets r.next. On the manager's thread.
  void abandon(FaultReport& r, ComponentHandling& h);

 private:
  void noteRecovery(ComponentHandling& h, std::int64_t t);
  static void markRecovering(const FaultReport& r, Component& c);

  RecoveryActions* actions_ = nullptr;
};

}  // namespace keel::fault
