// ColorBlobDetector (robot/components/vision), tested as a class on frames the robot's Camera
// renders of the paper arena: bearing and size of the red target straight ahead, to either
// side, behind, under camera noise; no false blob in noisy frames without the target; only
// the newest frame is processed; bad properties fail initialisation naming the property.
#include "robot/components/vision/color_blob_detector.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "profile/loader.hpp"
#include "robot/world/camera.hpp"
#include "robot/world/world.hpp"
#include "runtime/component_core.hpp"
#include "runtime/invoke.hpp"
#include "support/paths.hpp"
#include "support/recording_hooks.hpp"

namespace keel::robot {
namespace {

using ::testing::HasSubstr;
constexpr double kDeg = 180.0 / std::numbers::pi;

class Feeder : public Component {
 public:
  OutputDataPort<Image> image{this, "image"};
};

class Probe : public Component {
 public:
  InputDataPort<BlobReading> blob{this, "blob"};
};

/// A detector named "detector", fed by a Feeder, its readings kept by a Probe.
class DetectorRig {
 public:
  DetectorRig() {
    test::manage(detector, "detector", hooks);
    test::configureQueue(detector.image, QueuePolicy::Fifo, 4);  // to see older frames skipped
    test::configureQueue(probe.blob, QueuePolicy::UFifo, 256);
    test::wire(feeder.image, detector.image, keep_);
    test::wire(detector.blob, probe.blob, keep_);
  }
  void set(const std::string& name, PropertyValue value) {
    runtime::coreOf(detector).properties[name] = std::move(value);
  }
  bool initialize() { return runtime::transition(detector, keel::Transition::Initialize); }
  /// One frame, one execution, the reading it produced.
  BlobReading see(const Image& frame) {
    feeder.image.push(frame);
    EXPECT_EQ(detector.onExecute(), ReturnCode::Ok);
    const auto all = readings();
    EXPECT_EQ(all.size(), 1u);
    return all.empty() ? BlobReading{-1, -1, -1} : all.back();
  }
  std::vector<BlobReading> readings() {
    std::vector<BlobReading> out;
    while (auto r = probe.blob.pop()) out.push_back(*r);
    return out;
  }

  test::RecordingHooks hooks;
  ColorBlobDetector detector;
  Feeder feeder;
  Probe probe;

 private:
  std::vector<std::unique_ptr<detail::ConnectionBase>> keep_;
};

/// Where the target's centre lies from `pose`, in degrees, positive to the left.
double trueBearingDeg(const World& world, const Pose& pose) {
  const double b = std::atan2(world.target().y_m - pose.y_m, world.target().x_m - pose.x_m) - pose.heading_rad;
  return std::remainder(b, 2 * std::numbers::pi) * kDeg;
}

Image view(const Pose& pose, double noise_sigma = 0.0, std::uint64_t seed = 1) {
  CameraConfig config;
  config.noise_sigma = noise_sigma;
  config.seed = seed;
  return Camera(config).render(World::paperArena(), pose);
}

// ---- on the camera's frames ----

TEST(ColorBlobDetector, SeesTheTargetStraightAheadAsABigCentredBlob) {
  const World world = World::paperArena();
  DetectorRig rig;
  ASSERT_TRUE(rig.initialize());

  const BlobReading r = rig.see(view(world.start()));

  // 2.98 m to the target's face: ~5.6 px wide, f · 0.3 m / 2.98 m ≈ 7 px tall.
  const double focal = 40.0 / std::tan(30.0 / kDeg);
  EXPECT_GE(r[kBlobPixels], 30.0);
  EXPECT_NEAR(r[kBlobBearingDeg], 0.0, 0.5);
  EXPECT_NEAR(r[kBlobHeightPx], focal * 0.3 / (3.5 - 0.12 - 0.4), 1.0);
}

TEST(ColorBlobDetector, GivesTheTargetsBearingWithinTwoDegreesToEitherSide) {
  const World world = World::paperArena();
  DetectorRig rig;
  ASSERT_TRUE(rig.initialize());
  const Pose poses[] = {
      {0.4, 1.5, -15.0 / kDeg},  // from the start, turned right: target to the left
      {0.4, 1.5, 20.0 / kDeg},   // turned left: target to the right
      {2.6, 1.0, 0.2},           // close, below the line: the target up and to the left
      {2.6, 2.0, -0.2},          // close, above it (below obstacle C): to the right
  };

  for (const Pose& pose : poses) {
    const BlobReading r = rig.see(view(pose));
    const double expected = trueBearingDeg(world, pose);
    EXPECT_GT(r[kBlobPixels], 20.0) << pose.x_m << ", " << pose.y_m << ", " << pose.heading_rad;
    EXPECT_NEAR(r[kBlobBearingDeg], expected, 2.0) << pose.x_m << ", " << pose.y_m;
    EXPECT_GT(std::fabs(expected), 10.0);
  }
}

TEST(ColorBlobDetector, ReportsNoBlobWhenFacingAway) {
  const World world = World::paperArena();
  DetectorRig rig;
  ASSERT_TRUE(rig.initialize());

  const BlobReading r = rig.see(view({0.4, 1.5, std::numbers::pi}));

  EXPECT_EQ(r, (BlobReading{0.0, 0.0, 0.0}));
}

TEST(ColorBlobDetector, StillFindsTheTargetUnderCameraNoise) {
  const World world = World::paperArena();
  DetectorRig rig;
  ASSERT_TRUE(rig.initialize());
  const BlobReading clean = rig.see(view(world.start()));

  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const BlobReading noisy = rig.see(view(world.start(), 10.0, seed));
    EXPECT_NEAR(noisy[kBlobPixels], clean[kBlobPixels], 0.1 * clean[kBlobPixels]) << seed;
    EXPECT_NEAR(noisy[kBlobBearingDeg], 0.0, 1.0) << seed;
    EXPECT_NEAR(noisy[kBlobHeightPx], clean[kBlobHeightPx], 1.0) << seed;
  }
}

TEST(ColorBlobDetector, FindsNoFalseBlobInAHundredNoisyFramesWithoutTheTarget) {
  // Facing the near wall and obstacle A: floor, ceiling and grey walls at every shade.
  CameraConfig config;
  config.noise_sigma = 10.0;
  Camera camera(config);
  const World world = World::paperArena();
  DetectorRig rig;
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 100; ++i) {
    const Pose pose{0.4 + 0.01 * i, 1.5, i % 2 ? std::numbers::pi : 1.2};
    EXPECT_EQ(rig.see(camera.render(world, pose)), (BlobReading{0.0, 0.0, 0.0})) << i;
  }
}

