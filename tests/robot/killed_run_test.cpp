// keel run killed with -9 while the robot drives: nothing it started stays behind. Its motion
// board (keel_motion_board, which the actuator started) ends on its own when it sees its parent
// gone, and removes its truth file; the vision's component processes end with the run's lock.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "log/schema.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"
#include "support/temp_log.hpp"

namespace keel::test {
namespace {

using namespace std::chrono_literals;
namespace ev = log::schema::event;
namespace fd = log::schema::field;

TEST(KilledRun, KeelRunKilledWithMinus9LeavesNoMotionBoardOrComponentProcessRunning) {
  const std::string log = tempPath("keel_killed_robot");
  const pid_t keel = fork();
  if (keel == 0) {
    if (!freopen("/dev/null", "w", stdout)) _exit(126);
    execl(KEEL_CLI, KEEL_CLI, "run", (std::string(KEEL_ROBOT) + "/navigation.xml").c_str(), "--duration", "60", "--log",
          log.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  bool started = false;
  for (int i = 0; i < 600 && !started; ++i) {  // 30 s: a loaded machine
    std::this_thread::sleep_for(50ms);
    for (const auto& e : eventsOf(readLog(log), ev::kEngine)) started |= e.value(fd::kPhase, "") == "started";
  }
  ASSERT_TRUE(started) << slurp(log);
  std::this_thread::sleep_for(500ms);  // driving
  // The vision's component process and its standby (started once the active one runs): both
  // must be there, so that "nothing left behind" covers a standby too.
  std::vector<std::pair<long, std::string>> children;
  long board = 0;
  int hosts = 0;
  for (int i = 0; i < 200 && (board == 0 || hosts < 2); ++i) {  // 10 s: a loaded machine
    if (i > 0) std::this_thread::sleep_for(50ms);
    children = childrenOf(keel);
    board = 0;
    hosts = 0;
    for (const auto& [pid, comm] : children) {
      if (comm.rfind("keel_motion_bo", 0) == 0) board = pid;  // comm is cut at 15 characters
      hosts += comm == "keel-host";
    }
  }
  ASSERT_NE(board, 0) << "no motion board among keel run's children";
  EXPECT_EQ(hosts, 2) << "the vision's component process and its standby";
  const std::string truth = argumentOf(board, "--truth");

  ::kill(keel, SIGKILL);
  ::waitpid(keel, nullptr, 0);
  bool all_gone = false;
  for (int i = 0; i < 250 && !all_gone; ++i) {  // 5 s; the board looks every 20 ms
    std::this_thread::sleep_for(20ms);
    all_gone = true;
    for (const auto& child : children) all_gone &= processGone(child.first);
  }
  for (const auto& [pid, comm] : children)
    EXPECT_TRUE(processGone(pid)) << comm << " (pid " << pid << ") outlived keel run";
  if (!truth.empty()) {
    EXPECT_FALSE(std::filesystem::exists(truth)) << "the board left its truth file " << truth;
  }
  for (const auto& child : children)  // what outlived it must not outlive the test too
    if (!processGone(child.first)) ::kill(static_cast<pid_t>(child.first), SIGKILL);
  if (!truth.empty()) std::filesystem::remove(truth);
  std::filesystem::remove(log);
}

}  // namespace
}  // namespace keel::test
