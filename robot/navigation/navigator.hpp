// The path planner's decisions (paper Fig. 5): follow the coloured target seen by the camera,
// go around what the obstacle-avoidance component reports ahead, stop at the target — and never
// move without fresh obstacle information (paper §5.2: "the navigation components do not command
// movement when the obstacle detection application is faulty/stopped"). One decision per
// planner cycle, as a motion-board command. Pure logic: the PathPlanner component feeds it.
// Thread-safety: none; one owner.
#pragma once

#include <cstdint>
#include <optional>

#include "robot/motion_board/protocol.hpp"

namespace keel::robot {

struct NavigatorConfig {
  int cruise_rpm = 120;          // forward speed
  int turn_rpm = 80;             // rpm difference when turning in place to avoid or search
  int min_steer_rpm = 30;        // smallest rpm difference when steering toward the target
  double steer_gain = 4.0;       // rpm difference per degree of bearing
  double aligned_deg = 6.0;      // drive forward when the target is within this bearing
  double min_blob_px = 4.0;      // smaller blobs are noise
  double goal_height_px = 30.0;  // the target this tall and centred, and blocked: arrived
  double goal_bearing_deg = 15.0;
  double extra_turn_s = 0.20;  // keep turning this long once the way ahead is clear
  double detour_s = 1.5;       // then drive forward this long
  double lost_after_s = 0.5;   // no target this long: search
  double stale_after_s = 0.5;  // obstacle information older than this: halt
};

/// What the obstacle-avoidance component reports: the filtered range ahead and whether the way
/// is blocked (with its own hysteresis).
struct ObstacleInfo {
  double distance_cm = 0.0;
  bool blocked = false;
};

/// What the colour-blob detector found (robot_types.hpp BlobReading, unpacked).
struct BlobInfo {
  double pixels = 0.0;
  double bearing_deg = 0.0;
  double height_px = 0.0;
};

class Navigator {
 public:
  enum class Mode : std::uint8_t { Search, Track, Avoid, Clear, Detour, Goal, Halted };

  explicit Navigator(NavigatorConfig config = {}) : config_(config) {}

  /// Inputs that arrived since the last cycle (nullopt: none arrived).
  void onObstacle(const ObstacleInfo& info);
  void onBlob(const BlobInfo& blob);
  /// One planner cycle, `dt_s` after the previous one: the command to send.
  [[nodiscard]] MotionCommand decide(double dt_s);

  [[nodiscard]] Mode mode() const { return mode_; }
  [[nodiscard]] const NavigatorConfig& config() const { return config_; }

 private:
  [[nodiscard]] bool targetVisible() const;
  [[nodiscard]] bool atGoal() const;
  MotionCommand track() const;
  MotionCommand turnAway() const;
  MotionCommand search() const;  // turn left in place, slower than when avoiding

  NavigatorConfig config_;
  Mode mode_ = Mode::Search;
  ObstacleInfo obstacle_{};
  BlobInfo blob_{};
  double obstacle_age_s_ = 1e9;
  double blob_age_s_ = 1e9;
  double mode_time_s_ = 0.0;  // time in the current mode
  bool avoid_left_ = false;   // side chosen for the current avoidance
};

[[nodiscard]] const char* toString(Navigator::Mode mode);

}  // namespace keel::robot
