// UltrasonicSensor: one sonar of the test robot (paper Fig. 5). Picks its reading (`index`) out
// of the board's status frame and publishes it as a range in cm. It does no checking of its own:
// the profile's <validity> 3..3000 on `range` makes an unplugged sonar's 0 a `range` fault on
// the spot (paper §5.1.2). Thread-safety: a component.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include <keel/component.hpp>

namespace keel::robot {

class UltrasonicSensor : public Component {
 public:
  InputDataPort<std::array<double, 4>> sonars{this, "sonars"};
  OutputDataPort<double> range{this, "range"};

  ReturnCode onInitialize() override {
    const auto index = property<std::int64_t>("index", 0);
    if (index < 0 || index > 3) rejectProperty("index", "must be 0..3 (got " + std::to_string(index) + ")");
    index_ = static_cast<std::size_t>(index);
    return ReturnCode::Ok;
  }

  ReturnCode onExecute() override {
    std::optional<std::array<double, 4>> newest;
    while (auto s = sonars.pop()) newest = s;
    if (newest) range.push((*newest)[index_]);
    return ReturnCode::Ok;
  }

 private:
  std::size_t index_ = 0;
};

}  // namespace keel::robot
