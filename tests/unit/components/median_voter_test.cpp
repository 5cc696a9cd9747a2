// MedianVoter / MedianVoter5 (components/voters): median-of-N voting, tested as classes:
// properties set as the runtime sets them, inputs fed through connected output ports,
// onExecute called directly (one call = one period), faults captured by RecordingHooks.
#include "components/voters/median_voter.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "runtime/component_core.hpp"
#include "runtime/invoke.hpp"
#include "support/recording_hooks.hpp"

namespace keel {
namespace {

using components::MedianVoterN;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

template <std::size_t N>
class Feeder : public Component {
 public:
  Feeder() {
    for (std::size_t i = 0; i < N; ++i)
      out.push_back(std::make_unique<OutputDataPort<double>>(this, "out" + std::to_string(i)));
  }
  std::vector<std::unique_ptr<OutputDataPort<double>>> out;
};

class Probe : public Component {
 public:
  InputDataPort<double> output{this, "output"};
  InputDataPort<int> agreeing{this, "agreeing"};
};

/// A voter named "voter", each input fed by its own output port, its outputs read by a Probe.
template <std::size_t N>
class VoterRig {
 public:
  VoterRig() {
    test::manage(voter, "voter", hooks);
    for (std::size_t i = 0; i < N; ++i) {
      test::configureQueue(voter.in[i], QueuePolicy::Last, 1);  // as the profile says
      test::wire(*feeder.out[i], voter.in[i], keep_);
    }
    test::configureQueue(probe.output, QueuePolicy::UFifo, 256);
    test::configureQueue(probe.agreeing, QueuePolicy::UFifo, 256);
    test::wire(voter.output, probe.output, keep_);
    test::wire(voter.agreeing, probe.agreeing, keep_);
  }
  void set(const std::string& name, const PropertyValue& value) { runtime::coreOf(voter).properties[name] = value; }
  bool initialize() { return runtime::transition(voter, Transition::Initialize); }
  /// One period: the inputs given a value deliver it (nullopt: that input stays silent).
  void cycle(const std::array<std::optional<double>, N>& values) {
    for (std::size_t i = 0; i < N; ++i)
      if (values[i]) feeder.out[i]->push(*values[i]);
    EXPECT_EQ(voter.onExecute(), ReturnCode::Ok);
  }
  std::vector<double> outputs() {
    std::vector<double> v;
    while (auto x = probe.output.pop()) v.push_back(*x);
    return v;
  }
  std::vector<int> agreeing() {
    std::vector<int> v;
    while (auto x = probe.agreeing.pop()) v.push_back(*x);
    return v;
  }
  std::vector<FaultEvent> faults() const { return hooks.faults(); }

  test::RecordingHooks hooks;
  MedianVoterN<N> voter;
  Feeder<N> feeder;
  Probe probe;

 private:
  std::vector<std::unique_ptr<detail::ConnectionBase>> keep_;
};

std::string detailOf(const FaultEvent& f) { return std::string(f.detailText()); }
constexpr std::nullopt_t kSilent = std::nullopt;

// ---- median of three (paper §5.1.4) ----

TEST(MedianVoter, MasksASonarStuckAtZeroAndReportsItOnce) {
  VoterRig<3> rig;
  rig.set("sources", std::string("sonar_a sonar_b sonar_c"));
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 50; ++i) rig.cycle({150.0 + i % 3, 0.0, 152.0 + i % 5});

  const auto outputs = rig.outputs();
  ASSERT_EQ(outputs.size(), 50u);
  for (double v : outputs) {  // the median of {a, 0, c} is min(a, c): never the stuck 0
    EXPECT_GE(v, 150.0);
    EXPECT_LE(v, 156.0);
  }
  EXPECT_EQ(rig.agreeing(), std::vector<int>(50, 2));
  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].kind, FaultKind::Vote);
  EXPECT_EQ(faults[0].componentName(), "sonar_b");
  EXPECT_EQ(detailOf(faults[0]), "in1 = 0 deviates from median 150 by 150 (tolerance 10)");
}

