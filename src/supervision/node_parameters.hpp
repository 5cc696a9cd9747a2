// The parameter values keel restarts a ROS 2 node with (docs/ros2-nodes.md): its profile's
// <parameters>, typed as rcl types a `-p name:=value`, overlaid by every change the node
// announced on /parameter_events, written as the ROS 2 params file (`--params-file`) of its
// restart. Used by the node supervisor; pure functions, but writeParamsFile, which writes a file.
// Thread-safety: functions of their arguments.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "keel/result.hpp"
#include "profile/model.hpp"
#include "profile/parameter_value.hpp"

namespace keel::supervision {

/// A node's parameters by name.
using ParameterMap = std::map<std::string, profile::ParameterValue, std::less<>>;

/// `text` typed as rcl types the value of `-p name:=text` (rcl_yaml_param_parser): a YAML
/// scalar — quoted: a string; plain: a bool (`true`, `yes`, `on`, `y` and their negations, in
/// YAML's three cases), else an integer (C's strtoll, base 0: `0x10` is 16), else a double
/// (strtod, `.inf`, `.nan`), else a string — or a flow sequence of scalars of one type (`[1, 2]`).
/// Nothing where rcl has no value or refuses one: empty, `[]`, mixed types, a mapping.
std::optional<profile::ParameterValue> rosValueOf(std::string_view text);

/// The profile's <parameters>, typed by rosValueOf (those with no value left out).
ParameterMap typedParameters(const std::vector<profile::NodeParameter>& parameters);

/// `update` applied to `values`: its new and changed values set, its deleted names erased.
void overlay(ParameterMap& values, const profile::ParameterUpdate& update);

/// `value` as a params file holds it, so that rcl gives the node back the same type and value: a
/// string double-quoted (never `yes` or `1.0` taken for a bool or a number), a double with a
/// decimal point or exponent (`1.0`, `.inf`), an array as a flow list. "" for an empty array,
/// which rcl cannot type (it leaves the parameter unset): left out of the file.
std::string yamlOf(const profile::ParameterValue& value);

/// The params file giving node `fqn` ("/ns/name") `values`: `fqn:` / `ros__parameters:` / one
/// `name: value` line each.
std::string paramsFileText(std::string_view fqn, const ParameterMap& values);

/// Writes paramsFileText(fqn, values) to `path`, whole or not at all (a temporary file renamed).
Result<void> writeParamsFile(const std::string& path, std::string_view fqn, const ParameterMap& values);

}  // namespace keel::supervision
