// The robot's camera (docs/robot_world.md): a pinhole looking along the robot's heading that
// renders a World as a small RGB image by casting one ray per column — boxes as grey walls
// shaded by distance, the target as a band of its colour, plain floor and ceiling, optional
// Gaussian pixel noise. Called by the vision-sensor component and tests.
// Deterministic given the seed; thread-safety: none (render() advances the noise generator).
#pragma once

#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <random>
#include <span>
#include <type_traits>

#include "robot/world/world.hpp"

namespace keel::robot {

/// Row-major RGB, 3 bytes per pixel, row 0 at the top, in a buffer of fixed capacity: a frame is
/// trivially copyable, so it crosses processes as bytes (the robot's detector runs in a process of
/// its own, docs/isolation.md). The first 3 × w × h bytes of `rgb` are the pixels.
struct Image {
  static constexpr int kMaxPixels = 80 * 60;  // the robot camera's resolution (CameraConfig)

  int w = 0;
  int h = 0;
  std::array<std::uint8_t, 3 * kMaxPixels> rgb{};

  /// Whether w × h pixels, neither negative, fit the buffer.
  [[nodiscard]] bool fits() const { return w >= 0 && h >= 0 && static_cast<std::int64_t>(w) * h <= kMaxPixels; }
  /// The 3 × w × h bytes of the pixels (fits() required).
  [[nodiscard]] std::span<const std::uint8_t> pixels() const { return {rgb.data(), byteCount()}; }
  [[nodiscard]] std::span<std::uint8_t> pixels() { return {rgb.data(), byteCount()}; }
  [[nodiscard]] Rgb at(int x, int y) const;
  /// Same size and same pixels (the bytes past them do not count).
  friend bool operator==(const Image& a, const Image& b);

 private:
  [[nodiscard]] std::size_t byteCount() const {
    assert(fits());
    return 3 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  }
};
static_assert(std::is_trivially_copyable_v<Image>, "a frame crosses processes as bytes");

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
