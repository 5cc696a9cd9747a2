// The fields of a generated message type (keel::msg::<pkg>::<Name>) by name, so that keel can
// reach a field of a value by its dotted path ("linear.x", <validity field=".."> in
// docs/profiles.md) without knowing the type at compile time. keel_msggen.py writes one table
// per message (<keel/msg/<pkg>/msg/detail/<name>__fields.hpp>, a MessageFieldsOf<T>), and the
// message's registration (dds_type.hpp) carries it under the type's ROS 2 name. Authors never
// name this header. Thread-safety: the tables are constants; visits are reentrant.
#pragma once

#include <cstdint>
#include <span>
#include <type_traits>

namespace keel::detail {

/// Called with each number of a field, in order; returning false stops the visit.
using NumberVisitor = bool (*)(void* context, double value);
/// Called with each message of a field (its address), in order; returning false stops the visit.
using MessageVisitor = bool (*)(void* context, const void* message);

/// What a field holds (each element of it, for an array): only numbers can be range-checked.
enum class FieldKind : std::uint8_t {
  Number,   // the integer and floating types, byte and char
  Bool,     // bool
  String,   // string, string<=N
  Message,  // another message, whose fields a path continues into
};

/// One field of a message, as its .msg declares it.
struct MessageField {
  const char* name;  ///< as in the .msg: "linear"
  const char* type;  ///< as in the .msg, a message by its ROS 2 name: "float64[36]", "geometry_msgs/msg/Vector3"
  FieldKind kind;
  bool array;  ///< T[N], T[] or T[<=N]: each element is visited
  /// Message: the fields of the nested type; otherwise null.
  std::span<const MessageField> (*nested)();
  /// Number: visits each element of the field of the message at `message`; otherwise null.
  /// False when a visitor stopped it.
  bool (*numbers)(const void* message, void* context, NumberVisitor visit);
  /// Message: visits each element (each nested message) likewise; otherwise null.
  bool (*messages)(const void* message, void* context, MessageVisitor visit);
};

/// The table of the message type M: `static std::span<const MessageField> fields()`, in the
/// .msg's order. Specialised by each message's generated __fields.hpp.
template <class M>
struct MessageFieldsOf;

template <class P>
struct MemberOf;
template <class M, class F>
struct MemberOf<F M::*> {
  using Message = M;
  using Field = F;
};

/// The `numbers` of the field P (a pointer to a member: a number, or an array of numbers).
template <auto P>
bool visitNumbers(const void* message, void* context, NumberVisitor visit) {
  using Of = MemberOf<decltype(P)>;
  const typename Of::Field& field = static_cast<const typename Of::Message*>(message)->*P;
  if constexpr (std::is_arithmetic_v<typename Of::Field>) {
    return visit(context, static_cast<double>(field));
  } else {
    for (const auto& e : field)
      if (!visit(context, static_cast<double>(e))) return false;
    return true;
  }
}

/// The `messages` of the field P (a pointer to a member: a message, or an array of messages).
template <auto P>
bool visitMessages(const void* message, void* context, MessageVisitor visit) {
  using Of = MemberOf<decltype(P)>;
  const typename Of::Field& field = static_cast<const typename Of::Message*>(message)->*P;
  if constexpr (requires(const typename Of::Field& f) { f.begin(); }) {
    for (const auto& e : field)
      if (!visit(context, &e)) return false;
    return true;
  } else {
    return visit(context, &field);
  }
}

}  // namespace keel::detail
