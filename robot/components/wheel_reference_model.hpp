// WheelReferenceModel: the reference model of the process-model detector (paper §5.1.3, Fig. 6).
// Gets the wheel targets in effect, one pair per status frame, and publishes what each wheel's
// rpm should be (robot/navigation/wheel_reference.hpp), sample for sample with the measured rpm,
// so the stock SlidingWindowMonitor can compare the two. Thread-safety: a component.
#pragma once

#include <array>
#include <optional>

#include <keel/component.hpp>

#include "robot/navigation/wheel_reference.hpp"

namespace keel::robot {

class WheelReferenceModel : public Component {
 public:
  InputDataPort<std::array<double, 2>> wheel_targets{this, "wheel_targets"};
  OutputDataPort<double> left_reference{this, "left_reference"};
  OutputDataPort<double> right_reference{this, "right_reference"};

  ReturnCode onInitialize() override {
    const auto tau_ms = property<double>("time_constant_ms", 150.0);
    const auto sample_ms = property<double>("sample_ms", 20.0);
    if (!(tau_ms > 0)) rejectProperty("time_constant_ms", "must be > 0");
    if (!(sample_ms > 0)) rejectProperty("sample_ms", "must be > 0");
    model_.emplace(tau_ms / 1000.0, sample_ms / 1000.0);
    return ReturnCode::Ok;
  }

  ReturnCode onExecute() override {
    while (std::optional<std::array<double, 2>> t = wheel_targets.pop()) {
      const auto& rpm = model_->update(*t);
      left_reference.push(rpm[0]);
      right_reference.push(rpm[1]);
    }
    return ReturnCode::Ok;
  }

  ReturnCode onReset() override {
    model_->reset();
    return ReturnCode::Ok;
  }

 private:
  std::optional<WheelReference> model_;
};

}  // namespace keel::robot
