// `keel run --set INSTANCE.PROPERTY=VALUE` (runtime/property_settings): how the text is split,
// and the settings typed against a plan like the profiles' overrides, all or nothing.
#include "plan/property_settings.hpp"

#include <gtest/gtest.h>

#include "profile/loader.hpp"
#include "support/paths.hpp"

namespace keel::plan {
namespace {

TEST(PropertySetting, SplitsAtTheLastDotBeforeTheFirstEqualsSign) {
  auto s = parsePropertySetting("navigation.planner.speed=0.4=x.y");
  ASSERT_TRUE(s) << s.error().message;
  EXPECT_EQ(s->instance, "navigation.planner");
  EXPECT_EQ(s->property, "speed");
  EXPECT_EQ(s->value, "0.4=x.y");
  EXPECT_EQ(s->text, "navigation.planner.speed=0.4=x.y");

  auto empty = parsePropertySetting("actuator.label=");
  ASSERT_TRUE(empty);
  EXPECT_EQ(empty->instance, "actuator");
  EXPECT_EQ(empty->value, "");
}

TEST(PropertySetting, RejectsTextThatIsNotInstancePropertyEqualsValue) {
  for (const char* bad : {"actuator.seed", "seed=3", "=3", ".seed=3", "actuator.=3", ""}) {
    auto s = parsePropertySetting(bad);
    ASSERT_FALSE(s) << bad;
    EXPECT_EQ(s.error().message,
              std::string("--set '") + bad + "': expected INSTANCE.PROPERTY=VALUE (e.g. actuator.seed=7)");
  }
}

class PropertySettings : public ::testing::Test {
 protected:
  void SetUp() override {
    auto set = profile::load(std::string(KEEL_TEST_PROFILES) + "/pipeline.xml");
    ASSERT_TRUE(set);
    set_ = std::move(*set);
    auto plan = makePlan(set_);
    ASSERT_TRUE(plan) << plan.error().message;
    plan_ = std::move(*plan);
  }
  Result<void> apply(const std::vector<std::string>& texts) {
    std::vector<PropertySetting> settings;
    settings.reserve(texts.size());
    for (const auto& t : texts) settings.push_back(*parsePropertySetting(t));
    return applyPropertySettings(plan_, settings);
  }
  const PropertyValue& value(const std::string& instance, const std::string& property) {
    return plan_.find(instance)->properties.find(property)->second;
  }
  profile::ProfileSet set_;
  Plan plan_;
};

TEST_F(PropertySettings, AreTypedAsDeclaredAndWinOverTheProfilesOverrides) {
  ASSERT_EQ(value("counter", "step"), PropertyValue(std::int64_t{2}));  // pipeline.xml's override

  auto r = apply({"counter.step=5", "summer.gain=0.25", "summer.label= relayed ", "summer.gain=3"});

  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(value("counter", "step"), PropertyValue(std::int64_t{5}));
  EXPECT_EQ(value("summer", "gain"), PropertyValue(3.0));                      // the later one
  EXPECT_EQ(value("summer", "label"), PropertyValue(std::string("relayed")));  // trimmed, as in a profile
}

TEST_F(PropertySettings, ReportEveryBadSettingALineEachAndSetNothing) {
  auto r = apply({"counter.step=5", "countr.step=1", "counter.stride=1", "counter.step=1.5", "summer.gain=x"});

  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message,
            "--set 'countr.step=1': no instance 'countr' (instances: counter, summer, events, doubler, caller)\n"
            "--set 'counter.stride=1': component 'Counter' of instance 'counter' has no property 'stride' "
            "(properties: step)\n"
            "--set 'counter.step=1.5': property 'step' of instance 'counter' is of type int: the value must be an "
            "int, got '1.5'\n"
            "--set 'summer.gain=x': property 'gain' of instance 'summer' is of type double: the value must be a "
            "finite double, got 'x'");
  EXPECT_EQ(value("counter", "step"), PropertyValue(std::int64_t{2}));  // untouched
}

TEST_F(PropertySettings, NameTheComponentsPropertiesOrNone) {
  auto r = apply({"doubler.factor=2"});

  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message,
            "--set 'doubler.factor=2': component 'Doubler' of instance 'doubler' has no property 'factor' "
            "(properties: none)");
}

}  // namespace
}  // namespace keel::plan
