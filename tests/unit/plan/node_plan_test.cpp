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
            "node/planned_badly.xml:8: <process> of subcomponent 'wander': a ROS 2 node is a process of its own "
            "(standby=\"N\" keeps N more of a lifecycle node ready)\n"
            "node/planned_badly.xml:13: <process standby=\"1\"> of subcomponent 'calm': a standby node waits "
            "configured and inactive, which only a lifecycle node can: its profile (node/minimal.xml) has no "
            "<lifecycle/>\n"
            "node/planned_badly.xml:17: <publish> of wander.cmd: 'wander' is a ROS 2 node, whose ports are its own "
            "topics already (<topic> in its node profile); connect a component to it instead");
}

TEST(NodePlan, ALifecycleNodesStandbysHaveNamesOfTheirOwn) {
  auto set = profile::load(dataPath("node/standby.xml"));
  ASSERT_TRUE(set.ok()) << profile::test::joined(set);
  auto plan = makePlan(*set);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  const PlannedInstance* wander = plan->find("wander");
  ASSERT_NE(wander, nullptr);
  EXPECT_EQ(wander->node_standby, 2);
  EXPECT_TRUE(wander->process.empty());  // a node is no component process
  EXPECT_TRUE(plan->processes.empty());
  // Two standbys, and the one promoted to serve keeps its name: three names.
  EXPECT_EQ(standbyNodeNames(*wander), (std::vector<std::string>{"/robot/wander_standby_1", "/robot/wander_standby_2",
                                                                 "/robot/wander_standby_3"}));
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
  // The sonar's connection to the node's input port is the node's topic, written by keel.
  ASSERT_EQ(plan->dds.size(), 1u);
  const profile::DdsBinding& b = plan->dds[0].binding;
  EXPECT_TRUE(b.publish);
  EXPECT_EQ(b.endpoint.component + "." + b.endpoint.port, "sonar.range");
  EXPECT_EQ(b.topic, "/sonar/a");
  EXPECT_EQ(b.type, "sensor_msgs/msg/Range");
  EXPECT_EQ(b.qos, profile::DdsQos::SensorData);
}

TEST(NodePlan, BetweenTwoNodesKeelWritesOnlyWhatTheyDoNotSayToEachOtherAlready) {
  auto set = profile::load(dataPath("node/two_nodes.xml"));
  ASSERT_TRUE(set.ok()) << profile::test::joined(set);
  auto plan = makePlan(*set);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  // ranger.range is on wander's input topic already; ranger.far, on /sonar/far, is carried over.
  ASSERT_EQ(plan->dds.size(), 1u);
  EXPECT_EQ(plan->dds[0].binding.endpoint.port, "far");
  EXPECT_EQ(plan->dds[0].binding.topic, "/sonar/a");
}

}  // namespace
}  // namespace keel::plan
