// CMVision in three passes over one frame: (1) classify and run-length encode each row,
// (2) unite the runs of adjacent rows that share a column (4-connectivity: runs that only touch
// diagonally share none) with a union-find whose parent is always the lower run index, so every
// root is the first run of its region in raster order, (3) sum each region's pixels from its
// runs, drop the small ones and sort by area. O(pixels + runs · α(runs)); no allocation.
// CMVision classifies with three table look-ups (one bit per colour class); for one class the
// six comparisons below cost the same and need no tables.
#include "robot/components/vision/color_segmenter.hpp"

#include <algorithm>
#include <cassert>
#include <stdexcept>
#include <string>

namespace keel::robot {

bool YuvBox::valid() const {
  const auto in = [](int lo, int hi) { return 0 <= lo && lo <= hi && hi <= 255; };
  return in(y_min, y_max) && in(u_min, u_max) && in(v_min, v_max);
}

ColorSegmenter::ColorSegmenter(const YuvBox& colour, int min_area, int width, int height)
    : colour_(colour), min_area_(min_area) {
  assert(colour.valid() && min_area >= 1);
  prepare(width, height);
}

void ColorSegmenter::prepare(int w, int h) {
  if (w < 0 || h < 0) throw std::invalid_argument("ColorSegmenter: negative image size");
  const std::size_t max_runs = static_cast<std::size_t>(h) * (static_cast<std::size_t>(w) + 1) / 2 + 1;
  if (runs_.size() < max_runs) {
    runs_.resize(max_runs);
    region_of_.resize(max_runs);
    accumulators_.resize(max_runs);
    regions_.resize(max_runs);
  }
  if (row_mask_.size() < static_cast<std::size_t>(w) + 1) row_mask_.resize(static_cast<std::size_t>(w) + 1);
  if (row_start_.size() < static_cast<std::size_t>(h) + 1) row_start_.resize(static_cast<std::size_t>(h) + 1);
}

std::span<const Region> ColorSegmenter::segment(const Image& image) {
  if (!image.fits())
    throw std::invalid_argument("ColorSegmenter: a " + std::to_string(image.w) + " x " + std::to_string(image.h) +
                                " image does not fit a frame's " + std::to_string(Image::kMaxPixels) + " pixels");
  return segment(image.w, image.h, image.pixels());
}

std::span<const Region> ColorSegmenter::segment(int w, int h, std::span<const std::uint8_t> rgb) {
  if (w < 0 || h < 0 || rgb.size() != 3 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h))
    throw std::invalid_argument("ColorSegmenter: a " + std::to_string(w) + " x " + std::to_string(h) + " image needs " +
                                std::to_string(3LL * w * h) + " bytes, got " + std::to_string(rgb.size()));
  prepare(w, h);  // a no-op unless the image is larger than any before
  encodeRows(w, h, rgb.data());
  connectRows(h);
  gatherRegions();
  return {regions_.data(), static_cast<std::size_t>(region_count_)};
}

void ColorSegmenter::encodeRows(int w, int h, const std::uint8_t* rgb) {
  run_count_ = 0;
  std::uint8_t* mask = row_mask_.data();
  const YuvBox c = colour_;
  for (int y = 0; y < h; ++y) {
    row_start_[y] = run_count_;
    const std::uint8_t* px = rgb + 3 * static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    for (int x = 0; x < w; ++x) {  // classify without a branch, then encode
      const std::uint8_t* rgb_x = px + 3 * static_cast<std::ptrdiff_t>(x);
      const Yuv p = toYuv(rgb_x[0], rgb_x[1], rgb_x[2]);
      mask[x] = (p.y >= c.y_min) & (p.y <= c.y_max) & (p.u >= c.u_min) & (p.u <= c.u_max) & (p.v >= c.v_min) &
                (p.v <= c.v_max);
    }
    mask[w] = 0;     // closes a run that reaches the right edge
    int start = -1;  // first column of the open run, -1 if none
    for (int x = 0; x <= w; ++x) {
      if (mask[x] && start < 0) {
        start = x;
      } else if (!mask[x] && start >= 0) {
        runs_[run_count_] = Run{start, x - 1, y, run_count_};
        ++run_count_;
        start = -1;
      }
    }
  }
  row_start_[h] = run_count_;
}

void ColorSegmenter::connectRows(int h) {
  for (int y = 1; y < h; ++y) {
    const int above_end = row_start_[y];
    int above = row_start_[y - 1];
    for (int i = above_end; i < row_start_[y + 1]; ++i) {
      const Run& run = runs_[i];
      // Runs of a row are sorted and disjoint: skip those ending left of this one, then unite
      // with every run that starts at or before its end (each shares at least one column).
      while (above < above_end && runs_[above].x1 < run.x0) ++above;
      for (int k = above; k < above_end && runs_[k].x0 <= run.x1; ++k) unite(i, k);
    }
  }
}

int ColorSegmenter::find(int run) {
  while (runs_[run].parent != run) {
    Run& r = runs_[run];
    r.parent = runs_[r.parent].parent;  // path halving
    run = r.parent;
  }
  return run;
}

void ColorSegmenter::unite(int a, int b) {
  const int ra = find(a);
  const int rb = find(b);
  if (ra == rb) return;
  // The lower index becomes the root: a U-shape's arms, found as two regions, merge at the
  // bottom row into the one whose first run came first.
  runs_[std::max(ra, rb)].parent = std::min(ra, rb);
}

void ColorSegmenter::gatherRegions() {
  accumulator_count_ = 0;
  for (int i = 0; i < run_count_; ++i) {
    const int root = find(i);  // ≤ i, so a root is met before every other run of its region
    if (root == i) {
      region_of_[i] = accumulator_count_;
      const Run& r = runs_[i];
      accumulators_[accumulator_count_++] = Accumulator{0, 0, 0, r.x0, r.y, r.x1, r.y};
    }
    const Run& r = runs_[i];
    Accumulator& a = accumulators_[region_of_[root]];
    const std::int64_t length = r.x1 - r.x0 + 1;
    a.area += length;
    a.sum_x += (static_cast<std::int64_t>(r.x0) + r.x1) * length / 2;  // x0 + … + x1
    a.sum_y += static_cast<std::int64_t>(r.y) * length;
    a.x_min = std::min(a.x_min, r.x0);
    a.x_max = std::max(a.x_max, r.x1);
    a.y_max = r.y;  // runs come in raster order; y_min is the root's row
  }
  int kept = 0;
  for (int i = 0; i < accumulator_count_; ++i) {
    const Accumulator& a = accumulators_[i];
    if (a.area < min_area_) continue;
    const auto area = static_cast<double>(a.area);
    regions_[kept++] = Region{static_cast<int>(a.area),
                              static_cast<double>(a.sum_x) / area + 0.5,
                              static_cast<double>(a.sum_y) / area + 0.5,
                              a.x_min,
                              a.y_min,
                              a.x_max,
                              a.y_max};
  }
  region_count_ = kept;
  std::sort(regions_.begin(), regions_.begin() + kept, [](const Region& a, const Region& b) {
    if (a.area != b.area) return a.area > b.area;
    if (a.y_min != b.y_min) return a.y_min < b.y_min;
    if (a.x_min != b.x_min) return a.x_min < b.x_min;
    return a.cx < b.cx;
  });
}

}  // namespace keel::robot
