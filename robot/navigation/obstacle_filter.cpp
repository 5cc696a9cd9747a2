// The primary obstacle filter: median of the last kWindow ranges, blocked with hysteresis.
#include "robot/navigation/obstacle_filter.hpp"

#include <algorithm>

namespace keel::robot {

ObstacleInfo PrimaryObstacleFilter::update(double range_cm) {
  State& s = state_;
  s.window[s.next] = range_cm;
  s.next = (s.next + 1) % kWindow;
  ++s.count;
  const std::size_t n = std::min<std::size_t>(s.count, kWindow);
  std::array<double, kWindow> sorted = s.window;
  std::sort(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(n));
  const double filtered = sorted[n / 2];
  if (filtered < config_.block_cm) s.blocked = true;
  else if (filtered > config_.clear_cm) s.blocked = false;
  return ObstacleInfo{filtered, s.blocked};
}

}  // namespace keel::robot