TEST(MedianVoter, OutputsTheMiddleValueWhenAllAgree) {
  VoterRig<3> rig;
  ASSERT_TRUE(rig.initialize());

  rig.cycle({101.0, 99.0, 100.0});

  EXPECT_THAT(rig.outputs(), ElementsAre(100.0));
  EXPECT_THAT(rig.agreeing(), ElementsAre(3));
  EXPECT_TRUE(rig.faults().empty());
}

TEST(MedianVoter, OutputsNothingWhileTwoOfThreeInputsAreMissing) {
  VoterRig<3> rig;
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 10; ++i) rig.cycle({100.0, kSilent, kSilent});

  EXPECT_TRUE(rig.outputs().empty());
  EXPECT_TRUE(rig.agreeing().empty());
  EXPECT_TRUE(rig.faults().empty());
}

TEST(MedianVoter, VotesWithTwoOfThreeInputsPresent) {
  VoterRig<3> rig;
  ASSERT_TRUE(rig.initialize());

  rig.cycle({100.0, kSilent, 104.0});

  EXPECT_THAT(rig.outputs(), ElementsAre(102.0));
  EXPECT_THAT(rig.agreeing(), ElementsAre(2));
}

TEST(MedianVoter, KeepsTheLatestValueOfAnInputThatDeliveredEarlier) {
  VoterRig<3> rig;
  ASSERT_TRUE(rig.initialize());

  rig.cycle({100.0, 101.0, 102.0});
  rig.cycle({100.0, kSilent, 104.0});  // in1 still counts with 101

  EXPECT_THAT(rig.outputs(), ElementsAre(101.0, 101.0));
}

TEST(MedianVoter, ForgetsAnInputSilentForStaleAfterExecutions) {
  VoterRig<3> rig;
  rig.set("stale_after", std::int64_t{2});
  ASSERT_TRUE(rig.initialize());

  rig.cycle({100.0, 101.0, 102.0});
  rig.cycle({100.0, kSilent, kSilent});  // silent once: still present
  rig.cycle({100.0, kSilent, kSilent});  // silent twice: missing, one input left

  EXPECT_THAT(rig.outputs(), ElementsAre(101.0, 101.0));
  rig.cycle({100.0, 103.0, kSilent});  // in1 is back
  EXPECT_THAT(rig.outputs(), ElementsAre(101.5));
}

TEST(MedianVoter, ReArmsAnInputOnceItAgreesAgain) {
  VoterRig<3> rig;
  rig.set("sources", std::string("sonar_a sonar_b sonar_c"));
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 10; ++i) rig.cycle({200.0, 200.0, 0.0});
  ASSERT_EQ(rig.faults().size(), 1u);
  rig.cycle({200.0, 200.0, 205.0});  // sonar_c agrees again
  for (int i = 0; i < 10; ++i) rig.cycle({200.0, 200.0, 3000.0});

  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 2u);
  EXPECT_EQ(faults[1].componentName(), "sonar_c");
  EXPECT_EQ(detailOf(faults[1]), "in2 = 3000 deviates from median 200 by 2800 (tolerance 10)");
}

TEST(MedianVoter, NamesTheVoterAndThePortWhenSourcesAreNotGiven) {
  VoterRig<3> rig;
  ASSERT_TRUE(rig.initialize());

  rig.cycle({0.0, 152.3, 152.3});

  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].componentName(), "voter");
  EXPECT_EQ(detailOf(faults[0]), "in0 = 0 deviates from median 152.3 by 152.3 (tolerance 10)");
}

TEST(MedianVoter, ReportsOnceAndOutputsNothingWhenNoMajorityAgrees) {
  VoterRig<3> rig;
  rig.set("sources", std::string("sonar_a sonar_b sonar_c"));
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 5; ++i) rig.cycle({0.0, 100.0, 200.0});

  EXPECT_TRUE(rig.outputs().empty());  // nothing can be masked
  EXPECT_EQ(rig.agreeing(), std::vector<int>(5, 1));
  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);  // about the voter: no source can be blamed
  EXPECT_EQ(faults[0].kind, FaultKind::Vote);
  EXPECT_EQ(faults[0].componentName(), "voter");
  EXPECT_THAT(detailOf(faults[0]), HasSubstr("no majority: 1 of 3 inputs within 10 of median 100"));
}

