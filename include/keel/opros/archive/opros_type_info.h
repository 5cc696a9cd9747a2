// opros_type_info.h — keel's own OPRoS-compatible version of OPRoS's "pseudo RTTI".
//
// OPRoS names every port data type with a string: `typeName(T*)` overloads give it, and
// `getTypeName(T*)` composes it, e.g. "std::vector<OPRoS::Float64Array>" is spelled
// "std::vector<Float64Array>". A user type supplies `inline std::string typeName(UserType*)` next
// to itself (found by argument-dependent lookup); the spellings below are OPRoS's own, including
// its "w_char_t". Where OPRoS would fail to compile (a type without typeName), keel falls back to
// the demangled C++ name. Header-only, stateless, thread-safe.
#pragma once

#include <array>
#include <complex>
#include <cstddef>
#include <cstdlib>
#include <deque>
#include <list>
#include <map>
#include <memory>
#include <queue>
#include <set>
#include <stack>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <valarray>
#include <vector>

#include "opros_type_traits.h"

#if __has_include(<cxxabi.h>)
#include <cxxabi.h>
#define KEEL_OPROS_HAVE_CXXABI 1
#endif

inline std::string typeName(bool*) { return "bool"; }
inline std::string typeName(char*) { return "char"; }
inline std::string typeName(signed char*) { return "signed char"; }
inline std::string typeName(unsigned char*) { return "unsigned char"; }
inline std::string typeName(wchar_t*) { return "w_char_t"; }  // sic: OPRoS's spelling
inline std::string typeName(short*) { return "short"; }
inline std::string typeName(unsigned short*) { return "unsigned short"; }
inline std::string typeName(int*) { return "int"; }
inline std::string typeName(unsigned int*) { return "unsigned int"; }
inline std::string typeName(long*) { return "long"; }
inline std::string typeName(unsigned long*) { return "unsigned long"; }
inline std::string typeName(long long*) { return "long long"; }
inline std::string typeName(unsigned long long*) { return "unsigned long long"; }
inline std::string typeName(float*) { return "float"; }
inline std::string typeName(double*) { return "double"; }
inline std::string typeName(long double*) { return "long double"; }
inline std::string typeName(std::string*) { return "std::string"; }
inline std::string typeName(std::wstring*) { return "std::wstring"; }

// The composite overloads are declared before getTypeName so that its lookup sees them all;
// user types are found at instantiation through their own namespace.
template <typename T>
std::string getTypeName(T*);

template <typename T, typename A>
std::string typeName(std::vector<T, A>*);
template <typename T, typename A>
std::string typeName(std::deque<T, A>*);
template <typename T, typename A>
std::string typeName(std::list<T, A>*);
template <typename T, typename C>
std::string typeName(std::queue<T, C>*);
template <typename T, typename C, typename P>
std::string typeName(std::priority_queue<T, C, P>*);
template <typename T, typename C>
std::string typeName(std::stack<T, C>*);
template <typename T, typename P, typename A>
std::string typeName(std::set<T, P, A>*);
template <typename T, typename P, typename A>
std::string typeName(std::multiset<T, P, A>*);
template <typename K, typename V, typename P, typename A>
std::string typeName(std::map<K, V, P, A>*);
template <typename K, typename V, typename P, typename A>
std::string typeName(std::multimap<K, V, P, A>*);
template <typename T>
std::string typeName(std::complex<T>*);
template <typename T>
std::string typeName(std::valarray<T>*);
// keel additions, for the containers keel's archive also serialises.
template <typename A, typename B>
std::string typeName(std::pair<A, B>*);
template <typename T, std::size_t N>
std::string typeName(std::array<T, N>*);
template <typename T, typename H, typename E, typename A>
std::string typeName(std::unordered_set<T, H, E, A>*);
template <typename K, typename V, typename H, typename E, typename A>
std::string typeName(std::unordered_map<K, V, H, E, A>*);
// A pointer type is its pointee's name followed by '*'.
template <typename T>
std::string typeName(T**);

