// PathPlanner: the test robot's planner (paper Fig. 5): the colour blob from the detector and
// the obstacle information from the avoidance component in, a motion command out to the
// actuator each cycle (robot/navigation/navigator.hpp). It never commands motion without fresh
// obstacle information (§5.2). Its timing (ages of inputs, time in a mode) is measured between
// executions, whatever the task's period. Thread-safety: a component.
#pragma once

#include <array>
#include <chrono>
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
    c.cruise_rpm = static_cast<int>(property<std::int64_t>("cruise_rpm", c.cruise_rpm));
    c.turn_rpm = static_cast<int>(property<std::int64_t>("turn_rpm", c.turn_rpm));
    c.goal_height_px = property<double>("goal_height_px", c.goal_height_px);
    if (c.cruise_rpm <= 0) rejectProperty("cruise_rpm", "must be > 0");
    if (c.turn_rpm <= 0) rejectProperty("turn_rpm", "must be > 0");
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
    const auto now = std::chrono::steady_clock::now();
    const double dt = last_ ? std::chrono::duration<double>(now - *last_).count() : 0.0;
    last_ = now;
    const MotionCommand c = nav_.decide(dt);
    command.push({static_cast<double>(c.type), static_cast<double>(c.parameter)});
    return ReturnCode::Ok;
  }

  ReturnCode onReset() override {
    nav_ = Navigator(nav_.config());
    last_.reset();
    return ReturnCode::Ok;
  }

 private:
  Navigator nav_;
  std::optional<std::chrono::steady_clock::time_point> last_;  // the previous cycle
};

}  // namespace keel::robot
