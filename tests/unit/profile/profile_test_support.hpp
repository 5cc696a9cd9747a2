// Helpers for the profile reader's tests: fixture paths under KEEL_PROFILE_TEST_DATA (a compile
// definition naming tests/unit/profile/data) and diagnostics as "file:line: message" strings
// with that directory removed, so expectations read like `keel validate` output.
// Used by tests/unit/profile/*_test.cpp. Thread-safety: pure functions.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "profile/loader.hpp"
#include "support/paths.hpp"

#ifndef KEEL_PROFILE_TEST_DATA
#error "KEEL_PROFILE_TEST_DATA must name tests/unit/profile/data"
#endif

namespace keel::profile::test {

inline std::string dataPath(const std::string& relative) {
  return std::string(KEEL_PROFILE_TEST_DATA) + "/" + relative;
}

/// `text` with every occurrence of the data directory prefix removed.
inline std::string relative(std::string text) {
  const std::string prefix = std::string(KEEL_PROFILE_TEST_DATA) + "/";
  for (auto at = text.find(prefix); at != std::string::npos; at = text.find(prefix, at)) {
    text.erase(at, prefix.size());
  }
  return text;
}

/// The problems of loading fixture `relative_path`; empty when it loads.
inline std::vector<std::string> problems(const std::string& relative_path) {
  const auto result = load(dataPath(relative_path));
  std::vector<std::string> out;
  if (result.ok()) return out;
  for (const Diagnostic& d : result.error()) out.push_back(relative(d.str()));
  return out;
}

/// The warnings of loading fixture `relative_path` ("file:line: message"); the problems, each
/// prefixed "error: ", when it does not load.
inline std::vector<std::string> warnings(const std::string& relative_path) {
  const auto result = load(dataPath(relative_path));
  std::vector<std::string> out;
  if (!result.ok()) {
    for (const Diagnostic& d : result.error()) out.push_back("error: " + relative(d.str()));
    return out;
  }
  for (const Diagnostic& d : result->warnings) out.push_back(relative(d.str()));
  return out;
}

/// All diagnostics of a failed load, one per line, for assertion messages.
inline std::string joined(const Result<ProfileSet, Diagnostics>& result) {
  std::string out;
  if (result.ok()) return out;
  for (const Diagnostic& d : result.error()) out += relative(d.str()) + "\n";
  return out;
}

/// The absolute, normalised path a fixture is keyed by in a ProfileSet.
inline std::string keyOf(const std::string& relative_path) {
  return std::filesystem::weakly_canonical(dataPath(relative_path)).string();
}

}  // namespace keel::profile::test
