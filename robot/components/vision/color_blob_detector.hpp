// keel::robot::ColorBlobDetector: the test robot's object detector (paper Fig. 5). Segments
// the newest camera frame for the target's colour with a CMVision-style ColorSegmenter and
// sends the largest blob's size, bearing and height to the path planner. Header-only; the
// registration lives with the robot's component library. Contract: docs/robot_components.md.
// Thread-safety: a component; its callbacks are serialised.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <keel/component.hpp>

#include "robot/components/robot_types.hpp"
#include "robot/components/vision/color_segmenter.hpp"

namespace keel::robot {

class ColorBlobDetector : public Component {
 public:
  /// The red target of the paper arena (220, 30, 30) is YUV (87, 96, 223); floor, ceiling and
  /// grey walls sit at U, V ≈ 128. The box leaves more than 6 sigma of camera noise 10 around
  /// the target and more than 6 sigma between V 128 and v_min.
  static constexpr YuvBox kDefaultColour{30, 200, 60, 140, 170, 255};
  static constexpr int kDefaultMinArea = 4;
  static constexpr double kDefaultFovDeg = 60.0;
  static constexpr std::int64_t kMaxMinArea = 1 << 24;

  /// Camera frames (LAST, 1: only the newest matters).
  InputDataPort<Image> image{this, "image"};
  /// One reading per processed frame; {0, 0, 0} when no blob is found.
  OutputDataPort<BlobReading> blob{this, "blob"};

  /// Reads and checks the properties and builds the segmenter (the only allocation). A bad
  /// value throws keel::PropertyError naming the property, so the load fails with the reason.
  ReturnCode onInitialize() override {
    YuvBox c;
    c.y_min = channel("y_min", kDefaultColour.y_min);
    c.y_max = channel("y_max", kDefaultColour.y_max);
    c.u_min = channel("u_min", kDefaultColour.u_min);
    c.u_max = channel("u_max", kDefaultColour.u_max);
    c.v_min = channel("v_min", kDefaultColour.v_min);
    c.v_max = channel("v_max", kDefaultColour.v_max);
    ordered("y", c.y_min, c.y_max);
    ordered("u", c.u_min, c.u_max);
    ordered("v", c.v_min, c.v_max);
    const auto min_area = property<std::int64_t>("min_area", kDefaultMinArea);
    if (min_area < 1 || min_area > kMaxMinArea)
      rejectProperty("min_area", "must be between 1 and " + std::to_string(kMaxMinArea) + " (got " +
                                     std::to_string(min_area) + ")");
    fov_deg_ = property<double>("fov_deg", kDefaultFovDeg);
    if (!std::isfinite(fov_deg_) || fov_deg_ <= 0.0 || fov_deg_ >= 180.0)
      rejectProperty("fov_deg", "must be greater than 0 and less than 180 (got " + std::to_string(fov_deg_) + ")");
    segmenter_.emplace(c, static_cast<int>(min_area));
    return ReturnCode::Ok;
  }

  /// Processes the newest frame that arrived (older ones are skipped) and sends one reading.
  ReturnCode onExecute() override {
    std::optional<Image> newest;
    while (std::optional<Image> frame = image.pop()) newest = frame;
    if (newest) blob.push(detect(*newest));
    return ReturnCode::Ok;
  }

  /// The reading for one frame. A malformed frame (a negative size, more pixels than it holds) throws.
  [[nodiscard]] BlobReading detect(const Image& frame) {
    const std::span<const Region> regions = segmenter_->segment(frame);
    if (regions.empty()) return BlobReading{0.0, 0.0, 0.0};
    const Region& r = regions.front();
    return BlobReading{static_cast<double>(r.area), bearingDeg(r.cx, frame.w, fov_deg_),
                       static_cast<double>(r.height())};
  }

  /// Bearing in degrees, positive to the left, of image column coordinate `cx` (pixel c
  /// covers [c, c+1), as Region::cx) for a pinhole of horizontal field `fov_deg` over `width`
  /// columns: atan((w/2 − cx) / f), f = (w/2) / tan(fov/2) — the camera's own ray model.
  [[nodiscard]] static double bearingDeg(double cx, int width, double fov_deg) {
    constexpr double kDeg = 180.0 / std::numbers::pi;
    const double half = width / 2.0;
    const double focal = half / std::tan(fov_deg / kDeg / 2.0);
    return std::atan((half - cx) / focal) * kDeg;
  }

 private:
  int channel(std::string_view name, int fallback) const {
    const auto value = property<std::int64_t>(name, fallback);
    if (value < 0 || value > 255) rejectProperty(name, "must be between 0 and 255 (got " + std::to_string(value) + ")");
    return static_cast<int>(value);
  }

  void ordered(const std::string& axis, int lo, int hi) const {
    if (lo > hi)
      rejectProperty(axis + "_min",
                     "must not exceed " + axis + "_max (got " + std::to_string(lo) + " > " + std::to_string(hi) + ")");
  }

  double fov_deg_ = kDefaultFovDeg;
  std::optional<ColorSegmenter> segmenter_;  // built by onInitialize
};

}  // namespace keel::robot