TEST(ColorBlobDetector, DefaultColourTakesRedsAndNothingElseOfTheArena) {
  const auto takes = [](Rgb c) { return ColorBlobDetector::kDefaultColour.contains(toYuv(c.r, c.g, c.b)); };
  EXPECT_TRUE(takes({220, 30, 30}));  // the target
  EXPECT_TRUE(takes({255, 0, 0}));
  EXPECT_TRUE(takes({150, 20, 20}));     // a dark red
  EXPECT_FALSE(takes({90, 90, 80}));     // floor
  EXPECT_FALSE(takes({170, 170, 175}));  // ceiling
  EXPECT_FALSE(takes({220, 220, 220}));  // a near wall
  EXPECT_FALSE(takes({255, 128, 0}));    // orange
  EXPECT_FALSE(takes({255, 0, 255}));    // magenta
}

// ---- frames and conventions ----

TEST(ColorBlobDetector, ProcessesOnlyTheNewestFrameAndOnlyWhenOneArrived) {
  const World world = World::paperArena();
  DetectorRig rig;
  ASSERT_TRUE(rig.initialize());

  rig.feeder.image.push(view({0.4, 1.5, -15.0 / kDeg}));
  rig.feeder.image.push(view({0.4, 1.5, std::numbers::pi}));  // the newest: no target
  ASSERT_EQ(rig.detector.onExecute(), ReturnCode::Ok);
  ASSERT_EQ(rig.detector.onExecute(), ReturnCode::Ok);  // nothing new: nothing sent

  EXPECT_EQ(rig.readings(), (std::vector<BlobReading>{{0.0, 0.0, 0.0}}));
}

TEST(ColorBlobDetector, BearingIsPositiveTowardsColumnZeroAndZeroAtTheCentre) {
  EXPECT_DOUBLE_EQ(ColorBlobDetector::bearingDeg(40.0, 80, 60.0), 0.0);
  EXPECT_NEAR(ColorBlobDetector::bearingDeg(0.0, 80, 60.0), 30.0, 1e-12);  // the left edge
  EXPECT_NEAR(ColorBlobDetector::bearingDeg(80.0, 80, 60.0), -30.0, 1e-12);
  // The camera's column rays: column c looks atan((w/2 - (c + 0.5)) / f) off the heading.
  const double focal = 40.0 / std::tan(30.0 / kDeg);
  EXPECT_NEAR(ColorBlobDetector::bearingDeg(10.5, 80, 60.0), std::atan(29.5 / focal) * kDeg, 1e-12);
}

