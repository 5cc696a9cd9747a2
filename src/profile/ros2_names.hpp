// The names ROS 2 gives things, checked as ROS 2 checks them: topics, message types, node names
// and namespaces (rmw's rules, in rmw's words where it has them), parameter names, and the
// dotted field paths of a message. Each check returns why the name is not one, or "" when it is.
// Used by the <dds> reader and the node profile reader. Thread-safety: pure functions.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace keel::profile::detail {

/// ROS 2's longest fully qualified topic name: 255 less the 8 characters the rmw reserves for
/// its DDS prefixes and suffixes (`rt/`, `rq/`, `Request`).
inline constexpr std::size_t kMaxTopicLength = 247;
/// The longest namespace (rmw's RMW_NAMESPACE_MAX_LENGTH) and node name.
inline constexpr std::size_t kMaxNamespaceLength = 245;
inline constexpr std::size_t kMaxNodeNameLength = 255;

/// Why `topic` is not a ROS 2 topic name keel can use. A relative name is allowed and taken
/// from the root ("scan" is "/scan"): keel's own ports belong to no node.
std::string topicProblem(std::string_view topic);

/// Why `type` is not a ROS 2 message type name (`pkg/msg/Name`).
std::string typeProblem(std::string_view type);

/// Why `ns` is not a node namespace (rmw_validate_namespace): "/" or "/a/b".
std::string namespaceProblem(std::string_view ns);

/// Why `name` is not a node name (rmw_validate_node_name).
std::string nodeNameProblem(std::string_view name);

/// Why `name` is not a ROS 2 parameter name: tokens of letters, digits and '_', none starting
/// with a digit, separated by '.'.
std::string parameterNameProblem(std::string_view name);

/// Why `path` is not a path to a field of a message: names of letters, digits and '_', none
/// starting with a digit, separated by '.' ("linear.x").
std::string fieldPathProblem(std::string_view path);

/// Why `name` is not an environment variable's name: a letter or '_', then letters, digits, '_'.
std::string environmentNameProblem(std::string_view name);

}  // namespace keel::profile::detail
