// keel run --log-tee as a user runs it: every line of the fault log, keel run's and its
// component processes' alike, also goes to the tee, right after the log has it; a pipe whose
// reader never reads holds nothing up, and the run says how many lines the tee dropped.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "log/schema.hpp"
#include "support/env.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/pipe_reader.hpp"
#include "support/process.hpp"
#include "support/temp_log.hpp"

namespace keel {
namespace {

namespace ev = log::schema::event;
namespace fd = log::schema::field;
using namespace std::chrono_literals;

std::string profile(const std::string& name) { return std::string(KEEL_TEST_PROFILES) + "/" + name; }

class LogTee : public ::testing::Test {
 protected:
  keel::test::ScopedEnv component_path_{"KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS};
  void TearDown() override {
    for (const auto& f : {log_, tee_, report_}) std::filesystem::remove(f);
  }
  std::string log_ = test::tempPath("keel_tee_run");
  std::string tee_ = test::tempPath("keel_tee_copy");
  std::string report_ = test::tempPath("keel_tee_report", ".txt");
};

std::vector<std::string> sorted(std::vector<std::string> lines) {
  std::sort(lines.begin(), lines.end());
  return lines;
}

TEST_F(LogTee, APipeGetsExactlyTheLogsLinesKeelRunsAndItsComponentProcesses) {
  test::PipeReader pipe;
  ASSERT_TRUE(pipe.ok());
  auto r = test::runProcess({KEEL_CLI, "run", profile("isolation/stream.xml"), "--duration", "1", "--log", log_,
                             "--log-tee", pipe.path(), "--set", "checker.report=" + report_});
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_TRUE(pipe.finish(5s)) << "a process still holds the pipe";
  const std::vector<std::string> logged = test::linesOf(test::slurp(log_));
  const std::vector<std::string> teed = test::linesOf(pipe.text());
  // Lines of several processes reach the log at reserved offsets and the pipe each as its
  // writer gets to it: the same lines, not necessarily in the same order.
  EXPECT_EQ(sorted(teed), sorted(logged));
  std::size_t from_host = 0;  // the lifecycle of `source`, written by its process
  for (const auto& line : teed) {
    const auto rec = nlohmann::json::parse(line);
    from_host += rec.value(fd::kEvent, "") == ev::kState && rec.value(fd::kComponent, "") == "source";
  }
  EXPECT_EQ(from_host, 4u) << "Ready, Active, Inactive, Destroyed";
  EXPECT_EQ(r.err.find("tee"), std::string::npos) << r.err;
}

TEST_F(LogTee, AFileGetsTheSameLinesAsTheLogAppendedToWhatItHad) {
  std::ofstream(tee_) << "before\n";
  auto r = test::runProcess(
      {KEEL_CLI, "run", profile("pipeline.xml"), "--duration", "0.3", "--log", log_, "--log-tee", tee_});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(test::slurp(tee_), "before\n" + test::slurp(log_));
}

// The pipe is full before the run starts and nobody reads it: every line is dropped from it,
// none waits for it, and each process says how many it dropped.
TEST_F(LogTee, APipeNobodyReadsDoesNotHoldTheRunUpAndTheDroppedLinesAreCounted) {
  int fds[2];
  ASSERT_EQ(::pipe2(fds, O_CLOEXEC | O_NONBLOCK), 0);
  ::fcntl(fds[1], F_SETPIPE_SZ, 4096);
  const std::string full(4096, '#');
  ASSERT_EQ(::write(fds[1], full.data(), full.size()), 4096);
  const std::string path = "/proc/" + std::to_string(::getpid()) + "/fd/" + std::to_string(fds[1]);
  const auto start = std::chrono::steady_clock::now();
  auto r = test::runProcess({KEEL_CLI, "run", profile("isolation/stream.xml"), "--duration", "1", "--log", log_,
                             "--log-tee", path, "--set", "checker.report=" + report_});
  const auto took = std::chrono::steady_clock::now() - start;
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_LT(took, 10s) << "the run waited for the pipe";
  char rest[8192];
  EXPECT_EQ(::read(fds[0], rest, sizeof rest), 4096) << "only what the test put there";
  ::close(fds[0]);
  ::close(fds[1]);

  const auto log = test::readLog(log_);
  const std::regex dropped(R"(the log's tee '(.*)' dropped (\d+) of (\d+) lines: its reader was behind, or gone)");
  std::size_t keel_run = 0, hosts = 0;
  for (const auto& w : test::eventsOf(log, ev::kWarning)) {
    std::smatch m;
    const std::string message = w.value(fd::kMessage, "");
    if (!std::regex_match(message, m, dropped)) continue;
    EXPECT_EQ(m[2], m[3]) << "every line dropped: " << message;
    if (!w.contains(fd::kPid)) EXPECT_EQ(m[1], path) << "the name keel run was given";
    else EXPECT_EQ(m[1].str().rfind("/proc/", 0), 0u) << "keel run's descriptor: " << message;
    (w.contains(fd::kPid) ? hosts : keel_run) += 1;
  }
  EXPECT_EQ(keel_run, 1u) << r.err;
  EXPECT_EQ(hosts, 2u) << "the active host and its standby, each stopped with the run: " << r.err;
  EXPECT_NE(r.err.find("dropped"), std::string::npos) << "said on stderr too";
}

TEST_F(LogTee, AFifoWithoutAReaderIsRefusedBeforeTheRunStarts) {
  const std::string fifo = test::tempPath("keel_tee_fifo", "");
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto r = test::runProcess({KEEL_CLI, "run", profile("pipeline.xml"), "--duration", "0.3", "--log-tee", fifo});
  std::filesystem::remove(fifo);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cannot open the log's tee '" + fifo + "': no process reads that FIFO (start its reader first)"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace keel
