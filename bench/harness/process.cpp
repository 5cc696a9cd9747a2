// Child processes of the harness: see process.hpp.
#include "process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string_view>
#include <system_error>
#include <utility>

namespace keel::bench {
namespace {

/// Waits until `fd` is readable (or hung up); false at the deadline or on a poll error.
bool readable(int fd, Deadline deadline) {
  for (;;) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() < 0) return false;
    pollfd p{.fd = fd, .events = POLLIN, .revents = 0};
    const int rc = poll(&p, 1, static_cast<int>(left.count()));
    if (rc > 0) return true;
    if (rc == 0 && std::chrono::steady_clock::now() >= deadline) return false;
    if (rc < 0 && errno != EINTR) return false;
  }
}

void setStdio(posix_spawn_file_actions_t& actions, Stdio io) {
  if (io.in >= 0) posix_spawn_file_actions_adddup2(&actions, io.in, STDIN_FILENO);
  else posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  if (io.out >= 0) posix_spawn_file_actions_adddup2(&actions, io.out, STDOUT_FILENO);
  if (io.err >= 0) posix_spawn_file_actions_adddup2(&actions, io.err, STDERR_FILENO);
}

void setAttributes(posix_spawnattr_t& attr, bool fifo, bool ownGroup) {
  short flags = POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF;
  sigset_t none, all;
  sigemptyset(&none);
  sigfillset(&all);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &all);
  if (fifo) {
    const sched_param param{.sched_priority = kFifoPriority};
    flags |= POSIX_SPAWN_SETSCHEDULER;
    posix_spawnattr_setschedpolicy(&attr, SCHED_FIFO);
    posix_spawnattr_setschedparam(&attr, &param);
  }
  if (ownGroup) {
    flags |= POSIX_SPAWN_SETPGROUP;
    posix_spawnattr_setpgroup(&attr, 0);
  }
  posix_spawnattr_setflags(&attr, flags);
}

}  // namespace

Fd& Fd::operator=(Fd&& other) noexcept {
  if (this != &other) reset(other.release());
  return *this;
}

int Fd::release() {
  const int fd = fd_;
  fd_ = -1;
  return fd;
}

void Fd::reset(int fd) {
  if (fd_ >= 0) close(fd_);
  fd_ = fd;
}

bool Pipe::open() {
  read.reset();
  write.reset();
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) return false;
  read.reset(fds[0]);
  write.reset(fds[1]);
  return true;
}

std::optional<std::string> LineReader::next(Deadline deadline) {
  for (;;) {
    if (const auto nl = buf_.find('\n'); nl != std::string::npos) {
      std::string line = buf_.substr(0, nl);
      buf_.erase(0, nl + 1);
      return line;
    }
    if (end_ || !readable(fd_, deadline)) break;
    char chunk[4096];
    const ssize_t got = ::read(fd_, chunk, sizeof chunk);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      end_ = true;
      break;
    }
    buf_.append(chunk, static_cast<std::size_t>(got));
  }
  if (!end_ || buf_.empty()) return std::nullopt;
  return std::exchange(buf_, {});
}

Result<Process> Process::spawn(const std::vector<std::string>& argv, Stdio io, bool fifo, bool ownGroup,
                               const std::vector<EnvChange>& env) {
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // The harness's environment less the variables `env` changes, then those it sets.
  std::vector<std::string> changed;
  std::vector<char*> envp;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string_view entry(*e);
    const std::string_view name = entry.substr(0, entry.find('='));
    if (std::none_of(env.begin(), env.end(), [&](const EnvChange& c) { return c.name == name; })) envp.push_back(*e);
  }
  for (const EnvChange& c : env)
    if (c.value) changed.push_back(c.name + "=" + *c.value);
  for (std::string& e : changed) envp.push_back(e.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attr;
  posix_spawn_file_actions_init(&actions);
  posix_spawnattr_init(&attr);
  setStdio(actions, io);
  setAttributes(attr, fifo, ownGroup);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, args[0], &actions, &attr, args.data(), envp.data());
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&actions);
  if (rc == EPERM && fifo) return fail(std::string("SCHED_FIFO not permitted: ") + std::generic_category().message(rc));
  if (rc != 0) return fail(argv[0] + ": " + std::generic_category().message(rc));
  const int pidfd = static_cast<int>(syscall(SYS_pidfd_open, pid, 0));
  if (pidfd < 0) {
    const int err = errno;
    kill(pid, SIGKILL);
    while (waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {}
    return fail(std::string("pidfd_open: ") + std::generic_category().message(err));
  }
  return Process(pid, Fd(pidfd), ownGroup);
}

