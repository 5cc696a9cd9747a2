// The exit watch (src/supervision/exit_watch.hpp): each watched process's end said once, at once,
// with its status when it is keel's child, and reaped.
#include "supervision/exit_watch.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <string>

#include "runtime/clock.hpp"
#include "supervision/spawner.hpp"

namespace keel::supervision {
namespace {

// What the watch said, by pid, for the test thread to wait on.
struct Seen {
  std::mutex mutex;
  std::condition_variable changed;
  std::map<pid_t, Exit> exits;
  std::map<pid_t, int> calls;

  ExitWatch::OnExit recorder() {
    return [this](pid_t pid, const Exit& e) {
      std::lock_guard lock(mutex);
      exits[pid] = e;
      ++calls[pid];
      changed.notify_all();
    };
  }
  // The generous bound is a hang's, not a speed goal: `keel bench` measures the speed.
  bool waitFor(std::size_t n, std::chrono::seconds within = std::chrono::seconds(30)) {
    std::unique_lock lock(mutex);
    return changed.wait_for(lock, within, [&] { return exits.size() >= n; });
  }
};

pid_t start(Spawner& spawner, const std::string& script) {
  auto pid = spawner.start({"/bin/sh", {"-c", script}, {}});
  EXPECT_TRUE(pid) << pid.error().message;
  return pid ? *pid : -1;
}

TEST(ExitWatch, SaysHowEachChildEndedAndReapsIt) {
  Spawner spawner;
  ExitWatch watch;
  Seen seen;
  const pid_t three = start(spawner, "exit 3");
  const pid_t killed = start(spawner, "kill -KILL $$");
  const pid_t aborted = start(spawner, "ulimit -c 0; kill -ABRT $$");
  ASSERT_TRUE(watch.watch(three, seen.recorder()));
  ASSERT_TRUE(watch.watch(killed, seen.recorder()));
  ASSERT_TRUE(watch.watch(aborted, seen.recorder()));
  ASSERT_TRUE(seen.waitFor(3));
  std::lock_guard lock(seen.mutex);
  EXPECT_EQ(describe(seen.exits[three]), "exited with status 3");
  EXPECT_EQ(describe(seen.exits[killed]), "killed by signal 9 (SIGKILL)");
  EXPECT_EQ(describe(seen.exits[aborted]), "killed by signal 6 (SIGABRT)");
  for (pid_t pid : {three, killed, aborted}) {
    EXPECT_EQ(seen.calls[pid], 1);
    errno = 0;
    EXPECT_EQ(::waitpid(pid, nullptr, WNOHANG), -1) << "process " << pid << " was not reaped";
    EXPECT_EQ(errno, ECHILD);
  }
}

TEST(ExitWatch, ADeathIsSeenWhenItHappensNotAtTheNextLook) {
  Spawner spawner;
  ExitWatch watch;
  Seen seen;
  const pid_t pid = start(spawner, "exec sleep 60");
  ASSERT_TRUE(watch.watch(pid, seen.recorder()));
  ASSERT_FALSE(seen.waitFor(1, std::chrono::seconds(0))) << "an exit said before the process ended";
  const std::int64_t killed_at = runtime::steadyNs();
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  ASSERT_TRUE(seen.waitFor(1));
  std::lock_guard lock(seen.mutex);
  EXPECT_EQ(describe(seen.exits[pid]), "killed by signal 9 (SIGKILL)");
  EXPECT_GE(seen.exits[pid].at_ns, killed_at);
}

TEST(ExitWatch, AProcessThatIsNotKeelsChildEndsWithAnUnknownStatus) {
  Spawner spawner;
  ExitWatch watch;
  Seen seen;
  // The shell starts a sleep in the background, says its pid and exits: the sleep is then
  // nobody's child here (its parent is init, or the nearest subreaper, not this process).
  int pipe_fds[2];
  ASSERT_EQ(::pipe2(pipe_fds, O_CLOEXEC), 0);
  auto sh = spawner.start({"/bin/sh", {"-c", "sleep 60 >/dev/null 2>&1 & echo $! >&3"}, {pipe_fds[1]}});
  ASSERT_TRUE(sh) << sh.error().message;
  ::close(pipe_fds[1]);
  char buf[32] = {};
  ASSERT_GT(::read(pipe_fds[0], buf, sizeof buf - 1), 0);
  ::close(pipe_fds[0]);
  ::waitpid(*sh, nullptr, 0);
  const pid_t orphan = static_cast<pid_t>(std::stol(buf));
  ASSERT_TRUE(watch.watch(orphan, seen.recorder()));
  ASSERT_EQ(::kill(orphan, SIGKILL), 0);
  ASSERT_TRUE(seen.waitFor(1));
  std::lock_guard lock(seen.mutex);
  EXPECT_EQ(seen.exits[orphan].status, -1);
  EXPECT_EQ(describe(seen.exits[orphan]), "exited (its status is its parent's, not keel's)");
}

TEST(ExitWatch, AProcessAlreadyGoneCannotBeWatched) {
  Spawner spawner;
  ExitWatch watch;
  const pid_t pid = start(spawner, "exit 0");
  ASSERT_EQ(::waitpid(pid, nullptr, 0), pid);
  auto watched = watch.watch(pid, [](pid_t, const Exit&) {});
  ASSERT_FALSE(watched);
  EXPECT_EQ(watched.error().message, "cannot watch process " + std::to_string(pid) + ": No such process");
}

TEST(ExitWatch, AfterStopNothingIsSaidAndNothingWatchedAnyMore) {
  Spawner spawner;
  ExitWatch watch;
  Seen seen;
  const pid_t pid = start(spawner, "exec sleep 60");
  ASSERT_TRUE(watch.watch(pid, seen.recorder()));
  watch.stop();
  ::kill(pid, SIGKILL);
  int status = 0;
  EXPECT_EQ(::waitpid(pid, &status, 0), pid) << "the stopped watch reaped it";
  EXPECT_FALSE(seen.waitFor(1, std::chrono::seconds(1)));
  const pid_t later = start(spawner, "exit 0");
  auto watched = watch.watch(later, seen.recorder());
  ASSERT_FALSE(watched);
  EXPECT_EQ(watched.error().message, "cannot watch process " + std::to_string(later) + ": the watch has stopped");
  ::waitpid(later, nullptr, 0);
}

TEST(ExitWatch, ManyProcessesEndingTogetherAreEachSaidOnce) {
  Spawner spawner;
  ExitWatch watch;
  Seen seen;
  std::map<pid_t, int> wanted;
  for (int i = 0; i < 40; ++i) {
    const pid_t pid = start(spawner, "sleep 0.2; exit " + std::to_string(i));
    ASSERT_TRUE(watch.watch(pid, seen.recorder()));
    wanted[pid] = i;
  }
  ASSERT_TRUE(seen.waitFor(wanted.size()));
  std::lock_guard lock(seen.mutex);
  for (const auto& [pid, code] : wanted) {
    EXPECT_EQ(describe(seen.exits[pid]), "exited with status " + std::to_string(code));
    EXPECT_EQ(seen.calls[pid], 1);
  }
}

}  // namespace
}  // namespace keel::supervision
