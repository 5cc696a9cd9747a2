// ROS 2's naming on the DDS wire (src/dds/dds_ports): topic `/a/b` is DDS topic `rt/a/b`, type
// `pkg/msg/Name` is `pkg::msg::dds_::Name_`, and ROS_DOMAIN_ID overrides a profile's domain.
#include <gtest/gtest.h>

#include <cstdlib>

#include "dds/dds_ports.hpp"
#include "dds/type_registry.hpp"

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
  const char* before = std::getenv("ROS_DOMAIN_ID");
  const std::string saved = before ? before : "";
  ::unsetenv("ROS_DOMAIN_ID");
  EXPECT_EQ(*effectiveDomain(7), 7);
  ::setenv("ROS_DOMAIN_ID", "42", 1);
  EXPECT_EQ(*effectiveDomain(7), 42);
  ::setenv("ROS_DOMAIN_ID", "", 1);  // set but empty: as unset (as rcl takes it)
  EXPECT_EQ(*effectiveDomain(7), 7);
  for (const char* bad : {"4x", "233", "-1", " 5"}) {  // not a number; beyond DDS's port formula
    ::setenv("ROS_DOMAIN_ID", bad, 1);
    const auto d = effectiveDomain(7);
    ASSERT_FALSE(d.ok()) << bad;
    EXPECT_EQ(d.error().message,
              std::string("ROS_DOMAIN_ID='") + bad + "' is not a DDS domain id (a whole number from 0 to 232)");
  }
  if (before) ::setenv("ROS_DOMAIN_ID", saved.c_str(), 1);
  else ::unsetenv("ROS_DOMAIN_ID");
}

}  // namespace
}  // namespace keel::dds
