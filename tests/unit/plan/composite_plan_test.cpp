// A composite in the plan: its subcomponents are instances named inside the composite's
// instance, and a fault policy given where the composite is used covers those that have none.
#include <gtest/gtest.h>

#include "plan/plan.hpp"
#include "unit/profile/profile_test_support.hpp"

namespace keel::plan {
namespace {

using profile::test::dataPath;

TEST(CompositePlan, AFaultPolicyOnACompositeCoversItsSubcomponents) {
  auto set = profile::load(dataPath("plan/composite_policy.xml"));
  ASSERT_TRUE(set.ok()) << profile::test::joined(set);
  auto plan = makePlan(*set);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  for (const char* inner : {"front.s1", "front.s2", "front.s3", "front.voter"}) {
    SCOPED_TRACE(inner);
    const PlannedInstance* i = plan->find(inner);
    ASSERT_NE(i, nullptr);
    ASSERT_TRUE(i->policy.has_value());
    EXPECT_EQ(i->policy->severity, profile::Severity::Stop);
  }
  for (const char* inner : {"rear.s1", "rear.voter"}) {
    SCOPED_TRACE(inner);
    const PlannedInstance* i = plan->find(inner);
    ASSERT_NE(i, nullptr);
    EXPECT_FALSE(i->policy.has_value());
  }
}

// The plan keeps each composite and its members: what the engine derives its state from and a
// `composite` scope stops.
TEST(CompositePlan, EachCompositeIsKeptWithItsMembers) {
  auto set = profile::load(dataPath("plan/composite_policy.xml"));
  ASSERT_TRUE(set.ok()) << profile::test::joined(set);
  auto plan = makePlan(*set);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  ASSERT_EQ(plan->composites.size(), 2u);
  EXPECT_EQ(plan->composites[0].name, "front");
  EXPECT_EQ(plan->composites[0].members, (std::vector<std::string>{"front.s1", "front.s2", "front.s3", "front.voter"}));
  EXPECT_EQ(plan->composites[1].name, "rear");
  EXPECT_EQ(plan->composites[1].members.size(), 4u);
}

}  // namespace
}  // namespace keel::plan
