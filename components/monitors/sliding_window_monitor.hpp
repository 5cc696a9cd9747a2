// keel::components::SlidingWindowMonitor: the paper's process-model fault detector (§5.1.3,
// Fig. 6). A reference model and the monitored component get the same input; their outputs
// arrive here as `target` and `reference`, are filtered over a sliding window, and a `model`
// fault is reported about the monitored component when the filtered target falls below
// `threshold` × the filtered reference (mode `ratio`) or strays more than `threshold` from it
// (mode `absolute`). Registered as "SlidingWindowMonitor" in libkeel_stock; the contract is in
// docs/stock_components.md. Thread-safety: a component; its callbacks are serialised.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>

#include <keel/component.hpp>

#include "moving_average.hpp"

namespace keel::components {

class SlidingWindowMonitor : public Component {
 public:
  enum class Mode { Ratio, Absolute };
  static constexpr std::int64_t kMaxWindow = 1 << 20;

  /// Output of the monitored component (FIFO: every sample counts).
  InputDataPort<double> target{this, "target"};
  /// Output of the reference model, sample for sample with `target`.
  InputDataPort<double> reference{this, "reference"};
  /// Per judged sample: filtered target / filtered reference (ratio mode) or
  /// filtered target - filtered reference (absolute mode).
  OutputDataPort<double> residual{this, "residual"};

  /// Reads and checks the properties and sizes the windows (the only allocation). A bad value
  /// throws keel::PropertyError naming the property, so the load fails with the reason.
  ReturnCode onInitialize() override {
    const auto window = property<std::int64_t>("window", 9);
    threshold_ = property<double>("threshold", 0.5);
    const auto mode = property<std::string>("mode", "ratio");
    const auto min_consecutive = property<std::int64_t>("min_consecutive", 1);
    min_reference_ = property<double>("min_reference", 1.0);
    monitored_ = property<std::string>("monitored", "");

    if (window < 1 || window > kMaxWindow)
      rejectProperty("window",
                     "must be between 1 and " + std::to_string(kMaxWindow) + " (got " + std::to_string(window) + ")");
    if (mode == "ratio") mode_ = Mode::Ratio;
    else if (mode == "absolute") mode_ = Mode::Absolute;
    else rejectProperty("mode", "must be 'ratio' or 'absolute' (got '" + mode + "')");
    if (!std::isfinite(threshold_) || (mode_ == Mode::Ratio && threshold_ <= 0) || threshold_ < 0)
      rejectProperty("threshold",
                     std::string(mode_ == Mode::Ratio ? "must be > 0 in ratio mode" : "must be >= 0 in absolute mode") +
                         " (got " + std::to_string(threshold_) + ")");
    if (min_consecutive < 1)
      rejectProperty("min_consecutive", "must be at least 1 (got " + std::to_string(min_consecutive) + ")");
    if (!std::isfinite(min_reference_) || min_reference_ < 0)
      rejectProperty("min_reference", "must be >= 0 (got " + std::to_string(min_reference_) + ")");
    if (monitored_.size() >= FaultEvent{}.component.size())
      rejectProperty("monitored", "is longer than a fault event can name (" +
                                      std::to_string(FaultEvent{}.component.size() - 1) + " characters)");

    min_consecutive_ = static_cast<std::size_t>(min_consecutive);
    target_avg_.reset(static_cast<std::size_t>(window));
    reference_avg_.reset(static_cast<std::size_t>(window));
    forget();
    return ReturnCode::Ok;
  }

  /// Consumes every complete (target, reference) pair that has arrived, in arrival order.
  ReturnCode onExecute() override {
    while (!target.empty() && !reference.empty()) {  // only this callback pops
      const std::optional<double> t = target.pop();
      const std::optional<double> r = reference.pop();
      if (!t || !r) break;
      step(*t, *r);
    }
    return ReturnCode::Ok;
  }

  /// A reset starts from empty windows and no open fault episode.
  ReturnCode onReset() override {
    forget();
    return ReturnCode::Ok;
  }

 private:
  /// One pair of samples: filter, then judge once both windows are full.
  void step(double t, double r) {
    if (!std::isfinite(t) || !std::isfinite(r)) return;  // not filtered: see the docs
    const double ft = target_avg_.push(t);
    const double fr = reference_avg_.push(r);
    if (!target_avg_.full()) return;  // nothing is judged until the window is full
    if (mode_ == Mode::Ratio && (std::fabs(fr) < min_reference_ || fr == 0.0))
      return;  // reference ~0 (standing still): the ratio says nothing; counters unchanged
    const double value = mode_ == Mode::Ratio ? ft / fr : ft - fr;
    residual.push(value);
    const bool violating = mode_ == Mode::Ratio ? value < threshold_ : std::fabs(value) > threshold_;
    track(violating, ft, fr, value);
  }

  /// One fault per episode: opened after `min_consecutive` violating samples in a row, closed
  /// (re-armed) after `window` non-violating samples in a row.
  void track(bool violating, double ft, double fr, double value) {
    if (violating) {
      clear_run_ = 0;
      ++violating_run_;
      if (!in_episode_ && violating_run_ >= min_consecutive_) {
        in_episode_ = true;
        report(ft, fr, value);
      }
      return;
    }
    violating_run_ = 0;
    if (in_episode_ && ++clear_run_ >= target_avg_.window()) {
      in_episode_ = false;
      clear_run_ = 0;
    }
  }

  void report(double ft, double fr, double value) {
    char detail[192];  // formatted on the stack: no allocation on the fault path
    const std::size_t n = violating_run_;
    const char* plural = n == 1 ? "" : "s";
    if (mode_ == Mode::Ratio)
      std::snprintf(detail, sizeof detail,
                    "filtered target %.4g %s %.4g \u00d7 reference %.4g (ratio %.3g) for %zu "
                    "sample%s (window %zu)",
                    ft, fr > 0 ? "<" : ">", threshold_, fr, value, n, plural, target_avg_.window());
    else
      std::snprintf(detail, sizeof detail,
                    "|filtered target %.4g - reference %.4g| = %.4g > %.4g for %zu sample%s "
                    "(window %zu)",
                    ft, fr, std::fabs(value), threshold_, n, plural, target_avg_.window());
    reportFault(FaultEvent(FaultKind::Model, monitored_, detail));
  }

  void forget() {
    target_avg_.clear();
    reference_avg_.clear();
    violating_run_ = clear_run_ = 0;
    in_episode_ = false;
  }

  // configuration (onInitialize)
  Mode mode_ = Mode::Ratio;
  double threshold_ = 0.5;
  double min_reference_ = 1.0;
  std::size_t min_consecutive_ = 1;
  std::string monitored_;
  // state
  MovingAverage target_avg_;
  MovingAverage reference_avg_;
  std::size_t violating_run_ = 0;  // judged violating samples in a row
  std::size_t clear_run_ = 0;      // judged non-violating samples in a row, during an episode
  bool in_episode_ = false;        // a fault was reported and has not cleared yet
};

}  // namespace keel::components
