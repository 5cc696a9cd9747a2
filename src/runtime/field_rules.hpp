// <validity field="a.b.c"> on a port whose type is a generated message (docs/profiles.md): the
// path resolved once, at load, against the type's table of fields
// (keel/detail/message_fields.hpp), and checked on every value the port sends or receives as a
// ValidityRule checks a number. A violation is a `range` fault of the port's owner whose detail
// names the field, the element, the value and the bounds. The same paths let a connection carry
// one numeric field of a message (a FieldTap).
// Thread-safety: rules are immutable once set on a port (before start); checks are reentrant
// and allocate nothing.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "keel/data_port.hpp"
#include "keel/detail/message_fields.hpp"
#include "keel/detail/validity.hpp"
#include "keel/result.hpp"

namespace keel::runtime {

/// The most names a path may have (a message nests no deeper in practice).
inline constexpr std::size_t kMaxFieldDepth = 16;

/// One <validity field="..">: the field each name of the path reaches, the last a number or an
/// array of numbers; every array on the way is checked element by element.
struct FieldRule {
  std::string path;  // as the profile gives it: "poses.position.x"
  std::vector<const detail::MessageField*> steps;
  detail::ValidityRule rule;
};

/// The fields `path` names in the message type `type` (its ROS 2 name) whose fields are
/// `fields`, or why it names none: a name that is not there (with the fields that are, and the
/// nearest), a path that ends at a message, or that reaches a bool or a string.
Result<std::vector<const detail::MessageField*>> resolveFieldPath(std::span<const detail::MessageField> fields,
                                                                  std::string_view type, std::string_view path);

/// The field `path` names for a connection that carries it: as resolveFieldPath, and one
/// number per message, so no array on the way or at its end.
Result<std::vector<const detail::MessageField*>> resolveFieldTap(std::span<const detail::MessageField> fields,
                                                                 std::string_view type, std::string_view path);

/// The path of every numeric field of a type, nested messages' fields included, in the .msg's
/// order: "linear.x", "linear.y", ... (what a <validity field=".."> may name).
std::vector<std::string> numericFieldPaths(std::span<const detail::MessageField> fields);

}  // namespace keel::runtime

namespace keel::detail {

/// A connection that carries one numeric field of a message port's values (a port_connection
/// whose <source> names a `field`): each value the port sends, once its rules passed, gives the
/// field's number to `out`, a port of the message port's owner connected to the target.
struct FieldTap {
  std::vector<const MessageField*> steps;  // no array on the way: one number per message
  OutputDataPort<double>* out = nullptr;
};

/// The field rules of one port, in the profile's order, and the numeric fields it sends on.
struct FieldRules {
  std::vector<runtime::FieldRule> rules;
  std::vector<FieldTap> taps{};
};

/// Sends the number `tap` reaches in the message at `message` on its port (checkFields does, for
/// each tap, once the rules passed).
void sendField(const FieldTap& tap, const void* message);

}  // namespace keel::detail
