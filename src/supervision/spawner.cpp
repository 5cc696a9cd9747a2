#include "supervision/spawner.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <future>
#include <system_error>

namespace keel::supervision {
namespace {

Result<pid_t> startNow(const ChildSpec& spec) {
  // Copies above every target first, so that no dup2 overwrites a source another one still needs.
  std::vector<int> high;
  high.reserve(spec.fds.size());
  for (int fd : spec.fds)
    high.push_back(::fcntl(fd, F_DUPFD_CLOEXEC, kFirstChildFd + 64 + static_cast<int>(spec.fds.size())));
  std::vector<std::string> args;
  args.reserve(1 + spec.args.size());
  args.push_back(spec.executable);
  args.insert(args.end(), spec.args.begin(), spec.args.end());
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  for (std::size_t j = 0; j < high.size(); ++j)
    posix_spawn_file_actions_adddup2(&actions, high[j], kFirstChildFd + static_cast<int>(j));
  // Nothing else of keel run's: not every descriptor it holds is close-on-exec (CycloneDDS's
  // sockets are not, nor what a component opens without O_CLOEXEC), and a child started after
  // keel run joined DDS would otherwise hold its participant's sockets for its whole life.
  posix_spawn_file_actions_addclosefrom_np(&actions, kFirstChildFd + static_cast<int>(high.size()));
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, defaults;
  sigemptyset(&none);
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGINT);
  sigaddset(&defaults, SIGTERM);
  sigaddset(&defaults, SIGPIPE);
  sigaddset(&defaults, SIGUSR2);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
  pid_t pid = 0;
  const int rc = ::posix_spawn(&pid, spec.executable.c_str(), &actions, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  for (int fd : high)
    if (fd >= 0) ::close(fd);
  if (rc != 0) return fail(fmt::format("cannot start '{}': {}", spec.executable, std::generic_category().message(rc)));
  return pid;
}

}  // namespace

std::string describeExit(int status) {
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* abbrev = sigabbrev_np(sig);
    return fmt::format("killed by signal {} (SIG{}{})", sig, abbrev ? abbrev : "?",
                       WCOREDUMP(status) ? ", core dumped" : "");
  }
  if (WIFEXITED(status)) return fmt::format("exited with status {}", WEXITSTATUS(status));
  return fmt::format("ended (wait status {:#x})", status);
}

Result<pid_t> Spawner::start(const ChildSpec& spec) {
  if (thread_.isCurrent()) return startNow(spec);
  std::promise<Result<pid_t>> started;
  auto result = started.get_future();
  thread_.post([&] { started.set_value(startNow(spec)); });
  return result.get();
}

}  // namespace keel::supervision
