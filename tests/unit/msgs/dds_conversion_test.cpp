// keel::msg::dds::toDds / fromDds (generated, keel/msg/<pkg>/msg/detail/<name>__dds.hpp): a
// value converted to idlc's C sample and back is equal to itself; to DDS borrows strings and
// number sequences (the sample points into the C++ value) and builds the rest in the scratch;
// bounded strings and sequences are truncated to their bound. No DDS entity is made here
// (cyclone_roundtrip_test.cpp serializes through CycloneDDS). Touches nothing.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "keel/msg/diagnostic_msgs/msg/detail/diagnostic_array__dds.hpp"
#include "keel/msg/geometry_msgs/msg/detail/pose_stamped__dds.hpp"
#include "keel/msg/geometry_msgs/msg/detail/twist__dds.hpp"
#include "keel/msg/keel_test_msgs/msg/detail/everything__dds.hpp"
#include "keel/msg/keel_test_msgs/msg/detail/nothing__dds.hpp"
#include "keel/msg/sensor_msgs/msg/detail/imu__dds.hpp"
#include "keel/msg/sensor_msgs/msg/detail/joint_state__dds.hpp"
#include "keel/msg/sensor_msgs/msg/detail/laser_scan__dds.hpp"
#include "keel/msg/std_msgs/msg/detail/empty__dds.hpp"
#include "keel/msg/std_msgs/msg/detail/float64__dds.hpp"
#include "keel/msg/std_msgs/msg/detail/float64_multi_array__dds.hpp"
#include "keel/msg/std_msgs/msg/detail/header__dds.hpp"
#include "keel/msg/std_msgs/msg/detail/string__dds.hpp"
#include "unit/msgs/sample_values.hpp"

