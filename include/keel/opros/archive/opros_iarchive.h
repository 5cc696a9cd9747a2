// opros_iarchive.h — keel's own OPRoS-compatible version of OPRoS's input archive.
//
// `opros::archive::iarchive` is the abstract reader; `ar >> x` (and `ar & x`) loads everything
// `ar << x` saves (opros_oarchive.h), into an object of the same type. A container is replaced
// only once all of it was read. Errors throw opros::archive exceptions (opros_archive_common.h);
// a reader never reads past what the stream holds. An archive is used by one thread at a time.
#pragma once

#include <algorithm>
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

class iarchive : public archive {
 public:
  ~iarchive() override = default;

  // One value of each primitive type; throws if the stream holds something else or ends.
  virtual iarchive& load(bool& value) = 0;
  virtual iarchive& load(char& value) = 0;
  virtual iarchive& load(signed char& value) = 0;
  virtual iarchive& load(unsigned char& value) = 0;
  virtual iarchive& load(wchar_t& value) = 0;
  virtual iarchive& load(short& value) = 0;
  virtual iarchive& load(unsigned short& value) = 0;
  virtual iarchive& load(int& value) = 0;
  virtual iarchive& load(unsigned int& value) = 0;
  virtual iarchive& load(long& value) = 0;
  virtual iarchive& load(unsigned long& value) = 0;
  virtual iarchive& load(long long& value) = 0;
  virtual iarchive& load(unsigned long long& value) = 0;
  virtual iarchive& load(float& value) = 0;
  virtual iarchive& load(double& value) = 0;
  virtual iarchive& load(long double& value) = 0;
  virtual iarchive& load(std::string& value) = 0;
  virtual iarchive& load(std::wstring& value) = 0;
  // A block written by save_binary. With *data null, allocates it with new[] (the caller
  // delete[]s it); otherwise *data holds size bytes, and a larger block throws. size becomes the
  // block's length.
  virtual iarchive& load_binary(char** data, long& size) = 0;

  // The element count written by write_size.
  virtual std::size_t read_size() = 0;
  virtual iarchive& read_start_tag(const std::string& name) = 0;
  virtual iarchive& read_end_tag(const std::string& name) = 0;
};

