// Test support: reads a keel fault log (JSON lines) and finds records in it, by the names of
// the log's schema (src/fault/log_schema.hpp).
#pragma once

#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fault/log_schema.hpp"

namespace keel::test {

inline std::vector<nlohmann::json> readLog(const std::string& path) {
  std::vector<nlohmann::json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  return out;
}

/// The `to` states of `component`'s state records, in order.
inline std::vector<std::string> statesOf(const std::vector<nlohmann::json>& log, const std::string& component) {
  std::vector<std::string> out;
  for (const auto& r : log)
    if (r.value(fault::schema::field::kEvent, "") == fault::schema::event::kState &&
        r.value(fault::schema::field::kComponent, "") == component)
      out.push_back(r.value(fault::schema::field::kTo, ""));
  return out;
}

inline std::vector<nlohmann::json> eventsOf(const std::vector<nlohmann::json>& log, const std::string& event) {
  std::vector<nlohmann::json> out;
  for (const auto& r : log)
    if (r.value(fault::schema::field::kEvent, "") == event) out.push_back(r);
  return out;
}

}  // namespace keel::test
