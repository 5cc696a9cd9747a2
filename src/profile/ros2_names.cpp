// ROS 2's names, checked as ROS 2 checks them; see ros2_names.hpp.
#include "profile/ros2_names.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace keel::profile::detail {
namespace {

bool alnum(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; }
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }
bool identifierChar(char c) { return alnum(c) || c == '_'; }

/// Why `name` is not tokens of letters, digits and '_' separated by `sep`, none empty and none
/// starting with a digit; `what` names the tokens in messages ("name", "token").
std::string tokensProblem(std::string_view name, char sep, std::string_view what) {
  if (name.empty()) return "it is empty";
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t end = std::min(name.find(sep, start), name.size());
    const std::string_view token = name.substr(start, end - start);
    if (token.empty()) return fmt::format("it has an empty {} ('{}' first, last or twice)", what, sep);
    for (char c : token)
      if (!identifierChar(c)) return fmt::format("'{}' is not allowed (letters, digits, '_' and '{}' only)", c, sep);
    if (digit(token.front())) return fmt::format("its {} '{}' starts with a digit", what, token);
    start = end + 1;
  }
  return {};
}

}  // namespace

std::string topicProblem(std::string_view topic) {
  if (topic.empty()) return "it is empty";
  if (topic.front() == '~') return "'~' names a node's private namespace, and keel's ports belong to no ROS node";
  if (topic.back() == '/') return "it ends with '/'";
  std::string_view rest = topic.front() == '/' ? topic.substr(1) : topic;
  if (rest.empty()) return "it names no topic";
  std::size_t start = 0;
  while (start <= rest.size()) {
    const std::size_t end = std::min(rest.find('/', start), rest.size());
    const std::string_view token = rest.substr(start, end - start);
    if (token.empty()) return "it has an empty token ('//')";
    if (digit(token.front())) return fmt::format("its token '{}' starts with a digit", token);
    for (char c : token)
      if (!identifierChar(c))
        return fmt::format("'{}' is not allowed (ROS 2 names have letters, digits, '_' and '/')", c);
    start = end + 1;
  }
  if (rest.size() + 1 > kMaxTopicLength)
    return fmt::format("it is {} characters long, and ROS 2's longest is {}", rest.size() + 1, kMaxTopicLength);
  return {};
}

std::string typeProblem(std::string_view type) {
  const std::size_t a = type.find('/');
  const std::size_t b = a == std::string_view::npos ? a : type.find('/', a + 1);
  if (a == std::string_view::npos || b == std::string_view::npos || type.substr(a, b - a) != "/msg" ||
      type.find('/', b + 1) != std::string_view::npos)
    return "it must be written as ROS 2 writes it: package/msg/Name, e.g. std_msgs/msg/Float64";
  const std::string_view pkg = type.substr(0, a);
  const std::string_view name = type.substr(b + 1);
  if (pkg.empty() || !std::islower(static_cast<unsigned char>(pkg.front())))
    return "the package must start with a lower-case letter";
  for (char c : pkg)
    if (!(std::islower(static_cast<unsigned char>(c)) || digit(c) || c == '_'))
      return fmt::format("'{}' in the package name (lower case, digits and '_' only)", c);
  if (name.empty() || !std::isupper(static_cast<unsigned char>(name.front())))
    return "the message name must start with an upper-case letter";
  for (char c : name)
    if (!alnum(c)) return fmt::format("'{}' in the message name", c);
  return {};
}

// rmw_validate_namespace's checks, in its order and with its messages (the offending part added).
std::string namespaceProblem(std::string_view ns) {
  if (ns == "/") return {};
  if (ns.empty()) return "namespace must not be empty";
  if (ns.front() != '/') return "namespace must be absolute, it must lead with a '/'";
  if (ns.back() == '/') return "namespace must not end with a '/', unless only a '/'";
  for (char c : ns)
    if (!identifierChar(c) && c != '/')
      return fmt::format("namespace must not contain characters other than alphanumerics, '_', or '/' ('{}')", c);
  for (std::size_t i = 0; i + 1 < ns.size(); ++i) {
    if (ns[i] != '/') continue;
    if (ns[i + 1] == '/') return "namespace must not contain repeated '/'";
    if (digit(ns[i + 1])) {
      const std::string_view token = ns.substr(i + 1, ns.find('/', i + 1) - (i + 1));
      return fmt::format("namespace must not have a token that starts with a number ('{}')", token);
    }
  }
  if (ns.size() > kMaxNamespaceLength)
    return fmt::format("namespace should not exceed {} characters (it has {})", kMaxNamespaceLength, ns.size());
  return {};
}

// rmw_validate_node_name's checks, in its order and with its messages.
std::string nodeNameProblem(std::string_view name) {
  if (name.empty()) return "node name must not be empty";
  for (char c : name)
    if (!identifierChar(c))
      return fmt::format("node name must not contain characters other than alphanumerics or '_' ('{}')", c);
  if (digit(name.front())) return "node name must not start with a number";
  if (name.size() > kMaxNodeNameLength)
    return fmt::format("node name length should not exceed {} (it has {})", kMaxNodeNameLength, name.size());
  return {};
}

std::string parameterNameProblem(std::string_view name) { return tokensProblem(name, '.', "token"); }

std::string fieldPathProblem(std::string_view path) { return tokensProblem(path, '.', "field name"); }

std::string environmentNameProblem(std::string_view name) {
  if (name.empty()) return "it is empty";
  if (digit(name.front())) return "it starts with a digit";
  for (char c : name)
    if (!identifierChar(c)) return fmt::format("'{}' is not allowed (letters, digits and '_' only)", c);
  return {};
}

}  // namespace keel::profile::detail
