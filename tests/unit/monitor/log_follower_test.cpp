#include "monitor/log_follower.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "support/temp_log.hpp"

namespace keel::monitor {
namespace {

/// A scratch file, empty at first, removed at the end.
struct Scratch {
  Scratch() : path_(test::tempPath("keel_follower")) { std::filesystem::remove(path_); }
  ~Scratch() { std::filesystem::remove(path_); }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  Scratch(Scratch&&) = delete;
  Scratch& operator=(Scratch&&) = delete;
  const std::string& path() const { return path_; }
  std::string path_;
};

void writeAt(const std::string& path, off_t at, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::pwrite(fd, bytes.data(), bytes.size(), at), static_cast<ssize_t>(bytes.size()));
  ::close(fd);
}

TEST(LogFollower, HandsOutWholeLinesOnlyAndTheRestWhenItIsWritten) {
  Scratch log;
  writeAt(log.path(), 0, "{\"a\":1}\n{\"b\":");
  auto follower = LogFollower::open(log.path());
  ASSERT_TRUE(follower) << follower.error().message;
  std::vector<std::string> lines;
  follower->read(lines);
  EXPECT_EQ(lines, (std::vector<std::string>{"{\"a\":1}"}));

  writeAt(log.path(), 13, "2}\n");
  lines.clear();
  follower->read(lines);
  EXPECT_EQ(lines, (std::vector<std::string>{"{\"b\":2}"}));
  EXPECT_EQ(follower->offset(), 16U);
}

TEST(LogFollower, WaitsForAGapAnotherProcessReservedAndReadsItInOrderOnceFilled) {
  Scratch log;
  // Process A reserved 8 bytes and has not written them; B wrote its line after them.
  writeAt(log.path(), 0, "{\"a\":1}\n");
  writeAt(log.path(), 16, "{\"c\":3}\n");
  auto follower = LogFollower::open(log.path());
  ASSERT_TRUE(follower);
  std::vector<std::string> lines;
  follower->read(lines);
  EXPECT_EQ(lines, (std::vector<std::string>{"{\"a\":1}"})) << "nothing past the gap yet";

  writeAt(log.path(), 8, "{\"b\":2}\n");
  lines.clear();
  follower->read(lines);
  EXPECT_EQ(lines, (std::vector<std::string>{"{\"b\":2}", "{\"c\":3}"}));
}

TEST(LogFollower, GivesUpOnAGapNoOneFillsAndReadsOn) {
  Scratch log;
  writeAt(log.path(), 8, "{\"c\":3}\n");  // 8 NUL bytes first: a writer that died
  auto follower = LogFollower::open(log.path());
  ASSERT_TRUE(follower);
  std::vector<std::string> lines;
  follower->read(lines);
  EXPECT_TRUE(lines.empty());
  std::this_thread::sleep_for(LogFollower::kGapPatience + std::chrono::milliseconds(100));
  follower->read(lines);
  EXPECT_EQ(lines, (std::vector<std::string>{"{\"c\":3}"}));
}

TEST(LogFollower, WakesWhenTheLogIsWrittenTo) {
  Scratch log;
  writeAt(log.path(), 0, "");
  auto follower = LogFollower::open(log.path());
  ASSERT_TRUE(follower);
  std::thread writer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    writeAt(log.path(), 0, "{\"a\":1}\n");
  });
  const auto t0 = std::chrono::steady_clock::now();
  follower->wait(std::chrono::seconds(20));
  const auto waited = std::chrono::steady_clock::now() - t0;
  writer.join();
  EXPECT_LT(waited, std::chrono::seconds(10)) << "woken by the write, not the timeout";
  std::vector<std::string> lines;
  follower->read(lines);
  EXPECT_EQ(lines.size(), 1U);
}

TEST(LogFollower, ALogThatCannotBeOpenedIsAnErrorNamingIt) {
  auto follower = LogFollower::open("/nonexistent/run.jsonl");
  ASSERT_FALSE(follower);
  EXPECT_NE(follower.error().message.find("/nonexistent/run.jsonl"), std::string::npos);
}

}  // namespace
}  // namespace keel::monitor
