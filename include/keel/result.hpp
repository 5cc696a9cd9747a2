// keel::Result<T>: a value or an error message, for failures that are expected (a bad profile,
// a library that does not load). Framework code returns these instead of throwing.
// Header-only; a Result is a plain value (not thread-safe to share mutably, like any value).
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace keel {

/// The error side of a Result: a human-readable message, already naming who/where/why.
struct Error {
  std::string message;
};

template <class T, class E = Error>
class [[nodiscard]] Result {
 public:
  // Implicit, both: a function returning a Result returns its value or its Error as they are.
  Result(T value) : v_(std::in_place_index<0>, std::move(value)) {}
  Result(E error) : v_(std::in_place_index<1>, std::move(error)) {}

  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() & { return std::get<0>(v_); }
  const T& value() const& { return std::get<0>(v_); }
  T&& value() && { return std::get<0>(std::move(v_)); }
  const E& error() const { return std::get<1>(v_); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  std::variant<T, E> v_;
};

/// Result of an operation with no value.
template <class E>
class [[nodiscard]] Result<void, E> {
 public:
  Result() = default;
  Result(E error) : error_(std::move(error)), ok_(false) {}  // implicit, as above
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const E& error() const { return error_; }

 private:
  E error_{};
  bool ok_ = true;
};

/// Convenience: `return keel::fail("why");`
inline Error fail(std::string message) { return Error{std::move(message)}; }

}  // namespace keel
