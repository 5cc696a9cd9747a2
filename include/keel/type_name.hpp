// keel::typeName<T>(): the name a port's data type has in profiles (`data_type`). Builtin
// numbers, std::string, std::vector and std::array of those, keel::Event and keel::FaultEvent
// have short names; other types use their demangled C++ name unless declared with
// KEEL_TYPE_NAME(T, "name"). Header-only; thread-safe (returns static data).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <typeinfo>
#include <vector>

#include "keel/event.hpp"
#include "keel/fault_event.hpp"

namespace keel {

namespace detail {
std::string demangle(const char* mangled);  // defined in libkeel
}

template <class T>
struct TypeName {
  static std::string get() { return detail::demangle(typeid(T).name()); }
};

#define KEEL_TYPE_NAME(T, NAME)               \
  template <>                                 \
  struct keel::TypeName<T> {                  \
    static std::string get() { return NAME; } \
  }

template <class T>
const std::string& typeName() {
  static const std::string name = TypeName<T>::get();
  return name;
}

#define KEEL_DETAIL_BUILTIN_NAME(T, NAME)     \
  template <>                                 \
  struct TypeName<T> {                        \
    static std::string get() { return NAME; } \
  };
KEEL_DETAIL_BUILTIN_NAME(bool, "bool")
KEEL_DETAIL_BUILTIN_NAME(char, "char")
KEEL_DETAIL_BUILTIN_NAME(std::int8_t, "int8")
KEEL_DETAIL_BUILTIN_NAME(std::uint8_t, "uint8")
KEEL_DETAIL_BUILTIN_NAME(std::int16_t, "int16")
KEEL_DETAIL_BUILTIN_NAME(std::uint16_t, "uint16")
KEEL_DETAIL_BUILTIN_NAME(int, "int")
KEEL_DETAIL_BUILTIN_NAME(unsigned, "unsigned")
KEEL_DETAIL_BUILTIN_NAME(long, "long")
KEEL_DETAIL_BUILTIN_NAME(unsigned long, "unsigned long")
KEEL_DETAIL_BUILTIN_NAME(long long, "long long")
KEEL_DETAIL_BUILTIN_NAME(unsigned long long, "unsigned long long")
KEEL_DETAIL_BUILTIN_NAME(float, "float")
KEEL_DETAIL_BUILTIN_NAME(double, "double")
KEEL_DETAIL_BUILTIN_NAME(std::string, "string")
KEEL_DETAIL_BUILTIN_NAME(Event, "keel::Event")
KEEL_DETAIL_BUILTIN_NAME(FaultEvent, "keel::FaultEvent")
#undef KEEL_DETAIL_BUILTIN_NAME

template <class T>
struct TypeName<std::vector<T>> {
  static std::string get() { return "std::vector<" + typeName<T>() + ">"; }
};

template <class T, std::size_t N>
struct TypeName<std::array<T, N>> {
  static std::string get() { return "std::array<" + typeName<T>() + "," + std::to_string(N) + ">"; }
};

/// Profiles may spell a type differently ("std::string", "vector<double>", "int32"); this maps
/// the common spellings onto typeName's. Defined in libkeel.
std::string canonicalTypeName(std::string_view written);

}  // namespace keel
