// SlidingWindowMonitor (components/monitors): the paper's process-model detector, tested as a
// class: properties set as the runtime sets them, inputs fed through connected output ports,
// onExecute called directly, faults captured by RecordingHooks. Expected fault instants are
// computed here from a naive moving average (sum of the last W samples / W), independently of
// the monitor's ring buffer.
#include "components/monitors/sliding_window_monitor.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "runtime/component_core.hpp"
#include "runtime/invoke.hpp"
#include "support/recording_hooks.hpp"

namespace keel {
namespace {

using components::SlidingWindowMonitor;
using ::testing::HasSubstr;

class Feeder : public Component {
 public:
  OutputDataPort<double> target{this, "target"};
  OutputDataPort<double> reference{this, "reference"};
};

class Probe : public Component {
 public:
  InputDataPort<double> residual{this, "residual"};
};

/// A monitor named "monitor", its inputs fed by a Feeder, its residual read by a Probe.
class MonitorRig {
 public:
  MonitorRig() {
    test::manage(monitor, "monitor", hooks);
    test::configureQueue(monitor.target, QueuePolicy::Fifo, 64);  // as the profile says
    test::configureQueue(monitor.reference, QueuePolicy::Fifo, 64);
    test::configureQueue(probe.residual, QueuePolicy::UFifo, 1024);
    test::wire(feeder.target, monitor.target, keep_);
    test::wire(feeder.reference, monitor.reference, keep_);
    test::wire(monitor.residual, probe.residual, keep_);
  }
  void set(const std::string& name, PropertyValue value) {
    runtime::coreOf(monitor).properties[name] = std::move(value);
  }
  bool initialize() { return runtime::transition(monitor, Transition::Initialize); }
  /// One pair of samples, then one execution.
  void feed(double target, double reference) {
    feeder.target.push(target);
    feeder.reference.push(reference);
    EXPECT_EQ(monitor.onExecute(), ReturnCode::Ok);
  }
  std::vector<FaultEvent> faults() const { return hooks.faults(); }
  std::vector<double> residuals() {
    std::vector<double> out;
    while (auto v = probe.residual.pop()) out.push_back(*v);
    return out;
  }

  test::RecordingHooks hooks;
  SlidingWindowMonitor monitor;
  Feeder feeder;
  Probe probe;