namespace opros::detail {

// The readable C++ name of a mangled one, or the mangled one where it cannot be demangled.
inline std::string demangle(const char* mangled) {
#ifdef KEEL_OPROS_HAVE_CXXABI
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> readable(abi::__cxa_demangle(mangled, nullptr, nullptr, &status), std::free);
  if (status == 0 && readable) return readable.get();
#endif
  return mangled;
}

// "<prefix><first>,<second>...>" from the OPRoS names of the arguments.
template <typename... Ts>
std::string compose(const char* prefix) {
  std::string name(prefix);
  bool first = true;
  ((name.append(first ? "" : ",").append(getTypeName(static_cast<Ts*>(nullptr))), first = false), ...);
  return name.append(">");
}

}  // namespace opros::detail

// The OPRoS name of T: its typeName overload; "Enum" for an enumeration without one (as OPRoS);
// otherwise the demangled C++ name.
template <typename T>
std::string getTypeName(T*) {
  using U = std::remove_cv_t<T>;
  if constexpr (requires(U * p) { typeName(p); }) {
    return typeName(static_cast<U*>(nullptr));
  } else if constexpr (std::is_enum_v<U>) {
    return "Enum";
  } else {
    return opros::detail::demangle(typeid(U).name());
  }
}

template <typename T, typename A>
std::string typeName(std::vector<T, A>*) {
  return opros::detail::compose<T>("std::vector<");
}
template <typename T, typename A>
std::string typeName(std::deque<T, A>*) {
  return opros::detail::compose<T>("std::deque<");
}
template <typename T, typename A>
std::string typeName(std::list<T, A>*) {
  return opros::detail::compose<T>("std::list<");
}
template <typename T, typename C>
std::string typeName(std::queue<T, C>*) {
  return opros::detail::compose<T>("std::queue<");
}
template <typename T, typename C, typename P>
std::string typeName(std::priority_queue<T, C, P>*) {
  return opros::detail::compose<T>("std::priority_queue<");
}
template <typename T, typename C>
std::string typeName(std::stack<T, C>*) {
  return opros::detail::compose<T>("std::stack<");
}
template <typename T, typename P, typename A>
std::string typeName(std::set<T, P, A>*) {
  return opros::detail::compose<T>("std::set<");
}
template <typename T, typename P, typename A>
std::string typeName(std::multiset<T, P, A>*) {
  return opros::detail::compose<T>("std::multiset<");
}
template <typename K, typename V, typename P, typename A>
std::string typeName(std::map<K, V, P, A>*) {
  return opros::detail::compose<K, V>("std::map<");
}
template <typename K, typename V, typename P, typename A>
std::string typeName(std::multimap<K, V, P, A>*) {
  return opros::detail::compose<K, V>("std::multimap<");
}
template <typename T>
std::string typeName(std::complex<T>*) {
  return opros::detail::compose<T>("std::complex<");
}
template <typename T>
std::string typeName(std::valarray<T>*) {
  return opros::detail::compose<T>("std::valarray<");
}
template <typename A, typename B>
std::string typeName(std::pair<A, B>*) {
  return opros::detail::compose<A, B>("std::pair<");
}
template <typename T, std::size_t N>
std::string typeName(std::array<T, N>*) {
  return "std::array<" + getTypeName(static_cast<T*>(nullptr)) + "," + std::to_string(N) + ">";
}
template <typename T, typename H, typename E, typename A>
std::string typeName(std::unordered_set<T, H, E, A>*) {
  return opros::detail::compose<T>("std::unordered_set<");
}
template <typename K, typename V, typename H, typename E, typename A>
std::string typeName(std::unordered_map<K, V, H, E, A>*) {
  return opros::detail::compose<K, V>("std::unordered_map<");
}
template <typename T>
std::string typeName(T**) {
  return getTypeName(static_cast<T*>(nullptr)).append("*");
}

// OPRoS's shorthand for a user type's typeName.
#define DEFINE_CLASS_TYPE_NAME(a) \
  inline std::string typeName(a*) { return std::string(#a); }
