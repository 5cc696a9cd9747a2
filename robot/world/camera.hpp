// The robot's camera (docs/robot_world.md): a pinhole looking along the robot's heading that
// renders a World as a small RGB image by casting one ray per column — boxes as grey walls
// shaded by distance, the target as a band of its colour, plain floor and ceiling, optional
// Gaussian pixel noise. Called by the vision-sensor component and tests.
// Deterministic given the seed; thread-safety: none (render() advances the noise generator).
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "robot/world/world.hpp"

namespace keel::robot {

/// Row-major RGB, 3 bytes per pixel, row 0 at the top.
struct Image {
  int w = 0;
  int h = 0;
  std::vector<std::uint8_t> rgb;

  [[nodiscard]] Rgb at(int x, int y) const;
  friend bool operator==(const Image&, const Image&) = default;
};

struct CameraConfig {
  int width = 80;
  int height = 60;
  double fov_rad = 1.0471975511965976;  // 60° horizontal
  double camera_height_m = 0.15;
  double wall_height_m = 0.5;  // every box
  double target_height_m = 0.3;
  double max_range_m = 10.0;
  double noise_sigma = 0.0;  // per channel, in 0..255 units; 0 = none
  std::uint64_t seed = 1;
  Rgb floor{90, 90, 80};
  Rgb ceiling{170, 170, 175};
};

class Camera {
 public:
  explicit Camera(CameraConfig config = {});

  /// What a camera at `pose` sees in `world`.
  [[nodiscard]] Image render(const World& world, const Pose& pose);

  [[nodiscard]] const CameraConfig& config() const { return config_; }

 private:
  [[nodiscard]] double focalPx() const;  // the pinhole's focal length in pixels
  void drawColumn(Image& image, int column, const RayHits& hits, double cos_offset, const Rgb& target_colour) const;
  void addNoise(Image& image);

  CameraConfig config_;
  std::mt19937_64 rng_;
};

}  // namespace keel::robot
