// A node profile's <command> made what keel runs without a shell: its words split as POSIX sh
// splits them (quotes and backslashes only; whatever else a shell would do is refused), and
// its first word made an absolute path, looked up on the node's PATH as execvp would.
// Used by the node profile reader (node_profile.cpp). Thread-safety: functions of their
// arguments (and of the file system).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "keel/result.hpp"

namespace keel::profile::detail {

/// The words of `text` as sh would pass them to the program: blanks and line breaks separate
/// words; '...' keeps everything; "..." keeps everything but `\"` `\\` `\$` `` \` `` (and a
/// backslash before a line break, which drops both); outside quotes a backslash keeps the next
/// character. An error (why, with the character's position) for an unterminated quote and for
/// what needs a shell: unquoted | ; & < > $ ` * ? [ ( ), `$` or `` ` `` in double quotes, a word
/// starting with ~ or #, and a first word NAME=value.
Result<std::vector<std::string>> splitCommand(std::string_view text);

/// The absolute path of the program `word` names, or why there is none. With a '/', `word` is
/// taken from `folder` (the profile's) unless absolute; without one it is looked up in each
/// directory of `path` in turn (an empty or relative entry from `folder`, where the node runs),
/// the first regular, executable file found. `path`: the node's PATH; nullopt when it has none.
/// `path_from` says whose PATH it is, for the message ("keel's PATH").
Result<std::string> findExecutable(const std::string& word, const std::optional<std::string>& path,
                                   std::string_view path_from, const std::string& folder);

}  // namespace keel::profile::detail
