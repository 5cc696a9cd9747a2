// ColorSegmenter (robot/components/vision): the CMVision-style algorithm on hand-drawn masks
// (connectivity, thresholds, ordering, minimum area), cross-checked against a naive flood fill
// on random masks, and timed on camera frames. The ColorBlobDetector component on frames the
// Camera renders of the paper arena is in color_blob_detector_test.cpp.
#include "robot/components/vision/color_segmenter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "robot/components/vision/color_blob_detector.hpp"
#include "robot/world/camera.hpp"
#include "robot/world/world.hpp"

namespace keel::robot {
namespace {

constexpr Rgb kRed{220, 30, 30};  // the arena's target
constexpr Rgb kGrey{90, 90, 80};  // the arena's floor

/// A w × h image, red where red(x, y) holds, floor grey elsewhere.
template <class Red>
Image paint(int w, int h, Red red) {
  Image image{w, h, {}};
  const std::span<std::uint8_t> px = image.pixels();
  std::size_t i = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const Rgb p = red(x, y) ? kRed : kGrey;
      px[i++] = p.r;
      px[i++] = p.g;
      px[i++] = p.b;
    }
  }
  return image;
}

/// An image drawn as text: '#' a red pixel, anything else grey; all rows equally long.
Image art(const std::vector<std::string>& rows) {
  return paint(rows.empty() ? 0 : static_cast<int>(rows[0].size()), static_cast<int>(rows.size()),
               [&](int x, int y) { return rows[y][x] == '#'; });
}

ColorSegmenter segmenter(int min_area = 1) { return {ColorBlobDetector::kDefaultColour, min_area}; }

std::vector<Region> regionsOf(const Image& image, int min_area = 1) {
  ColorSegmenter s = segmenter(min_area);
  const auto found = s.segment(image);
  return {found.begin(), found.end()};
}

// ---- colour ----

TEST(ColorSegmenter, ConvertsRgbToBt601Yuv) {
  EXPECT_EQ(toYuv(0, 0, 0), (Yuv{0, 128, 128}));
  EXPECT_EQ(toYuv(255, 255, 255), (Yuv{255, 128, 128}));
  EXPECT_EQ(toYuv(128, 128, 128), (Yuv{128, 128, 128}));
  EXPECT_EQ(toYuv(220, 30, 30), (Yuv{87, 96, 223}));  // the target: strongly red (high V)
  EXPECT_EQ(toYuv(255, 0, 0), (Yuv{77, 85, 255}));    // the extremes stay within 0..255
  EXPECT_EQ(toYuv(0, 0, 255), (Yuv{29, 255, 107}));
  EXPECT_EQ(toYuv(0, 255, 255), (Yuv{178, 171, 0}));
  // Within one level of the real-valued formulas over a grid of colours (0 and 255 included).
  for (int r = 0; r < 256; r += 15) {
    for (int g = 0; g < 256; g += 15) {
      for (int b = 0; b < 256; b += 15) {
        const double y = 0.299 * r + 0.587 * g + 0.114 * b;
        const Yuv p = toYuv(static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(b));
        EXPECT_TRUE(p.y >= 0 && p.y <= 255 && p.u >= 0 && p.u <= 255 && p.v >= 0 && p.v <= 255);
        EXPECT_NEAR(p.y, y, 1.0);
        EXPECT_NEAR(p.u, std::clamp(128.0 + 0.5 * (b - y) / 0.886, 0.0, 255.0), 1.0);
        EXPECT_NEAR(p.v, std::clamp(128.0 + 0.5 * (r - y) / 0.701, 0.0, 255.0), 1.0);
      }
    }
  }
}

TEST(ColorSegmenter, ThresholdBoundsAreInclusive) {
  // Grey level g is YUV (g, 128, 128): a box Y 100..150 takes 100 and 150, not 99 or 151.
  Image image{4, 1, {99, 99, 99, 100, 100, 100, 150, 150, 150, 151, 151, 151}};
  ColorSegmenter s(YuvBox{100, 150, 128, 128, 128, 128}, 1);

  const auto regions = s.segment(image);

  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].x_min, 1);
  EXPECT_EQ(regions[0].x_max, 2);
}

// ---- connectivity ----

TEST(ColorSegmenter, FindsNothingInAnEmptyImage) {
  EXPECT_TRUE(regionsOf(Image{}).empty());
  EXPECT_TRUE(regionsOf(Image{5, 0, {}}).empty());
  EXPECT_TRUE(regionsOf(art({".....", "....."})).empty());
}

