// Lexical parsing of profile values; see values.hpp.
#include "profile/values.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

namespace keel::profile::detail {
namespace {

bool isXmlSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

/// Removes all whitespace except single spaces between two words ("unsigned   int").
std::string squeezeType(std::string_view text) {
  std::string out;
  bool pending_space = false;
  for (char c : trim(text)) {
    if (isXmlSpace(c)) {
      pending_space = true;
      continue;
    }
    const bool word = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
    if (pending_space && word && !out.empty() &&
        (std::isalnum(static_cast<unsigned char>(out.back())) != 0 || out.back() == '_')) {
      out += ' ';
    }
    pending_space = false;
    out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

const std::vector<std::pair<std::string_view, std::string_view>>& typeTable() {
  static const std::vector<std::pair<std::string_view, std::string_view>> table = {
      {"bool", "bool"},
      {"boolean", "bool"},
      {"int", "int"},
      {"long", "int"},
      {"short", "int"},
      {"long long", "int"},
      {"long int", "int"},
      {"short int", "int"},
      {"signed", "int"},
      {"signed int", "int"},
      {"int8_t", "int"},
      {"int16_t", "int"},
      {"int32_t", "int"},
      {"int64_t", "int"},
      {"std::int64_t", "int"},
      {"unsigned", "int"},
      {"unsigned int", "int"},
      {"unsigned short", "int"},
      {"unsigned long", "int"},
      {"unsigned long long", "int"},
      {"uint8_t", "int"},
      {"uint16_t", "int"},
      {"uint32_t", "int"},
      {"uint64_t", "int"},
      {"size_t", "int"},
      {"std::size_t", "int"},
      {"float", "double"},
      {"double", "double"},
      {"string", "string"},
      {"std::string", "string"},
      {"double[]", "double[]"},
      {"float[]", "double[]"},
      {"vector<double>", "double[]"},
      {"std::vector<double>", "double[]"},
      {"vector<float>", "double[]"},
      {"std::vector<float>", "double[]"},
  };
  return table;
}

}  // namespace

std::string_view trim(std::string_view text) {
  while (!text.empty() && isXmlSpace(text.front())) text.remove_prefix(1);
  while (!text.empty() && isXmlSpace(text.back())) text.remove_suffix(1);
  return text;
}

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool equalsNoCase(std::string_view a, std::string_view b) { return a.size() == b.size() && lower(a) == lower(b); }

std::optional<double> parseDouble(std::string_view text, bool allow_inf) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (!text.empty() && (text.front() == '-' || text.front() == '+')) return std::nullopt;
  }
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size()) return std::nullopt;
  if (std::isnan(value)) return std::nullopt;
  if (std::isinf(value) && !allow_inf) return std::nullopt;
  return value;
}

std::optional<std::int64_t> parseInt(std::string_view text) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (!text.empty() && (text.front() == '-' || text.front() == '+')) return std::nullopt;
  }
  if (text.empty()) return std::nullopt;
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size()) return std::nullopt;
  return value;
}

std::optional<bool> parseBool(std::string_view text) {
  return parseWord<bool>(text, {{"true", true}, {"false", false}, {"1", true}, {"0", false}});
}

std::optional<std::vector<double>> parseDoubleList(std::string_view text, bool allow_inf) {
  std::vector<double> out;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (isXmlSpace(text[i]) || text[i] == ',')) ++i;
    if (i == text.size()) break;
    std::size_t j = i;
    while (j < text.size() && !isXmlSpace(text[j]) && text[j] != ',') ++j;
    const auto value = parseDouble(text.substr(i, j - i), allow_inf);
    if (!value) return std::nullopt;
    out.push_back(*value);
    i = j;
  }
  return out;
}

std::optional<std::string> normalisePropertyType(std::string_view written) {
  const std::string key = squeezeType(written);
  for (const auto& [name, type] : typeTable()) {
    if (key == name) return std::string(type);
  }
  return std::nullopt;
}

bool isUnsignedType(std::string_view written) {
  const std::string key = squeezeType(written);
  return key.rfind("unsigned", 0) == 0 || key.rfind("uint", 0) == 0 || key == "size_t" || key == "std::size_t";
}

std::optional<PropertyValue> parsePropertyValue(const std::string& type, std::string_view text) {
  if (type == "bool") {
    if (auto v = parseBool(text)) return PropertyValue{*v};
  } else if (type == "int") {
    if (auto v = parseInt(text)) return PropertyValue{*v};
  } else if (type == "double") {
    if (auto v = parseDouble(text)) return PropertyValue{*v};
  } else if (type == "string") {
    return PropertyValue{std::string(trim(text))};
  } else if (type == "double[]") {
    if (auto v = parseDoubleList(text)) return PropertyValue{std::move(*v)};
  }
  return std::nullopt;
}

std::string describeType(const std::string& type) {
  if (type == "bool") return "a bool (true, false, 1 or 0)";
  if (type == "int") return "an int";
  if (type == "double") return "a finite double";
  if (type == "double[]") return "a double[] (finite numbers separated by spaces or commas)";
  return "a " + type;
}

}  // namespace keel::profile::detail
