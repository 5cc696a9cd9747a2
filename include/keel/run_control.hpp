// keel::RunControl: what a component that knows when the job is done (a mission referee) adds
// to its bases to end the run, as the end of its duration would: `keel run` stops and
// destroys everything cleanly and exits 0. Opt-in, so that ending a run is visible in the
// class's declaration.
//
//   class MissionReferee : public keel::Component, public keel::RunControl { ... };
//   ...   endRun("goal reached", "mission", R"("goal_reached":true,"collisions":0)");
//
// Thread-safety: endRun may be called from any callback of the component, onStop included.
#pragma once

#include <string_view>

namespace keel {

class RunControl {
 public:
  virtual ~RunControl() = default;

 protected:
  /// Ends the run.
  /// - Callable from any callback, onStop included (a run that ends for another reason, its
  ///   duration or a signal, still gets the record below); returns at once.
  /// - The first call of the run wins, from whichever component; later calls are ignored.
  /// - `summary` is printed by `keel run`: "ended by <instance>: <summary>".
  /// - With a non-empty `event`, once every component has stopped (their onStop ran) the fault
  ///   log's last record is {"t_ns":…, "event": event, "component": <instance>, <fields_json>},
  ///   where `fields_json` is the members of a JSON object without braces
  ///   (`"goal_reached":true,"collisions":0`). It is checked when the record is written; if it
  ///   is malformed the record has "fields_error" (why) instead of them. t_ns, event and
  ///   component are keel's: members of those names are dropped.
  /// Without a runtime (a component not run by keel), or in a class that is not a
  /// keel::Component, it does nothing.
  void endRun(std::string_view summary, std::string_view event = {}, std::string_view fields_json = {});
};

}  // namespace keel
