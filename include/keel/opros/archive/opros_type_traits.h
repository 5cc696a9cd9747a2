// opros_type_traits.h — keel's own OPRoS-compatible version of OPRoS's type traits.
//
// OPRoS spelled out its own traits before <type_traits> existed; code that names them
// (`opros::is_enum<T>::value`, `opros::remove_const<T>::type`, ...) gets them here, built on the
// standard ones. keel's archive does not use them itself. Header-only, stateless.
#pragma once

#include <cstddef>
#include <type_traits>

namespace opros {

// A built-in arithmetic type (bool, the character types, integers, floating point).
template <typename T>
struct is_primitive : std::bool_constant<std::is_arithmetic_v<std::remove_cv_t<T>>> {};

// A C array of known bound.
template <typename T>
struct is_array : std::false_type {};
template <typename T, std::size_t N>
struct is_array<T[N]> : std::true_type {};

template <typename T>
struct is_pointer : std::is_pointer<T> {};

// As in OPRoS, unions count as classes.
template <typename T>
struct is_class : std::bool_constant<std::is_class_v<T> || std::is_union_v<T>> {};

template <typename T>
struct is_enum : std::is_enum<T> {};

template <typename T>
struct remove_const {
  typedef std::remove_const_t<T> type;
};

template <typename T>
struct add_const {
  typedef std::add_const_t<T> type;
};

template <typename T>
struct remove_reference {
  typedef std::remove_reference_t<T> type;
};

template <typename T>
struct remove_pointer {
  typedef std::remove_pointer_t<T> type;
};

}  // namespace opros