TEST(MedianVoter, TreatsANonFiniteInputAsAnOutlier) {
  VoterRig<3> rig;
  rig.set("sources", std::string("sonar_a sonar_b sonar_c"));
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 3; ++i) rig.cycle({100.0, std::numeric_limits<double>::quiet_NaN(), 102.0});

  EXPECT_THAT(rig.outputs(), ElementsAre(101.0, 101.0, 101.0));
  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].componentName(), "sonar_b");
  EXPECT_EQ(detailOf(faults[0]), "in1 = nan is not a finite number");
}

TEST(MedianVoter, ToleranceRatioScalesWithTheMedian) {
  VoterRig<3> rig;
  rig.set("tolerance_ratio", 0.1);  // 10 % of the median, instead of tolerance
  rig.set("sources", std::string("a b c"));
  ASSERT_TRUE(rig.initialize());

  rig.cycle({1000.0, 1050.0, 1200.0});  // median 1050, tolerance 105: 1000 agrees, 1200 not

  EXPECT_THAT(rig.outputs(), ElementsAre(1050.0));
  EXPECT_THAT(rig.agreeing(), ElementsAre(2));
  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].componentName(), "c");
  EXPECT_EQ(detailOf(faults[0]), "in2 = 1200 deviates from median 1050 by 150 (tolerance 105 = 0.1 \u00d7 median)");
}

// ---- median of five ----

TEST(MedianVoter5, MasksTwoOutliersAndReportsEach) {
  VoterRig<5> rig;
  rig.set("sources", std::string("s0 s1 s2 s3 s4"));
  ASSERT_TRUE(rig.initialize());

  for (int i = 0; i < 4; ++i) rig.cycle({200.0, 0.0, 202.0, 900.0, 205.0});

  EXPECT_THAT(rig.outputs(), ElementsAre(202.0, 202.0, 202.0, 202.0));
  EXPECT_THAT(rig.agreeing(), ElementsAre(3, 3, 3, 3));
  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 2u);
  EXPECT_EQ(faults[0].componentName(), "s1");
  EXPECT_EQ(detailOf(faults[0]), "in1 = 0 deviates from median 202 by 202 (tolerance 10)");
  EXPECT_EQ(faults[1].componentName(), "s3");
  EXPECT_EQ(detailOf(faults[1]), "in3 = 900 deviates from median 202 by 698 (tolerance 10)");
}

TEST(MedianVoter5, NeedsThreeOfFiveInputsPresent) {
  VoterRig<5> rig;
  ASSERT_TRUE(rig.initialize());

  rig.cycle({100.0, kSilent, 101.0, kSilent, kSilent});
  EXPECT_TRUE(rig.outputs().empty());
  rig.cycle({kSilent, kSilent, kSilent, 102.0, kSilent});

  EXPECT_THAT(rig.outputs(), ElementsAre(101.0));
}

// ---- properties ----

TEST(MedianVoter, FailsInitializeWhenSourcesDoNotNameEveryInput) {
  VoterRig<3> rig;
  rig.set("sources", std::string("sonar_a sonar_b"));

  EXPECT_FALSE(rig.initialize());

  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].kind, FaultKind::Exception);
  EXPECT_THAT(detailOf(faults[0]), HasSubstr("component 'voter': property 'sources' must name 3 components"));
}

TEST(MedianVoter, FailsInitializeOnANegativeTolerance) {
  VoterRig<3> rig;
  rig.set("tolerance", -1.0);

  EXPECT_FALSE(rig.initialize());

  const auto faults = rig.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_THAT(detailOf(faults[0]), HasSubstr("property 'tolerance' must be >= 0"));
}

TEST(MedianVoter, FailsInitializeOnANegativeStaleAfter) {
  VoterRig<3> rig;
  rig.set("stale_after", std::int64_t{-1});

  EXPECT_FALSE(rig.initialize());

  EXPECT_EQ(rig.voter.state(), State::Error);
}

}  // namespace
}  // namespace keel
