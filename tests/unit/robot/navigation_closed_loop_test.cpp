// The test robot's navigation logic in closed loop with the simulator, in simulated time (no
// keel runtime, no clock): the same pieces the components run — the three front sonars voted by
// median, the primary (or secondary) obstacle filter, the camera and colour segmenter, the
// navigator — at the components' rates (board 20 ms, planner 50 ms, camera 100 ms). It pins the
// nominal behaviour the robot scenarios rely on: the paper arena's target reached without a
// collision, for many seeds and with sonar and pixel noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "robot/components/vision/color_blob_detector.hpp"
#include "robot/components/vision/color_segmenter.hpp"
#include "robot/navigation/navigator.hpp"
#include "robot/navigation/obstacle_filter.hpp"
#include "robot/sim/sim_host.hpp"

namespace keel::robot {
namespace {

struct Outcome {
  bool goal = false;
  double collisions = 0;
  double min_clearance_m = 0;
  double distance_to_target_m = 0;
  double time_s = 0;
};

template <class Filter>
Outcome drive(std::uint64_t seed, double sonar_noise_cm, double pixel_noise, double max_s = 60.0) {
  SimHostConfig sim_config;
  sim_config.seed = seed;
  sim_config.sonar_noise_cm = sonar_noise_cm;
  SimHost host(sim_config);
  CameraConfig cam_config;
  cam_config.seed = seed;
  cam_config.noise_sigma = pixel_noise;
  Camera camera(cam_config);
  ColorSegmenter segmenter(ColorBlobDetector::kDefaultColour, ColorBlobDetector::kDefaultMinArea);
  Filter filter;
  Navigator nav;
  Outcome out;
  for (int ms = 20; ms <= max_s * 1000; ms += 10) {
    if (ms % 20 == 0) {
      (void)host.step(0.020);
      const Simulator& sim = host.board().simulator();
      std::array<double, 3> front{};
      for (std::size_t i = 0; i < 3; ++i) front[i] = sim.sonarCm(static_cast<SonarId>(i));
      std::sort(front.begin(), front.end());
      nav.onObstacle(filter.update(front[1]));
    }
    if (ms % 100 == 0) {
      const Image frame = camera.render(host.world(), host.board().simulator().pose());
      const auto regions = segmenter.segment(frame);
      if (regions.empty()) nav.onBlob(BlobInfo{});
      else
        nav.onBlob(BlobInfo{static_cast<double>(regions.front().area),
                            ColorBlobDetector::bearingDeg(regions.front().cx, frame.w, 60.0),
                            static_cast<double>(regions.front().height())});
    }
    if (ms % 50 == 0) {
      const auto before = nav.mode();
      const MotionCommand c = nav.decide(0.05);
      if (std::getenv("NAV_TRACE") && (nav.mode() != before || ms % 1000 == 0)) {
        const TruthSample& t = host.truth();
        std::printf("%5d ms %-7s (%.2f, %.2f) h %.0f deg, cmd %d/%d\n", ms, toString(nav.mode()), t.x_m, t.y_m,
                    t.heading_rad * 57.3, static_cast<int>(c.type), c.parameter);
      }
      host.onBytes(encode(c));
      if (nav.mode() == Navigator::Mode::Goal && std::fabs(host.truth().rpm_left) < 0.5) break;
    }
  }
  const TruthSample& t = host.truth();
  out.goal = nav.mode() == Navigator::Mode::Goal;
  out.collisions = t.collisions;
  out.min_clearance_m = t.min_clearance_m;
  out.distance_to_target_m = std::hypot(t.x_m - host.world().target().x_m, t.y_m - host.world().target().y_m);
  out.time_s = t.t_s;
  return out;
}

TEST(NavigationClosedLoop, ThePrimaryAvoiderReachesTheTargetWithoutCollisionForManySeeds) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Outcome o = drive<PrimaryObstacleFilter>(seed, 1.0, 6.0);
    EXPECT_TRUE(o.goal) << "seed " << seed;
    EXPECT_EQ(o.collisions, 0) << "seed " << seed;
    EXPECT_LT(o.distance_to_target_m, 0.8) << "seed " << seed;
    EXPECT_GT(o.min_clearance_m, 0.03) << "seed " << seed;
    EXPECT_LT(o.time_s, 30.0) << "seed " << seed;
    std::printf("seed %llu: goal %d t %.1f s, clearance %.3f m, distance %.2f m\n",
                static_cast<unsigned long long>(seed), o.goal, o.time_s, o.min_clearance_m, o.distance_to_target_m);
  }
}

TEST(NavigationClosedLoop, TheSecondaryAvoiderAlsoReachesTheTarget) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Outcome o = drive<SecondaryObstacleFilter>(seed, 1.0, 6.0);
    EXPECT_TRUE(o.goal) << "seed " << seed;
    EXPECT_EQ(o.collisions, 0) << "seed " << seed;
  }
}

}  // namespace
}  // namespace keel::robot
