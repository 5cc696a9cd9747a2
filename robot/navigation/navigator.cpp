// The path planner's state machine; see navigator.hpp. Modes:
//   Search  no target in view: turn left in place until it shows
//   Track   steer toward the target (turn in place when off-axis, else forward)
//   Avoid   the way ahead is blocked: turn in place to the chosen side until it clears
//   Clear   keep turning a little, so the body clears what the beam just left
//   Detour  drive forward past the obstacle, then Track (or Search)
//   Goal    blocked by the target itself: stop for good
//   Halted  obstacle information is stale (obstacle detection stopped): stop until it returns
#include "robot/navigation/navigator.hpp"

#include <algorithm>
#include <cmath>

namespace keel::robot {
namespace {

MotionCommand command(MotionType type, double rpm) {
  return MotionCommand{type, static_cast<std::int16_t>(std::lround(rpm))};
}

}  // namespace

const char* toString(Navigator::Mode mode) {
  switch (mode) {
    case Navigator::Mode::Search: return "search";
    case Navigator::Mode::Track: return "track";
    case Navigator::Mode::Avoid: return "avoid";
    case Navigator::Mode::Clear: return "clear";
    case Navigator::Mode::Detour: return "detour";
    case Navigator::Mode::Goal: return "goal";
    case Navigator::Mode::Halted: return "halted";
  }
  return "?";
}

void Navigator::onObstacle(const ObstacleInfo& info) {
  obstacle_ = info;
  obstacle_age_s_ = 0.0;
}

void Navigator::onBlob(const BlobInfo& blob) {
  blob_ = blob;
  blob_age_s_ = 0.0;
}

bool Navigator::targetVisible() const {
  return blob_age_s_ <= config_.lost_after_s && blob_.pixels >= config_.min_blob_px;
}

bool Navigator::atGoal() const {
  return targetVisible() && blob_.height_px >= config_.goal_height_px &&
         std::fabs(blob_.bearing_deg) <= config_.goal_bearing_deg;
}

MotionCommand Navigator::track() const {
  const double b = blob_.bearing_deg;
  if (std::fabs(b) <= config_.aligned_deg) return command(MotionType::Forward, config_.cruise_rpm);
  const double diff = std::clamp(config_.steer_gain * std::fabs(b), static_cast<double>(config_.min_steer_rpm),
                                 static_cast<double>(config_.turn_rpm));
  return command(b > 0 ? MotionType::TurnLeft : MotionType::TurnRight, diff);
}

MotionCommand Navigator::search() const { return command(MotionType::TurnLeft, config_.turn_rpm * 0.75); }

MotionCommand Navigator::turnAway() const {
  return command(avoid_left_ ? MotionType::TurnLeft : MotionType::TurnRight, config_.turn_rpm);
}

MotionCommand Navigator::decide(double dt) {
  obstacle_age_s_ += dt;
  blob_age_s_ += dt;
  mode_time_s_ += dt;
  const auto enter = [this](Mode m) {
    if (m != mode_) mode_time_s_ = 0.0;
    mode_ = m;
  };
  if (mode_ == Mode::Goal) return command(MotionType::Stop, 0);
  // Ages were just advanced past the last input: stale means more than one cycle beyond.
  if (obstacle_age_s_ > config_.stale_after_s + dt) {
    enter(Mode::Halted);
    return command(MotionType::Stop, 0);
  }
  if (mode_ == Mode::Halted) enter(Mode::Search);
  const bool blocked = obstacle_.blocked;
  switch (mode_) {
    case Mode::Search:
      if (!targetVisible()) return search();
      enter(Mode::Track);
      [[fallthrough]];
    case Mode::Track:
      if (blocked) {
        if (atGoal()) {
          enter(Mode::Goal);
          return command(MotionType::Stop, 0);
        }
        // Pass on the side the target is on; straight ahead, to the right.
        avoid_left_ = targetVisible() && blob_.bearing_deg > config_.aligned_deg;
        enter(Mode::Avoid);
        return turnAway();
      }
      if (!targetVisible()) {
        enter(Mode::Search);
        return search();
      }
      return track();
    case Mode::Avoid:
      if (!blocked) enter(Mode::Clear);
      return turnAway();
    case Mode::Clear:
    case Mode::Detour:
      if (blocked) {
        enter(Mode::Avoid);
        return turnAway();
      }
      if (mode_ == Mode::Clear) {
        if (mode_time_s_ < config_.extra_turn_s) return turnAway();
        enter(Mode::Detour);
      } else if (mode_time_s_ >= config_.detour_s) {
        enter(targetVisible() ? Mode::Track : Mode::Search);
        return targetVisible() ? track() : search();
      }
      return command(MotionType::Forward, config_.cruise_rpm);
    case Mode::Goal:
    case Mode::Halted: break;
  }
  return command(MotionType::Stop, 0);
}

}  // namespace keel::robot
