// The signal-model rule of paper §5.1.2 as ports apply it: `<validity><min>…</min><max>…</max>`
// on a data port. Numbers, and arrays of numbers (std::vector, std::array), can be checked;
// NaN and infinity always violate a rule. One bound applies to every element; several bounds
// apply element by element (and the array must have that many elements). A message's fields are
// checked by the same rules, one per field path (checkFields).
// Thread-safety: a rule is immutable once set on a port (before start).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace keel {
class Component;
}

namespace keel::detail {

/// `x` as an E, for an injected out-of-range value: a number E cannot hold saturates to E's
/// range (NaN to an integer type's lowest value), where a plain cast would be undefined.
template <class E>
E saturatingCast(double x) {
  using L = std::numeric_limits<E>;
  if constexpr (std::is_integral_v<E>) {
    if (std::isnan(x) || x <= static_cast<double>(L::lowest())) return L::lowest();
    if (x >= static_cast<double>(L::max())) return L::max();
  } else {
    if (std::isfinite(x) && std::fabs(x) > static_cast<double>(L::max())) return x > 0 ? L::infinity() : -L::infinity();
  }
  return static_cast<E>(x);
}

template <class T>
struct NumericTraits {
  static constexpr bool numeric = std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;
  static std::size_t size(const T&) { return 1; }
  static double at(const T& v, std::size_t) { return static_cast<double>(v); }
  static void fill(T& v, double x) { v = saturatingCast<T>(x); }
};
template <class E>
struct NumericTraits<std::vector<E>> {
  static constexpr bool numeric = NumericTraits<E>::numeric;
  static std::size_t size(const std::vector<E>& v) { return v.size(); }
  static double at(const std::vector<E>& v, std::size_t i) { return static_cast<double>(v[i]); }
  static void fill(std::vector<E>& v, double x) {
    if (v.empty()) v.resize(1);
    for (auto& e : v) e = saturatingCast<E>(x);
  }
};
template <class E, std::size_t N>
struct NumericTraits<std::array<E, N>> {
  static constexpr bool numeric = NumericTraits<E>::numeric;
  static std::size_t size(const std::array<E, N>&) { return N; }
  static double at(const std::array<E, N>& v, std::size_t i) { return static_cast<double>(v[i]); }
  static void fill(std::array<E, N>& v, double x) {
    for (auto& e : v) e = saturatingCast<E>(x);
  }
};

/// What was wrong with a value.
struct Violation {
  std::size_t index = 0;  // element
  double value = 0;
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  std::size_t size_expected = 0;  // nonzero: the array had the wrong number of elements
  std::size_t size_got = 0;
  bool array = false;  // the value was an array (the index is meaningful)
};

struct ValidityRule {
  std::vector<double> min;  // empty: none; one: all elements; n: element-wise
  std::vector<double> max;

  double minAt(std::size_t i) const {
    return min.empty() ? -std::numeric_limits<double>::infinity() : min[min.size() == 1 ? 0 : i];
  }
  double maxAt(std::size_t i) const {
    return max.empty() ? std::numeric_limits<double>::infinity() : max[max.size() == 1 ? 0 : i];
  }
  std::size_t elementWise() const {
    std::size_t n = min.size() > 1 ? min.size() : 0;
    return max.size() > n ? (max.size() > 1 ? max.size() : n) : n;
  }

  /// True when `v` satisfies the rule; otherwise fills `out`.
  template <class T>
  bool check(const T& v, Violation& out) const {
    using Tr = NumericTraits<T>;
    const std::size_t n = Tr::size(v);
    if (std::size_t want = elementWise(); want != 0 && n != want) {
      out.size_expected = want;
      out.size_got = n;
      return false;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const double x = Tr::at(v, i);
      const double lo = minAt(i), hi = maxAt(i);
      if (std::isfinite(x) && x >= lo && x <= hi) continue;
      out = Violation{i, x, lo, hi, 0, 0, !std::is_arithmetic_v<T>};
      return false;
    }
    return true;
  }
};

/// Reports a `range` fault of `owner` found on `port` (defined in libkeel).
void reportRange(Component& owner, const std::string& port, const Violation& v, bool on_delivery);

/// The <validity field=".."> rules of a port whose type is a generated message (set by the
/// runtime before start; src/runtime/field_rules.hpp).
struct FieldRules;
/// Checks the message at `value` against `rules`. On the first violation, reports a `range`
/// fault of `owner` found on `port`, naming the field, and returns false (defined in libkeel).
bool checkFields(const FieldRules& rules, const void* value, Component& owner, const std::string& port,
                 bool on_delivery);

/// Fault injection (`out_of_range`): records the manifestation on `owner` and marks the
/// calling thread as pushing an injected value until endInjectedCorruption() (libkeel).
void noteInjectedCorruption(Component& owner);
void endInjectedCorruption();

}  // namespace keel::detail
