// StateEstimator (components/estimators): diagnosis by state estimation, tested as a class:
// properties set as the runtime sets them, samples fed through connected output ports,
// onExecute called directly, faults captured by RecordingHooks. The filter is checked against
// closed forms computed here (a constant observed twice, a scalar filter's steady state, the
// chi-square quantiles of a table); isolation against a plant simulated here with the model's
// own noise, faulted one way at a time.
#include "components/estimators/state_estimator.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "runtime/component_core.hpp"
#include "runtime/invoke.hpp"
#include "support/recording_hooks.hpp"

namespace keel {
namespace {

using components::StateEstimator;
using ::testing::HasSubstr;

class Feeder : public Component {
 public:
  std::array<OutputDataPort<double>, 2> u{{{this, "u0"}, {this, "u1"}}};
  std::array<OutputDataPort<double>, 3> y{{{this, "y0"}, {this, "y1"}, {this, "y2"}}};
};

class Probe : public Component {
 public:
  std::array<InputDataPort<double>, 3> estimate{{{this, "estimate0"}, {this, "estimate1"}, {this, "estimate2"}}};
  InputDataPort<double> statistic{this, "statistic"};
  InputDataPort<double> threshold{this, "threshold"};
};

/// An estimator named "estimator" with `inputs` inputs and `measurements` measurements fed by a
/// Feeder, its outputs read by a Probe (the newest value of each).
class Rig {
 public:
  Rig(int inputs, int measurements) : inputs_(inputs), measurements_(measurements) {
    test::manage(est, "estimator", hooks);
    for (int i = 0; i < inputs; ++i) {
      test::configureQueue(est.u[static_cast<std::size_t>(i)], QueuePolicy::Fifo, 64);
      test::wire(feeder.u[static_cast<std::size_t>(i)], est.u[static_cast<std::size_t>(i)], keep_);
    }
    for (int i = 0; i < measurements; ++i) {
      test::configureQueue(est.y[static_cast<std::size_t>(i)], QueuePolicy::Fifo, 64);
      test::wire(feeder.y[static_cast<std::size_t>(i)], est.y[static_cast<std::size_t>(i)], keep_);
      test::configureQueue(probe.estimate[static_cast<std::size_t>(i)], QueuePolicy::Last, 1);
      test::wire(est.estimate[static_cast<std::size_t>(i)], probe.estimate[static_cast<std::size_t>(i)], keep_);
    }
    test::configureQueue(probe.statistic, QueuePolicy::Last, 1);
    test::configureQueue(probe.threshold, QueuePolicy::Last, 1);
    test::wire(est.statistic, probe.statistic, keep_);
    test::wire(est.threshold, probe.threshold, keep_);
  }
  void set(const std::string& name, PropertyValue value) { runtime::coreOf(est).properties[name] = std::move(value); }
  bool initialize() { return runtime::transition(est, Transition::Initialize); }
  std::string refusal() const { return runtime::coreOf(est).refused_text; }
  std::string refusedProperty() const { return runtime::coreOf(est).refused_property; }
  /// One sample (inputs, then measurements; NaN: that measurement does not arrive), one execution.
  void feed(const std::vector<double>& u, const std::vector<double>& y) {
    for (int i = 0; i < inputs_; ++i) feeder.u[static_cast<std::size_t>(i)].push(u[static_cast<std::size_t>(i)]);
    for (int i = 0; i < measurements_; ++i)
      if (!std::isnan(y[static_cast<std::size_t>(i)]))
        feeder.y[static_cast<std::size_t>(i)].push(y[static_cast<std::size_t>(i)]);
    EXPECT_EQ(est.onExecute(), ReturnCode::Ok);
  }
  double estimate(int i) { return *probe.estimate[static_cast<std::size_t>(i)].peek(); }
  double statistic() const { return *probe.statistic.peek(); }
  double threshold() const { return *probe.threshold.peek(); }
  std::vector<FaultEvent> faults() const { return hooks.faults(); }

  test::RecordingHooks hooks;
  StateEstimator est;
  Feeder feeder;
  Probe probe;

