// A test's environment variable, set (or removed) for a scope and put back as it was after: what
// the keel runs a test starts, and the code it calls in process, read. The tests' one place that
// changes the environment.
#pragma once

#include <charconv>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace keel::test {

class ScopedEnv {
 public:
  /// Sets `name` to `value`; with no value, removes it.
  ScopedEnv(std::string name, const std::optional<std::string>& value) : name_(std::move(name)) {
    if (const char* old = std::getenv(name_.c_str())) old_ = old;
    set(value);
  }
  ~ScopedEnv() { set(old_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;
  ScopedEnv(ScopedEnv&&) = delete;
  ScopedEnv& operator=(ScopedEnv&&) = delete;

  /// Changes it again within the scope; the value before the scope is still what comes back.
  void set(const std::optional<std::string>& value) const {
    // GoogleTest runs one test at a time, on the main thread, and a test changes its environment
    // before it starts a thread that could read it (an engine's, a child's) or after they end.
    if (value) ::setenv(name_.c_str(), value->c_str(), 1);  // NOLINT(concurrency-mt-unsafe): above
    else ::unsetenv(name_.c_str());                         // NOLINT(concurrency-mt-unsafe): above
  }

 private:
  std::string name_;
  std::optional<std::string> old_;
};

/// The whole number in environment variable `name`; `fallback` when it is unset or empty. A value
/// that is not one throws (the test fails, saying which).
inline int intFromEnv(const char* name, int fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return fallback;
  const std::string value(text);
  int v = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (ec != std::errc() || end != value.data() + value.size())
    throw std::invalid_argument(std::string(name) + "='" + value + "' is not a whole number");
  return v;
}

}  // namespace keel::test