Process::Process(Process&& other) noexcept
    : pid_(std::exchange(other.pid_, -1)), pidfd_(std::move(other.pidfd_)), group_(other.group_) {}

Process::~Process() {
  if (pid_ >= 0) killAndReap();
}

std::optional<int> Process::waitUntil(Deadline deadline) {
  if (pid_ < 0) return std::nullopt;
  if (!readable(pidfd_.get(), deadline)) {
    killAndReap();
    return std::nullopt;
  }
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {}
  pid_ = -1;
  pidfd_.reset();
  return status;
}

void Process::signal(int sig) const {
  if (pid_ >= 0) kill(group_ ? -pid_ : pid_, sig);
}

void Process::killAndReap() {
  kill(group_ ? -pid_ : pid_, SIGKILL);
  while (waitpid(pid_, nullptr, 0) < 0 && errno == EINTR) {}
  pid_ = -1;
  pidfd_.reset();
}

std::string becomeFifo() {
  const sched_param param{.sched_priority = kFifoPriority};
  const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  return rc == 0 ? "" : std::string("SCHED_FIFO not permitted: ") + std::generic_category().message(rc);
}

std::string findInPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  const std::string dirs = path ? path : "/usr/bin:/bin";
  for (std::size_t start = 0; start <= dirs.size();) {
    std::size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    std::string candidate = dirs.substr(start, end - start) + "/" + name;
    if (end > start && access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return {};
}

Captured runCaptured(const std::vector<std::string>& argv, bool fifo, Deadline deadline) {
  Captured out;
  Pipe pipe;
  if (!pipe.open()) {
    out.error = std::string("pipe: ") + std::generic_category().message(errno);
    return out;
  }
  auto proc = Process::spawn(argv, {.in = -1, .out = pipe.write.get(), .err = pipe.write.get()}, fifo, true);
  pipe.write.reset();  // end of file once the command (and whatever it spawned) is gone
  if (!proc) {
    out.error = proc.error().message;
    return out;
  }
  LineReader reader(pipe.read.get());
  while (auto line = reader.next(deadline)) out.lines.push_back(std::move(*line));
  const auto status = proc->waitUntil(
      reader.atEnd() ? std::max(deadline, std::chrono::steady_clock::now() + std::chrono::seconds(5))
                     : std::chrono::steady_clock::now());
  if (!status) {
    out.error = "killed: no end within the time allowed (output: " + (out.lines.empty() ? "none" : out.lines.back()) +
                ")";
    return out;
  }
  out.status = WIFEXITED(*status) ? WEXITSTATUS(*status) : 128 + WTERMSIG(*status);
  return out;
}

TempDir::TempDir(const std::string& prefix) {
  std::error_code ec;
  const auto base = std::filesystem::temp_directory_path(ec);
  std::string tmpl = (ec ? std::filesystem::path("/tmp") : base) / (prefix + "XXXXXX");
  if (mkdtemp(tmpl.data()) != nullptr) path_ = tmpl;
}

TempDir::~TempDir() {
  std::error_code ec;
  if (!path_.empty()) std::filesystem::remove_all(path_, ec);
}

}  // namespace keel::bench
