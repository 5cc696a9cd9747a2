// The obstacle-avoidance components of the test robot (paper Fig. 5, §5.3): the range ahead (the
// voter's median) in, {distance_cm, blocked} out to the path planner. ObstacleAvoidance, the
// primary algorithm, is stateful — its filter state is critical memory, checkpointed by the
// framework and restored on a reset (§5.3.1). ObstacleAvoidanceSecondary is the simpler backup
// that replaces it when it cannot be recovered (§5.3.2); same ports. Thread-safety: components.
#pragma once

#include <array>
#include <optional>

#include <keel/component.hpp>

#include "robot/navigation/obstacle_filter.hpp"

namespace keel::robot {

template <class Filter>
class ObstacleAvoidanceBase : public Component {
 public:
  InputDataPort<double> range{this, "range"};
  OutputDataPort<std::array<double, 2>> obstacle{this, "obstacle"};

  ReturnCode onInitialize() override {
    ObstacleFilterConfig c;
    c.block_cm = property<double>("block_cm", c.block_cm);
    c.clear_cm = property<double>("clear_cm", c.clear_cm);
    if (!(c.block_cm > 0)) rejectProperty("block_cm", "must be > 0");
    if (!(c.clear_cm >= c.block_cm)) rejectProperty("clear_cm", "must be at least block_cm");
    filter_ = Filter(c);
    return ReturnCode::Ok;
  }

  /// Every range that arrived is filtered; the newest result goes to the planner.
  ReturnCode onExecute() override {
    std::optional<ObstacleInfo> info;
    while (std::optional<double> r = range.pop()) info = filter_.update(*r);
    if (info) obstacle.push({info->distance_cm, info->blocked ? 1.0 : 0.0});
    return ReturnCode::Ok;
  }

 protected:
  Filter filter_;
};

class ObstacleAvoidance : public ObstacleAvoidanceBase<PrimaryObstacleFilter> {
 public:
  ObstacleAvoidance() { critical(filter_.state()); }
  /// The state is cleared here; the framework then restores it from the last checkpoint.
  ReturnCode onReset() override {
    filter_.state() = PrimaryObstacleFilter::State{};
    return ReturnCode::Ok;
  }
};

class ObstacleAvoidanceSecondary : public ObstacleAvoidanceBase<SecondaryObstacleFilter> {};

}  // namespace keel::robot
