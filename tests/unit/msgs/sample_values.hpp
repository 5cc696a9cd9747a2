// Message values for keel's message tests (tests/unit/msgs): every field set to something other
// than its default, sequences of several elements, UTF-8 strings. Pure functions; touch nothing.
#pragma once

#include <cstdint>
#include <string>

#include "keel/msg/diagnostic_msgs/msg/diagnostic_array.hpp"
#include "keel/msg/geometry_msgs/msg/pose_stamped.hpp"
#include "keel/msg/geometry_msgs/msg/twist.hpp"
#include "keel/msg/keel_test_msgs/msg/everything.hpp"
#include "keel/msg/sensor_msgs/msg/imu.hpp"
#include "keel/msg/sensor_msgs/msg/joint_state.hpp"
#include "keel/msg/sensor_msgs/msg/laser_scan.hpp"
#include "keel/msg/std_msgs/msg/header.hpp"

namespace keel::test {

inline msg::std_msgs::Header header(std::string frame) {
  msg::std_msgs::Header h;
  h.stamp.sec = -12;
  h.stamp.nanosec = 999'999'999u;
  h.frame_id = std::move(frame);
  return h;
}

inline msg::geometry_msgs::Twist twist() {
  msg::geometry_msgs::Twist t;
  t.linear.x = 0.5;
  t.linear.y = -1.5;
  t.linear.z = 2e-9;
  t.angular.x = 1.0 / 3.0;
  t.angular.z = -0.25;
  return t;
}

inline msg::geometry_msgs::PoseStamped poseStamped() {
  msg::geometry_msgs::PoseStamped p;
  p.header = header("map");
  p.pose.position.x = 10.0;
  p.pose.position.y = -20.0;
  p.pose.position.z = 0.125;
  p.pose.orientation.z = 0.70710678118654752;
  p.pose.orientation.w = 0.70710678118654752;
  return p;
}

inline msg::sensor_msgs::LaserScan laserScan(int n) {
  msg::sensor_msgs::LaserScan s;
  s.header = header("laser");
  s.angle_min = -1.5f;
  s.angle_max = 1.5f;
  s.angle_increment = 3.0f / static_cast<float>(n);
  s.time_increment = 1e-5f;
  s.scan_time = 0.1f;
  s.range_min = 0.05f;
  s.range_max = 30.0f;
  for (int i = 0; i < n; ++i) {
    s.ranges.push_back(0.5f + static_cast<float>(i) * 0.01f);
    s.intensities.push_back(static_cast<float>(i % 7));
  }
  return s;
}

inline msg::sensor_msgs::JointState jointState() {
  msg::sensor_msgs::JointState j;
  j.header = header("arm");
  j.name = {"shoulder", "elbow", "wrist_ü"};
  j.position = {0.1, -0.2, 0.3};
  j.velocity = {1.0, 2.0, 3.0};
  j.effort = {-4.0, 5.5, 0.0};
  return j;
}

inline msg::diagnostic_msgs::DiagnosticArray diagnosticArray() {
  msg::diagnostic_msgs::DiagnosticArray a;
  a.header = header("");
  msg::diagnostic_msgs::DiagnosticStatus ok;
  ok.level = msg::diagnostic_msgs::DiagnosticStatus::OK;
  ok.name = "keel: motor";
  ok.message = "running";
  ok.hardware_id = "m1";
  msg::diagnostic_msgs::DiagnosticStatus error;
  error.level = msg::diagnostic_msgs::DiagnosticStatus::ERROR;
  error.name = "keel: sonar";
  error.message = "no echo for 120 ms";
  error.hardware_id = "s3";
  error.values = {{"kind", "timeout"}, {"since", "12.5"}};
  a.status = {ok, error};
  return a;
}

inline msg::sensor_msgs::Imu imu() {
  msg::sensor_msgs::Imu m;
  m.header = header("imu");
  m.orientation.w = 1.0;
  m.angular_velocity.z = 0.02;
  m.linear_acceleration.z = 9.81;
  for (std::size_t i = 0; i < 9; ++i) {
    m.orientation_covariance[i] = static_cast<double>(i) * 0.1;
    m.angular_velocity_covariance[i] = -static_cast<double>(i);
    m.linear_acceleration_covariance[i] = static_cast<double>(i * i);
  }
  return m;
}

inline msg::keel_test_msgs::Everything everything() {
  msg::keel_test_msgs::Everything e;
  e.header = header("everything");
  e.twist = twist();
  e.part = {"part", {1.0, 2.0, 3.0}, {true, false}};
  e.pair = {msg::keel_test_msgs::Part{"left", {4.0, 5.0, 6.0}, {}}, msg::keel_test_msgs::Part{"right", {}, {true}}};
  e.parts = {e.part, e.pair[0], e.pair[1]};
  e.few_parts = {e.pair[1]};
  e.flag = false;
  e.b = 255;
  e.c = 'x';
  e.i8 = -128;
  e.u8 = 200;
  e.i16 = -30000;
  e.u16 = 60000;
  e.i32 = -2'000'000'000;
  e.u32 = 4'000'000'000u;
  e.i64 = -9'000'000'000'000'000'000;
  e.u64 = 18'000'000'000'000'000'000u;
  e.f32 = -0.1f;
  e.f64 = 6.02214076e23;
  e.distance = -1.0;
  e.text = "ünïcödé text";
  e.quoted = "";
  e.short_text = "ok";
  e.texts = {"one", "", "three"};
  e.text_pair = {"p", "q"};
  e.short_texts = {"ab", "abc"};
  e.short_pair = {"x", "yz"};
  e.few_texts = {"f"};
  e.flags = {true, true, false, true};
  e.flag_triple = {false, true, false};
  e.values = {-1.0, 0.0, 1e300};
  e.quad = {1.0f, 2.0f, 3.0f, 4.0f};
  e.bytes = {0, 1, 255};
  e.octets = {9, 8};
  e.chars = {'a', 'b'};
  e.tiny = {-1, 1};
  e.big = {1, 18'446'744'073'709'551'615u};
  e.class_ = 17;
  e.module = 18;
  return e;
}

}  // namespace keel::test
