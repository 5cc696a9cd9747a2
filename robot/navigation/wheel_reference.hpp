// The wheel reference model of the process-model detector (paper §5.1.3, Fig. 6): what each
// wheel's rpm should be given the commands sent, a first-order motor response with the drive's
// known time constant. Fed one commanded (left, right) target per status frame; its output goes
// to the sliding-window monitors beside the measured rpm. Pure logic, header-only.
// Thread-safety: none; one owner.
#pragma once

#include <array>
#include <cmath>

namespace keel::robot {

class WheelReference {
 public:
  WheelReference(double time_constant_s, double sample_s) : alpha_(1.0 - std::exp(-sample_s / time_constant_s)) {}

  /// Advances by one sample toward `target` (left, right rpm); returns the modelled rpm.
  const std::array<double, 2>& update(const std::array<double, 2>& target) {
    for (std::size_t w = 0; w < 2; ++w) rpm_[w] += (target[w] - rpm_[w]) * alpha_;
    return rpm_;
  }
  void reset() { rpm_ = {0.0, 0.0}; }
  [[nodiscard]] const std::array<double, 2>& rpm() const { return rpm_; }

 private:
  double alpha_;
  std::array<double, 2> rpm_{};
};

}  // namespace keel::robot
