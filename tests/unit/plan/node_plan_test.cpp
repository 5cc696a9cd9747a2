// The plan of ROS 2 nodes (src/plan/plan.hpp): what cannot be asked of a node is refused with
// its line.
#include <gtest/gtest.h>

#include "plan/plan.hpp"
#include "unit/profile/profile_test_support.hpp"

namespace keel::plan {
namespace {

using profile::test::dataPath;
using profile::test::relative;

TEST(NodePlan, ANodeTakesNoProcessAndNoDdsBindingOfItsOwnPorts) {
  auto set = profile::load(dataPath("node/planned_badly.xml"));
  ASSERT_TRUE(set.ok()) << profile::test::joined(set);
  auto plan = makePlan(*set);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(relative(plan.error().message),
            "node/planned_badly.xml:8: <process> of subcomponent 'wander': a ROS 2 node is a process of its own\n"
            "node/planned_badly.xml:12: <publish> of wander.cmd: 'wander' is a ROS 2 node, whose ports are its own "
            "topics already (<topic> in its node profile); connect a component to it instead");
}

TEST(NodePlan, ANodeIsPlannedWithItsProfileAndAnAttachedOneSaysSo) {
  auto set = profile::load(dataPath("node/app.xml"));
  ASSERT_TRUE(set.ok()) << profile::test::joined(set);
  auto plan = makePlan(*set);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  const PlannedInstance* wander = plan->find("wander");
  const PlannedInstance* watcher = plan->find("watcher");
  const PlannedInstance* planner = plan->find("planner");
  ASSERT_TRUE(wander && watcher && planner);
  ASSERT_NE(wander->node, nullptr);
  EXPECT_EQ(wander->node->fullName(), "/robot/wander");
  EXPECT_FALSE(wander->attached);
  ASSERT_NE(watcher->node, nullptr);
  EXPECT_TRUE(watcher->attached);
  EXPECT_EQ(planner->node, nullptr);
  EXPECT_TRUE(plan->hasNodes());
}

}  // namespace
}  // namespace keel::plan
