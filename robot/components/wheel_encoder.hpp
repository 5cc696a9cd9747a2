// WheelEncoder and RateGyro: the odometry sensors of the test robot, read by instances of their
// own (encoder_left, encoder_right, gyro) so that a fault of one is told apart from the
// actuator's, which drives the motors (docs/robot.md, "Diagnosis by state estimation").
// WheelEncoder picks its wheel's count (`index`) out of each status frame's counts and publishes
// the wheel's speed over the frame in rpm; RateGyro publishes each frame's yaw rate in rad/s.
// Each publishes once per status frame, so that a consumer pairing them with the frame's other
// samples stays in step: on the first frame after a start or a reset the encoder, which needs two
// counts, publishes NaN (no reading). Thread-safety: components.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include <keel/component.hpp>

namespace keel::robot {

class WheelEncoder : public Component {
 public:
  /// The (left, right) encoder counts of each status frame (FIFO: every frame counts).
  InputDataPort<std::array<double, 2>> counts{this, "counts"};
  /// The wheel's mean speed over the frame, rpm; NaN on the first frame.
  OutputDataPort<double> rpm{this, "rpm"};

  ReturnCode onInitialize() override {
    const auto index = property<std::int64_t>("index", 0);
    if (index < 0 || index > 1)
      rejectProperty("index", "must be 0 (left) or 1 (right) (got " + std::to_string(index) + ")");
    const auto per_rev = property<std::int64_t>("counts_per_revolution", 360);
    if (per_rev < 1) rejectProperty("counts_per_revolution", "must be >= 1 (got " + std::to_string(per_rev) + ")");
    const auto period_ms = property<double>("period", 20.0);
    if (!(period_ms > 0)) rejectProperty("period", "must be > 0 ms (got " + std::to_string(period_ms) + ")");
    index_ = static_cast<std::size_t>(index);
    per_count_ = 60.0 / (static_cast<double>(per_rev) * period_ms / 1000.0);
    last_.reset();
    return ReturnCode::Ok;
  }

  ReturnCode onExecute() override {
    while (auto frame = counts.pop()) {
      const auto now = static_cast<std::int32_t>(static_cast<std::int64_t>((*frame)[index_]));
      if (!last_) {
        rpm.push(std::numeric_limits<double>::quiet_NaN());
      } else {
        // A 32-bit counter: the difference in unsigned arithmetic is right across a wrap.
        const auto d = static_cast<std::int32_t>(static_cast<std::uint32_t>(now) - static_cast<std::uint32_t>(*last_));
        rpm.push(d * per_count_);
      }
      last_ = now;
    }
    return ReturnCode::Ok;
  }

  ReturnCode onReset() override {
    last_.reset();
    return ReturnCode::Ok;
  }

 private:
  std::size_t index_ = 0;
  double per_count_ = 60.0 / (360 * 0.02);
  std::optional<std::int32_t> last_;
};

class RateGyro : public Component {
 public:
  /// Each status frame's gyro reading, mrad/s (FIFO).
  InputDataPort<double> raw{this, "raw"};
  /// The yaw rate, rad/s, counter-clockwise positive.
  OutputDataPort<double> yaw_rate{this, "yaw_rate"};

  ReturnCode onExecute() override {
    while (auto r = raw.pop()) yaw_rate.push(*r / 1000.0);
    return ReturnCode::Ok;
  }
};

}  // namespace keel::robot
