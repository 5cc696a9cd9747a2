// The spawner (src/supervision/spawner.hpp): what a child it starts gets, and how its end is said.
#include "supervision/spawner.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <sstream>
#include <string>
#include <thread>

#include "supervision/exit_watch.hpp"
#include "support/env.hpp"
#include "support/paths.hpp"

namespace keel::supervision {
namespace {

// What a child wrote to descriptor 3 (a pipe) until it closed it, and its wait status.
struct Said {
  std::string text;
  int status = 0;
};

Said runAndRead(Spawner& spawner, ChildSpec spec) {
  int pipe_fds[2];
  EXPECT_EQ(::pipe2(pipe_fds, O_CLOEXEC), 0);
  spec.fds = {pipe_fds[1]};
  auto pid = spawner.start(spec);
  ::close(pipe_fds[1]);
  Said said;
  if (!pid) {
    ADD_FAILURE() << pid.error().message;
    ::close(pipe_fds[0]);
    return said;
  }
  char buf[512];
  for (ssize_t n; (n = ::read(pipe_fds[0], buf, sizeof buf)) > 0;) said.text.append(buf, static_cast<std::size_t>(n));
  ::close(pipe_fds[0]);
  EXPECT_EQ(::waitpid(*pid, &said.status, 0), *pid);
  return said;
}

std::string fileText(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::filesystem::path freshDir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

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

TEST(Spawner, AChildGetsKeelsEnvironmentWithTheGivenVariablesSetOverIt) {
  test::ScopedEnv kept("KEEL_SPAWNER_TEST_KEPT", "kept");
  test::ScopedEnv over("KEEL_SPAWNER_TEST_OVER", "keel's");
  Spawner spawner;
  ChildSpec spec{"/bin/sh",
                 {"-c", "echo \"$KEEL_SPAWNER_TEST_KEPT $KEEL_SPAWNER_TEST_OVER $KEEL_SPAWNER_TEST_NEW\" >&3"},
                 {}};
  spec.environment = {"KEEL_SPAWNER_TEST_OVER=the node's", "KEEL_SPAWNER_TEST_NEW=new"};
  const Said said = runAndRead(spawner, spec);
  EXPECT_EQ(said.text, "kept the node's new\n");
  EXPECT_EQ(describeExit(said.status), "exited with status 0");
}

TEST(Spawner, AChildRunsInTheGivenDirectory) {
  const auto dir = freshDir("keel_spawner_dir");
  Spawner spawner;
  ChildSpec spec{"/bin/sh", {"-c", "pwd >&3"}, {}};
  spec.directory = dir.string();
  EXPECT_EQ(runAndRead(spawner, spec).text, dir.string() + "\n");
  spec.directory = (dir / "missing").string();
  auto pid = spawner.start(spec);
  ASSERT_FALSE(pid);
  EXPECT_EQ(pid.error().message, "cannot start '/bin/sh' in '" + spec.directory + "': No such file or directory");
  std::filesystem::remove_all(dir);
}

TEST(Spawner, AChildsOutputAndErrorsAreAppendedToItsOutputFile) {
  const auto dir = freshDir("keel_spawner_output");
  const auto out = dir / "run.node.out";
  { std::ofstream(out) << "earlier\n"; }
  Spawner spawner;
  ChildSpec spec{"/bin/sh", {"-c", "echo out; echo err >&2; echo out again; exec 3>&-"}, {}};
  spec.output = out.string();
  EXPECT_EQ(describeExit(runAndRead(spawner, spec).status), "exited with status 0");
  EXPECT_EQ(fileText(out), "earlier\nout\nerr\nout again\n");
  spec.output = (dir / "no" / "such" / "dir.out").string();
  auto pid = spawner.start(spec);
  ASSERT_FALSE(pid);
  EXPECT_EQ(pid.error().message,
            "cannot open '" + spec.output + "' for the output of '/bin/sh': No such file or directory");
  std::filesystem::remove_all(dir);
}

// The program keel-node-exec executes keeps its pid: after the exec, the process is the program.
std::string commOf(pid_t pid) {
  std::string comm;
  std::ifstream(std::filesystem::path("/proc") / std::to_string(pid) / "comm") >> comm;
  return comm;
}

TEST(Spawner, AChildStartedThroughTheShimDiesWithTheSpawnersThreadAndOneStartedDirectlyDoesNot) {
  ExitWatch watch;
  std::promise<Exit> shimmed_end;
  pid_t shimmed = 0, direct = 0;
  {
    Spawner spawner;
    ChildSpec spec{"/bin/sleep", {"60"}, {}};
    spec.shim = KEEL_NODE_EXEC;
    auto pid = spawner.start(spec);
    ASSERT_TRUE(pid) << pid.error().message;
    shimmed = *pid;
    auto plain = spawner.start({"/bin/sleep", {"60"}, {}});
    ASSERT_TRUE(plain) << plain.error().message;
    direct = *plain;
    ASSERT_TRUE(watch.watch(shimmed, [&](pid_t, const Exit& e) { shimmed_end.set_value(e); }));
    // Until the shim asked for SIGKILL, the spawner's end would not kill it: wait for its exec.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (commOf(shimmed) != "sleep" && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ASSERT_EQ(commOf(shimmed), "sleep") << "the shim did not become the program, keeping its pid";
  }  // the spawner's thread ends
  auto ended = shimmed_end.get_future();
  ASSERT_EQ(ended.wait_for(std::chrono::seconds(30)), std::future_status::ready)
      << "the shimmed child outlived its spawner";
  EXPECT_EQ(describe(ended.get()), "killed by signal 9 (SIGKILL)");
  EXPECT_EQ(::kill(direct, 0), 0) << "a child started directly died with the spawner too: the test shows nothing";
  ::kill(direct, SIGKILL);
  waitStatus(direct);
}

TEST(Spawner, TheShimStartsNothingWhenKeelRunIsNoLongerItsParent) {
  Spawner spawner;
  // keel-node-exec told that its parent is pid 2 (never this test): keel run "died" before it
  // asked to die with it.
  const Said said = runAndRead(spawner, {KEEL_NODE_EXEC, {"2", "/bin/sh", "-c", "echo ran >&3"}, {}});
  EXPECT_EQ(said.text, "");
  EXPECT_EQ(describeExit(said.status), "exited with status 127");
}

TEST(Spawner, TheShimSaysWhenTheProgramCannotBeExecuted) {
  const auto dir = freshDir("keel_spawner_shim");
  Spawner spawner;
  ChildSpec spec{(dir / "missing-node").string(), {}, {}};
  spec.shim = KEEL_NODE_EXEC;
  spec.output = (dir / "out").string();
  auto pid = spawner.start(spec);
  ASSERT_TRUE(pid) << pid.error().message;
  EXPECT_EQ(describeExit(waitStatus(*pid)), "exited with status 127");
  EXPECT_EQ(fileText(dir / "out"),
            "keel-node-exec: cannot execute '" + spec.executable + "': No such file or directory\n");
  const Said usage = runAndRead(spawner, {KEEL_NODE_EXEC, {"x", "/bin/true"}, {}});
  EXPECT_EQ(describeExit(usage.status), "exited with status 2");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace keel::supervision
