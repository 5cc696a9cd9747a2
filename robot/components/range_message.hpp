// RangeMessage: one sonar's reading as ROS 2 publishes a ranger's (robot/ros2.xml): a range in
// cm from an UltrasonicSensor in (after its <validity>: an unplugged sonar's 0 never gets here),
// a sensor_msgs/msg/Range out, for keel's <dds> to put on a topic. Stamped with the system
// clock, as ROS 2 stamps; ULTRASOUND, with the beam's field of view and the board's range.
// Thread-safety: a component.
#pragma once

#include <chrono>
#include <optional>
#include <string>

#include <keel/component.hpp>
#include <keel/msg/sensor_msgs/msg/range.hpp>

namespace keel::robot {

class RangeMessage : public Component {
 public:
  InputDataPort<double> cm{this, "cm"};
  OutputDataPort<msg::sensor_msgs::Range> range{this, "range"};

  ReturnCode onInitialize() override {
    message_.header.frame_id = property<std::string>("frame_id", "sonar");
    message_.radiation_type = msg::sensor_msgs::Range::ULTRASOUND;
    message_.field_of_view = static_cast<float>(property<double>("field_of_view", 0.52));
    message_.min_range = static_cast<float>(property<double>("min_range", 0.03));
    message_.max_range = static_cast<float>(property<double>("max_range", 30.0));
    if (message_.header.frame_id.empty()) rejectProperty("frame_id", "must not be empty");
    if (!(message_.field_of_view > 0)) rejectProperty("field_of_view", "must be > 0");
    if (!(message_.max_range > message_.min_range)) rejectProperty("max_range", "must exceed min_range");
    return ReturnCode::Ok;
  }

  ReturnCode onExecute() override {
    std::optional<double> newest;
    while (auto v = cm.pop()) newest = v;
    if (!newest) return ReturnCode::Ok;
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count();
    message_.header.stamp.sec = static_cast<std::int32_t>(ns / 1'000'000'000);
    message_.header.stamp.nanosec = static_cast<std::uint32_t>(ns % 1'000'000'000);
    message_.range = static_cast<float>(*newest / 100.0);
    range.push(message_);
    return ReturnCode::Ok;
  }

 private:
  msg::sensor_msgs::Range message_;
};

}  // namespace keel::robot