 private:
  std::vector<std::unique_ptr<detail::ConnectionBase>> keep_;
};

/// Naive moving average of x[i-w+1 .. i] (requires i + 1 >= w).
double windowMean(const std::vector<double>& x, std::size_t i, std::size_t w) {
  return std::accumulate(x.begin() + static_cast<std::ptrdiff_t>(i + 1 - w),
                         x.begin() + static_cast<std::ptrdiff_t>(i + 1), 0.0) /
         static_cast<double>(w);
}

std::string detailOf(const FaultEvent& f) { return std::string(f.detailText()); }

// ---- the paper's experiment (Fig. 6) ----

TEST(SlidingWindowMonitor, ReportsOneModelFaultWhenTheWheelDecaysBelowHalfTheReference) {
  // Arrange: reference 120 rpm; the driver is switched off at sample 100 and the wheel's rpm
  // decays (inertia) from 120 towards 20.
  constexpr std::size_t kWindow = 9;
  constexpr std::size_t kSamples = 400;
  std::vector<double> reference(kSamples, 120.0);
  std::vector<double> target(kSamples, 120.0);
  for (std::size_t i = 100; i < kSamples; ++i)
    target[i] = 20.0 + 100.0 * std::exp(-static_cast<double>(i - 100) / 12.0);
  std::optional<std::size_t> expected;
  for (std::size_t i = kWindow - 1; i < kSamples && !expected; ++i)
    if (windowMean(target, i, kWindow) < 0.5 * windowMean(reference, i, kWindow)) expected = i;
  ASSERT_TRUE(expected.has_value());
  const double margin = windowMean(target, *expected, kWindow) - 60.0;
  ASSERT_GT(std::fabs(margin), 1e-6) << "the crossing must not sit on the threshold";

  MonitorRig rig;
  rig.set("window", std::int64_t{9});
  rig.set("threshold", 0.5);
  rig.set("mode", std::string("ratio"));
  rig.set("monitored", std::string("left_driver"));
  ASSERT_TRUE(rig.initialize());

  // Act
  std::optional<std::size_t> reported_at;
  for (std::size_t i = 0; i < kSamples; ++i) {
    rig.feed(target[i], reference[i]);
    if (!reported_at && !rig.faults().empty()) reported_at = i;
  }

  // Assert: exactly one fault, at the first sample where the filtered condition holds.
  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(reported_at, expected);
  EXPECT_EQ(faults[0].kind, FaultKind::Model);
  EXPECT_EQ(faults[0].componentName(), "left_driver");
  EXPECT_THAT(detailOf(faults[0]), HasSubstr("filtered target "));
  EXPECT_THAT(detailOf(faults[0]), HasSubstr("< 0.5 \u00d7 reference 120 "));
  EXPECT_THAT(detailOf(faults[0]), HasSubstr("for 1 sample (window 9)"));
}

TEST(SlidingWindowMonitor, StaysSilentOnNoisyButEqualSignals) {
  // Arrange: both signals 120 rpm with independent N(0, 5) noise.
  std::mt19937 rng(20110321);
  std::normal_distribution<double> noise(0.0, 5.0);
  MonitorRig rig;
  rig.set("monitored", std::string("left_driver"));
  ASSERT_TRUE(rig.initialize());

  // Act
  for (int i = 0; i < 10000; ++i) {
    rig.feed(120.0 + noise(rng), 120.0 + noise(rng));
    if (i % 500 == 0) rig.residuals();  // keep the probe's queue small
  }

  // Assert
  EXPECT_TRUE(rig.faults().empty());
}

TEST(SlidingWindowMonitor, StaysSilentOnNoisyButEqualSignalsInAbsoluteMode) {
  std::mt19937 rng(42);
  std::normal_distribution<double> noise(0.0, 5.0);
  MonitorRig rig;
  rig.set("mode", std::string("absolute"));
  rig.set("threshold", 15.0);  // the filtered difference has sigma 5 * sqrt(2 / 9) = 2.4
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 10000; ++i) {
    rig.feed(120.0 + noise(rng), 120.0 + noise(rng));
    if (i % 500 == 0) rig.residuals();
  }

  EXPECT_TRUE(rig.faults().empty());
}

// ---- the window, consecutive samples and episodes ----

TEST(SlidingWindowMonitor, JudgesNothingUntilTheWindowIsFull) {
  MonitorRig rig;
  rig.set("window", std::int64_t{9});
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 8; ++i) rig.feed(0.0, 120.0);  // violating, but only 8 of 9 samples

  EXPECT_TRUE(rig.faults().empty());
  EXPECT_TRUE(rig.residuals().empty());

  rig.feed(0.0, 120.0);  // the ninth fills the window

  EXPECT_EQ(rig.faults().size(), 1u);
  EXPECT_EQ(rig.residuals(), std::vector<double>{0.0});  // ratio 0 / 120
}

TEST(SlidingWindowMonitor, WaitsForMinConsecutiveViolatingSamples) {
  MonitorRig rig;
  rig.set("window", std::int64_t{1});
  rig.set("min_consecutive", std::int64_t{3});
  ASSERT_TRUE(rig.initialize());

  rig.feed(10.0, 100.0);
  rig.feed(10.0, 100.0);
  rig.feed(100.0, 100.0);  // the run of two is broken
  rig.feed(10.0, 100.0);
  rig.feed(10.0, 100.0);
  EXPECT_TRUE(rig.faults().empty());

  rig.feed(10.0, 100.0);  // third in a row

  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_THAT(detailOf(faults[0]), HasSubstr("for 3 samples (window 1)"));
}

TEST(SlidingWindowMonitor, ReArmsOnlyAfterAWindowOfCleanSamples) {
  // Window 3, reference 100, threshold 0.5: a step of the raw target between 100 (good) and
  // 0 (bad) moves the filtered target through 33 and 67, so g good raw samples followed by bad
  // ones give g clean judged samples (the last is the first bad raw sample, filtered 67).
  MonitorRig rig;
  rig.set("window", std::int64_t{3});
  ASSERT_TRUE(rig.initialize());
  auto run = [&](double value, int n) {
    for (int i = 0; i < n; ++i) rig.feed(value, 100.0);
  };

  run(100.0, 3);
  run(0.0, 5);
  ASSERT_EQ(rig.faults().size(), 1u);

  run(100.0, 2);  // 2 clean samples < window: the episode stays open
  run(0.0, 5);
  EXPECT_EQ(rig.faults().size(), 1u);

  run(100.0, 3);  // 3 clean samples = window: re-armed
  run(0.0, 5);
  EXPECT_EQ(rig.faults().size(), 2u);
}

