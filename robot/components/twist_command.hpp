// TwistCommand: the test robot's ROS 2 teleoperation input (robot/ros2.xml). A ROS 2 node's
// velocity command (geometry_msgs/msg/Twist, on /cmd_vel through keel's <dds>) in, the motion
// board's command out: the board drives straight or turns in place (Table 3), so a Twist
// becomes the one of the two that asks more of the wheels (twistToMotion). Aperiodic: it runs
// when a Twist arrives and pushes one command per execution; what it pushed stays in effect
// until the next. A reset (the profile's handling of a `remote` fault: the node gone) pushes a
// stop. Thread-safety: a component.
#pragma once

#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include <keel/component.hpp>
#include <keel/msg/geometry_msgs/msg/twist.hpp>

#include "robot/motion_board/protocol.hpp"

namespace keel::robot {

/// The wheels and body that turn m/s and rad/s into the board's rpm (robot/motion_board/simulator.hpp).
struct DriveGeometry {
  double wheel_radius_m = 0.0325;
  double track_width_m = 0.140;
  double max_rpm = 300.0;
};

/// A Twist as the motion board's nearest command: forward or backward at the wheels' rpm for
/// `linear_mps`, or a turn in place whose rpm difference gives `angular_rps` — whichever needs
/// the faster wheel — clamped to max_rpm; below 1 rpm, or not finite, a stop.
[[nodiscard]] inline MotionCommand twistToMotion(double linear_mps, double angular_rps, const DriveGeometry& g) {
  if (!std::isfinite(linear_mps) || !std::isfinite(angular_rps)) return {};
  const double rpm_per_mps = 60.0 / (2.0 * std::numbers::pi * g.wheel_radius_m);
  const double straight = linear_mps * rpm_per_mps;                       // each wheel
  const double spin = angular_rps * g.track_width_m / 2.0 * rpm_per_mps;  // each wheel, ±
  const auto rpm = [&](double v) { return static_cast<std::int16_t>(std::lround(std::fmin(v, g.max_rpm))); };
  if (std::fabs(straight) >= std::fabs(spin) && std::fabs(straight) >= 1.0)
    return {straight > 0 ? MotionType::Forward : MotionType::Backward, rpm(std::fabs(straight))};
  if (std::fabs(spin) >= 0.5)  // the parameter of a turn is the right − left difference
    return {angular_rps > 0 ? MotionType::TurnLeft : MotionType::TurnRight, rpm(2.0 * std::fabs(spin))};
  return {};
}

class TwistCommand : public Component {
 public:
  InputDataPort<msg::geometry_msgs::Twist> cmd_vel{this, "cmd_vel"};
  /// {motion_type, parameter} of the protocol's motion frame.
  OutputDataPort<std::array<double, 2>> command{this, "command"};

  ReturnCode onInitialize() override {
    geometry_.wheel_radius_m = property<double>("wheel_radius_m", geometry_.wheel_radius_m);
    geometry_.track_width_m = property<double>("track_width_m", geometry_.track_width_m);
    geometry_.max_rpm = property<double>("max_rpm", geometry_.max_rpm);
    if (!(geometry_.wheel_radius_m > 0)) rejectProperty("wheel_radius_m", "must be > 0");
    if (!(geometry_.track_width_m > 0)) rejectProperty("track_width_m", "must be > 0");
    if (!(geometry_.max_rpm > 0)) rejectProperty("max_rpm", "must be > 0");
    return ReturnCode::Ok;
  }

  ReturnCode onExecute() override {
    std::optional<msg::geometry_msgs::Twist> newest;
    while (auto t = cmd_vel.pop()) newest = t;
    if (newest) push(twistToMotion(newest->linear.x, newest->angular.z, geometry_));
    return ReturnCode::Ok;
  }

  /// The velocity command zeroed: the robot stops, and stays stopped until a Twist arrives.
  ReturnCode onReset() override {
    while (cmd_vel.pop()) {}
    push(MotionCommand{});
    return ReturnCode::Ok;
  }

 private:
  void push(const MotionCommand& c) { command.push({static_cast<double>(c.type), static_cast<double>(c.parameter)}); }

  DriveGeometry geometry_;
};

}  // namespace keel::robot
