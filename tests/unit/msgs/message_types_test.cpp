// keel's message types as authors meet them: ROS 2's header paths and names, keel::typeName,
// defaults and constants from the .msg, keyword field names. The shipped messages (msgs/) and
// keel's test set (tests/unit/msgs/keel_test_msgs), both generated at build time. Touches nothing.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>

#include "keel/msg/builtin_interfaces/msg/time.hpp"
#include "keel/msg/diagnostic_msgs/msg/diagnostic_array.hpp"
#include "keel/msg/geometry_msgs/msg/pose_stamped.hpp"
#include "keel/msg/geometry_msgs/msg/twist.hpp"
#include "keel/msg/keel_test_msgs/msg/everything.hpp"
#include "keel/msg/keel_test_msgs/msg/nothing.hpp"
#include "keel/msg/sensor_msgs/msg/imu.hpp"
#include "keel/msg/sensor_msgs/msg/joint_state.hpp"
#include "keel/msg/sensor_msgs/msg/laser_scan.hpp"
#include "keel/msg/std_msgs/msg/empty.hpp"
#include "keel/msg/std_msgs/msg/float64.hpp"
#include "keel/msg/std_msgs/msg/header.hpp"
#include "keel/msg/std_msgs/msg/multi_array_layout.hpp"
#include "keel/msg/std_msgs/msg/string.hpp"
#include "keel/type_name.hpp"

namespace {

namespace msg = keel::msg;

TEST(MessageTypes, TypeNameIsTheRos2Name) {
  EXPECT_EQ(keel::typeName<msg::std_msgs::Float64>(), "std_msgs/msg/Float64");
  EXPECT_EQ(keel::typeName<msg::std_msgs::String>(), "std_msgs/msg/String");
  EXPECT_EQ(keel::typeName<msg::geometry_msgs::PoseStamped>(), "geometry_msgs/msg/PoseStamped");
  EXPECT_EQ(keel::typeName<msg::sensor_msgs::LaserScan>(), "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(keel::typeName<msg::diagnostic_msgs::DiagnosticArray>(), "diagnostic_msgs/msg/DiagnosticArray");
  EXPECT_EQ(keel::typeName<msg::builtin_interfaces::Time>(), "builtin_interfaces/msg/Time");
  EXPECT_EQ(keel::typeName<msg::std_msgs::MultiArrayLayout>(), "std_msgs/msg/MultiArrayLayout");
  EXPECT_EQ(keel::typeName<msg::keel_test_msgs::Everything>(), "keel_test_msgs/msg/Everything");
}

TEST(MessageTypes, FieldsAreNamedAndTypedAsInTheMsgFile) {
  msg::std_msgs::Float64 f;
  f.data = 2.5;
  static_assert(std::is_same_v<decltype(f.data), double>);
  msg::geometry_msgs::PoseStamped p;
  p.header.frame_id = "map";
  p.header.stamp.sec = 3;
  p.pose.orientation.w = 1.0;
  static_assert(std::is_same_v<decltype(p.header.stamp.nanosec), std::uint32_t>);
  static_assert(std::is_same_v<decltype(msg::sensor_msgs::Imu{}.orientation_covariance), std::array<double, 9>>);
  static_assert(std::is_same_v<decltype(msg::sensor_msgs::LaserScan{}.ranges), std::vector<float>>);
  static_assert(std::is_same_v<decltype(msg::sensor_msgs::JointState{}.name), std::vector<std::string>>);
  static_assert(std::is_same_v<decltype(msg::diagnostic_msgs::DiagnosticStatus{}.level), std::uint8_t>);
  EXPECT_EQ(p.header.frame_id, "map");
}

TEST(MessageTypes, AnUnsetFieldIsZeroAndValuesCompareByValue) {
  msg::sensor_msgs::Imu a;
  EXPECT_EQ(a.linear_acceleration.z, 0.0);
  EXPECT_EQ(a.orientation_covariance[8], 0.0);
  EXPECT_TRUE(a.header.frame_id.empty());
  msg::sensor_msgs::Imu b = a;
  EXPECT_EQ(a, b);
  b.orientation_covariance[4] = 0.1;
  EXPECT_NE(a, b);
  EXPECT_EQ(msg::std_msgs::Empty{}, msg::std_msgs::Empty{});
  static_assert(std::is_empty_v<msg::std_msgs::Empty>, "an empty message has no C++ member");
}

TEST(MessageTypes, DefaultsOfTheMsgFileAreDefaultMemberInitialisers) {
  const msg::keel_test_msgs::Everything e;
  EXPECT_TRUE(e.flag);
  EXPECT_EQ(e.b, 7);
  EXPECT_EQ(e.c, 65);
  EXPECT_EQ(e.i8, -8);
  EXPECT_EQ(e.u32, 32u);
  EXPECT_EQ(e.i64, std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(e.u64, std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(e.f32, 1.5f);
  EXPECT_EQ(e.f64, -2.25);
  EXPECT_EQ(e.distance, std::numeric_limits<double>::infinity());
  EXPECT_EQ(e.text, "default text");
  EXPECT_EQ(e.quoted, "a \"quoted\" word");
  EXPECT_EQ(e.short_text, "abc");
  EXPECT_EQ(e.text_pair, (std::array<std::string, 2>{"a", "b, c"}));
  EXPECT_EQ(e.flag_triple, (std::array<bool, 3>{true, false, true}));
  EXPECT_EQ(e.values, (std::vector<double>{1.0, 2.0}));
  EXPECT_TRUE(e.texts.empty());
  EXPECT_EQ(e.i32, -32);
}

TEST(MessageTypes, ConstantsAreStaticMembers) {
  EXPECT_EQ(msg::diagnostic_msgs::DiagnosticStatus::OK, 0);
  EXPECT_EQ(msg::diagnostic_msgs::DiagnosticStatus::ERROR, 2);
  static_assert(std::is_same_v<decltype(msg::diagnostic_msgs::DiagnosticStatus::STALE), const std::uint8_t>);
  using E = msg::keel_test_msgs::Everything;
  static_assert(E::ANSWER == 42 && E::YES && E::HALF == 0.5);
  static_assert(E::LOWEST == std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(std::string_view(E::GREETING), "say \"hi\"");
  EXPECT_EQ(msg::keel_test_msgs::Nothing::NOTHING, 0);
  static_assert(std::is_empty_v<msg::keel_test_msgs::Nothing>);
}

TEST(MessageTypes, AFieldNamedAfterACppKeywordGetsATrailingUnderscore) {
  msg::keel_test_msgs::Everything e;
  e.class_ = 3;  // `int32 class` in the .msg
  e.module = 4;  // an IDL keyword, no C++ one: its name is kept
  EXPECT_EQ(e.class_ + e.module, 7);
}

}  // namespace
