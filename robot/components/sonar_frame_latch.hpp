// SonarFrameLatch: the obstacle-avoidance task's first member. It takes the board's newest sonar
// frame once per cycle and hands that one frame to the task's three sonars, which run right
// after it on the same thread. The motion task pushes frames from another thread; without the
// latch each sonar took the newest frame when its own turn came, and a frame pushed between two
// sonars' turns gave them different frames in one cycle — near an obstacle's edge, a real
// disagreement for the voter. A frame pushed mid-cycle now waits for the next cycle.
// Thread-safety: a component.
#pragma once

#include <array>
#include <optional>

#include <keel/component.hpp>

namespace keel::robot {

class SonarFrameLatch : public Component {
 public:
  InputDataPort<std::array<double, 4>> in{this, "in"};
  OutputDataPort<std::array<double, 4>> out{this, "out"};

  ReturnCode onExecute() override {
    std::optional<std::array<double, 4>> newest;
    while (auto s = in.pop()) newest = s;
    if (newest) out.push(*newest);
    return ReturnCode::Ok;
  }
};

}  // namespace keel::robot
