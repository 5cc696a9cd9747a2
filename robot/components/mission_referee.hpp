// MissionReferee: judges the test robot's mission from the simulation's ground truth, as an
// observer outside the robot (the paper's experimenter): the target reached (the robot at rest
// within `goal_radius_m` of it), or a safe stop (at rest elsewhere for `stopped_after_s` after
// having moved); collisions and the smallest clearance on the way. When the mission ends it ends
// the run with a `mission` record; at a shutdown for another reason it records how far it got.
// Optionally writes a trace (CSV, one row per execution) and the world (JSON) for the plots.
// Thread-safety: a component.
#pragma once

#include <cstdio>
#include <optional>
#include <string>

#include <keel/component.hpp>
#include <keel/run_control.hpp>

#include "robot/sim/sim_host.hpp"
#include "robot/sim/truth.hpp"

namespace keel::robot {

class MissionReferee : public Component, public RunControl {
 public:
  /// For the trace only (Fig. 6): measured and reference wheel rpm, latest values.
  InputDataPort<double> measured_left{this, "measured_left"};
  InputDataPort<double> measured_right{this, "measured_right"};
  InputDataPort<double> reference_left{this, "reference_left"};
  InputDataPort<double> reference_right{this, "reference_right"};

  ReturnCode onInitialize() override;
  ReturnCode onExecute() override;
  ReturnCode onStop() override;
  ReturnCode onDestroy() override;

 private:
  void finish(const char* how);
  void writeTrace(const TruthSample& t);
  void writeWorld(const std::string& path) const;

  std::optional<World> world_;
  std::optional<TruthReader> truth_;
  std::optional<TruthSample> last_;
  double goal_radius_m_ = 0.75;
  double settle_s_ = 0.5;
  double stopped_after_s_ = 3.0;
  double at_rest_since_s_ = -1.0;
  double first_t_s_ = -1.0;
  bool moved_ = false;
  bool finished_ = false;
  std::FILE* trace_ = nullptr;
  double signals_[4] = {0, 0, 0, 0};
};

}  // namespace keel::robot
