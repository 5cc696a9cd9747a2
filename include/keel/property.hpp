// Typed component properties (docs/author-api.md): the values of a component profile's
// properties/property, after subcomponent overrides, read with Component::property<T>().
// Header-only conversion rules; a value that cannot be represented as T is a PropertyError.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

namespace keel {

/// bool, int (int64), double, string, double[] — as the profile's `type` says.
using PropertyValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

class PropertyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  PropertyError(const std::string& what, std::string property)
      : std::runtime_error(what), property_(std::move(property)) {}
  /// The property refused; empty when the error names none.
  const std::string& property() const noexcept { return property_; }

 private:
  std::string property_;
};

namespace detail {

[[noreturn]] void throwPropertyError(std::string_view component, std::string_view name, std::string_view why);

template <class T>
T propertyAs(const PropertyValue* v, std::string_view component, std::string_view name) {
  if (!v) throwPropertyError(component, name, "no such property");
  if constexpr (std::is_same_v<T, bool>) {
    if (const auto* b = std::get_if<bool>(v)) return *b;
    throwPropertyError(component, name, "is not a bool");
  } else if constexpr (std::is_integral_v<T>) {
    if (const auto* i = std::get_if<std::int64_t>(v)) {
      if (*i < static_cast<std::int64_t>(std::numeric_limits<T>::min()) ||
          (*i > 0 && static_cast<std::uint64_t>(*i) > std::numeric_limits<T>::max()))
        throwPropertyError(component, name, "is out of range for the requested integer type");
      return static_cast<T>(*i);
    }
    throwPropertyError(component, name, "is not an integer");
  } else if constexpr (std::is_floating_point_v<T>) {
    if (const auto* d = std::get_if<double>(v)) return static_cast<T>(*d);
    if (const auto* i = std::get_if<std::int64_t>(v)) return static_cast<T>(*i);
    throwPropertyError(component, name, "is not a number");
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (const auto* s = std::get_if<std::string>(v)) return *s;
    throwPropertyError(component, name, "is not a string");
  } else if constexpr (std::is_same_v<T, std::vector<double>>) {
    if (const auto* a = std::get_if<std::vector<double>>(v)) return *a;
    if (const auto* d = std::get_if<double>(v)) return {*d};
    throwPropertyError(component, name, "is not a double[]");
  } else {
    static_assert(!sizeof(T*),
                  "property<T>: T must be bool, an integer, a floating point, "
                  "std::string or std::vector<double>");
  }
}

}  // namespace detail
}  // namespace keel
