// Test support: reads a keel fault log (JSON lines) and finds records in it, by the names of
// the log's schema (src/log/schema.hpp).
#pragma once

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "log/schema.hpp"

namespace keel::test {

inline std::vector<nlohmann::json> readLog(const std::string& path) {
  std::vector<nlohmann::json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  return out;
}

/// A log file as a reader finds it after its writers were killed: the lines up to the last
/// '\n', each a whole JSON object, and what follows (a line being written, which may be
/// partial). `problem` names the first line that is not a JSON object ("" when none).
struct LogLines {
  std::vector<std::string> lines;
  std::string partial;
  std::string problem;
};

/// `line` with its control bytes (a NUL of a hole) made visible, cut after 300 bytes.
inline std::string printable(const std::string& line) {
  std::string out;
  for (char c : line.substr(0, 300)) {
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
    else out += "\\x" + std::string(1, "0123456789abcdef"[(c >> 4) & 0xf]) + "0123456789abcdef"[c & 0xf];
  }
  return line.size() > 300 ? out + "..." : out;
}

inline LogLines readLogLines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  LogLines out;
  std::size_t at = 0;
  for (std::size_t nl; (nl = text.find('\n', at)) != std::string::npos; at = nl + 1) {
    out.lines.push_back(text.substr(at, nl - at));
    if (!out.problem.empty()) continue;
    const std::string& line = out.lines.back();
    const std::string where = "line " + std::to_string(out.lines.size()) + " (byte " + std::to_string(at) + ")";
    if (line.find('\0') != std::string::npos) {
      out.problem = where + " has NUL bytes, a place reserved and never written: " + printable(line);
      continue;
    }
    const nlohmann::json record = nlohmann::json::parse(line, nullptr, false);
    if (record.is_discarded() || !record.is_object()) out.problem = where + " is not a JSON object: " + printable(line);
  }
  out.partial = text.substr(at);
  return out;
}

/// The `to` states of `component`'s state records, in order: the name's own states, those of
/// whichever object stands for it (records marked `serving: false` left out).
inline std::vector<std::string> statesOf(const std::vector<nlohmann::json>& log, const std::string& component) {
  std::vector<std::string> out;
  for (const auto& r : log)
    if (r.value(log::schema::field::kEvent, "") == log::schema::event::kState &&
        r.value(log::schema::field::kComponent, "") == component && r.value(log::schema::field::kServing, true))
      out.push_back(r.value(log::schema::field::kTo, ""));
  return out;
}

/// The state records of one object under `component`'s name, in order: the component created
/// for the instance, or (`alternative`) its alternative.
inline std::vector<nlohmann::json> objectStatesOf(const std::vector<nlohmann::json>& log, const std::string& component,
                                                  bool alternative) {
  std::vector<nlohmann::json> out;
  for (const auto& r : log)
    if (r.value(log::schema::field::kEvent, "") == log::schema::event::kState &&
        r.value(log::schema::field::kComponent, "") == component &&
        r.value(log::schema::field::kAlternative, false) == alternative)
      out.push_back(r);
  return out;
}

inline std::vector<nlohmann::json> eventsOf(const std::vector<nlohmann::json>& log, const std::string& event) {
  std::vector<nlohmann::json> out;
  for (const auto& r : log)
    if (r.value(log::schema::field::kEvent, "") == event) out.push_back(r);
  return out;
}

}  // namespace keel::test