 private:
  int inputs_;
  int measurements_;
  std::vector<std::unique_ptr<detail::ConnectionBase>> keep_;
};

// ---- the filter against closed forms ----------------------------------------------------------

// A constant (A = 1, Q = 0) seen by two sensors of variances r1, r2, from x0 = 0 with variance p0:
// after k samples the estimate is the precision-weighted mean, P_k = 1 / (1/p0 + k/r1 + k/r2),
// x_k = P_k (Σ y1 / r1 + Σ y2 / r2).
TEST(StateEstimator, AConstantSeenTwiceIsThePrecisionWeightedMeanOfEverySample) {
  Rig rig(0, 2);
  rig.set("states", std::string("level"));
  rig.set("measurements", std::string("a.out b.out"));
  rig.set("A", std::string("1"));
  rig.set("C", std::string("1; 1"));
  rig.set("Q", std::string("0"));
  rig.set("R", std::string("4 9"));
  rig.set("P0", std::string("100"));
  rig.set("false_alarm", 1e-9);
  rig.set("actuator", std::string("plant"));
  ASSERT_TRUE(rig.initialize()) << rig.refusal();
  const double p0 = 100, r1 = 4, r2 = 9;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n1(0, 2), n2(0, 3);
  double s1 = 0, s2 = 0;
  for (int k = 1; k <= 50; ++k) {
    const double y1 = 5 + n1(rng), y2 = 5 + n2(rng);
    s1 += y1;
    s2 += y2;
    rig.feed({}, {y1, y2});
    const double pk = 1 / (1 / p0 + k / r1 + k / r2);
    EXPECT_NEAR(rig.estimate(0), pk * (s1 / r1 + s2 / r2), 1e-9) << "sample " << k;
    EXPECT_DOUBLE_EQ(rig.estimate(0), rig.estimate(1));  // both see the one state
  }
  EXPECT_TRUE(rig.faults().empty());
}

// y = C x + D u: what a measurement sees of the inputs directly is taken off before the update.
// The constant above, an input u = 3 that moves nothing (B = 0), the first sensor seeing 2 u
// besides the state: the estimate of the state is the same weighted mean of y1 - 6 and y2, and
// the first measurement's estimate is it plus 6.
TEST(StateEstimator, WhatAMeasurementSeesOfTheInputsDirectlyIsTakenOffBeforeTheUpdate) {
  Rig rig(1, 2);
  rig.set("states", std::string("level"));
  rig.set("inputs", std::string("u"));
  rig.set("measurements", std::string("a.out b.out"));
  rig.set("A", std::string("1"));
  rig.set("B", std::string("0"));
  rig.set("C", std::string("1; 1"));
  rig.set("D", std::string("2; 0"));
  rig.set("Q", std::string("0"));
  rig.set("R", std::string("4 9"));
  rig.set("P0", std::string("100"));
  rig.set("actuator", std::string("plant"));
  ASSERT_TRUE(rig.initialize()) << rig.refusal();
  const double p0 = 100, r1 = 4, r2 = 9;
  std::mt19937_64 rng(8);
  std::normal_distribution<double> n1(0, 2), n2(0, 3);
  double s1 = 0, s2 = 0;
  for (int k = 1; k <= 20; ++k) {
    const double y1 = 5 + 6 + n1(rng), y2 = 5 + n2(rng);
    s1 += y1 - 6;
    s2 += y2;
    rig.feed({3.0}, {y1, y2});
    const double x = (s1 / r1 + s2 / r2) / (1 / p0 + k / r1 + k / r2);
    EXPECT_NEAR(rig.estimate(1), x, 1e-9) << "sample " << k;
    EXPECT_NEAR(rig.estimate(0), x + 6, 1e-9) << "sample " << k;
  }
  EXPECT_TRUE(rig.faults().empty());
}

// A scalar x' = a x + w, y = x + v reaches the steady state of the Riccati equation: the prior
// variance P solves P² + P (r (1 - a²) - q) - q r = 0, and the gain is K = P / (P + r). From
// x = 0 on zeros, one sample y = 1 moves the estimate by K; its NIS is 1 / (P + r).
TEST(StateEstimator, AScalarFilterReachesTheSteadyStateGainOfTheRiccatiEquation) {
  Rig rig(0, 1);
  const double a = 0.9, q = 0.5, r = 2.0;
  rig.set("states", std::string("x"));
  rig.set("measurements", std::string("s.out"));
  rig.set("A", std::string("0.9"));
  rig.set("C", std::string("1"));
  rig.set("Q", std::string("0.5"));
  rig.set("R", std::string("2"));
  rig.set("window", std::int64_t{1});
  rig.set("actuator", std::string("plant"));
  ASSERT_TRUE(rig.initialize()) << rig.refusal();
  for (int k = 0; k < 300; ++k) rig.feed({}, {0.0});
  const double b = r * (1 - a * a) - q;
  const double p = (-b + std::sqrt(b * b + 4 * q * r)) / 2;
  rig.feed({}, {1.0});
  EXPECT_NEAR(rig.estimate(0), p / (p + r), 1e-12);
  EXPECT_NEAR(rig.statistic(), 1 / (p + r), 1e-12);
}

// The threshold is the chi-square quantile 1 - false_alarm of the window's degrees of freedom
// (values of a printed table: 3.841 for 1 dof at 5 %, 5.991 for 2, 18.307 for 10).
TEST(StateEstimator, TheThresholdIsTheChiSquareQuantileOfTheWindowsDegreesOfFreedom) {
  for (const auto& [window, dof, quantile] : std::vector<std::tuple<std::int64_t, int, double>>{
           {1, 1, 3.841458820694124}, {2, 2, 5.991464547107979}, {10, 10, 18.307038053275146}}) {
    Rig rig(0, 1);
    rig.set("states", std::string("x"));
    rig.set("measurements", std::string("s.out"));
    rig.set("A", std::string("1"));
    rig.set("C", std::string("1"));
    rig.set("Q", std::string("1"));
    rig.set("R", std::string("1"));
    rig.set("window", window);
    rig.set("false_alarm", 0.05);
    rig.set("actuator", std::string("plant"));
    ASSERT_TRUE(rig.initialize()) << rig.refusal();
    for (int k = 0; k < window; ++k) rig.feed({}, {0.0});
    EXPECT_NEAR(rig.threshold(), quantile, 1e-9) << dof << " dof";
  }
}

// ---- isolation on a simulated plant -------------------------------------------------------------

// Two wheels (rpm) lagging their targets, seen by their encoders and by a gyro, which sees the
// yaw rate: (right - left) × k. The plant here is the model with its own noise.
constexpr double kLag = 0.875;         // exp(-20 ms / 150 ms), rounded
constexpr double kYaw = 0.0243;        // rad/s per rpm of difference
constexpr double kEncoderSigma = 2.5;  // rpm
constexpr double kGyroSigma = 0.01;    // rad/s
constexpr double kProcessSigma = 1.0;  // rpm per step

void configureWheels(Rig& rig, double false_alarm = 1e-6, std::int64_t readmit_after = 0) {
  rig.set("states", std::string("left right"));
  rig.set("inputs", std::string("target_left target_right"));
  rig.set("measurements", std::string("encoder_left.rpm encoder_right.rpm gyro.yaw_rate"));
  rig.set("A", std::string("0.875 0; 0 0.875"));
  rig.set("B", std::string("0.125 0; 0 0.125"));
  rig.set("C", std::string("1 0; 0 1; -0.0243 0.0243"));
  rig.set("Q", std::string("1 1"));
  rig.set("R", std::string("6.25 6.25 0.0001"));
  rig.set("window", std::int64_t{5});
  rig.set("false_alarm", false_alarm);
  rig.set("readmit_after", readmit_after);
  rig.set("actuator", std::string("actuator"));
}

enum class Break { None, EncoderLeftDead, EncoderRightDead, GyroDead, LeftMotorOff };

struct Plant {
  explicit Plant(std::uint64_t seed) : rng(seed) {}
  /// One step toward the targets; what the sensors read after it, faulted by `fault`.
  std::vector<double> step(double target_left, double target_right, Break fault) {
    std::normal_distribution<double> w(0, kProcessSigma), e(0, kEncoderSigma), g(0, kGyroSigma);
    const double drive_left = fault == Break::LeftMotorOff ? 0.0 : target_left;
    left = kLag * left + (1 - kLag) * drive_left + w(rng);
    right = kLag * right + (1 - kLag) * target_right + w(rng);
    std::vector<double> y{left + e(rng), right + e(rng), kYaw * (right - left) + g(rng)};
    if (fault == Break::EncoderLeftDead) y[0] = 0;
    if (fault == Break::EncoderRightDead) y[1] = 0;
    if (fault == Break::GyroDead) y[2] = 0;
    return y;
  }
  std::mt19937_64 rng;
  double left = 0;
  double right = 0;
};

// Drives ahead at 60 rpm, then turns (40 / 80 rpm); the fault from sample 200 on.
std::vector<FaultEvent> drive(Rig& rig, Break fault, std::uint64_t seed, int samples = 400) {
  Plant plant(seed);
  for (int k = 0; k < samples; ++k) {
    const bool turning = (k / 100) % 2 == 1;
    const double tl = turning ? 40 : 60, tr = turning ? 80 : 60;
    rig.feed({tl, tr}, plant.step(tl, tr, k >= 200 ? fault : Break::None));
  }
  return rig.faults();
}

TEST(StateEstimator, EachDeadSensorIsAccusedByItsMeasurementAndTheOthersCarryTheEstimate) {
  const std::vector<std::tuple<Break, std::string, std::string, int>> cases{{Break::EncoderLeftDead, "encoder_left",
                                                                             "encoder_left", 0},
                                                                            {Break::EncoderRightDead, "encoder_right",
                                                                             "encoder_right", 1},
                                                                            {Break::GyroDead, "gyro", "gyro", 2}};
  for (const auto& [fault, component, measurement, index] : cases) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      Rig rig(2, 3);
      configureWheels(rig);
      ASSERT_TRUE(rig.initialize()) << rig.refusal();
      const auto faults = drive(rig, fault, seed);
      ASSERT_EQ(faults.size(), 1u) << measurement << " seed " << seed;
      EXPECT_EQ(faults[0].kind, FaultKind::Model);
      EXPECT_EQ(faults[0].componentName(), component);
      EXPECT_EQ(faults[0].measurementName(), measurement);
      EXPECT_THAT(std::string(faults[0].detailText()), HasSubstr("measurement '" + measurement + "' disagrees"));
      EXPECT_FALSE(rig.est.bank().trusted(index));
      // The lost measurement, estimated from the others, is the plant's true value, not 0.
      if (index < 2) {
        EXPECT_NEAR(rig.estimate(index), index == 0 ? 40.0 : 80.0, 8.0) << measurement;
      }
    }
  }
}

