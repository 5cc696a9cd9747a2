// The simulated robot's 2-D world (docs/robot_world.md): axis-aligned boxes (walls, obstacles),
// one circular coloured target and a start pose, in metres and radians (the Pose frame of the
// motion board). Answers exact ray casts (for the sonars and the camera), body collisions and
// clearances. Called by the simulator's sonar callback, the Camera and tests.
// Thread-safety: immutable after construction; const calls are safe from any thread.
#pragma once

#include <cstdint>
#include <vector>

#include "robot/motion_board/simulator.hpp"

namespace keel::robot {

/// The robot body's footprint (210 × 140 mm), the default for collides() and clearance().
inline constexpr double kBodyLengthM = 0.210;
inline constexpr double kBodyWidthM = 0.140;

/// An axis-aligned rectangle: a wall or an obstacle. min < max on both axes.
struct Box {
  double min_x = 0.0;
  double min_y = 0.0;
  double max_x = 0.0;
  double max_y = 0.0;
};

struct Rgb {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

/// The coloured target the robot follows: a disc in plan (a cylinder to the camera).
struct Target {
  double x_m = 0.0;
  double y_m = 0.0;
  double radius_m = 0.1;
  Rgb colour{220, 30, 30};
};

/// Distances along one ray to the first box and to the target, each capped at the ray's max.
struct RayHits {
  double box_m = 0.0;
  double target_m = 0.0;
  [[nodiscard]] double nearest() const { return box_m < target_m ? box_m : target_m; }
};

class World {
 public:
  World(std::vector<Box> boxes, Target target, Pose start);

  /// A 4 m × 3 m room (interior 0..4 × 0..3), three obstacles, a red target; see the doc.
  static World paperArena();

  /// Distance from (x, y) along heading to the first box edge or the target, at most max_m;
  /// 0 when (x, y) is inside one.
  [[nodiscard]] double rayCast(double x_m, double y_m, double heading_rad, double max_m) const;
  /// Both distances separately (the camera draws a wall behind the target).
  [[nodiscard]] RayHits castRay(double x_m, double y_m, double heading_rad, double max_m) const;

  /// Whether a body centred at (x, y), its length along heading, overlaps any box.
  [[nodiscard]] bool collides(double x_m, double y_m, double heading_rad, double length_m = kBodyLengthM,
                              double width_m = kBodyWidthM) const;
  /// Smallest distance from that body to any box; 0 when it overlaps one.
  [[nodiscard]] double clearance(double x_m, double y_m, double heading_rad, double length_m = kBodyLengthM,
                                 double width_m = kBodyWidthM) const;

  [[nodiscard]] const std::vector<Box>& boxes() const { return boxes_; }
  [[nodiscard]] const Target& target() const { return target_; }
  [[nodiscard]] const Pose& start() const { return start_; }

 private:
  std::vector<Box> boxes_;
  Target target_;
  Pose start_;
};

/// The simulator's sonar callback over a copy of `world`: range in cm, kFreeSpaceCm if nothing
/// lies within kMaxRangeCm.
RayCast sonarRayCast(const World& world);

}  // namespace keel::robot
