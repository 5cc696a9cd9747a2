// The message types DDS ports can carry: every keel::detail::DdsType registered by generated
// message code (keel's shipped messages in libkeel, a user's keel_add_messages library), found
// by ROS 2 name, each with the table of its fields a <validity field=".."> names. Thread-safety: registration in static
// initialisers (libraries being loaded, under the dynamic loader's lock); lookups from any thread.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "keel/detail/dds_type.hpp"

namespace keel::dds {

/// The type registered under ROS 2 name `ros_name` ("std_msgs/msg/Float64"), or null.
const detail::DdsType* findType(std::string_view ros_name);
/// Every registered ROS 2 name, sorted (for messages).
std::vector<std::string> typeNames();

}  // namespace keel::dds