// ---- modes and guards ----

TEST(SlidingWindowMonitor, AbsoluteModeReportsADifferenceBeyondTheThreshold) {
  MonitorRig rig;
  rig.set("window", std::int64_t{5});
  rig.set("mode", std::string("absolute"));
  rig.set("threshold", 10.0);
  rig.set("monitored", std::string("odometry"));
  ASSERT_TRUE(rig.initialize());
  for (int i = 0; i < 5; ++i) rig.feed(100.0, 100.0);
  rig.residuals();

  rig.feed(130.0, 100.0);  // filtered target 106: within 10
  EXPECT_TRUE(rig.faults().empty());
  rig.feed(130.0, 100.0);  // filtered target 112

  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].kind, FaultKind::Model);
  EXPECT_EQ(faults[0].componentName(), "odometry");
  EXPECT_EQ(detailOf(faults[0]), "|filtered target 112 - reference 100| = 12 > 10 for 1 sample (window 5)");
  const auto residuals = rig.residuals();
  ASSERT_EQ(residuals.size(), 2u);
  EXPECT_NEAR(residuals[0], 6.0, 1e-9);  // filtered target - filtered reference
  EXPECT_NEAR(residuals[1], 12.0, 1e-9);
}

TEST(SlidingWindowMonitor, AbsoluteModeAlsoReportsATargetAboveTheReference) {
  MonitorRig rig;
  rig.set("window", std::int64_t{1});
  rig.set("mode", std::string("absolute"));
  rig.set("threshold", 10.0);
  ASSERT_TRUE(rig.initialize());

  rig.feed(80.0, 100.0);

  ASSERT_EQ(rig.faults().size(), 1u);
}

TEST(SlidingWindowMonitor, DoesNotJudgeTheRatioWhileTheReferenceIsNearZero) {
  // The robot stands still: reference below min_reference (default 1.0), target 0.
  MonitorRig rig;
  rig.set("window", std::int64_t{3});
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 100; ++i) rig.feed(0.0, i % 2 ? 0.5 : 0.0);

  EXPECT_TRUE(rig.faults().empty());
  EXPECT_TRUE(rig.residuals().empty());  // no ratio is defined

  for (int i = 0; i < 3; ++i) rig.feed(0.0, 120.0);  // it drives; the wheel does not turn

  EXPECT_EQ(rig.faults().size(), 1u);
}

TEST(SlidingWindowMonitor, RatioModeWorksWhenDrivingBackwards) {
  MonitorRig rig;
  rig.set("window", std::int64_t{1});
  ASSERT_TRUE(rig.initialize());

  rig.feed(-118.0, -120.0);  // healthy: ratio ~1
  EXPECT_TRUE(rig.faults().empty());
  rig.feed(-20.0, -120.0);  // ratio 0.17

  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_THAT(detailOf(faults[0]), HasSubstr("filtered target -20 > 0.5 \u00d7 reference -120"));
}

TEST(SlidingWindowMonitor, FaultIsAboutTheMonitorItselfWhenNothingIsMonitored) {
  MonitorRig rig;
  rig.set("window", std::int64_t{1});
  ASSERT_TRUE(rig.initialize());

  rig.feed(0.0, 100.0);

  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].componentName(), "monitor");
}

TEST(SlidingWindowMonitor, SkipsPairsWithANonFiniteSample) {
  MonitorRig rig;
  rig.set("window", std::int64_t{2});
  ASSERT_TRUE(rig.initialize());

  rig.feed(100.0, 100.0);
  rig.feed(std::numeric_limits<double>::quiet_NaN(), 100.0);
  rig.feed(100.0, std::numeric_limits<double>::infinity());
  rig.feed(100.0, 100.0);

  EXPECT_TRUE(rig.faults().empty());
  EXPECT_EQ(rig.residuals(), std::vector<double>{1.0});  // only the two finite pairs counted
}

