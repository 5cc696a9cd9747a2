// The spawner (src/supervision/spawner.hpp): what a child it starts gets, and how its end is said.
#include "supervision/spawner.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <future>
#include <string>

namespace keel::supervision {
namespace {

int waitStatus(pid_t pid) {
  int status = 0;
  EXPECT_EQ(::waitpid(pid, &status, 0), pid);
  return status;
}

TEST(Spawner, AChildGetsTheGivenDescriptorsFromThreeAndNoOtherOfTheParents) {
  int pipe_fds[2];
  ASSERT_EQ(::pipe2(pipe_fds, O_CLOEXEC), 0);
  const int stray = ::fcntl(pipe_fds[1], F_DUPFD, 9);  // not close-on-exec: the child must not get it
  ASSERT_GE(stray, 9);
  Spawner spawner;
  // Writes to 3 (the pipe), then exits 7 if the stray descriptor is open in it, 0 if not.
  const std::string script = "echo given >&3; if true >&" + std::to_string(stray) + " 2>/dev/null; then exit 7; fi";
  auto pid = spawner.start({"/bin/sh", {"-c", script}, {pipe_fds[1]}});
  ASSERT_TRUE(pid) << pid.error().message;
  const int status = waitStatus(*pid);
  ::close(pipe_fds[1]);
  ::close(stray);
  char buf[16] = {};
  const ssize_t n = ::read(pipe_fds[0], buf, sizeof buf - 1);
  ::close(pipe_fds[0]);
  EXPECT_EQ(std::string(buf, n > 0 ? static_cast<std::size_t>(n) : 0), "given\n");
  EXPECT_EQ(describeExit(status), "exited with status 0") << "the parent's stray descriptor reached the child";
}

TEST(Spawner, AChildRunsInAProcessGroupOfItsOwn) {
  Spawner spawner;
  auto pid = spawner.start({"/bin/sleep", {"5"}, {}});
  ASSERT_TRUE(pid) << pid.error().message;
  EXPECT_EQ(::getpgid(*pid), *pid);
  EXPECT_NE(::getpgid(*pid), ::getpgrp());
  ::kill(*pid, SIGKILL);
  EXPECT_EQ(describeExit(waitStatus(*pid)), "killed by signal 9 (SIGKILL)");
}

TEST(Spawner, AProgramThatCannotStartIsAnErrorNamingIt) {
  Spawner spawner;
  auto pid = spawner.start({"/nonexistent/keel-host", {}, {}});
  ASSERT_FALSE(pid);
  EXPECT_EQ(pid.error().message, "cannot start '/nonexistent/keel-host': No such file or directory");
}

TEST(Spawner, AJobOnTheSpawnersThreadStartsChildrenWithoutWaitingForItself) {
  Spawner spawner;
  std::promise<Result<pid_t>> started;
  spawner.post([&] { started.set_value(spawner.start({"/bin/sh", {"-c", "exit 3"}, {}})); });
  auto future = started.get_future();
  ASSERT_EQ(future.wait_for(std::chrono::seconds(30)), std::future_status::ready) << "the spawner waited for itself";
  auto pid = future.get();
  ASSERT_TRUE(pid) << pid.error().message;
  EXPECT_EQ(describeExit(waitStatus(*pid)), "exited with status 3");
}

}  // namespace
}  // namespace keel::supervision