TEST(StateEstimator, AWheelThatStopsFollowingItsTargetIsTheActuatorsFaultNotASensors) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    Rig rig(2, 3);
    configureWheels(rig);
    ASSERT_TRUE(rig.initialize()) << rig.refusal();
    const auto faults = drive(rig, Break::LeftMotorOff, seed);
    ASSERT_EQ(faults.size(), 1u) << "seed " << seed;
    EXPECT_EQ(faults[0].componentName(), "actuator");
    EXPECT_EQ(faults[0].measurementName(), "");
    EXPECT_THAT(std::string(faults[0].detailText()), HasSubstr("the measurements agree, not the model"));
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(rig.est.bank().trusted(i));
  }
}

// ---- calibration: the false-alarm rate is the one stated ----------------------------------------

// On nominal data the windowed statistic of the full filter is chi-square with 15 dof (3
// measurements × 5 samples; fewer once a false alarm excluded one), so it exceeds its 1 %
// quantile on about 1 % of samples: the filter's innovation covariance and the threshold are
// both right. Over 50 000 samples: 500 expected, a standard deviation of ~22 were they
// independent (overlapping windows make it wider; 560 seen). A threshold off by a factor of ten
// in probability, or an innovation covariance without R, falls far outside.
TEST(StateEstimator, OnNominalNoiseTheStatisticExceedsItsThresholdAtTheStatedRate) {
  Rig rig(2, 3);
  configureWheels(rig, 0.01);
  ASSERT_TRUE(rig.initialize()) << rig.refusal();
  Plant plant(11);
  int above = 0;
  const int samples = 50000;
  for (int k = 0; k < samples; ++k) {
    const bool turning = (k / 100) % 2 == 1;
    const double tl = turning ? 40 : 60, tr = turning ? 80 : 60;
    rig.feed({tl, tr}, plant.step(tl, tr, Break::None));
    if (k >= 100 && rig.statistic() > rig.threshold()) ++above;  // from the filter's steady state
  }
  EXPECT_GT(above, 400);
  EXPECT_LT(above, 650);
}