TEST(SlidingWindowMonitor, PairsSamplesInArrivalOrderAcrossExecutions) {
  MonitorRig rig;
  rig.set("window", std::int64_t{1});
  ASSERT_TRUE(rig.initialize());

  for (double t : {100.0, 10.0, 100.0}) rig.feeder.target.push(t);
  ASSERT_EQ(rig.monitor.onExecute(), ReturnCode::Ok);  // no reference yet: nothing judged
  EXPECT_TRUE(rig.residuals().empty());
  for (int i = 0; i < 3; ++i) rig.feeder.reference.push(100.0);
  ASSERT_EQ(rig.monitor.onExecute(), ReturnCode::Ok);  // all three pairs in one execution

  EXPECT_EQ(rig.residuals(), (std::vector<double>{1.0, 0.1, 1.0}));
  EXPECT_EQ(rig.faults().size(), 1u);
}

TEST(SlidingWindowMonitor, ResetStartsFromEmptyWindows) {
  MonitorRig rig;
  rig.set("window", std::int64_t{4});
  ASSERT_TRUE(rig.initialize());
  for (int i = 0; i < 4; ++i) rig.feed(0.0, 100.0);
  ASSERT_EQ(rig.faults().size(), 1u);

  ASSERT_EQ(rig.monitor.onReset(), ReturnCode::Ok);
  for (int i = 0; i < 3; ++i) rig.feed(0.0, 100.0);  // window not full again yet
  EXPECT_EQ(rig.faults().size(), 1u);
  rig.feed(0.0, 100.0);  // full again, and the old episode was forgotten

  EXPECT_EQ(rig.faults().size(), 2u);
}

// ---- properties ----

struct BadProperty {
  std::string name;
  PropertyValue value;
  std::string message;
};

class SlidingWindowMonitorBadProperty : public ::testing::TestWithParam<BadProperty> {};

TEST_P(SlidingWindowMonitorBadProperty, FailsInitializeNamingTheProperty) {
  MonitorRig rig;
  const BadProperty& bad = GetParam();
  if (bad.name == "threshold" && bad.message.find("absolute") != std::string::npos)
    rig.set("mode", std::string("absolute"));
  rig.set(bad.name, bad.value);

  EXPECT_FALSE(rig.initialize());

  EXPECT_EQ(rig.monitor.state(), State::Error);
  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].kind, FaultKind::Exception);
  EXPECT_THAT(detailOf(faults[0]), HasSubstr("component 'monitor': property '" + bad.name + "' "));
  EXPECT_THAT(detailOf(faults[0]), HasSubstr(bad.message));
}

INSTANTIATE_TEST_SUITE_P(
    SlidingWindowMonitor, SlidingWindowMonitorBadProperty,
    ::testing::Values(BadProperty{"window", std::int64_t{0}, "must be between 1 and 1048576 (got 0)"},
                      BadProperty{"window", std::string("nine"), "is not an integer"},
                      BadProperty{"mode", std::string("relative"), "must be 'ratio' or 'absolute' (got 'relative')"},
                      BadProperty{"threshold", 0.0, "must be > 0 in ratio mode"},
                      BadProperty{"threshold", -1.0, "must be >= 0 in absolute mode"},
                      BadProperty{"min_consecutive", std::int64_t{0}, "must be at least 1 (got 0)"},
                      BadProperty{"min_reference", -1.0, "must be >= 0"},
                      BadProperty{"monitored", std::string(64, 'x'), "is longer than a fault event can name"}),
    [](const ::testing::TestParamInfo<BadProperty>& param) { return param.param.name + std::to_string(param.index); });

TEST(SlidingWindowMonitor, UsesThePaperDefaultsWithoutProperties) {
  // window 9, threshold 0.5, ratio mode, min_consecutive 1.
  MonitorRig rig;
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 8; ++i) rig.feed(59.0, 120.0);
  EXPECT_TRUE(rig.faults().empty());
  rig.feed(59.0, 120.0);

  EXPECT_EQ(rig.faults().size(), 1u);
}

}  // namespace
}  // namespace keel
