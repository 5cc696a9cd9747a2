#include "supervision/node_parameters.hpp"

#include <fmt/format.h>
#include <unistd.h>
#include <atomic>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <string>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

namespace keel::supervision {

namespace {

using profile::ParameterValue;

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

bool oneOf(std::string_view s, std::initializer_list<std::string_view> words) {
  for (std::string_view w : words)
    if (s == w) return true;
  return false;
}

/// A plain YAML scalar typed as rcl_yaml_param_parser's get_value types it.
ParameterValue plainValue(const std::string& s) {
  if (oneOf(s, {"Y", "y", "yes", "Yes", "YES", "true", "True", "TRUE", "on", "On", "ON"})) return true;
  if (oneOf(s, {"N", "n", "no", "No", "NO", "false", "False", "FALSE", "off", "Off", "OFF"})) return false;
  char* end = nullptr;
  errno = 0;
  const long long i = std::strtoll(s.c_str(), &end, 0);
  if (errno == 0 && end != s.c_str() && *end == '\0') return static_cast<std::int64_t>(i);
  if (oneOf(s, {".nan", ".NaN", ".NAN"})) return std::nan("");
  if (oneOf(s, {".inf", ".Inf", ".INF"})) return HUGE_VAL;
  if (oneOf(s, {"-.inf", "-.Inf", "-.INF"})) return -HUGE_VAL;
  errno = 0;
  const double d = std::strtod(s.c_str(), &end);
  if (errno == 0 && end != s.c_str() && *end == '\0') return d;
  return s;
}

void appendUtf8(std::string& out, std::uint32_t cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

/// The text of YAML's double-quoted scalar `s` (its quotes included); nothing if malformed.
std::optional<std::string> doubleQuoted(std::string_view s) {
  if (s.size() < 2 || s.front() != '"' || s.back() != '"') return std::nullopt;
  std::string out;
  for (std::size_t i = 1; i + 1 < s.size(); ++i) {
    if (s[i] == '"') return std::nullopt;
    if (s[i] != '\\') {
      out += s[i];
      continue;
    }
    if (++i + 1 >= s.size()) return std::nullopt;
    const char c = s[i];
    int hex = c == 'x' ? 2 : c == 'u' ? 4 : c == 'U' ? 8 : 0;
    if (hex > 0) {
      if (i + static_cast<std::size_t>(hex) + 1 >= s.size()) return std::nullopt;
      std::uint32_t cp = 0;
      for (int k = 0; k < hex; ++k) {
        const char h = s[++i];
        const int v = h >= '0' && h <= '9'   ? h - '0'
                      : h >= 'a' && h <= 'f' ? h - 'a' + 10
                      : h >= 'A' && h <= 'F' ? h - 'A' + 10
                                             : -1;
        if (v < 0) return std::nullopt;
        cp = cp * 16 + static_cast<std::uint32_t>(v);
      }
      appendUtf8(out, cp);
      continue;
    }
    switch (c) {
      case '0': out += '\0'; break;
      case 'a': out += '\a'; break;
      case 'b': out += '\b'; break;
      case 't':
      case '\t': out += '\t'; break;
      case 'n': out += '\n'; break;
      case 'v': out += '\v'; break;
      case 'f': out += '\f'; break;
      case 'r': out += '\r'; break;
      case 'e': out += '\x1b'; break;
      case ' ':
      case '"':
      case '/':
      case '\\': out += c; break;
      default: return std::nullopt;
    }
  }
  return out;
}

/// One scalar: quoted, a string; plain, typed. Nothing if malformed or empty.
std::optional<ParameterValue> scalarOf(std::string_view s) {
  s = trim(s);
  if (s.empty()) return std::nullopt;
  if (s.front() == '"') {
    auto text = doubleQuoted(s);
    if (!text) return std::nullopt;
    return ParameterValue(std::move(*text));
  }
  if (s.front() == '\'') {
    if (s.size() < 2 || s.back() != '\'') return std::nullopt;
    std::string out;
    for (std::size_t i = 1; i + 1 < s.size(); ++i) {
      if (s[i] == '\'' && (i + 2 >= s.size() || s[++i] != '\'')) return std::nullopt;  // '' is one '
      out += s[i];
    }
    return ParameterValue(std::move(out));
  }
  if (s.front() == '#' || s.front() == '{' || s.front() == '[') return std::nullopt;  // a comment, a mapping
  if (const auto comment = s.find(" #"); comment != std::string_view::npos) s = trim(s.substr(0, comment));
  return plainValue(std::string(s));
}

/// The items of flow sequence `s` ("[a, 'b', 1]"): split at the commas outside quotes.
std::optional<std::vector<std::string_view>> itemsOf(std::string_view s) {
  std::vector<std::string_view> items;
  std::size_t from = 1;
  char quote = 0;
  for (std::size_t i = 1; i + 1 < s.size(); ++i) {
    const char c = s[i];
    if (quote == '"' && c == '\\') ++i;
    else if (quote != 0 && c == quote) quote = 0;
    else if (quote == 0 && (c == '"' || c == '\'')) quote = c;
    else if (quote == 0 && (c == '[' || c == '{' || c == ']' || c == '}')) return std::nullopt;  // nested
    else if (quote == 0 && c == ',') {
      items.push_back(s.substr(from, i - from));
      from = i + 1;
    }
  }
  items.push_back(s.substr(from, s.size() - 1 - from));
  if (items.size() == 1 && trim(items[0]).empty()) items.clear();
  return items;
}

template <class T>
std::optional<ParameterValue> sequenceOf(const std::vector<ParameterValue>& items) {
  std::vector<T> out;
  for (const ParameterValue& v : items) {
    if (!std::holds_alternative<T>(v)) return std::nullopt;  // rcl: "Sequence should be of same type"
    out.push_back(std::get<T>(v));
  }
  return ParameterValue(std::move(out));
}

/// Whether code point `cp` may stand in a YAML file as it is (libyaml's printable set).
bool printable(std::uint32_t cp) {
  return (cp >= 0x20 && cp <= 0x7E) || cp == 0x85 || (cp >= 0xA0 && cp <= 0xD7FF) ||
         (cp >= 0xE000 && cp <= 0xFFFD && cp != 0xFEFF) || (cp >= 0x10000 && cp <= 0x10FFFF);
}

/// The code point of the UTF-8 sequence at `s[i]` and its length; length 0 if it is not UTF-8.
std::pair<std::uint32_t, std::size_t> decodeUtf8(std::string_view s, std::size_t i) {
  const auto b = static_cast<unsigned char>(s[i]);
  const std::size_t n = b < 0x80 ? 1 : (b >> 5) == 0x6 ? 2 : (b >> 4) == 0xE ? 3 : (b >> 3) == 0x1E ? 4 : 0;
  if (n == 0 || i + n > s.size()) return {0, 0};
  std::uint32_t cp = n == 1 ? b : b & (0x7F >> n);
  for (std::size_t k = 1; k < n; ++k) {
    const auto c = static_cast<unsigned char>(s[i + k]);
    if ((c >> 6) != 0x2) return {0, 0};
    cp = (cp << 6) | (c & 0x3F);
  }
  constexpr std::uint32_t kLeast[] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < kLeast[n] || (cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) return {0, 0};  // overlong, surrogate
  return {cp, n};
}

/// `s` as a YAML double-quoted scalar: `"` and `\` escaped, and what libyaml would not read as
/// it is (control characters, bytes that are not UTF-8: `\xNN`, U+00NN).
std::string yamlQuoted(std::string_view s) {
  std::string out = "\"";
  for (std::size_t i = 0; i < s.size();) {
    const auto [cp, n] = decodeUtf8(s, i);
    if (n == 0) {
      out += fmt::format("\\x{:02X}", static_cast<unsigned char>(s[i]));
      ++i;
      continue;
    }
    if (cp == '"' || cp == '\\') out += '\\';
    if (cp == '\n') out += "\\n";
    else if (cp == '\t') out += "\\t";
    else if (!printable(cp)) out += cp <= 0xFF ? fmt::format("\\x{:02X}", cp) : fmt::format("\\u{:04X}", cp);
    else out.append(s.substr(i, n));
    i += n;
  }
  return out + '"';
}

std::string doubleText(double d) {
  if (std::isnan(d)) return ".nan";
  if (std::isinf(d)) return d > 0 ? ".inf" : "-.inf";
  std::string out = fmt::format("{}", d);  // the shortest text that reads back as d
  if (out.find_first_of(".eE") == std::string::npos) out += ".0";
  return out;
}

std::string scalarText(bool b) { return b ? "true" : "false"; }
std::string scalarText(std::int64_t i) { return std::to_string(i); }
std::string scalarText(double d) { return doubleText(d); }
std::string scalarText(const std::string& s) { return yamlQuoted(s); }

/// A parameter's name as a key: plain when it is made of a name's characters, else quoted.
std::string keyOf(std::string_view name) {
  const bool plain = !name.empty() && name.find_first_not_of(
                                          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                          "0123456789_.") == std::string_view::npos;
  return plain ? std::string(name) : yamlQuoted(name);
}

}  // namespace

std::optional<ParameterValue> rosValueOf(std::string_view text) {
  text = trim(text);
  if (text.empty() || text.front() != '[') return scalarOf(text);
  if (text.back() != ']') return std::nullopt;
  const auto items = itemsOf(text);
  if (!items || items->empty()) return std::nullopt;  // rcl leaves `[]` unset
  std::vector<ParameterValue> values;
  for (std::string_view item : *items) {
    auto v = scalarOf(item);
    if (!v) return std::nullopt;
    values.push_back(std::move(*v));
  }
  switch (values.front().index()) {
    case 0: return sequenceOf<bool>(values);
    case 1: return sequenceOf<std::int64_t>(values);
    case 2: return sequenceOf<double>(values);
    default: return sequenceOf<std::string>(values);
  }
}

ParameterMap typedParameters(const std::vector<profile::NodeParameter>& parameters) {
  ParameterMap out;
  for (const auto& p : parameters)
    if (auto v = rosValueOf(p.value)) out.insert_or_assign(p.name, std::move(*v));
  return out;
}

void overlay(ParameterMap& values, const profile::ParameterUpdate& update) {
  for (const auto& [name, value] : update.set) values.insert_or_assign(name, value);
  for (const auto& name : update.deleted) values.erase(name);
}

std::string yamlOf(const ParameterValue& value) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::int64_t> || std::is_same_v<T, double> ||
                      std::is_same_v<T, std::string>) {
          return scalarText(v);
        } else {
          if (v.empty()) return {};
          std::string out = "[";
          for (std::size_t i = 0; i < v.size(); ++i)
            out += (i ? ", " : "") + scalarText(static_cast<typename T::value_type>(v[i]));
          return out + "]";
        }
      },
      value);
}

std::string paramsFileText(std::string_view fqn, const ParameterMap& values) {
  std::string out = fmt::format("# keel run: the parameters of {} as it last had them, for its restart\n", fqn);
  out += fmt::format("{}:\n  ros__parameters:\n", fqn);
  for (const auto& [name, value] : values) {
    const std::string yaml = yamlOf(value);
    if (!yaml.empty()) out += fmt::format("    {}: {}\n", keyOf(name), yaml);
  }
  return out;
}

Result<void> writeParamsFile(const std::string& path, std::string_view fqn, const ParameterMap& values) {
  const std::string text = paramsFileText(fqn, values);
  static std::atomic<unsigned> written{0};  // two threads may write one file: each its own temporary
  const std::string temporary = fmt::format("{}.{}.{}.tmp", path, ::getpid(), written.fetch_add(1));
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) return fail(fmt::format("cannot write '{}'", temporary));
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    return fail(fmt::format("cannot write '{}': {}", path, ec.message()));
  }
  return {};
}

}  // namespace keel::supervision
