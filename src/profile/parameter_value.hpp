// A ROS 2 parameter's value, typed as rcl_interfaces/msg/ParameterValue types it, and a change of
// a node's parameters as /parameter_events announces it. One definition for the layers that meet
// over it: the DDS layer reads the changes, the supervision layer keeps each node's values and
// restarts the node with them (docs/ros2-nodes.md). Thread-safety: plain values.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace keel::profile {

/// bool, integer, double, string and their arrays. A byte array has no place here: a ROS 2
/// params file cannot hold one (rcl types a YAML list by its items).
using ParameterValue = std::variant<bool, std::int64_t, double, std::string, std::vector<bool>,
                                    std::vector<std::int64_t>, std::vector<double>, std::vector<std::string>>;

/// What one parameter event of a node says: the values of its new and changed parameters, and
/// the names of those it deleted (or set to no value).
struct ParameterUpdate {
  std::vector<std::pair<std::string, ParameterValue>> set;
  std::vector<std::string> deleted;
  bool operator==(const ParameterUpdate&) const = default;
};

}  // namespace keel::profile
