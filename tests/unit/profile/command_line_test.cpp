// A node's <command> made what keel runs without a shell (src/profile/command_line.hpp): words
// split as POSIX sh splits them, what needs a shell refused with where it is, and the program
// found on the node's PATH or beside the profile, as execvp would find it.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "profile/command_line.hpp"

namespace keel::profile::detail {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;

std::vector<std::string> words(std::string_view text) {
  auto r = splitCommand(text);
  EXPECT_TRUE(r.ok()) << text << ": " << r.error().message;
  return r.ok() ? *r : std::vector<std::string>{};
}

std::string refusal(std::string_view text) {
  auto r = splitCommand(text);
  EXPECT_FALSE(r.ok()) << text;
  return r.ok() ? std::string() : r.error().message;
}

TEST(CommandLine, SplitsAtBlanksAndLineBreaks) {
  EXPECT_THAT(words("python3 wander.py --speed 0.2"), ElementsAre("python3", "wander.py", "--speed", "0.2"));
  EXPECT_THAT(words("  a\t\tb\n  c  "), ElementsAre("a", "b", "c"));
  EXPECT_THAT(words(""), ElementsAre());
}

TEST(CommandLine, SingleQuotesKeepEverything) {
  EXPECT_THAT(words(R"(echo 'a b' 'x"y\z' '')"), ElementsAre("echo", "a b", R"(x"y\z)", ""));
  EXPECT_THAT(words(R"(echo 'it'\''s' pre'fix'post)"), ElementsAre("echo", "it's", "prefixpost"));
  EXPECT_THAT(words("echo '$HOME | *'"), ElementsAre("echo", "$HOME | *"));
}

TEST(CommandLine, DoubleQuotesEscapeOnlyQuoteBackslashDollarAndBackquote) {
  EXPECT_THAT(words(R"(echo "a \"b\" \\ \$ \` \n c")"), ElementsAre("echo", R"(a "b" \ $ ` \n c)"));
  EXPECT_THAT(words("echo \"one\\\ntwo\" \"\""), ElementsAre("echo", "onetwo", ""));
  EXPECT_THAT(words(R"x(echo "a|b;c&d<e>f*g?h[i](j)")x"), ElementsAre("echo", "a|b;c&d<e>f*g?h[i](j)"));
}

TEST(CommandLine, ABackslashOutsideQuotesKeepsTheNextCharacter) {
  EXPECT_THAT(words(R"(echo a\ b \| \$x \\ \')"), ElementsAre("echo", "a b", "|", "$x", R"(\)", "'"));
  EXPECT_THAT(words("echo one \\\ntwo"), ElementsAre("echo", "one", "two"));  // a continued line
  EXPECT_THAT(words("a~b c#d e=f"), ElementsAre("a~b", "c#d", "e=f"));        // special only at a word's start
}

TEST(CommandLine, RefusesWhatNeedsAShellSayingWhere) {
  const std::string tail = " needs a shell, and keel starts the command without one (quote it to pass it as it is)";
  EXPECT_EQ(refusal("node | tee log"), "unquoted '|' (character 6)" + tail);
  for (char c : std::string(";&<>$`*?[()")) {
    const std::string text = std::string("node x") + c;
    EXPECT_EQ(refusal(text), fmt::format("unquoted '{}' (character 7)", c) + tail) << text;
  }
  EXPECT_EQ(refusal("node ~/map.yaml"), "'~' at the start of a word (character 6)" + tail);
  EXPECT_EQ(refusal("node # a comment"), "'#' at the start of a word (character 6)" + tail);
  EXPECT_EQ(refusal(R"(node "$HOME")"), "'$' in double quotes (character 7)" + tail);
  EXPECT_EQ(refusal(R"(node "`date`")"), "'`' in double quotes (character 7)" + tail);
  EXPECT_EQ(refusal("ROS_LOG_DIR=/tmp node"),
            "its first word 'ROS_LOG_DIR=/tmp' would set a variable in a shell: give it in <environment>");
}

TEST(CommandLine, RefusesAnUnterminatedQuoteOrATrailingBackslash) {
  EXPECT_EQ(refusal("node 'a b"), "the single quote at character 6 is never closed");
  EXPECT_EQ(refusal(R"(node "a \" b)"), "the double quote at character 6 is never closed");
  EXPECT_EQ(refusal(R"(node a\)"), R"(the '\' at character 7, the last, escapes nothing)");
}

/// A scratch folder with programs in it, removed at the end of the test.
class CommandLineLookup : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("keel_command_line_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "bin");
    fs::create_directories(dir_ / "other");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string program(const std::string& relative, bool executable) {
    const fs::path p = dir_ / relative;
    std::ofstream(p) << "#!/bin/sh\nexit 0\n";
    fs::permissions(p, executable ? fs::perms(0755) : fs::perms(0644));
    return p.string();
  }
  std::string folder() const { return dir_.string(); }

  fs::path dir_;
};

TEST_F(CommandLineLookup, TakesTheFirstExecutableFileOnThePathSkippingOthers) {
  program("bin/node_a", false);
  program("other/node_a", true);
  const auto found = findExecutable("node_a", folder() + "/bin:" + folder() + "/other", "keel's PATH", "/");
  ASSERT_TRUE(found.ok()) << found.error().message;
  EXPECT_EQ(*found, folder() + "/other/node_a");
}

TEST_F(CommandLineLookup, AnEmptyOrRelativePathEntryIsTheProfilesFolder) {
  const std::string exe = program("node_b", true);
  program("bin/node_c", true);
  EXPECT_EQ(findExecutable("node_b", "/nonexistent::", "keel's PATH", folder()).value(), exe);
  EXPECT_EQ(findExecutable("node_c", "bin", "keel's PATH", folder()).value(), folder() + "/bin/node_c");
}

TEST_F(CommandLineLookup, AWordWithASlashIsTakenFromTheProfilesFolder) {
  const std::string exe = program("bin/node_d", true);
  EXPECT_EQ(findExecutable("bin/node_d", std::nullopt, "keel's PATH", folder()).value(), exe);
  EXPECT_EQ(findExecutable("./bin/../bin/node_d", std::nullopt, "keel's PATH", folder()).value(), exe);
  EXPECT_EQ(findExecutable(exe, std::nullopt, "keel's PATH", "/elsewhere").value(), exe);
}

TEST_F(CommandLineLookup, SaysWhereItLookedWhenThereIsNoProgram) {
  const std::string plain = program("bin/node_e", false);
  EXPECT_EQ(findExecutable("node_e", "/nonexistent:bin", "keel's PATH", folder()).error().message,
            "'node_e' is not an executable file in any directory of keel's PATH (" + plain +
                " is there, but not executable): /nonexistent:bin");
  EXPECT_EQ(
      findExecutable("node_f", "/nonexistent", "the PATH of its <environment> (line 4)", folder()).error().message,
      "'node_f' is not an executable file in any directory of the PATH of its <environment> (line 4): "
      "/nonexistent");
  EXPECT_EQ(findExecutable("node_e", std::nullopt, "keel's PATH", folder()).error().message,
            "'node_e' cannot be looked up: keel's PATH is empty or not set (name the program by its path, or set PATH "
            "in <environment>)");
  EXPECT_EQ(findExecutable("./bin/node_e", std::nullopt, "keel's PATH", folder()).error().message,
            "'./bin/node_e' is not executable (" + plain + "): make it so (chmod +x), or run it with its interpreter");
  EXPECT_EQ(findExecutable("./nothing", std::nullopt, "keel's PATH", folder()).error().message,
            "'./nothing' does not exist (looked for " + folder() + "/nothing)");
  EXPECT_EQ(findExecutable("./bin", std::nullopt, "keel's PATH", folder()).error().message,
            "'./bin' is not a regular file (" + folder() + "/bin)");
  EXPECT_EQ(findExecutable("", std::nullopt, "keel's PATH", folder()).error().message,
            "its first word, the program, is empty");
}

}  // namespace
}  // namespace keel::profile::detail
