#include "supervision/spawner.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <future>
#include <string_view>
#include <system_error>

namespace keel::supervision {
namespace {

/// keel run's environment with `overrides` ("NAME=value") set over it.
std::vector<std::string> environmentWith(const std::vector<std::string>& overrides) {
  std::vector<std::string> env;
  auto nameOf = [](std::string_view entry) { return entry.substr(0, entry.find('=')); };
  for (char** e = environ; *e; ++e) {
    const std::string_view entry(*e);
    bool overridden = false;
    for (const auto& o : overrides) overridden |= nameOf(o) == nameOf(entry);
    if (!overridden) env.emplace_back(entry);
  }
  env.insert(env.end(), overrides.begin(), overrides.end());
  return env;
}

std::vector<char*> pointersTo(std::vector<std::string>& strings) {
  std::vector<char*> out;
  out.reserve(strings.size() + 1);
  for (auto& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

Result<pid_t> startNow(const ChildSpec& spec) {
  // The output file is opened here rather than by a spawn action, so that a file that cannot be
  // opened is said as such, not as a failure to start the program.
  int output = -1;
  if (!spec.output.empty()) {
    output = ::open(spec.output.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | (spec.fresh_output ? O_TRUNC : 0),
                    0644);
    if (output < 0)
      return fail(fmt::format("cannot open '{}' for the output of '{}': {}", spec.output, spec.executable,
                              std::generic_category().message(errno)));
  }
  // Copies above every target first, so that no dup2 overwrites a source another one still needs.
  std::vector<int> high;
  high.reserve(spec.fds.size());
  for (int fd : spec.fds)
    high.push_back(::fcntl(fd, F_DUPFD_CLOEXEC, kFirstChildFd + 64 + static_cast<int>(spec.fds.size())));
  std::vector<std::string> args;
  args.reserve(3 + spec.args.size());
  if (!spec.shim.empty()) args.insert(args.end(), {spec.shim, std::to_string(::getpid())});
  args.push_back(spec.executable);
  args.insert(args.end(), spec.args.begin(), spec.args.end());
  std::vector<char*> argv = pointersTo(args);
  std::vector<std::string> env;
  std::vector<char*> envp;
  if (!spec.environment.empty()) {
    env = environmentWith(spec.environment);
    envp = pointersTo(env);
  }

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (output >= 0) {
    posix_spawn_file_actions_adddup2(&actions, output, STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, output, STDERR_FILENO);
  }
  for (std::size_t j = 0; j < high.size(); ++j)
    posix_spawn_file_actions_adddup2(&actions, high[j], kFirstChildFd + static_cast<int>(j));
  // Nothing else of keel run's: not every descriptor it holds is close-on-exec (CycloneDDS's
  // sockets are not, nor what a component opens without O_CLOEXEC), and a child started after
  // keel run joined DDS would otherwise hold its participant's sockets for its whole life.
  posix_spawn_file_actions_addclosefrom_np(&actions, kFirstChildFd + static_cast<int>(high.size()));
  if (!spec.directory.empty()) posix_spawn_file_actions_addchdir_np(&actions, spec.directory.c_str());
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
  const std::string& program = spec.shim.empty() ? spec.executable : spec.shim;
  const int rc = ::posix_spawn(&pid, program.c_str(), &actions, &attr, argv.data(),
                               envp.empty() ? environ : envp.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  for (int fd : high)
    if (fd >= 0) ::close(fd);
  if (output >= 0) ::close(output);
  if (rc != 0) {
    if (!spec.directory.empty() && ::access(spec.directory.c_str(), X_OK) != 0)
      return fail(fmt::format("cannot start '{}' in '{}': {}", spec.executable, spec.directory,
                              std::generic_category().message(rc)));
    return fail(fmt::format("cannot start '{}': {}", program, std::generic_category().message(rc)));
  }
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