// At the default false_alarm (1e-6 per test), 30 000 nominal samples (10 minutes at 50 Hz) raise
// no fault: the union bound puts the chance of any at 3 %.
TEST(StateEstimator, NominalNoiseRaisesNoFaultOverALongRunAtTheDefaultRate) {
  Rig rig(2, 3);
  configureWheels(rig);
  ASSERT_TRUE(rig.initialize()) << rig.refusal();
  Plant plant(12);
  for (int k = 0; k < 30000; ++k) {
    const bool turning = (k / 100) % 2 == 1;
    const double tl = turning ? 40 : 60, tr = turning ? 80 : 60;
    rig.feed({tl, tr}, plant.step(tl, tr, Break::None));
  }
  const auto faults = rig.faults();
  EXPECT_EQ(faults.size(), 0u) << (faults.empty() ? "" : std::string(faults[0].detailText()));
}

// ---- samples that do not arrive, readmission -----------------------------------------------------

TEST(StateEstimator, AMeasurementThatStopsArrivingIsLeftOutAndTheOthersGoOn) {
  Rig rig(2, 3);
  configureWheels(rig);
  ASSERT_TRUE(rig.initialize()) << rig.refusal();
  Plant plant(3);
  for (int k = 0; k < 300; ++k) {
    auto y = plant.step(60, 60, Break::None);
    if (k >= 100) y[0] = std::nan("");  // its sensor stopped: nothing on y0
    rig.feed({60, 60}, y);
  }
  EXPECT_TRUE(rig.faults().empty());
  EXPECT_NEAR(rig.estimate(0), 60.0, 8.0);  // estimated from the right encoder and the gyro
}

