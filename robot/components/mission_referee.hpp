// MissionReferee: judges the test robot's mission from the simulation's ground truth, as an
// observer outside the robot (the paper's experimenter): the target reached (the robot at rest
// within `goal_radius_m` of it), or a safe stop (at rest elsewhere for `stopped_after_s` after
// having moved); collisions and the smallest clearance on the way. When the mission ends it ends
// the run with a `mission` record; at a shutdown for another reason it records how far it got.
// It publishes the ground truth on its `truth` port and the world on its `world` port, so a
// recording holds the trajectory (keel report --plots); optionally it writes them as a trace (CSV,
// one row per execution) and the world (JSON) too.
// Thread-safety: a component.
#pragma once

#include <array>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <string>

#include <keel/component.hpp>
#include <keel/run_control.hpp>

#include "robot/sim/sim_host.hpp"
#include "robot/sim/truth.hpp"

namespace keel::robot {

/// The `truth` port's values: t_s, x_m, y_m, heading_rad, rpm_left, rpm_right, clearance_m,
/// collisions (robot/sim/truth.hpp's TruthSample, simulated time).
inline constexpr std::size_t kTruthValues = 8;
/// The `world` port carries this many boxes at most (a larger world is a bad `world` property).
inline constexpr std::size_t kWorldBoxes = 12;
/// The `world` port's values: the target's x, y, radius; the start's x, y, heading; then each box
/// as min_x, min_y, max_x, max_y, NaN past the last one.
inline constexpr std::size_t kWorldValues = 6 + 4 * kWorldBoxes;

class MissionReferee : public Component, public RunControl {
 public:
  /// The ground truth, each execution that reads a new sample: a recording's trajectory.
  OutputDataPort<std::array<double, kTruthValues>> truth{this, "truth"};
  /// The world, at the first execution (a late monitor client gets the newest value).
  OutputDataPort<std::array<double, kWorldValues>> world{this, "world"};
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
  [[nodiscard]] std::array<double, kWorldValues> worldValues() const;

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
  bool world_sent_ = false;
  std::FILE* trace_ = nullptr;
  double signals_[4] = {0, 0, 0, 0};
};

}  // namespace keel::robot
