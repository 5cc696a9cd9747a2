// The fault log's tee (src/log/fault_log.hpp, keel run --log-tee): each line goes to the tee
// right after the log has it. A file gets every line; a pipe gets each line whole or not at
// all, and a reader that is behind, or gone, never holds the writer up nor kills it: the lines
// it missed are counted.
#include "log/fault_log.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <climits>
#include <filesystem>
#include <string>
#include <vector>

#include "log/schema.hpp"
#include "support/pipe_reader.hpp"
#include "support/process.hpp"
#include "support/temp_log.hpp"

namespace keel::log {
namespace {

/// A pipe whose ends close with the test.
struct Pipe {
  int read_end = -1;
  int write_end = -1;
  Pipe() {
    int fds[2];
    EXPECT_EQ(::pipe2(fds, O_CLOEXEC), 0);
    read_end = fds[0];
    write_end = fds[1];
  }
  ~Pipe() {
    if (read_end >= 0) ::close(read_end);
    if (write_end >= 0) ::close(write_end);
  }
  Pipe(const Pipe&) = delete;
  Pipe& operator=(const Pipe&) = delete;
  /// The write end as another process (or this one) opens it: the same pipe.
  std::string path() const { return "/proc/self/fd/" + std::to_string(write_end); }
  /// Everything in the pipe now, without waiting.
  std::string drain() const {
    ::fcntl(read_end, F_SETFL, ::fcntl(read_end, F_GETFL) | O_NONBLOCK);
    std::string out;
    char buf[4096];
    for (ssize_t n; (n = ::read(read_end, buf, sizeof buf)) > 0;) out.append(buf, static_cast<std::size_t>(n));
    return out;
  }
};

using test::linesOf;

TEST(FaultLog, AFileTeeGetsEveryLineTheLogGets) {
  test::TempLog file("keel_tee_log");
  const std::string tee = test::tempPath("keel_tee_copy");
  std::filesystem::remove(tee);
  ASSERT_TRUE(file.log.openTee(tee));
  for (int i = 0; i < 5; ++i) file.log.write(schema::warning("line " + std::to_string(i)));
  EXPECT_EQ(test::slurp(tee), test::slurp(file.path));
  EXPECT_EQ(linesOf(test::slurp(tee)).size(), 5u);
  EXPECT_EQ(file.log.teeDropped(), 0u);
  EXPECT_EQ(file.log.teeLines(), 5u);
  std::filesystem::remove(tee);
}

TEST(FaultLog, APipeTeeWhoseReaderIsBehindDropsWholeLinesAndCountsThemWithoutWaiting) {
  test::TempLog file("keel_tee_log");
  Pipe pipe;
  ASSERT_GT(::fcntl(pipe.write_end, F_SETPIPE_SZ, 4096), 0);  // the smallest pipe: one page
  ASSERT_TRUE(file.log.openTee(pipe.path()));
  const int kLines = 200;  // ~12 KB: three times the pipe, nobody reading
  for (int i = 0; i < kLines; ++i) file.log.write(schema::warning("line " + std::to_string(i)));

  const std::vector<std::string> logged = linesOf(test::slurp(file.path));
  const std::vector<std::string> teed = linesOf(pipe.drain());
  ASSERT_EQ(logged.size(), static_cast<std::size_t>(kLines));
  ASSERT_FALSE(teed.empty());
  ASSERT_LT(teed.size(), logged.size());
  // The first lines, each whole, until the pipe was full; then none.
  EXPECT_EQ(teed, std::vector<std::string>(logged.begin(), logged.begin() + static_cast<long>(teed.size())));
  EXPECT_EQ(file.log.teeDropped(), logged.size() - teed.size());
  EXPECT_EQ(file.log.teeLines(), logged.size());
}

TEST(FaultLog, APipeTeeWhoseReaderIsGoneNeitherKillsNorStopsTheLog) {
  test::TempLog file("keel_tee_log");
  Pipe pipe;
  ASSERT_TRUE(file.log.openTee(pipe.path()));
  ::close(pipe.read_end);  // SIGPIPE on the next write, unless the log holds it off
  pipe.read_end = -1;
  file.log.write(schema::warning("one"));
  file.log.write(schema::warning("two"));
  EXPECT_EQ(test::readLog(file.path).size(), 2u);
  EXPECT_EQ(file.log.teeDropped(), 2u);
  sigset_t pending;
  sigpending(&pending);
  EXPECT_FALSE(sigismember(&pending, SIGPIPE)) << "the SIGPIPE the write raised is left pending";
}

TEST(FaultLog, ALineLongerThanPipeBufIsInTheLogButNotTornIntoThePipe) {
  test::TempLog file("keel_tee_log");
  Pipe pipe;
  ASSERT_TRUE(file.log.openTee(pipe.path()));
  file.log.write(schema::warning(std::string(PIPE_BUF, 'x')));  // a pipe writes more than this in pieces
  file.log.write(schema::warning("short"));
  const std::vector<std::string> logged = linesOf(test::slurp(file.path));
  ASSERT_EQ(logged.size(), 2u);
  EXPECT_EQ(linesOf(pipe.drain()), std::vector<std::string>{logged[1]});
  EXPECT_EQ(file.log.teeDropped(), 1u);
}

TEST(FaultLog, TheLogItselfIsRefusedAsItsTee) {
  test::TempLog file("keel_tee_log");
  auto opened = file.log.openTee(file.path);
  ASSERT_FALSE(opened);
  EXPECT_EQ(opened.error().message, "cannot open the log's tee '" + file.path + "': it is the log itself");
  file.log.write(schema::warning("one"));
  EXPECT_EQ(test::readLog(file.path).size(), 1u);
}

TEST(FaultLog, AFifoWithoutAReaderIsRefusedWithWhy) {
  const std::string fifo = test::tempPath("keel_tee_fifo", "");
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  FaultLog log;
  auto opened = log.openTee(fifo);  // does not wait for a reader
  ASSERT_FALSE(opened);
  EXPECT_EQ(opened.error().message,
            "cannot open the log's tee '" + fifo + "': no process reads that FIFO (start its reader first)");
  std::filesystem::remove(fifo);
}

}  // namespace
}  // namespace keel::log