namespace detail {

template <typename T>
inline constexpr bool always_false_in = false;

template <typename T>
struct is_input_nvp : std::false_type {};
template <typename T>
struct is_input_nvp<opros::nvp<T>> : std::true_type {};

// A `load_this(iarchive&, T&)` found for T.
template <typename T>
concept has_load_this = requires(iarchive& ar, T& t) {
  load_this(ar, t);
};

// Reads a count and that many elements, each default-constructed and then loaded.
template <typename Element, typename Add>
void read_elements(iarchive& ar, Add add) {
  const std::size_t count = ar.read_size();
  for (std::size_t i = 0; i < count; ++i) {
    Element element{};
    ar >> element;
    add(std::move(element));
  }
}

template <typename Sequence>
void read_sequence(iarchive& ar, Sequence& c) {
  Sequence result;
  read_elements<typename Sequence::value_type>(ar, [&result](typename Sequence::value_type&& e) {
    result.push_back(std::move(e));
  });
  c = std::move(result);
}

template <typename Set>
void read_set(iarchive& ar, Set& c) {
  Set result;
  read_elements<typename Set::value_type>(ar, [&result](typename Set::value_type&& e) { result.insert(std::move(e)); });
  c = std::move(result);
}

template <typename Map>
void read_map(iarchive& ar, Map& c) {
  Map result;
  const std::size_t count = ar.read_size();
  for (std::size_t i = 0; i < count; ++i) {
    typename Map::key_type key{};
    typename Map::mapped_type mapped{};
    ar >> key;
    ar >> mapped;
    result.emplace(std::move(key), std::move(mapped));
  }
  c = std::move(result);
}

template <typename T, typename A>
void read_container(iarchive& ar, std::vector<T, A>& c) {
  read_sequence(ar, c);
}
template <typename T, typename A>
void read_container(iarchive& ar, std::deque<T, A>& c) {
  read_sequence(ar, c);
}
template <typename T, typename A>
void read_container(iarchive& ar, std::list<T, A>& c) {
  read_sequence(ar, c);
}
template <typename T, typename P, typename A>
void read_container(iarchive& ar, std::set<T, P, A>& c) {
  read_set(ar, c);
}
template <typename T, typename P, typename A>
void read_container(iarchive& ar, std::multiset<T, P, A>& c) {
  read_set(ar, c);
}
template <typename T, typename H, typename E, typename A>
void read_container(iarchive& ar, std::unordered_set<T, H, E, A>& c) {
  read_set(ar, c);
}
template <typename T, typename H, typename E, typename A>
void read_container(iarchive& ar, std::unordered_multiset<T, H, E, A>& c) {
  read_set(ar, c);
}
template <typename K, typename V, typename P, typename A>
void read_container(iarchive& ar, std::map<K, V, P, A>& c) {
  read_map(ar, c);
}
template <typename K, typename V, typename P, typename A>
void read_container(iarchive& ar, std::multimap<K, V, P, A>& c) {
  read_map(ar, c);
}
template <typename K, typename V, typename H, typename E, typename A>
void read_container(iarchive& ar, std::unordered_map<K, V, H, E, A>& c) {
  read_map(ar, c);
}
template <typename K, typename V, typename H, typename E, typename A>
void read_container(iarchive& ar, std::unordered_multimap<K, V, H, E, A>& c) {
  read_map(ar, c);
}
template <typename T>
void read_container(iarchive& ar, std::valarray<T>& c) {
  std::vector<T> elements;
  read_sequence(ar, elements);
  c.resize(elements.size());
  std::copy(elements.begin(), elements.end(), std::begin(c));
}
template <typename T, std::size_t N>
void read_container(iarchive& ar, std::array<T, N>& c) {
  std::vector<T> elements;
  read_sequence(ar, elements);
  if (elements.size() != N) {
    throw archive_array_size_exception("opros archive: a std::array of " + std::to_string(N) +
                                       " elements cannot hold the " + std::to_string(elements.size()) +
                                       " in the stream");
  }
  std::move(elements.begin(), elements.end(), c.begin());
}
template <typename A, typename B>
void read_container(iarchive& ar, std::pair<A, B>& c) {
  ar >> c.first;
  ar >> c.second;
}
template <typename T>
void read_container(iarchive& ar, std::complex<T>& c) {
  T real{};
  T imag{};
  ar >> real;
  ar >> imag;
  c = std::complex<T>(real, imag);
}
template <typename T, typename C>
void read_container(iarchive& ar, std::stack<T, C>& c) {
  C elements;
  ar >> elements;
  c = std::stack<T, C>(std::move(elements));
}
template <typename T, typename C>
void read_container(iarchive& ar, std::queue<T, C>& c) {
  C elements;
  ar >> elements;
  c = std::queue<T, C>(std::move(elements));
}
template <typename T, typename C, typename P>
void read_container(iarchive& ar, std::priority_queue<T, C, P>& c) {
  C elements;
  ar >> elements;
  c = std::priority_queue<T, C, P>(P(), std::move(elements));
}

template <typename T>
concept readable_container = requires(iarchive& ar, T& t) {
  detail::read_container(ar, t);
};

// A C array: the stream must hold exactly as many elements.
template <typename T, std::size_t N>
void read_array(iarchive& ar, T (&array)[N]) {
  const std::size_t count = ar.read_size();
  if (count != N) {
    throw archive_array_size_exception("opros archive: an array of " + std::to_string(N) +
                                       " elements cannot hold the " + std::to_string(count) + " in the stream");
  }
  for (auto& element : array) ar >> element;
}

}  // namespace detail

template <typename T>
iarchive& operator>>(iarchive& ar, const opros::nvp<T>& named) {
  ar.read_start_tag(named.getName());
  ar >> named.getData();
  ar.read_end_tag(named.getName());
  return ar;
}

// Loads value; see the top of this file.
template <typename T>
iarchive& operator>>(iarchive& ar, T& value) {
  if constexpr (std::is_const_v<T>) {
    static_assert(detail::always_false_in<T>, "opros::archive cannot load into a const object");
  } else if constexpr (std::is_arithmetic_v<T>) {
    ar.load(value);
  } else if constexpr (std::is_enum_v<T>) {
    std::underlying_type_t<T> raw{};
    ar.load(raw);
    value = static_cast<T>(raw);
  } else if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, std::wstring>) {
    ar.load(value);
  } else if constexpr (detail::is_input_nvp<T>::value) {
    ar >> static_cast<const T&>(value);
  } else if constexpr (std::is_array_v<T>) {
    detail::read_array(ar, value);
  } else if constexpr (access::can_load<T>) {
    access::load(ar, value);
  } else if constexpr (access::can_serialize<T, iarchive>) {
    access::serialize(ar, value);
  } else if constexpr (detail::has_load_this<T>) {
    load_this(ar, value);
  } else if constexpr (detail::readable_container<T>) {
    detail::read_container(ar, value);
  } else {
    static_assert(detail::always_false_in<T>,
                  "opros::archive cannot load this type: give it members `save` and "
                  "`void load(opros::archive::iarchive&, const unsigned int)` (befriend "
                  "opros::archive::access if they are not public), or a function "
                  "`void load_this(opros::archive::iarchive&, T&)`");
  }
  return ar;
}

template <typename T>
iarchive& operator&(iarchive& ar, T& value) {
  return ar >> value;
}

template <typename T>
iarchive& operator&(iarchive& ar, const opros::nvp<T>& named) {
  return ar >> named;
}

}  // namespace archive
}  // namespace opros
