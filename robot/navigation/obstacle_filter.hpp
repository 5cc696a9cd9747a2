// The obstacle-avoidance algorithms of the test robot (paper Fig. 5 and §5.3): they filter the
// (voted) range ahead into what the path planner needs — the distance and whether the way is
// blocked. The primary algorithm is stateful (a median over the last samples and a blocked flag
// with hysteresis): exactly the state a reset must restore from its checkpoint (§5.3.1). The
// secondary, the backup that replaces it (§5.3.2), is a plain threshold on the latest sample.
// Pure logic: the ObstacleAvoidance components feed them. Thread-safety: none; one owner.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "robot/navigation/navigator.hpp"

namespace keel::robot {

struct ObstacleFilterConfig {
  double block_cm = 45.0;  // blocked when the filtered range falls below this...
  double clear_cm = 70.0;  // ...and clear again only above this
};

class PrimaryObstacleFilter {
 public:
  static constexpr std::size_t kWindow = 5;

  /// Everything the filter knows: trivially copyable, registered as critical memory.
  struct State {
    std::array<double, kWindow> window{};
    std::uint32_t count = 0;  // samples seen (the window is full from kWindow on)
    std::uint32_t next = 0;   // ring index
    bool blocked = false;
  };

  explicit PrimaryObstacleFilter(ObstacleFilterConfig config = {}) : config_(config) {}

  /// One range sample (cm); returns the information for the planner.
  ObstacleInfo update(double range_cm);

  [[nodiscard]] State& state() { return state_; }
  [[nodiscard]] const State& state() const { return state_; }

 private:
  ObstacleFilterConfig config_;
  State state_;
};

class SecondaryObstacleFilter {
 public:
  explicit SecondaryObstacleFilter(ObstacleFilterConfig config = {}) : config_(config) {}

  ObstacleInfo update(double range_cm) const {
    return ObstacleInfo{range_cm, range_cm < (config_.block_cm + config_.clear_cm) / 2};
  }

 private:
  ObstacleFilterConfig config_;
};

}  // namespace keel::robot