namespace {

namespace msg = keel::msg;
using keel::detail::DdsScratch;
using keel::msg::dds::fromDds;
using keel::msg::dds::toDds;

/// `value` to its C sample and back into `into` (which starts out holding something else, so
/// that a field fromDds forgets shows).
template <class C, class T>
T roundTrip(const T& value, T into = T{}) {
  C sample{};
  DdsScratch scratch;
  toDds(value, sample, scratch);
  fromDds(sample, into);
  return into;
}

TEST(DdsConversion, Float64AndStringComeBackEqual) {
  msg::std_msgs::Float64 f;
  f.data = -1.25e-7;
  EXPECT_EQ((roundTrip<std_msgs_msg_dds__Float64_>(f)), f);
  msg::std_msgs::String s;
  s.data = "grüße, ロボット";
  msg::std_msgs::String old;
  old.data = "something longer that must be replaced";
  EXPECT_EQ((roundTrip<std_msgs_msg_dds__String_>(s, old)), s);
  EXPECT_EQ((roundTrip<std_msgs_msg_dds__String_>(msg::std_msgs::String{}, old)), msg::std_msgs::String{});
}

TEST(DdsConversion, AStringIsBorrowedNotCopied) {
  msg::std_msgs::String s;
  s.data = "borrowed";
  std_msgs_msg_dds__String_ sample{};
  DdsScratch scratch;
  toDds(s, sample, scratch);
  EXPECT_EQ(sample.data, s.data.c_str());
}

TEST(DdsConversion, ANullStringFromDdsIsEmpty) {
  std_msgs_msg_dds__String_ sample{};
  sample.data = nullptr;
  msg::std_msgs::String s;
  s.data = "old";
  fromDds(sample, s);
  EXPECT_EQ(s.data, "");
}

TEST(DdsConversion, HeaderTwistAndPoseStampedComeBackEqual) {
  EXPECT_EQ((roundTrip<std_msgs_msg_dds__Header_>(keel::test::header("base_link"))), keel::test::header("base_link"));
  const auto twist = keel::test::twist();
  EXPECT_EQ((roundTrip<geometry_msgs_msg_dds__Twist_>(twist)), twist);
  const auto pose = keel::test::poseStamped();
  EXPECT_EQ((roundTrip<geometry_msgs_msg_dds__PoseStamped_>(pose)), pose);
}

TEST(DdsConversion, ALaserScanOf1000RangesIsLentToDds) {
  const auto scan = keel::test::laserScan(1000);
  sensor_msgs_msg_dds__LaserScan_ sample{};
  DdsScratch scratch;
  toDds(scan, sample, scratch);
  EXPECT_EQ(sample.ranges._buffer, scan.ranges.data());
  EXPECT_EQ(sample.ranges._length, 1000u);
  EXPECT_EQ(sample.ranges._maximum, 1000u);
  EXPECT_FALSE(sample.ranges._release);
  EXPECT_EQ(sample.intensities._buffer, scan.intensities.data());
  EXPECT_EQ(sample.header.frame_id, scan.header.frame_id.c_str());
  msg::sensor_msgs::LaserScan back;
  fromDds(sample, back);
  EXPECT_EQ(back, scan);
  EXPECT_NE(back.ranges.data(), scan.ranges.data());  // from DDS copies
}

TEST(DdsConversion, JointStateLendsItsNumbersAndItsNames) {
  const auto joints = keel::test::jointState();
  sensor_msgs_msg_dds__JointState_ sample{};
  DdsScratch scratch;
  toDds(joints, sample, scratch);
  EXPECT_EQ(sample.position._buffer, joints.position.data());
  EXPECT_EQ(sample.effort._buffer, joints.effort.data());
  ASSERT_EQ(sample.name._length, 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(sample.name._buffer[i], joints.name[i].c_str());
  msg::sensor_msgs::JointState back;
  fromDds(sample, back);
  EXPECT_EQ(back, joints);
}

TEST(DdsConversion, DiagnosticArrayWithNestedStatusesAndKeyValuesComesBackEqual) {
  const auto diagnostics = keel::test::diagnosticArray();
  diagnostic_msgs_msg_dds__DiagnosticArray_ sample{};
  DdsScratch scratch;
  toDds(diagnostics, sample, scratch);
  ASSERT_EQ(sample.status._length, 2u);
  const auto& status = sample.status._buffer[1];
  EXPECT_EQ(status.level, msg::diagnostic_msgs::DiagnosticStatus::ERROR);
  EXPECT_EQ(status.name, diagnostics.status[1].name.c_str());
  ASSERT_EQ(status.values._length, 2u);
  EXPECT_EQ(status.values._buffer[1].value, diagnostics.status[1].values[1].value.c_str());
  msg::diagnostic_msgs::DiagnosticArray back;
  back.status.resize(5);  // longer than what comes: must shrink
  fromDds(sample, back);
  EXPECT_EQ(back, diagnostics);
  EXPECT_EQ((roundTrip<diagnostic_msgs_msg_dds__DiagnosticArray_>(msg::diagnostic_msgs::DiagnosticArray{}, back)),
            msg::diagnostic_msgs::DiagnosticArray{});
}

TEST(DdsConversion, ImuCovariancesAreFixedArraysCopiedWhole) {
  const auto imu = keel::test::imu();
  sensor_msgs_msg_dds__Imu_ sample{};
  DdsScratch scratch;
  toDds(imu, sample, scratch);
  for (std::size_t i = 0; i < 9; ++i)
    EXPECT_EQ(sample.angular_velocity_covariance[i], imu.angular_velocity_covariance[i]);
  EXPECT_EQ((roundTrip<sensor_msgs_msg_dds__Imu_>(imu)), imu);
}

TEST(DdsConversion, FloatMultiArrayLendsItsDataAndCopiesItsDimensions) {
  msg::std_msgs::Float64MultiArray a;
  a.layout.dim.resize(2);
  a.layout.dim[0] = {"rows", 2, 6};
  a.layout.dim[1] = {"cols", 3, 3};
  a.layout.data_offset = 1;
  a.data = {0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0};
  std_msgs_msg_dds__Float64MultiArray_ sample{};
  DdsScratch scratch;
  toDds(a, sample, scratch);
  EXPECT_EQ(sample.data._buffer, a.data.data());
  EXPECT_NE(static_cast<void*>(sample.layout.dim._buffer), static_cast<void*>(a.layout.dim.data()));
  EXPECT_EQ(sample.layout.dim._buffer[0].label, a.layout.dim[0].label.c_str());
  EXPECT_EQ((roundTrip<std_msgs_msg_dds__Float64MultiArray_>(a)), a);
}

TEST(DdsConversion, AnEmptyMessageIsOnePlaceholderByte) {
  std_msgs_msg_dds__Empty_ sample{};
  sample.structure_needs_at_least_one_member = 9;
  DdsScratch scratch;
  toDds(msg::std_msgs::Empty{}, sample, scratch);
  EXPECT_EQ(sample.structure_needs_at_least_one_member, 0);
  EXPECT_EQ((roundTrip<std_msgs_msg_dds__Empty_>(msg::std_msgs::Empty{})), msg::std_msgs::Empty{});
  EXPECT_EQ((roundTrip<keel_test_msgs_msg_dds__Nothing_>(msg::keel_test_msgs::Nothing{})),
            msg::keel_test_msgs::Nothing{});
}

TEST(DdsConversion, EveryKindOfFieldComesBackEqual) {
  const auto e = keel::test::everything();
  EXPECT_EQ((roundTrip<keel_test_msgs_msg_dds__Everything_>(e)), e);
  EXPECT_EQ((roundTrip<keel_test_msgs_msg_dds__Everything_>(msg::keel_test_msgs::Everything{}, e)),
            msg::keel_test_msgs::Everything{});
}

TEST(DdsConversion, BoolSequencesAreCopiedIntoTheScratchAndOtherSequencesLent) {
  const auto e = keel::test::everything();
  keel_test_msgs_msg_dds__Everything_ sample{};
  DdsScratch scratch;
  toDds(e, sample, scratch);
  ASSERT_EQ(sample.flags._length, e.flags.size());
  for (std::size_t i = 0; i < e.flags.size(); ++i) EXPECT_EQ(sample.flags._buffer[i], e.flags[i]);
  EXPECT_EQ(sample.bytes._buffer, e.bytes.data());
  EXPECT_EQ(sample.octets._buffer, e.octets.data());
  EXPECT_EQ(sample.tiny._buffer, e.tiny.data());
  EXPECT_EQ(sample.big._buffer, e.big.data());
  EXPECT_EQ(sample.text_pair[1], e.text_pair[1].c_str());
  EXPECT_EQ(sample.texts._buffer[0], e.texts[0].c_str());
  EXPECT_EQ(sample.parts._buffer[1].name, e.parts[1].name.c_str());
  EXPECT_EQ(sample.class_, e.class_);
  EXPECT_EQ(sample.module_, e.module);
}

TEST(DdsConversion, BoundedStringsAndSequencesAreTruncatedToTheirBound) {
  auto e = keel::test::everything();
  e.short_text = "abcdefgh";              // string<=5
  e.short_pair = {"four", "xy"};          // string<=3[2]
  e.short_texts = {"abcd", "ab", "abc"};  // string<=3[]
  e.few_texts = {"one", "two", "three"};  // string[<=2]
  e.tiny = {1, 2, 3, 4, 5};               // int8[<=3]
  e.few_parts.resize(3);                  // Part[<=2]
  keel_test_msgs_msg_dds__Everything_ sample{};
  DdsScratch scratch;
  toDds(e, sample, scratch);
  EXPECT_STREQ(sample.short_text, "abcde");
  EXPECT_EQ(sample.tiny._length, 3u);
  EXPECT_EQ(sample.few_texts._length, 2u);
  EXPECT_EQ(sample.few_parts._length, 2u);
  msg::keel_test_msgs::Everything back;
  fromDds(sample, back);
  EXPECT_EQ(back.short_text, "abcde");
  EXPECT_EQ(back.short_pair, (std::array<std::string, 2>{"fou", "xy"}));
  EXPECT_EQ(back.short_texts, (std::vector<std::string>{"abc", "ab", "abc"}));
  EXPECT_EQ(back.few_texts, (std::vector<std::string>{"one", "two"}));
  EXPECT_EQ(back.tiny, (std::vector<std::int8_t>{1, 2, 3}));
  EXPECT_EQ(back.few_parts.size(), 2u);
}

TEST(DdsConversion, ABoundedStringFillingItsWholeArrayStopsAtTheArray) {
  keel_test_msgs_msg_dds__Everything_ sample{};
  std::memcpy(sample.short_text, "abcdef", 6);  // char[6], no terminating NUL: a broken sample
  msg::keel_test_msgs::Everything back;
  fromDds(sample, back);
  EXPECT_EQ(back.short_text, "abcdef");
}

}  // namespace
