// Column ray casting: column c looks at atan((w/2 - (c + 0.5)) / f) off the heading, f the focal
// length in pixels; an object of height H at perpendicular depth z spans the rows between
// h/2 - f (H - camera height) / z and h/2 + f camera height / z. Walls are painted first, then
// the target when it is nearer than the wall behind it.
#include "robot/world/camera.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

namespace keel::robot {
namespace {

void put(Image& image, int x, int y, const Rgb& c) {
  const std::size_t i = 3 *
                        (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.w) + static_cast<std::size_t>(x));
  image.rgb[i] = c.r;
  image.rgb[i + 1] = c.g;
  image.rgb[i + 2] = c.b;
}

/// Grey level of a wall at distance d: 220 up close, fading towards 60 far away.
Rgb wallShade(double d_m) {
  const auto level = static_cast<std::uint8_t>(std::lround(60.0 + 160.0 / (1.0 + 0.5 * d_m)));
  return Rgb{level, level, level};
}

}  // namespace

bool operator==(const Image& a, const Image& b) {
  return a.w == b.w && a.h == b.h && std::ranges::equal(a.pixels(), b.pixels());
}

Rgb Image::at(int x, int y) const {
  assert(x >= 0 && x < w && y >= 0 && y < h);
  const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x));
  return Rgb{rgb[i], rgb[i + 1], rgb[i + 2]};
}

Camera::Camera(CameraConfig config) : config_(config), rng_(config.seed) {
  assert(config_.width > 0 && config_.height > 0);
  // Checked in every build: a larger frame would be drawn past an Image's buffer.
  if (static_cast<std::int64_t>(config_.width) * config_.height > Image::kMaxPixels)
    throw std::invalid_argument("Camera: " + std::to_string(config_.width) + " x " + std::to_string(config_.height) +
                                " pixels exceed an Image's " + std::to_string(Image::kMaxPixels));
  assert(config_.fov_rad > 0.0 && config_.fov_rad < 3.0);
}

double Camera::focalPx() const { return (config_.width / 2.0) / std::tan(config_.fov_rad / 2.0); }

Image Camera::render(const World& world, const Pose& pose) {
  Image image{config_.width, config_.height, {}};
  const double focal = focalPx();
  for (int column = 0; column < config_.width; ++column) {
    const double offset = std::atan((config_.width / 2.0 - (column + 0.5)) / focal);
    const RayHits hits = world.castRay(pose.x_m, pose.y_m, pose.heading_rad + offset, config_.max_range_m);
    drawColumn(image, column, hits, std::cos(offset), world.target().colour);
  }
  if (config_.noise_sigma > 0.0) addNoise(image);
  return image;
}

void Camera::drawColumn(Image& image, int column, const RayHits& hits, double cos_offset,
                        const Rgb& target_colour) const {
  const double focal = focalPx();
  const double horizon = config_.height / 2.0;
  const auto paint = [&](double distance_m, double height_m, const Rgb& colour) {
    const double depth = std::max(distance_m * cos_offset, 1e-3);
    const double top = horizon - focal * (height_m - config_.camera_height_m) / depth;
    const double bottom = horizon + focal * config_.camera_height_m / depth;
    for (int row = 0; row < config_.height; ++row) {
      const double centre = row + 0.5;
      if (centre >= top && centre < bottom) put(image, column, row, colour);
    }
  };
  for (int row = 0; row < config_.height; ++row) {
    put(image, column, row, row + 0.5 < horizon ? config_.ceiling : config_.floor);
  }
  if (hits.box_m < config_.max_range_m) {
    paint(hits.box_m, config_.wall_height_m, wallShade(hits.box_m));
  }
  if (hits.target_m < hits.box_m && hits.target_m < config_.max_range_m) {
    paint(hits.target_m, config_.target_height_m, target_colour);
  }
}

void Camera::addNoise(Image& image) {
  std::normal_distribution<double> noise(0.0, config_.noise_sigma);
  for (std::uint8_t& channel : image.pixels()) {
    const double value = std::round(channel + noise(rng_));
    channel = static_cast<std::uint8_t>(std::clamp(value, 0.0, 255.0));
  }
}

}  // namespace keel::robot
