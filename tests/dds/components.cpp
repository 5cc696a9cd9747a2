// Components of the DDS interop tests (ros2_peer_test.py): echoes that send every message they
// take back out unchanged (the conversions both ways, against rclpy's), and a source of ranges.
// Their ports carry keel::msg types; the profiles are written by the test.
#include <keel/component.hpp>
#include <keel/msg/diagnostic_msgs/msg/diagnostic_array.hpp>
#include <keel/msg/geometry_msgs/msg/pose_stamped.hpp>
#include <keel/msg/geometry_msgs/msg/twist.hpp>
#include <keel/msg/keel_test_msgs/msg/nothing.hpp>
#include <keel/msg/sensor_msgs/msg/imu.hpp>
#include <keel/msg/sensor_msgs/msg/joint_state.hpp>
#include <keel/msg/sensor_msgs/msg/laser_scan.hpp>
#include <keel/msg/sensor_msgs/msg/range.hpp>
#include <keel/msg/std_msgs/msg/float64.hpp>
#include <keel/msg/std_msgs/msg/string.hpp>

#include <time.h>

#include <cstdio>
#include <string>

namespace {

/// Aperiodic: each value taken on `in` goes out on `out` as it came.
template <class T>
class Echo : public keel::Component {
 public:
  keel::InputDataPort<T> in{this, "in"};
  keel::OutputDataPort<T> out{this, "out"};

  keel::ReturnCode onExecute() override {
    while (auto v = in.pop()) out.push(*v);
    return keel::ReturnCode::Ok;
  }
};

using EchoTwist = Echo<keel::msg::geometry_msgs::Twist>;
using EchoPoseStamped = Echo<keel::msg::geometry_msgs::PoseStamped>;
using EchoString = Echo<keel::msg::std_msgs::String>;
using EchoFloat64 = Echo<keel::msg::std_msgs::Float64>;
using EchoLaserScan = Echo<keel::msg::sensor_msgs::LaserScan>;
using EchoJointState = Echo<keel::msg::sensor_msgs::JointState>;
using EchoImu = Echo<keel::msg::sensor_msgs::Imu>;
using EchoDiagnosticArray = Echo<keel::msg::diagnostic_msgs::DiagnosticArray>;
// A message type whose code is not linked into this library (its headers only): DDS cannot
// carry it, and loading says so.
using EchoUnlinked = Echo<keel::msg::keel_test_msgs::Nothing>;

/// Periodic: a sonar's reading, 0.5 m, 0.51 m, ... with its frame and field of view.
class RangeSource : public keel::Component {
 public:
  keel::OutputDataPort<keel::msg::sensor_msgs::Range> range{this, "range"};

  keel::ReturnCode onExecute() override {
    keel::msg::sensor_msgs::Range r;
    r.header.frame_id = "sonar_front";
    r.header.stamp.sec = static_cast<std::int32_t>(n_);
    r.radiation_type = keel::msg::sensor_msgs::Range::ULTRASOUND;
    r.field_of_view = 0.5f;
    r.min_range = 0.02f;
    r.max_range = 4.0f;
    r.range = 0.5f + 0.01f * static_cast<float>(n_++);
    range.push(r);
    return keel::ReturnCode::Ok;
  }

 private:
  unsigned n_ = 0;
};

/// Periodic: "<who> <n>" on `said`, n counting from 0 (a redundant role's writer).
class Announcer : public keel::Component {
 public:
  keel::OutputDataPort<keel::msg::std_msgs::String> said{this, "said"};

  keel::ReturnCode onInitialize() override {
    who_ = property<std::string>("who");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    keel::msg::std_msgs::String s;
    s.data = who_ + " " + std::to_string(n_++);
    said.push(s);
    return keel::ReturnCode::Ok;
  }

 private:
  std::string who_;
  unsigned long n_ = 0;
};

/// Aperiodic: appends each string taken on `heard` to the file `path`, one line each, after
/// CLOCK_MONOTONIC in ns (one clock for every network namespace of the machine).
class Recorder : public keel::Component {
 public:
  keel::InputDataPort<keel::msg::std_msgs::String> heard{this, "heard"};

  keel::ReturnCode onInitialize() override {
    file_ = std::fopen(property<std::string>("path").c_str(), "a");
    return file_ ? keel::ReturnCode::Ok : keel::ReturnCode::PreconditionNotMet;
  }
  keel::ReturnCode onExecute() override {
    while (auto s = heard.pop()) {
      timespec t{};
      clock_gettime(CLOCK_MONOTONIC, &t);
      std::fprintf(file_, "%lld %s\n", static_cast<long long>(t.tv_sec) * 1'000'000'000LL + t.tv_nsec, s->data.c_str());
    }
    std::fflush(file_);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onDestroy() override {
    if (file_) std::fclose(file_);
    file_ = nullptr;
    return keel::ReturnCode::Ok;
  }

 private:
  std::FILE* file_ = nullptr;
};

}  // namespace

KEEL_REGISTER_COMPONENT(Announcer)
KEEL_REGISTER_COMPONENT(Recorder)
KEEL_REGISTER_COMPONENT(EchoTwist)
KEEL_REGISTER_COMPONENT(EchoPoseStamped)
KEEL_REGISTER_COMPONENT(EchoString)
KEEL_REGISTER_COMPONENT(EchoFloat64)
KEEL_REGISTER_COMPONENT(EchoLaserScan)
KEEL_REGISTER_COMPONENT(EchoJointState)
KEEL_REGISTER_COMPONENT(EchoImu)
KEEL_REGISTER_COMPONENT(EchoDiagnosticArray)
KEEL_REGISTER_COMPONENT(EchoUnlinked)
KEEL_REGISTER_COMPONENT(RangeSource)
