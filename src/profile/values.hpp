// Lexical parsing of profile values: strict numbers, booleans, number lists, case-insensitive
// enum words, and property types/values (docs/profiles.md). Pure functions of their text; they
// report nothing themselves (see field_reader.hpp for the versions that produce diagnostics).
// Used by the profile parsers and validation. Thread-safety: stateless, reentrant.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "profile/model.hpp"

namespace keel::profile::detail {

/// `text` without leading and trailing XML whitespace (space, tab, CR, LF).
std::string_view trim(std::string_view text);

/// ASCII lower-case copy.
std::string lower(std::string_view text);

/// Whether the two words are equal ignoring ASCII case.
bool equalsNoCase(std::string_view a, std::string_view b);

/// The whole (trimmed) text as a decimal number. NaN never; infinities only if `allow_inf`.
std::optional<double> parseDouble(std::string_view text, bool allow_inf = false);

/// The whole (trimmed) text as a decimal integer (optional sign).
std::optional<std::int64_t> parseInt(std::string_view text);

/// true/false/1/0, case-insensitive.
std::optional<bool> parseBool(std::string_view text);

/// Numbers separated by whitespace and/or commas. An empty text is an empty list.
std::optional<std::vector<double>> parseDoubleList(std::string_view text, bool allow_inf = false);

/// A word looked up case-insensitively in `table`.
template <class E>
std::optional<E> parseWord(std::string_view text, const std::vector<std::pair<std::string_view, E>>& table) {
  const std::string_view word = trim(text);
  for (const auto& [name, value] : table) {
    if (equalsNoCase(word, name)) return value;
  }
  return std::nullopt;
}

/// "a, b or c" from the names of `table` (the first spelling of each value).
template <class E>
std::string wordList(const std::vector<std::pair<std::string_view, E>>& table) {
  std::vector<std::string_view> names;
  std::vector<E> seen;
  for (const auto& [name, value] : table) {
    bool dup = false;
    for (const auto& s : seen) dup = dup || s == value;  // auto: E may be bool (vector<bool>)
    if (!dup) {
      names.push_back(name);
      seen.push_back(value);
    }
  }
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += (i + 1 == names.size()) ? " or " : ", ";
    out += names[i];
  }
  return out;
}

/// The normalised property type ("bool" "int" "double" "string" "double[]") of a type as
/// written in a profile (C++ and OPRoS spellings: long, unsigned short, std::string,
/// std::vector<double>, ...); nullopt for an unknown type.
std::optional<std::string> normalisePropertyType(std::string_view written);

/// Whether `written` is an unsigned integer type (its values must not be negative).
bool isUnsignedType(std::string_view written);

/// The value of `text` as the normalised `type`; nullopt when it does not parse.
std::optional<PropertyValue> parsePropertyValue(const std::string& type, std::string_view text);

/// What a value of the normalised `type` looks like, for messages ("a double", ...).
std::string describeType(const std::string& type);

/// The list of property types, for messages.
inline constexpr std::string_view kPropertyTypes = "bool, int, double, string, double[]";

}  // namespace keel::profile::detail
