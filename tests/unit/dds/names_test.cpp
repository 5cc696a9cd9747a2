// ROS 2's naming on the DDS wire (src/dds/dds_ports): topic `/a/b` is DDS topic `rt/a/b`, type
// `pkg/msg/Name` is `pkg::msg::dds_::Name_`, and ROS_DOMAIN_ID overrides a profile's domain.
#include <gtest/gtest.h>

#include <cstdlib>

#include "dds/dds_ports.hpp"
#include "dds/type_registry.hpp"
#include "support/env.hpp"

namespace keel::dds {
namespace {

TEST(DdsNames, TopicsAndTypesAreNamedAsROS2NamesThemOnTheWire) {
  EXPECT_EQ(ddsTopicName("/cmd_vel"), "rt/cmd_vel");
  EXPECT_EQ(ddsTopicName("/sonar/range"), "rt/sonar/range");
  EXPECT_EQ(ddsTypeName("geometry_msgs/msg/Twist"), "geometry_msgs::msg::dds_::Twist_");
  EXPECT_EQ(ddsTypeName("std_msgs/msg/String"), "std_msgs::msg::dds_::String_");
}

TEST(DdsNames, EveryShippedTypeIsRegisteredUnderTheNameItsDescriptorHas) {
  for (const char* name : {"std_msgs/msg/Float64", "geometry_msgs/msg/Twist", "sensor_msgs/msg/LaserScan",
                           "diagnostic_msgs/msg/DiagnosticArray", "builtin_interfaces/msg/Time"}) {
    const detail::DdsType* t = findType(name);
    ASSERT_NE(t, nullptr) << name;
    EXPECT_STREQ(t->ros_name, name);
  }
  EXPECT_EQ(findType("std_msgs/msg/NoSuchThing"), nullptr);
}

TEST(DdsNames, RosDomainIdOverridesTheProfilesDomainAndABadOneIsAnError) {
  const test::ScopedEnv domain("ROS_DOMAIN_ID", std::nullopt);
  EXPECT_EQ(*effectiveDomain(7), 7);
  domain.set("42");
  EXPECT_EQ(*effectiveDomain(7), 42);
  domain.set("");  // set but empty: as unset (as rcl takes it)
  EXPECT_EQ(*effectiveDomain(7), 7);
  for (const char* bad : {"4x", "233", "-1", " 5"}) {  // not a number; beyond DDS's port formula
    domain.set(bad);
    const auto d = effectiveDomain(7);
    ASSERT_FALSE(d.ok()) << bad;
    EXPECT_EQ(d.error().message,
              std::string("ROS_DOMAIN_ID='") + bad + "' is not a DDS domain id (a whole number from 0 to 232)");
  }
}

}  // namespace
}  // namespace keel::dds