TEST(ColorBlobDetector, AMalformedFrameIsAnExceptionOfTheCallback) {
  DetectorRig rig;
  ASSERT_TRUE(rig.initialize());
  rig.feeder.image.push(Image{81, 60, {}});  // more pixels than a frame holds

  EXPECT_THROW(static_cast<void>(rig.detector.onExecute()), std::invalid_argument);
}

// ---- properties ----

struct BadProperty {
  std::string name;
  PropertyValue value;
  std::string message;
};

class ColorBlobDetectorBadProperty : public ::testing::TestWithParam<BadProperty> {};

TEST_P(ColorBlobDetectorBadProperty, FailsInitializeNamingTheProperty) {
  DetectorRig rig;
  const BadProperty& bad = GetParam();
  rig.set(bad.name, bad.value);

  EXPECT_FALSE(rig.initialize());

  EXPECT_EQ(rig.detector.state(), keel::State::Error);
  const auto faults = rig.hooks.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].kind, keel::FaultKind::Exception);
  const std::string detail(faults[0].detailText());
  EXPECT_THAT(detail, HasSubstr("component 'detector': property '" + bad.name + "' "));
  EXPECT_THAT(detail, HasSubstr(bad.message));
}

INSTANTIATE_TEST_SUITE_P(
    ColorBlobDetector, ColorBlobDetectorBadProperty,
    ::testing::Values(BadProperty{"y_min", std::int64_t{-1}, "must be between 0 and 255 (got -1)"},
                      BadProperty{"v_max", std::int64_t{256}, "must be between 0 and 255 (got 256)"},
                      BadProperty{"u_min", std::int64_t{141}, "must not exceed u_max (got 141 > 140)"},
                      BadProperty{"y_max", std::string("high"), "is not an integer"},
                      BadProperty{"min_area", std::int64_t{0}, "must be between 1 and 16777216 (got 0)"},
                      BadProperty{"fov_deg", 0.0, "must be greater than 0 and less than 180"},
                      BadProperty{"fov_deg", 180.0, "must be greater than 0 and less than 180"}),
    [](const ::testing::TestParamInfo<BadProperty>& param) { return param.param.name + std::to_string(param.index); });

TEST(ColorBlobDetector, MinAreaDropsATargetTooFarToBeBigEnough) {
  const World world = World::paperArena();
  DetectorRig rig;
  rig.set("min_area", std::int64_t{1000});
  ASSERT_TRUE(rig.initialize());

  EXPECT_EQ(rig.see(view(world.start())), (BlobReading{0.0, 0.0, 0.0}));
}

// ---- the profile ----

TEST(ColorBlobDetector, ProfileDeclaresTheClassPortsAndDefaults) {
  const auto path = std::filesystem::path(KEEL_ROBOT) / "components/profiles/ColorBlobDetector.xml";
  const auto loaded = profile::load(path.string());
  ASSERT_TRUE(loaded.ok());
  ASSERT_EQ(loaded->components.size(), 1u);
  const profile::ComponentProfile& p = loaded->components.begin()->second;
  ColorBlobDetector detector;

  EXPECT_EQ(p.name, "ColorBlobDetector");
  EXPECT_EQ(p.library_name, "keel_robot");
  EXPECT_EQ(p.execution.type, profile::ExecutionType::Aperiodic);
  const auto& ports = runtime::coreOf(detector).ports;
  ASSERT_EQ(p.data_ports.size(), ports.size());
  for (std::size_t i = 0; i < ports.size(); ++i) {
    EXPECT_EQ(p.data_ports[i].name, ports[i]->name());
    EXPECT_EQ(canonicalTypeName(p.data_ports[i].data_type), ports[i]->typeName());
  }
  EXPECT_EQ(p.data_ports[0].queue_policy, QueuePolicy::Last);
  const YuvBox c = ColorBlobDetector::kDefaultColour;
  const std::vector<std::pair<std::string, PropertyValue>> defaults = {
      {"y_min", std::int64_t{c.y_min}},
      {"y_max", std::int64_t{c.y_max}},
      {"u_min", std::int64_t{c.u_min}},
      {"u_max", std::int64_t{c.u_max}},
      {"v_min", std::int64_t{c.v_min}},
      {"v_max", std::int64_t{c.v_max}},
      {"min_area", std::int64_t{ColorBlobDetector::kDefaultMinArea}},
      {"fov_deg", ColorBlobDetector::kDefaultFovDeg}};
  ASSERT_EQ(p.properties.size(), defaults.size());
  for (std::size_t i = 0; i < defaults.size(); ++i) {
    EXPECT_EQ(p.properties[i].name, defaults[i].first);
    EXPECT_EQ(p.properties[i].value, defaults[i].second) << defaults[i].first;
  }
}

}  // namespace
}  // namespace keel::robot
