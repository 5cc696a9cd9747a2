// keel::robot::ColorSegmenter: CMVision-style colour segmentation (Bruce, Balch & Veloso 2000),
// the algorithm of the test robot's ColorBlobDetector (docs/robot_components.md). Pixels are
// classified by a YUV box threshold, each row's matches are run-length encoded, runs that
// overlap in adjacent rows are merged with union-find (4-connectivity) and every region's area,
// centroid and bounding box is returned, largest first. Called by ColorBlobDetector and tests.
// Thread-safety: none (segment() reuses preallocated buffers); pure, no keel runtime needed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "robot/world/camera.hpp"

namespace keel::robot {

/// A pixel in YUV (BT.601, full range 0..255, U and V centred on 128), as CMVision thresholds it.
struct Yuv {
  int y = 0;
  int u = 128;
  int v = 128;
  friend bool operator==(const Yuv&, const Yuv&) = default;
};

/// RGB → YUV with BT.601 weights in 8-bit fixed point (Y = 0.299 R + 0.587 G + 0.114 B,
/// U = 128 + 0.5 (B − Y) / 0.886, V = 128 + 0.5 (R − Y) / 0.701), rounded to nearest (ties
/// down). The weights × 256 sum to 256 for Y and to 0 (±128 each side) for U and V, so with the
/// +127 rounding term every result lies in 0..255 without clamping (pure red: V = 255, not 256).
/// >> floors (arithmetic shift of a negative value, C++20).
[[nodiscard]] constexpr Yuv toYuv(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  return Yuv{(77 * r + 150 * g + 29 * b + 127) >> 8, ((-43 * r - 85 * g + 128 * b + 127) >> 8) + 128,
             ((128 * r - 107 * g - 21 * b + 127) >> 8) + 128};
}

/// A colour class: [y_min, y_max] × [u_min, u_max] × [v_min, v_max], bounds inclusive, 0..255.
struct YuvBox {
  int y_min = 0;
  int y_max = 255;
  int u_min = 0;
  int u_max = 255;
  int v_min = 0;
  int v_max = 255;
  [[nodiscard]] bool contains(const Yuv& p) const {
    return p.y >= y_min && p.y <= y_max && p.u >= u_min && p.u <= u_max && p.v >= v_min && p.v <= v_max;
  }
  /// Every bound within 0..255 and every min ≤ its max.
  [[nodiscard]] bool valid() const;
};

/// One connected region of matching pixels. Coordinates: pixel (x, y) covers the square
/// [x, x+1) × [y, y+1), so the centroid of the single pixel (0, 0) is (0.5, 0.5) and the
/// image's centre is (w/2, h/2). Bounds are inclusive pixel indices.
struct Region {
  int area = 0;  // pixels
  double cx = 0.0;
  double cy = 0.0;
  int x_min = 0;
  int y_min = 0;
  int x_max = 0;
  int y_max = 0;
  [[nodiscard]] int width() const { return x_max - x_min + 1; }
  [[nodiscard]] int height() const { return y_max - y_min + 1; }
};

class ColorSegmenter {
 public:
  /// `colour` must be valid() and `min_area` ≥ 1 (asserted). Buffers are sized for a
  /// `width` × `height` image; segment() grows them once if handed a larger one.
  ColorSegmenter(const YuvBox& colour, int min_area, int width = 80, int height = 60);

  /// The regions of `colour` in `image` with at least `min_area` pixels, largest first (ties:
  /// topmost, then leftmost). The span stays valid until the next call. Allocation-free for
  /// images no larger than the prepared size. Throws std::invalid_argument when a dimension is
  /// negative, or the image does not fit its frame (Image::fits) or `rgb` is not 3 × w × h bytes.
  std::span<const Region> segment(const Image& image);
  std::span<const Region> segment(int w, int h, std::span<const std::uint8_t> rgb);

  /// Sizes every buffer for a w × h image (the only allocation; none when large enough).
  void prepare(int w, int h);

  [[nodiscard]] const YuvBox& colour() const { return colour_; }
  [[nodiscard]] int minArea() const { return min_area_; }

 private:
  struct Run {  // matching pixels x0..x1 (inclusive) of row y
    int x0;
    int x1;
    int y;
    int parent;  // union-find: index of a run of the same region, ≤ own index
  };
  struct Accumulator {  // a region's sums while runs are gathered
    std::int64_t area;
    std::int64_t sum_x;
    std::int64_t sum_y;
    int x_min, y_min, x_max, y_max;
  };

  void encodeRows(int w, int h, const std::uint8_t* rgb);
  void connectRows(int h);
  void gatherRegions();
  int find(int run);
  void unite(int a, int b);

  YuvBox colour_;
  int min_area_;
  // buffers sized by prepare() for the worst case (alternating pixels: ⌈w/2⌉ runs per row);
  // the counts say how much of each is in use
  std::vector<Run> runs_;
  std::vector<std::uint8_t> row_mask_;  // one row's classification, plus a closing 0
  std::vector<int> row_start_;          // runs of row y are runs_[row_start_[y] .. row_start_[y + 1])
  std::vector<int> region_of_;          // for a root run: its index in accumulators_
  std::vector<Accumulator> accumulators_;
  std::vector<Region> regions_;
  int run_count_ = 0;
  int accumulator_count_ = 0;
  int region_count_ = 0;
};

}  // namespace keel::robot
