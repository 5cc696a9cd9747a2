// The simulated robot's world and camera (robot/world): exact ray casts against boxes and the
// target, body collision and clearance at any heading, the paper arena's free path, the sonar
// adapter feeding the motion-board simulator, and the camera's rendering and noise.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "robot/world/camera.hpp"
#include "robot/world/world.hpp"

namespace keel::robot {
namespace {

constexpr double kPi = std::numbers::pi;

World worldOf(std::vector<Box> boxes, Target target = {100.0, 100.0, 0.1, {}}) {
  return World(std::move(boxes), target, Pose{});
}

bool isRed(const Rgb& c) { return c.r > 150 && c.g < 80 && c.b < 80; }

int redPixels(const Image& image) {
  int count = 0;
  for (int y = 0; y < image.h; ++y) {
    for (int x = 0; x < image.w; ++x) count += isRed(image.at(x, y)) ? 1 : 0;
  }
  return count;
}

int redColumns(const Image& image) {
  int count = 0;
  for (int x = 0; x < image.w; ++x) {
    for (int y = 0; y < image.h; ++y) {
      if (isRed(image.at(x, y))) {
        ++count;
        break;
      }
    }
  }
  return count;
}

// ---- ray casts ----

TEST(World, RayCastHitsAWallAtTheExactDistanceAtSeveralAngles) {
  const World world = worldOf({{2.0, -10.0, 2.5, 10.0}});
  for (double heading : {0.0, 0.3, -0.3, 0.7, -1.0, 1.2}) {
    EXPECT_NEAR(world.rayCast(0.0, 0.0, heading, 50.0), 2.0 / std::cos(heading), 1e-9) << heading;
  }
}

TEST(World, RayCastHitsTheNearestOfTwoBoxesWhateverTheirOrder) {
  const World world = worldOf({{3.0, -1.0, 3.5, 1.0}, {1.5, -1.0, 2.0, 1.0}, {-1.5, -1.0, -1.0, 1.0}});
  EXPECT_NEAR(world.rayCast(0.0, 0.0, 0.0, 10.0), 1.5, 1e-12);
  EXPECT_NEAR(world.rayCast(0.0, 0.0, kPi, 10.0), 1.0, 1e-12);
  EXPECT_NEAR(world.rayCast(2.2, 0.0, 0.0, 10.0), 0.8, 1e-12);  // between the two
}

TEST(World, RayCastThatMissesEverythingReturnsTheMaximum) {
  const World world = worldOf({{1.0, -1.0, 2.0, 1.0}});
  EXPECT_EQ(world.rayCast(0.0, 0.0, kPi / 2, 5.0), 5.0);
  EXPECT_EQ(world.rayCast(0.0, 0.0, kPi, 5.0), 5.0);
  EXPECT_EQ(world.rayCast(0.0, 0.0, 0.0, 0.5), 0.5);  // the box lies beyond the cap
}

TEST(World, RayCastFromInsideABoxReadsZero) {
  const World world = worldOf({{1.0, -1.0, 2.0, 1.0}});
  EXPECT_EQ(world.rayCast(1.5, 0.0, 0.3, 5.0), 0.0);
}

TEST(World, RayCastHitsTheTargetDiscAtItsSurface) {
  const World world = worldOf({{5.0, -5.0, 5.5, 5.0}}, Target{2.0, 0.0, 0.25, {}});
  EXPECT_NEAR(world.rayCast(0.0, 0.0, 0.0, 10.0), 1.75, 1e-12);
  const double heading = 0.05;  // off centre: the nearer root of the ray/circle quadratic
  const double expected = 2.0 * std::cos(heading) - std::sqrt(0.0625 - std::pow(2.0 * std::sin(heading), 2));
  EXPECT_NEAR(world.rayCast(0.0, 0.0, heading, 10.0), expected, 1e-12);
  EXPECT_NEAR(world.rayCast(0.0, 0.0, 0.2, 10.0), 5.0 / std::cos(0.2), 1e-9);  // passes beside it
  const RayHits hits = world.castRay(0.0, 0.0, 0.0, 10.0);
  EXPECT_NEAR(hits.target_m, 1.75, 1e-12);
  EXPECT_NEAR(hits.box_m, 5.0, 1e-12);
}

// ---- body collision and clearance ----

TEST(World, CollidesWhenTheBodyOverlapsABoxAndNotInFreeSpace) {
  const World world = worldOf({{1.0, -1.0, 2.0, 1.0}});
  EXPECT_FALSE(world.collides(0.5, 0.0, 0.0));
  EXPECT_TRUE(world.collides(0.9, 0.0, 0.0));   // nose 5 mm into the box
  EXPECT_TRUE(world.collides(1.5, 0.0, 0.3));   // wholly inside
  EXPECT_FALSE(world.collides(0.5, 2.0, 1.0));  // beside it
}

TEST(World, CollisionFollowsTheBodysHeading) {
  const World world = worldOf({{1.0, -1.0, 2.0, 1.0}});
  // At x = 0.92 the 210 mm length reaches the box, the 140 mm width does not.
  EXPECT_TRUE(world.collides(0.92, 0.0, 0.0));
  EXPECT_FALSE(world.collides(0.92, 0.0, kPi / 2));
  // At x = 0.88 only the diagonal reaches it: a corner at 45° sticks out 124 mm.
  EXPECT_FALSE(world.collides(0.88, 0.0, 0.0));
  EXPECT_TRUE(world.collides(0.88, 0.0, kPi / 4));
}

TEST(World, CollisionIsExactNearABoxCornerWhereBoundingBoxesWouldOverlap) {
  const World world = worldOf({{1.0, 1.0, 2.0, 2.0}});
  // Pointing at the corner from 141 mm away: the 105 mm half length falls short.
  EXPECT_FALSE(world.collides(0.9, 0.9, kPi / 4));
  EXPECT_FALSE(world.collides(0.9, 0.9, -kPi / 4));
  EXPECT_TRUE(world.collides(0.95, 0.95, kPi / 4));
}

TEST(World, ClearanceIsTheGapToTheNearestBox) {
  const World world = worldOf({{1.0, -1.0, 2.0, 1.0}, {-3.0, -1.0, -2.0, 1.0}});
  EXPECT_NEAR(world.clearance(0.5, 0.0, 0.0), 1.0 - 0.605, 1e-12);
  EXPECT_NEAR(world.clearance(0.5, 0.0, kPi / 2), 1.0 - 0.57, 1e-12);
  EXPECT_NEAR(world.clearance(0.5, 0.0, kPi / 4), 1.0 - 0.5 - 0.175 * std::sqrt(0.5), 1e-12);
  EXPECT_EQ(world.clearance(0.95, 0.0, 0.0), 0.0);
}

TEST(World, ClearanceToABoxCornerIsTheDiagonalGap) {
  const World world = worldOf({{1.0, 1.0, 2.0, 2.0}});
  EXPECT_NEAR(world.clearance(0.5, 0.5, 0.0), std::hypot(1.0 - 0.605, 1.0 - 0.57), 1e-12);
  // Nose pointing at the corner: box corner to body front edge.
  EXPECT_NEAR(world.clearance(0.9, 0.9, kPi / 4), 0.1 * std::sqrt(2.0) - 0.105, 1e-12);
}

// ---- the paper arena ----

/// Drives the body along straight segments between waypoints (heading along each segment,
/// turning in place at each waypoint) and returns the smallest clearance met.
double pathClearance(const World& world, const std::vector<Pose>& waypoints) {
  double least = 1e9;
  double previous_heading = waypoints.front().heading_rad;
  for (std::size_t i = 0; i + 1 < waypoints.size(); ++i) {
    const Pose& a = waypoints[i];
    const Pose& b = waypoints[i + 1];
    const double heading = std::atan2(b.y_m - a.y_m, b.x_m - a.x_m);
    for (int k = 0; k <= 20; ++k) {  // the turn in place at a
      const double h = previous_heading + (heading - previous_heading) * k / 20.0;
      least = std::min(least, world.clearance(a.x_m, a.y_m, h));
    }
    const int steps = static_cast<int>(std::hypot(b.x_m - a.x_m, b.y_m - a.y_m) / 0.01) + 1;
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      least = std::min(least, world.clearance(a.x_m + t * (b.x_m - a.x_m), a.y_m + t * (b.y_m - a.y_m), heading));
    }
    previous_heading = heading;
  }
  return least;
}

TEST(World, PaperArenaHasACollisionFreePathFromStartToTheTarget) {
  const World arena = World::paperArena();
  const Pose start = arena.start();
  const std::vector<Pose> waypoints{start, {1.0, 1.35, 0}, {1.9, 1.35, 0}, {2.4, 1.5, 0}, {3.2, 1.5, 0}};
  EXPECT_FALSE(arena.collides(start.x_m, start.y_m, start.heading_rad));
  EXPECT_GT(pathClearance(arena, waypoints), 0.05);
  const Target& target = arena.target();
  EXPECT_LT(std::hypot(target.x_m - 3.2, target.y_m - 1.5) - target.radius_m - kBodyLengthM / 2, 0.1);
}

TEST(World, PaperArenaBlocksTheStraightDriveButNotTheLineOfSight) {
  const World arena = World::paperArena();
  const Pose start = arena.start();
  bool blocked = false;
  for (int cm = 0; start.x_m + cm * 0.01 <= 3.2; ++cm)
    blocked = blocked || arena.collides(start.x_m + cm * 0.01, start.y_m, 0.0);
  EXPECT_TRUE(blocked);
  const RayHits hits = arena.castRay(start.x_m, start.y_m, 0.0, 10.0);
  EXPECT_NEAR(hits.target_m, 3.5 - 0.12 - 0.4, 1e-12);
  EXPECT_LT(hits.target_m, hits.box_m);
}

TEST(World, PaperArenaIsAClosedRoom) {
  const World arena = World::paperArena();
  for (int i = 0; i < 72; ++i) {
    EXPECT_LT(arena.rayCast(2.0, 0.2, i * kPi / 36, 100.0), 5.0) << i;
  }
}

TEST(World, SonarRayCastFeedsTheSimulatorInCentimetres) {
  const World arena = World::paperArena();
  const RayCast sonar = sonarRayCast(arena);
  EXPECT_NEAR(sonar(0.4, 1.5, kPi), 40.0, 1e-9);
  EXPECT_NEAR(sonar(0.4, 1.5, kPi / 2), 150.0, 1e-9);

  SimulatorConfig config;
  config.start = arena.start();
  config.ray_cast = sonarRayCast(arena);
  Simulator sim(config);
  sim.step(0.001);
  // Ahead, the beam's rays (7 over ±15°, 5° apart) meet obstacle A's near face before the
  // target; the ray 5° left of the axis is the nearest echo.
  const double a_cm = 100.0 * arena.rayCast(0.505, 1.5, 0.26 / 3, 30.0);
  EXPECT_NEAR(sim.sonarCm(SonarId::FrontB), a_cm, 1.0);
  EXPECT_LT(a_cm, 100.0 * (3.5 - 0.12 - 0.505));                        // nearer than the target
  EXPECT_NEAR(sim.sonarCm(SonarId::Back), 100.0 * (0.4 - 0.105), 1.0);  // west wall
}

// ---- camera ----

World targetAhead() { return worldOf({{5.0, -5.0, 5.5, 5.0}}, Target{3.0, 0.0, 0.12, Rgb{220, 30, 30}}); }

TEST(Camera, FacingTheTargetShowsRedInTheCentreColumns) {
  Camera camera;
  const Image image = camera.render(targetAhead(), Pose{1.0, 0.0, 0.0});
  ASSERT_EQ(image.w, 80);
  ASSERT_EQ(image.h, 60);
  EXPECT_TRUE(isRed(image.at(39, 30)));
  EXPECT_TRUE(isRed(image.at(40, 30)));
  EXPECT_FALSE(isRed(image.at(0, 30)));
  EXPECT_FALSE(isRed(image.at(79, 30)));
  EXPECT_FALSE(isRed(image.at(40, 0)));   // ceiling above the band
  EXPECT_FALSE(isRed(image.at(40, 59)));  // floor below it
}

TEST(Camera, TheTargetBandIsWiderAndTallerWhenCloser) {
  Camera camera;
  const Image close = camera.render(targetAhead(), Pose{2.0, 0.0, 0.0});
  const Image distant = camera.render(targetAhead(), Pose{0.0, 0.0, 0.0});
  EXPECT_GT(redColumns(close), redColumns(distant));
  EXPECT_GT(redColumns(distant), 0);
  int close_rows = 0, distant_rows = 0;
  for (int y = 0; y < 60; ++y) {
    close_rows += isRed(close.at(40, y)) ? 1 : 0;
    distant_rows += isRed(distant.at(40, y)) ? 1 : 0;
  }
  EXPECT_GT(close_rows, distant_rows);
}

TEST(Camera, TheTargetOffToOneSideAppearsOnThatSide) {
  Camera camera;
  const Image image = camera.render(targetAhead(), Pose{1.0, 0.0, -0.3});  // turned right
  int left = 0, right = 0;
  for (int x = 0; x < 80; ++x) {
    if (isRed(image.at(x, 30))) ++(x < 40 ? left : right);
  }
  EXPECT_GT(left, 0);
  EXPECT_EQ(right, 0);
}

TEST(Camera, FacingAWallShowsGreyWallAndNoRed) {
  Camera camera;
  const World arena = World::paperArena();
  const Image image = camera.render(arena, Pose{0.6, 1.0, kPi});  // facing the west wall
  EXPECT_EQ(redPixels(image), 0);
  const Rgb centre = image.at(40, 30);
  EXPECT_EQ(centre.r, centre.g);
  EXPECT_EQ(centre.g, centre.b);
  EXPECT_NE(centre, camera.config().floor);
  EXPECT_NE(centre, camera.config().ceiling);
}

TEST(Camera, ATargetBehindAnObstacleIsHidden) {
  Camera camera;
  const World world = worldOf({{1.5, -1.0, 1.7, 1.0}}, Target{3.0, 0.0, 0.12, Rgb{220, 30, 30}});
  EXPECT_EQ(redPixels(camera.render(world, Pose{0.0, 0.0, 0.0})), 0);
}

TEST(Camera, PaperArenaStartSeesTheTargetAhead) {
  Camera camera;
  const World arena = World::paperArena();
  const Image image = camera.render(arena, arena.start());
  EXPECT_TRUE(isRed(image.at(40, 30)));
}

TEST(Camera, SameSeedRendersIdenticalNoisyImages) {
  CameraConfig config;
  config.noise_sigma = 8.0;
  config.seed = 7;
  Camera a(config), b(config);
  const World world = targetAhead();
  EXPECT_EQ(a.render(world, Pose{1.0, 0.0, 0.0}), b.render(world, Pose{1.0, 0.0, 0.0}));
  EXPECT_EQ(a.render(world, Pose{1.0, 0.0, 0.1}), b.render(world, Pose{1.0, 0.0, 0.1}));
}

TEST(Camera, NoiseChangesPixelsAndDependsOnTheSeed) {
  CameraConfig noisy;
  noisy.noise_sigma = 8.0;
  CameraConfig other_seed = noisy;
  other_seed.seed = 2;
  Camera clean, a(noisy), b(other_seed);
  const World world = targetAhead();
  const Pose pose{1.0, 0.0, 0.0};
  const Image plain = clean.render(world, pose);
  const Image with_noise = a.render(world, pose);
  int differing = 0;
  for (std::size_t i = 0; i < plain.pixels().size(); ++i)
    differing += plain.pixels()[i] != with_noise.pixels()[i] ? 1 : 0;
  EXPECT_GT(differing, static_cast<int>(plain.pixels().size()) / 2);
  EXPECT_NE(with_noise, b.render(world, pose));
  EXPECT_EQ(plain, Camera().render(world, pose));  // no noise: the same image every time
  EXPECT_TRUE(isRed(with_noise.at(40, 30)));       // the target still reads red
}

TEST(Camera, RefusesAResolutionLargerThanAFrameHolds) {
  CameraConfig big;
  big.width = 81;  // × 60 rows: one column more than Image::kMaxPixels
  EXPECT_THROW(Camera{big}, std::invalid_argument);
  big.width = 120;  // × 40 rows: as many pixels as 80 × 60, in another shape
  big.height = 40;
  EXPECT_EQ(Camera(big).render(targetAhead(), Pose{}).pixels().size(), 3u * 120 * 40);
}

TEST(Camera, ImagesAreEqualWhenTheirSizeAndPixelsAre) {
  Image a{2, 1, {1, 2, 3, 4, 5, 6}};
  Image b = a;
  b.rgb[6] = 9;  // past the pixels: not part of the image
  EXPECT_EQ(a, b);
  b.rgb[5] = 9;
  EXPECT_NE(a, b);
  EXPECT_NE(a, (Image{1, 2, {1, 2, 3, 4, 5, 6}}));  // the same bytes, another shape
}

}  // namespace
}  // namespace keel::robot
