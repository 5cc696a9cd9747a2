// opros_oarchive.h — keel's own OPRoS-compatible version of OPRoS's output archive.
//
// `opros::archive::oarchive` is the abstract writer; `ar << x` (and `ar & x`) saves a primitive,
// std::string/std::wstring, an enumeration, a C array, an STL container (vector, deque, list,
// set, multiset, map, multimap, the unordered ones, valarray, array, pair, complex, stack, queue,
// priority_queue), a named value (OPROS_SERIALIZATION_NVP) or a user type with save/load members
// (through opros::archive::access) or a `save_this(oarchive&, T&)` function. The concrete archives
// (binary, raw, string) implement the virtual primitives. An archive is used by one thread at a time.
#pragma once

#include <array>
#include <complex>
#include <cstddef>
#include <deque>
#include <list>
#include <map>
#include <queue>
#include <set>
#include <stack>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <valarray>
#include <vector>

#include "opros_archive_common.h"
#include "opros_type_info.h"

namespace opros {
namespace archive {

class oarchive : public archive {
 public:
  ~oarchive() override = default;

  // One value of each primitive type.
  virtual oarchive& save(bool value) = 0;
  virtual oarchive& save(char value) = 0;
  virtual oarchive& save(signed char value) = 0;
  virtual oarchive& save(unsigned char value) = 0;
  virtual oarchive& save(wchar_t value) = 0;
  virtual oarchive& save(short value) = 0;
  virtual oarchive& save(unsigned short value) = 0;
  virtual oarchive& save(int value) = 0;
  virtual oarchive& save(unsigned int value) = 0;
  virtual oarchive& save(long value) = 0;
  virtual oarchive& save(unsigned long value) = 0;
  virtual oarchive& save(long long value) = 0;
  virtual oarchive& save(unsigned long long value) = 0;
  virtual oarchive& save(float value) = 0;
  virtual oarchive& save(double value) = 0;
  virtual oarchive& save(long double value) = 0;
  // Strings (call with a std::string: a string literal would pick save(bool)).
  virtual oarchive& save(const std::string& value) = 0;
  virtual oarchive& save(const std::wstring& value) = 0;
  // An opaque block of bytes.
  virtual oarchive& save_binary(const char* data, long size) = 0;

