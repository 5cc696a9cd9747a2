// <dds> of a package profile (docs/dds.md): what loads and how the plan carries it, and every
// error of the file's own syntax and of its bindings against the component profiles, each with
// its file:line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "plan/plan.hpp"
#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;

TEST(DdsProfile, BindingsLoadAndThePlanCarriesThemWithTheirSettings) {
  auto set = load(dataPath("dds/app.xml"));
  ASSERT_TRUE(set.ok()) << joined(set);
  EXPECT_TRUE(set->warnings.empty());
  auto plan = plan::makePlan(*set);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  ASSERT_EQ(plan->dds.size(), 2u);
  const plan::PlannedDds& pub = plan->dds[0];
  EXPECT_TRUE(pub.binding.publish);
  EXPECT_EQ(pub.domain, 7);
  EXPECT_EQ(pub.binding.endpoint.component, "sonar");
  EXPECT_EQ(pub.binding.endpoint.port, "range");
  EXPECT_EQ(pub.binding.topic, "/sonar/range");
  EXPECT_EQ(pub.binding.type, "sensor_msgs/msg/Range");
  EXPECT_EQ(pub.binding.qos, DdsQos::SensorData);
  EXPECT_EQ(pub.binding.liveliness_ms, 200.0);
  EXPECT_FALSE(pub.binding.deadline_ms);
  const plan::PlannedDds& sub = plan->dds[1];
  EXPECT_FALSE(sub.binding.publish);
  EXPECT_EQ(sub.binding.topic, "/cmd_vel");  // a relative name is taken from the root
  EXPECT_EQ(sub.binding.qos, DdsQos::Default);
  EXPECT_EQ(sub.binding.deadline_ms, 100.0);
  EXPECT_EQ(sub.binding.liveliness_ms, 250.5);
  EXPECT_EQ(sub.binding.depth, 3u);
  EXPECT_EQ(sub.binding.where.line, 14);
}

TEST(DdsProfile, RejectsTopicsTypesAndSettingsROS2WouldNotTakeEachWithItsLine) {
  EXPECT_THAT(
      problems("dds/bad_syntax.xml"),
      ElementsAre(
          "dds/bad_syntax.xml:8: domain of <dds> must be an integer from 0 to 232, got '300'",
          "dds/bad_syntax.xml:9: topic '/sonar//range' of <publish> of sonar.range is not a ROS 2 topic name: it has "
          "an empty token ('//')",
          "dds/bad_syntax.xml:10: topic '/9lives' of <publish> of sonar.range is not a ROS 2 topic name: its token "
          "'9lives' starts with a digit",
          "dds/bad_syntax.xml:10: type 'sensor_msgs/Range' of <publish> of sonar.range is not a ROS 2 message type: it "
          "must be written as ROS 2 writes it: package/msg/Name, e.g. std_msgs/msg/Float64",
          "dds/bad_syntax.xml:11: topic '~/private' of <publish> of sonar.range is not a ROS 2 topic name: '~' names a "
          "node's private namespace, and keel's ports belong to no ROS node",
          "dds/bad_syntax.xml:11: type 'sensor_msgs/msg/range' of <publish> of sonar.range is not a ROS 2 message "
          "type: the message name must start with an upper-case letter",
          "dds/bad_syntax.xml:12: topic '/cmd_vel/' of <subscribe> of planner.cmd is not a ROS 2 topic name: it ends "
          "with '/'",
          "dds/bad_syntax.xml:12: qos of <subscribe> of planner.cmd must be one of default, sensor_data, reliable or "
          "transient_local, got 'best'",
          "dds/bad_syntax.xml:13: topic '/cmd-vel' of <subscribe> of planner.cmd is not a ROS 2 topic name: '-' is not "
          "allowed (ROS 2 names have letters, digits, '_' and '/')",
          "dds/bad_syntax.xml:13: deadline of <subscribe> of planner.cmd (ms) must be a positive number, got '-5'",
          "dds/bad_syntax.xml:14: missing attribute 'topic' of <subscribe>",
          "dds/bad_syntax.xml:15: unknown attribute 'rate' of <subscribe>",
          "dds/bad_syntax.xml:15: depth of <subscribe> of planner.cmd must be a positive integer, got '0'",
          "dds/bad_syntax.xml:17: planner.cmd is bound to topic '/ok' twice (the first at line 16)"));
}

TEST(DdsProfile, RejectsBindingsToPortsThatAreMissingOfTheWrongKindDirectionOrType) {
  EXPECT_THAT(
      problems("dds/bad_ports.xml"),
      ElementsAre(
          "dds/bad_ports.xml:9: <publish>: no subcomponent 'lidar' (subcomponents: sonar, planner)",
          "dds/bad_ports.xml:10: <publish>: component 'sonar' has no port 'ranges' (ports: range, distance, alarm)",
          "dds/bad_ports.xml:11: <publish>: 'sonar.alarm' is an event port; DDS topics carry data ports' values",
          "dds/bad_ports.xml:12: <subscribe>: 'sonar.range' is an output data port of data_type "
          "'sensor_msgs/msg/Range'; <subscribe> needs an input port",
          "dds/bad_ports.xml:13: <publish>: topic '/distance' has type 'std_msgs/msg/Float64', but port "
          "'sonar.distance' has data_type 'double' (a keel::msg type's data_type is its ROS 2 name)",
          "dds/bad_ports.xml:14: <publish>: 'planner.cmd' is an input data port of data_type "
          "'geometry_msgs/msg/Twist'; <publish> needs an output port"));
}

TEST(DdsProfile, ARemoteSeverityWithoutASubscriptionIsAWarning) {
  EXPECT_THAT(warnings("dds/remote_without_subscription.xml"),
              ElementsAre(
                  "dds/remote_without_subscription.xml:7: <severity kind=\"remote\"> of subcomponent 'sonar' has "
                  "no effect: remote faults come from its DDS subscriptions, and this profile's <dds> has no "
                  "<subscribe> of it"));
  EXPECT_THAT(warnings("dds/app.xml"), ElementsAre());  // planner subscribes: its remote rule acts
}

TEST(DdsProfile, RedundancyOnACompositeIsRefusedAtItsLine) {
  auto set = load(dataPath("dds/redundant_composite.xml"));
  ASSERT_TRUE(set.ok()) << joined(set);
  auto plan = plan::makePlan(*set);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(relative(plan.error().message),
            "dds/redundant_composite.xml:7: <redundancy> of subcomponent 'array': 'valid/SonarArray.xml' is a "
            "composite; give the role to the components inside it whose topics it is about");
}

}  // namespace
}  // namespace keel::profile::test
