// The data types the test robot's components exchange on their ports, and the names profiles
// give them (`data_type`). Included by every robot component; plain values.
#pragma once

#include <array>

#include <keel/type_name.hpp>

#include "robot/world/camera.hpp"

/// A camera frame (robot/world/camera.hpp): 80 × 60 RGB by default, in a fixed buffer (it crosses
/// to the detector's process as bytes).
KEEL_TYPE_NAME(keel::robot::Image, "robot::Image");

namespace keel::robot {

/// What the colour-blob detector found in one frame, by index:
/// [0] pixels of the largest blob of the target colour (0: no blob),
/// [1] bearing of its centroid in degrees, positive to the left of the optical axis,
/// [2] its height in pixels (grows as the target comes closer).
using BlobReading = std::array<double, 3>;
inline constexpr std::size_t kBlobPixels = 0;
inline constexpr std::size_t kBlobBearingDeg = 1;
inline constexpr std::size_t kBlobHeightPx = 2;

}  // namespace keel::robot