TEST(ColorSegmenter, FindsASinglePixelWithItsCentre) {
  const auto regions = regionsOf(art({"....", "....", "...#"}));

  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].area, 1);
  EXPECT_DOUBLE_EQ(regions[0].cx, 3.5);
  EXPECT_DOUBLE_EQ(regions[0].cy, 2.5);
  EXPECT_EQ(regions[0].width(), 1);
  EXPECT_EQ(regions[0].height(), 1);
}

TEST(ColorSegmenter, AnImageThatMatchesEverywhereIsOneRegion) {
  const auto regions = regionsOf(paint(80, 60, [](int, int) { return true; }));

  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].area, 4800);
  EXPECT_DOUBLE_EQ(regions[0].cx, 40.0);
  EXPECT_DOUBLE_EQ(regions[0].cy, 30.0);
  EXPECT_EQ(regions[0].x_min, 0);
  EXPECT_EQ(regions[0].y_min, 0);
  EXPECT_EQ(regions[0].x_max, 79);
  EXPECT_EQ(regions[0].y_max, 59);
}

TEST(ColorSegmenter, DiagonalNeighboursAreNotConnected) {
  const auto regions = regionsOf(art({"#...", ".#..", "..#.", "...#"}));

  EXPECT_EQ(regions.size(), 4u);
  for (const Region& r : regions) EXPECT_EQ(r.area, 1);
}

TEST(ColorSegmenter, RunsThatShareOneColumnAreConnected) {
  const auto regions = regionsOf(art({"###...", "..####"}));

  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].area, 7);
}

TEST(ColorSegmenter, AUShapeMergesInItsLastRow) {
  const auto regions = regionsOf(art({"#...#", "#...#", "#...#", "#####"}));

  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].area, 11);
  EXPECT_DOUBLE_EQ(regions[0].cx, 2.5);
  EXPECT_EQ(regions[0].height(), 4);
}

TEST(ColorSegmenter, ACombWhoseTeethMeetOnlyInTheLastRowIsOneRegion) {
  // Five teeth and a hook, each its own region (its own union-find root) until the last row's
  // single run unites them all.
  const auto regions = regionsOf(art({"#.#.#.#.####", "#.#.#.#....#", "#.#.#.#..#.#", "#.#.#.#..#.#", "############"}));

  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].area, 16 + 2 + 7 + 12);
  EXPECT_EQ(regions[0].width(), 12);
}

// ---- ordering and minimum area ----

TEST(ColorSegmenter, ReturnsRegionsLargestFirstAndDropsSmallOnes) {
  const Image image = art({"#.....####", "#.##..####", "#.##......", "..........", "...###...."});

  const auto all = regionsOf(image);
  const auto kept = regionsOf(image, 4);

  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(all[0].area, 8);
  EXPECT_EQ(all[1].area, 4);
  EXPECT_EQ(all[2].area, 3);  // the column, topmost of the two of area 3
  EXPECT_EQ(all[2].x_min, 0);
  EXPECT_EQ(all[3].area, 3);
  EXPECT_EQ(all[3].y_min, 4);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0].area, 8);
  EXPECT_EQ(kept[1].area, 4);
}

/// Naive labelling: flood fill with 4-connectivity, one Region per component.
std::vector<Region> floodFill(const std::vector<std::uint8_t>& mask, int w, int h) {
  std::vector<int> label(mask.size(), -1);
  std::vector<Region> out;
  for (int start = 0; start < w * h; ++start) {
    if (!mask[start] || label[start] >= 0) continue;
    Region r{0, 0.0, 0.0, w, h, -1, -1};
    std::vector<int> stack{start};
    label[start] = start;
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      const int x = p % w, y = p / w;
      ++r.area;
      r.cx += x + 0.5;
      r.cy += y + 0.5;
      r.x_min = std::min(r.x_min, x), r.x_max = std::max(r.x_max, x);
      r.y_min = std::min(r.y_min, y), r.y_max = std::max(r.y_max, y);
      const int next[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& n : next) {
        const int q = n[1] * w + n[0];
        if (n[0] < 0 || n[0] >= w || n[1] < 0 || n[1] >= h || !mask[q] || label[q] >= 0) continue;
        label[q] = start;
        stack.push_back(q);
      }
    }
    r.cx /= r.area;
    r.cy /= r.area;
    out.push_back(r);
  }
  return out;
}