  // The element count of a sequence whose elements follow.
  virtual oarchive& write_size(std::size_t count) = 0;
  // Around a named value; archives without names ignore them.
  virtual oarchive& write_start_tag(const std::string& name) = 0;
  virtual oarchive& write_end_tag(const std::string& name) = 0;
};

namespace detail {

template <typename T>
inline constexpr bool always_false = false;

template <typename T>
struct is_nvp : std::false_type {};
template <typename T>
struct is_nvp<opros::nvp<T>> : std::true_type {};

// A `save_this(oarchive&, T&)` found for T (OPRoS's way to serialise a type from outside).
template <typename T>
concept has_save_this = requires(oarchive& ar, T& t) {
  save_this(ar, t);
};

// The underlying container of a stack, queue or priority_queue (its protected member `c`).
template <typename Adapter>
struct adapter_access : Adapter {
  static const typename Adapter::container_type& container(const Adapter& adapter) {
    return adapter.*(&adapter_access::c);
  }
};

template <typename Range>
void write_elements(oarchive& ar, const Range& range, std::size_t count) {
  ar.write_size(count);
  for (const auto& element : range) ar << element;
}

template <typename Map>
void write_entries(oarchive& ar, const Map& map) {
  ar.write_size(map.size());
  for (const auto& entry : map) {
    ar << entry.first;
    ar << entry.second;
  }
}

template <typename T, typename A>
void write_container(oarchive& ar, const std::vector<T, A>& c) {
  write_elements(ar, c, c.size());
}
template <typename T, typename A>
void write_container(oarchive& ar, const std::deque<T, A>& c) {
  write_elements(ar, c, c.size());
}
template <typename T, typename A>
void write_container(oarchive& ar, const std::list<T, A>& c) {
  write_elements(ar, c, c.size());
}
template <typename T, typename P, typename A>
void write_container(oarchive& ar, const std::set<T, P, A>& c) {
  write_elements(ar, c, c.size());
}
template <typename T, typename P, typename A>
void write_container(oarchive& ar, const std::multiset<T, P, A>& c) {
  write_elements(ar, c, c.size());
}
template <typename T, typename H, typename E, typename A>
void write_container(oarchive& ar, const std::unordered_set<T, H, E, A>& c) {
  write_elements(ar, c, c.size());
}
template <typename T, typename H, typename E, typename A>
void write_container(oarchive& ar, const std::unordered_multiset<T, H, E, A>& c) {
  write_elements(ar, c, c.size());
}
template <typename T>
void write_container(oarchive& ar, const std::valarray<T>& c) {
  write_elements(ar, c, c.size());
}
template <typename T, std::size_t N>
void write_container(oarchive& ar, const std::array<T, N>& c) {
  write_elements(ar, c, N);
}
template <typename K, typename V, typename P, typename A>
void write_container(oarchive& ar, const std::map<K, V, P, A>& c) {
  write_entries(ar, c);
}
template <typename K, typename V, typename P, typename A>
void write_container(oarchive& ar, const std::multimap<K, V, P, A>& c) {
  write_entries(ar, c);
}
template <typename K, typename V, typename H, typename E, typename A>
void write_container(oarchive& ar, const std::unordered_map<K, V, H, E, A>& c) {
  write_entries(ar, c);
}
template <typename K, typename V, typename H, typename E, typename A>
void write_container(oarchive& ar, const std::unordered_multimap<K, V, H, E, A>& c) {
  write_entries(ar, c);
}
template <typename A, typename B>
void write_container(oarchive& ar, const std::pair<A, B>& c) {
  ar << c.first;
  ar << c.second;
}
template <typename T>
void write_container(oarchive& ar, const std::complex<T>& c) {
  ar << c.real();
  ar << c.imag();
}
template <typename T, typename C>
void write_container(oarchive& ar, const std::stack<T, C>& c) {
  ar << adapter_access<std::stack<T, C>>::container(c);
}
template <typename T, typename C>
void write_container(oarchive& ar, const std::queue<T, C>& c) {
  ar << adapter_access<std::queue<T, C>>::container(c);
}
template <typename T, typename C, typename P>
void write_container(oarchive& ar, const std::priority_queue<T, C, P>& c) {
  ar << adapter_access<std::priority_queue<T, C, P>>::container(c);
}

template <typename T>
concept writable_container = requires(oarchive& ar, const T& t) {
  detail::write_container(ar, t);
};

}  // namespace detail

// Saves value; see the top of this file for what can be saved.
template <typename T>
oarchive& operator<<(oarchive& ar, const T& value) {
  if constexpr (std::is_arithmetic_v<T>) {
    ar.save(value);
  } else if constexpr (std::is_enum_v<T>) {
    ar.save(static_cast<std::underlying_type_t<T>>(value));
  } else if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, std::wstring>) {
    ar.save(value);
  } else if constexpr (detail::is_nvp<T>::value) {
    ar.write_start_tag(value.getName());
    ar << value.getData();
    ar.write_end_tag(value.getName());
  } else if constexpr (std::is_array_v<T>) {
    detail::write_elements(ar, value, std::extent_v<T>);
  } else if constexpr (access::can_save<T>) {
    access::save(ar, const_cast<T&>(value));  // OPRoS's save members are not const
  } else if constexpr (access::can_serialize<T, oarchive>) {
    access::serialize(ar, const_cast<T&>(value));
  } else if constexpr (detail::has_save_this<T>) {
    save_this(ar, const_cast<T&>(value));
  } else if constexpr (detail::writable_container<T>) {
    detail::write_container(ar, value);
  } else {
    static_assert(detail::always_false<T>,
                  "opros::archive cannot save this type: give it members "
                  "`void save(opros::archive::oarchive&, const unsigned int)` and `load` (befriend "
                  "opros::archive::access if they are not public), or a function "
                  "`void save_this(opros::archive::oarchive&, T&)`");
  }
  return ar;
}

template <typename T>
oarchive& operator&(oarchive& ar, const T& value) {
  return ar << value;
}

}  // namespace archive
}  // namespace opros
