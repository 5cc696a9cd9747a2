// PathPlanner: the test robot's planner (paper Fig. 5): the colour blob from the detector and
// the obstacle information from the avoidance component in, a motion command out to the
// actuator each cycle (robot/navigation/navigator.hpp). It never commands motion without fresh
// obstacle information (§5.2). Thread-safety: a component.
#pragma once

#include <array>
#include <optional>

#include <keel/component.hpp>

#include "robot/components/robot_types.hpp"
#include "robot/navigation/navigator.hpp"

namespace keel::robot {

class PathPlanner : public Component {
 public:
  InputDataPort<BlobReading> blob{this, "blob"};
  InputDataPort<std::array<double, 2>> obstacle{this, "obstacle"};
  /// {motion_type, parameter} of the protocol's motion frame.
  OutputDataPort<std::array<double, 2>> command{this, "command"};

  ReturnCode onInitialize() override {
    NavigatorConfig c;
    c.cycle_s = property<double>("cycle_ms", 50.0) / 1000.0;
    c.cruise_rpm = static_cast<int>(property<std::int64_t>("cruise_rpm", c.cruise_rpm));
    c.turn_rpm = static_cast<int>(property<std::int64_t>("turn_rpm", c.turn_rpm));
    c.goal_height_px = property<double>("goal_height_px", c.goal_height_px);
    if (!(c.cycle_s > 0) || c.cruise_rpm <= 0 || c.turn_rpm <= 0)
      throw PropertyError("component '" + instanceName() + "': cycle_ms, cruise_rpm and turn_rpm must be > 0");
    nav_ = Navigator(c);
    return ReturnCode::Ok;
  }

  ReturnCode onExecute() override {
    std::optional<std::array<double, 2>> o;
    while (auto v = obstacle.pop()) o = v;
    if (o) nav_.onObstacle(ObstacleInfo{(*o)[0], (*o)[1] != 0.0});
    std::optional<BlobReading> b;
    while (auto v = blob.pop()) b = v;
    if (b) nav_.onBlob(BlobInfo{(*b)[kBlobPixels], (*b)[kBlobBearingDeg], (*b)[kBlobHeightPx]});
    const MotionCommand c = nav_.decide();
    command.push({static_cast<double>(c.type), static_cast<double>(c.parameter)});
    return ReturnCode::Ok;
  }

  ReturnCode onReset() override {
    nav_ = Navigator(nav_.config());
    return ReturnCode::Ok;
  }

 private:
  Navigator nav_;
};

}  // namespace keel::robot