TEST(ColorSegmenter, AgreesWithAFloodFillOnRandomMasks) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 300; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 40), h = 1 + static_cast<int>(rng() % 30);
    const double density = (trial % 9 + 1) / 10.0;  // sparse dots to nearly full
    std::bernoulli_distribution on(density);
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(w * h));
    for (auto& m : mask) m = on(rng);
    const Image image = paint(w, h, [&](int x, int y) { return mask[y * w + x] != 0; });
    auto expected = floodFill(mask, w, h);
    auto found = regionsOf(image);
    const auto key = [](const Region& a, const Region& b) {
      return std::tie(a.y_min, a.x_min, a.x_max, a.area) < std::tie(b.y_min, b.x_min, b.x_max, b.area);
    };
    ASSERT_TRUE(
        std::is_sorted(found.begin(), found.end(), [](const Region& a, const Region& b) { return a.area > b.area; }));
    std::sort(expected.begin(), expected.end(), key);
    std::sort(found.begin(), found.end(), key);
    ASSERT_EQ(found.size(), expected.size()) << "trial " << trial;
    for (std::size_t i = 0; i < found.size(); ++i) {
      EXPECT_EQ(found[i].area, expected[i].area) << "trial " << trial;
      EXPECT_NEAR(found[i].cx, expected[i].cx, 1e-9);
      EXPECT_NEAR(found[i].cy, expected[i].cy, 1e-9);
      EXPECT_EQ(std::tie(found[i].x_min, found[i].y_min, found[i].x_max, found[i].y_max),
                std::tie(expected[i].x_min, expected[i].y_min, expected[i].x_max, expected[i].y_max));
    }
  }
}

// ---- buffers and bad input ----

TEST(ColorSegmenter, ReusesItsBuffersForEveryFrameOfThePreparedSize) {
  // The worst case for runs (a checkerboard: 40 runs per row, 2400 regions) and the best.
  const Image checker = paint(80, 60, [](int x, int y) { return (x + y) % 2 == 1; });
  const Image full = paint(80, 60, [](int, int) { return true; });
  ColorSegmenter s = segmenter();

  const Region* first = s.segment(checker).data();
  const auto regions = s.segment(checker);
  EXPECT_EQ(regions.size(), 2400u);
  EXPECT_EQ(regions.data(), first);
  EXPECT_EQ(s.segment(full).data(), first);
  EXPECT_EQ(s.segment(full).size(), 1u);
}

TEST(ColorSegmenter, GrowsForALargerImage) {
  ColorSegmenter s(ColorBlobDetector::kDefaultColour, 1, 2, 2);
  const Image wide = paint(9, 3, [](int x, int y) { return (y * 9 + x) % 2 == 1; });

  EXPECT_EQ(s.segment(wide).size(), 13u);  // every other pixel of a 9-wide raster: no joins
}

TEST(ColorSegmenter, RejectsASizeItsBufferDoesNotHold) {
  ColorSegmenter s = segmenter();
  EXPECT_THROW(s.segment(Image{-1, 4, {}}), std::invalid_argument);
  EXPECT_THROW(s.segment(Image{Image::kMaxPixels + 1, 1, {}}), std::invalid_argument);  // past the frame
  EXPECT_THROW(s.segment(4, 4, std::vector<std::uint8_t>(47)), std::invalid_argument);
}

// ---- cost ----

TEST(ColorSegmenter, SegmentsAnArenaFrameInWellUnderAMillisecond) {
  // Median of 1000 noisy 80 × 60 frames of the target straight ahead, rendering excluded.
  const World world = World::paperArena();
  CameraConfig config;
  config.noise_sigma = 10.0;
  Camera camera(config);
  const Image frame = camera.render(world, world.start());
  ColorSegmenter s = segmenter(ColorBlobDetector::kDefaultMinArea);
  std::vector<double> us;
  std::size_t found = 0;
  for (int i = 0; i < 1000; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    found += s.segment(frame).size();
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  std::nth_element(us.begin(), us.begin() + 500, us.end());
  std::printf("[ cost     ] ColorSegmenter: median %.1f us per 80x60 frame (1000 frames)\n", us[500]);
  ::testing::Test::RecordProperty("median_us", std::to_string(us[500]));
  EXPECT_EQ(found, 1000u);
  EXPECT_LT(us[500], 1000.0);
}

}  // namespace
}  // namespace keel::robot
