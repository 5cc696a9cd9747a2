// Every message keel ships (msgs/<pkg>/msg/<Name>.msg) is registered in libkeel for the DDS layer
// under its ROS 2 name, with its C++ type and idlc's descriptor of its DDS type. Reads msgs/;
// touches nothing.
#include <dds/dds.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <typeindex>

#include "dds/type_registry.hpp"
#include "keel/msg/sensor_msgs/msg/detail/laser_scan__dds.hpp"
#include "keel/msg/std_msgs/msg/detail/header__dds.hpp"
#include "support/paths.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path kShipped = fs::path(KEEL_SOURCE_DIR) / "msgs";

TEST(MessageRegistration, EveryShippedMessageIsRegisteredUnderItsRos2Name) {
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kShipped)) {
    if (entry.path().extension() != ".msg") continue;
    const std::string pkg = entry.path().parent_path().parent_path().filename();
    const std::string name = entry.path().stem();
    const std::string ros_name = fmt::format("{}/msg/{}", pkg, name);
    const keel::detail::DdsType* type = keel::dds::findType(ros_name);
    ASSERT_NE(type, nullptr) << ros_name << " is not registered";
    EXPECT_EQ(std::string(type->ros_name), ros_name);
    const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(type->descriptor);
    EXPECT_EQ(std::string(descriptor->m_typename), fmt::format("{}::msg::dds_::{}_", pkg, name));
    EXPECT_NE(type->make_outlet, nullptr);
    EXPECT_NE(type->deliver, nullptr);
    ++count;
  }
  EXPECT_EQ(count, 81) << "msgs/ holds 81 .msg files (msgs/SOURCES.md)";
}

TEST(MessageRegistration, EachShippedServiceIsItsRequestAndItsResponseUnderRmwsNames) {
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kShipped)) {
    if (entry.path().extension() != ".srv") continue;
    const std::string pkg = entry.path().parent_path().parent_path().filename();
    const std::string name = entry.path().stem();
    for (const char* half : {"Request", "Response"}) {
      const std::string ros_name = fmt::format("{}/srv/{}_{}", pkg, name, half);
      const keel::detail::DdsType* type = keel::dds::findType(ros_name);
      ASSERT_NE(type, nullptr) << ros_name << " is not registered";
      const auto* descriptor = static_cast<const dds_topic_descriptor_t*>(type->descriptor);
      // What rmw_fastrtps and rmw_cyclonedds name a service's halves on DDS.
      EXPECT_EQ(std::string(descriptor->m_typename), fmt::format("{}::srv::dds_::{}_{}_", pkg, name, half));
    }
    ++count;
  }
  EXPECT_EQ(count, 2) << "msgs/ holds 2 .srv files (msgs/SOURCES.md)";
}

TEST(MessageRegistration, TheRegisteredTypeIsTheCppTypeAndItsDescriptorIdlcs) {
  const keel::detail::DdsType* scan = keel::dds::findType("sensor_msgs/msg/LaserScan");
  ASSERT_NE(scan, nullptr);
  EXPECT_EQ(scan->type, std::type_index(typeid(keel::msg::sensor_msgs::LaserScan)));
  EXPECT_EQ(scan->descriptor, &sensor_msgs_msg_dds__LaserScan__desc);
  const keel::detail::DdsType* header = keel::dds::findType("std_msgs/msg/Header");
  ASSERT_NE(header, nullptr);
  EXPECT_EQ(header->type, std::type_index(typeid(keel::msg::std_msgs::Header)));
  EXPECT_EQ(static_cast<const dds_topic_descriptor_t*>(header->descriptor)->m_size, sizeof(std_msgs_msg_dds__Header_));
}

}  // namespace