TEST(StateEstimator, AnExcludedSensorConsistentAgainForReadmitAfterSamplesIsTrustedAgain) {
  Rig rig(2, 3);
  configureWheels(rig, 1e-6, /*readmit_after=*/100);
  ASSERT_TRUE(rig.initialize()) << rig.refusal();
  Plant plant(4);
  for (int k = 0; k < 600; ++k) {
    const bool turning = (k / 100) % 2 == 1;
    const double tl = turning ? 40 : 60, tr = turning ? 80 : 60;
    rig.feed({tl, tr}, plant.step(tl, tr, k >= 100 && k < 200 ? Break::GyroDead : Break::None));
    if (k == 199) {
      EXPECT_FALSE(rig.est.bank().trusted(2)) << "the dead gyro was not excluded";
    }
  }
  ASSERT_EQ(rig.faults().size(), 1u);
  EXPECT_TRUE(rig.est.bank().trusted(2));
}

// ---- bad properties ------------------------------------------------------------------------------

struct Refusal {
  std::string property;
  std::string value;
  std::string why;
};

TEST(StateEstimator, ABadModelIsRefusedNamingThePropertyAndWhy) {
  const std::vector<Refusal> cases{
      {"A", "0.875 0", "has 1 row of 2, the model needs 2×2 (a row per state: left right)"},
      {"B", "0.125; 0.125", "has 2 rows of 1, the model needs 2×2"},
      {"C", "1 0; 0 1",
       "has 2 rows of 2, the model needs 3×2 (a row per measurement: encoder_left encoder_right "
       "gyro; a column per state)"},
      {"C", "1 0; 0 1 2; 1 1", "row 2 has 3 values, row 1 has 2"},
      {"A", "1 x; 0 1", "'x' is not a finite number"},
      {"R", "6.25 -1 0.0001", "is not a covariance: it must be symmetric and positive definite"},
      {"R", "1 2 0; 0 1 0; 0 0 1", "is not a covariance: it must be symmetric and positive definite"},
      {"Q", "1 0; 0 -1", "is not a covariance: it must be symmetric and positive semi-definite"},
      {"measurements", "encoder_left.rpm encoder_right gyro.yaw_rate", "'encoder_right' is not [name=]component.port"},
      {"measurements", "encoder_left.rpm encoder_left.count gyro.yaw_rate",
       "names 'encoder_left' twice (name one of them: name=encoder_left.count)"},
  };
  for (const auto& c : cases) {
    Rig rig(2, 3);
    configureWheels(rig);
    rig.set(c.property, c.value);
    EXPECT_FALSE(rig.initialize()) << c.property << " = " << c.value;
    EXPECT_EQ(rig.refusedProperty(), c.property) << c.value;
    EXPECT_THAT(rig.refusal(), HasSubstr("property '" + c.property + "' " + c.why)) << c.value;
  }
  for (const double p : {0.0, 1.0, -0.5, 2.0}) {
    Rig rig(2, 3);
    configureWheels(rig, p);
    EXPECT_FALSE(rig.initialize());
    EXPECT_THAT(rig.refusal(), HasSubstr("property 'false_alarm' is a probability per test and must be in (0, 1)"));
  }
}

}  // namespace
}  // namespace keel
