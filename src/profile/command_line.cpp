// A node's command line split and its program found, without a shell; see command_line.hpp.
#include "profile/command_line.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string_view>

#include <fmt/format.h>

namespace keel::profile::detail {
namespace {

namespace fs = std::filesystem;

bool blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

/// Characters that mean something to sh outside quotes and that keel cannot do without one.
bool needsShell(char c) { return std::string_view("|;&<>$`*?[()").find(c) != std::string_view::npos; }

Error shellOnly(std::string_view what) {
  return fail(
      fmt::format("{} needs a shell, and keel starts the command without one (quote it to pass it as it is)", what));
}

/// Whether the word starting at text[at] begins NAME= unquoted: sh's variable assignment.
bool isAssignment(std::string_view text, std::size_t at) {
  std::size_t i = at;
  while (i < text.size() && (std::isalnum(static_cast<unsigned char>(text[i])) != 0 || text[i] == '_')) ++i;
  return i > at && i < text.size() && text[i] == '=' && std::isdigit(static_cast<unsigned char>(text[at])) == 0;
}

/// The inside of a "..." that opens at text[open]; `i` is left on the closing quote.
Result<void> doubleQuoted(std::string_view text, std::size_t open, std::size_t& i, std::string& word) {
  for (i = open + 1; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') return {};
    if (c == '$' || c == '`') return shellOnly(fmt::format("'{}' in double quotes (character {})", c, i + 1));
    if (c == '\\' && i + 1 < text.size() && std::string_view("\"\\$`\n").find(text[i + 1]) != std::string_view::npos) {
      ++i;
      if (text[i] != '\n') word += text[i];  // a backslash and a line break: both dropped
      continue;
    }
    word += c;
  }
  return fail(fmt::format("the double quote at character {} is never closed", open + 1));
}

}  // namespace

Result<std::vector<std::string>> splitCommand(std::string_view text) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\\' && i + 1 < text.size() && text[i + 1] == '\n') {  // a continued line
      ++i;
      continue;
    }
    if (blank(c)) {
      if (in_word) words.push_back(std::move(word));
      word.clear();
      in_word = false;
      continue;
    }
    if (!in_word) {
      if (c == '~' || c == '#') return shellOnly(fmt::format("'{}' at the start of a word (character {})", c, i + 1));
      if (words.empty() && isAssignment(text, i)) {
        const std::size_t end = std::min(text.find_first_of(" \t\n\r", i), text.size());
        return fail(fmt::format("its first word '{}' would set a variable in a shell: give it in <environment>",
                                text.substr(i, end - i)));
      }
      in_word = true;
    }
    if (c == '\\') {
      if (i + 1 == text.size()) return fail(fmt::format("the '\\' at character {}, the last, escapes nothing", i + 1));
      word += text[++i];
    } else if (c == '\'') {
      const std::size_t close = text.find('\'', i + 1);
      if (close == std::string_view::npos)
        return fail(fmt::format("the single quote at character {} is never closed", i + 1));
      word += text.substr(i + 1, close - i - 1);
      i = close;
    } else if (c == '"') {
      if (auto r = doubleQuoted(text, i, i, word); !r) return r.error();
    } else if (needsShell(c)) {
      return shellOnly(fmt::format("unquoted '{}' (character {})", c, i + 1));
    } else {
      word += c;
    }
  }
  if (in_word) words.push_back(std::move(word));
  return words;
}

namespace {

enum class Found { Executable, NotExecutable, NotRegular, Missing };

Found examine(const fs::path& p) {
  std::error_code ec;
  const fs::file_status st = fs::status(p, ec);
  if (ec || !fs::exists(st)) return Found::Missing;
  if (!fs::is_regular_file(st)) return Found::NotRegular;
  return ::access(p.c_str(), X_OK) == 0 ? Found::Executable : Found::NotExecutable;
}

/// `entry` of a PATH or a command word, absolute: an empty or relative one from `folder`.
fs::path fromFolder(std::string_view entry, const std::string& folder) {
  const fs::path p(entry.empty() ? "." : entry);
  return (p.is_absolute() ? p : fs::path(folder) / p).lexically_normal();
}

}  // namespace

Result<std::string> findExecutable(const std::string& word, const std::optional<std::string>& path,
                                   std::string_view path_from, const std::string& folder) {
  if (word.empty()) return fail("its first word, the program, is empty");
  if (word.find('/') != std::string::npos) {
    const fs::path p = fromFolder(word, folder);
    switch (examine(p)) {
      case Found::Executable: return p.string();
      case Found::Missing: return fail(fmt::format("'{}' does not exist (looked for {})", word, p.string()));
      case Found::NotRegular: return fail(fmt::format("'{}' is not a regular file ({})", word, p.string()));
      case Found::NotExecutable:
        return fail(fmt::format("'{}' is not executable ({}): make it so (chmod +x), or run it with its interpreter",
                                word, p.string()));
    }
  }
  if (!path || path->empty())
    return fail(
        fmt::format("'{}' cannot be looked up: {} is empty or not set (name the program by its path, or set "
                    "PATH in <environment>)",
                    word, path_from));
  std::string not_executable;  // the first file of that name found without the right to run it
  for (std::size_t start = 0; start <= path->size();) {
    const std::size_t end = std::min(path->find(':', start), path->size());
    const fs::path p = fromFolder(std::string_view(*path).substr(start, end - start), folder) / word;
    const Found f = examine(p);
    if (f == Found::Executable) return p.string();
    if (f == Found::NotExecutable && not_executable.empty()) not_executable = p.string();
    start = end + 1;
  }
  const std::string also = not_executable.empty() ? ""
                                                  : fmt::format(" ({} is there, but not executable)", not_executable);
  return fail(fmt::format("'{}' is not an executable file in any directory of {}{}: {}", word, path_from, also, *path));
}

}  // namespace keel::profile::detail
