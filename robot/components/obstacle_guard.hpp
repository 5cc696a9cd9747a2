// ObstacleGuard: the test robot's last word before its wheels when something outside keel
// drives it (robot/ros2.xml: a ROS 2 node's /cmd_vel through TwistCommand). A motion command
// in, the obstacle-avoidance component's {distance_cm, blocked} in, the command to send out to
// the actuator each cycle: the requested one, except no forward motion while the way ahead is
// blocked, and no motion at all without fresh obstacle information (older than
// `stale_after_ms`) — the path planner's own rules (robot/navigation/navigator.hpp), kept when
// the planner is someone else's. Turns in place and backing off pass. Thread-safety: a component.
#pragma once

#include <array>
#include <chrono>
#include <cmath>
#include <optional>

#include <keel/component.hpp>

#include "robot/motion_board/protocol.hpp"

namespace keel::robot {

class ObstacleGuard : public Component {
 public:
  /// {motion_type, parameter}: what the driver asks for; the last one holds until the next.
  InputDataPort<std::array<double, 2>> requested{this, "requested"};
  /// {distance_cm, blocked} from obstacle avoidance.
  InputDataPort<std::array<double, 2>> obstacle{this, "obstacle"};
  /// {motion_type, parameter}: what the actuator sends, every cycle.
  OutputDataPort<std::array<double, 2>> command{this, "command"};

  ReturnCode onInitialize() override {
    stale_after_ = std::chrono::milliseconds(property<std::int64_t>("stale_after_ms", 500));
    if (stale_after_.count() <= 0) rejectProperty("stale_after_ms", "must be > 0");
    return ReturnCode::Ok;
  }

  ReturnCode onExecute() override {
    while (auto r = requested.pop()) requested_ = *r;
    const auto now = std::chrono::steady_clock::now();
    while (auto o = obstacle.pop()) {
      blocked_ = (*o)[1] != 0.0;
      obstacle_at_ = now;
    }
    const bool fresh = obstacle_at_ && now - *obstacle_at_ <= stale_after_;
    const bool forward = std::lround(requested_[0]) == static_cast<long>(MotionType::Forward);
    command.push(!fresh || (forward && blocked_) ? std::array<double, 2>{0.0, 0.0} : requested_);
    return ReturnCode::Ok;
  }

  ReturnCode onReset() override {
    requested_ = {0.0, 0.0};
    obstacle_at_.reset();
    return ReturnCode::Ok;
  }

 private:
  std::chrono::milliseconds stale_after_{500};
  std::array<double, 2> requested_{0.0, 0.0};  // Stop until asked
  bool blocked_ = true;
  std::optional<std::chrono::steady_clock::time_point> obstacle_at_;
};

}  // namespace keel::robot
