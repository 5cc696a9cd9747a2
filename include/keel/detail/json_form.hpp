// A port value's JSON form, for the live monitor's port channels (docs/monitor.md): numbers,
// booleans, and fixed-size arrays of them. Other types have none (JsonForm<T>::kHas is false),
// and their ports are not shown. NaN and infinities are JSON's null.
// Thread-safety: functions of their arguments.
#pragma once

#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>

namespace keel::detail {

template <class E>
void appendJsonScalar(std::string& out, E v) {
  if constexpr (std::is_same_v<E, bool>) {
    out += v ? "true" : "false";
  } else {
    if constexpr (std::is_floating_point_v<E>) {
      if (!std::isfinite(v)) {
        out += "null";
        return;
      }
    }
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
  }
}

template <class T>
struct JsonForm {
  static constexpr bool kHas = std::is_arithmetic_v<T>;
  /// "number", "integer", "boolean" or "array": the JSON Schema type of the value.
  static constexpr const char* schemaType() {
    return std::is_same_v<T, bool> ? "boolean" : std::is_integral_v<T> ? "integer" : "number";
  }
  static void append(std::string& out, const T& v) { appendJsonScalar(out, v); }
};

template <class E, std::size_t N>
struct JsonForm<std::array<E, N>> {
  static constexpr bool kHas = std::is_arithmetic_v<E>;
  static constexpr const char* schemaType() { return "array"; }
  static void append(std::string& out, const std::array<E, N>& v) {
    out += '[';
    for (std::size_t i = 0; i < N; ++i) {
      if (i) out += ',';
      appendJsonScalar(out, v[i]);
    }
    out += ']';
  }
};

}  // namespace keel::detail
