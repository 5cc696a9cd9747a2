// BoardLink: opening the motion board's byte stream three ways; see board_link.hpp.
#include "robot/components/board_link.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace keel::robot {
namespace {

std::string defaultProgram() {
  char self[PATH_MAX] = {};
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return "keel_motion_board";
  return (std::filesystem::path(std::string(self, static_cast<std::size_t>(n))).parent_path() / "keel_motion_board")
      .string();
}

/// One line from `fd` within `timeout_ms`, without the newline; "" on timeout or EOF.
std::string readLine(int fd, int timeout_ms) {
  std::string line;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd pfd{fd, POLLIN, 0};
    if (poll(&pfd, 1, 50) <= 0) continue;
    char c = 0;
    if (read(fd, &c, 1) != 1) return "";
    if (c == '\n') return line;
    line += c;
  }
  return "";
}

}  // namespace

BoardLink::BoardLink(const BoardLinkConfig& config) {
  if (config.device == "inprocess") {
    inprocess_ = std::make_unique<InProcessBoard>(config.sim, config.period_ms);
    fd_ = inprocess_->fd();
    fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL) | O_NONBLOCK);
    description_ = "in-process simulated board";
  } else if (config.device == "spawn") {
    spawn(config);
  } else {
    openDevice(config.device);
    description_ = config.device;
  }
}

void BoardLink::spawn(const BoardLinkConfig& config) {
  const std::string program = config.program.empty() ? defaultProgram() : config.program;
  std::vector<std::string> args = {program,
                                   "--seed",
                                   std::to_string(config.sim.seed),
                                   "--world",
                                   config.sim.world,
                                   "--deadman-ms",
                                   std::to_string(config.sim.deadman_ms),
                                   "--period-ms",
                                   std::to_string(config.period_ms),
                                   "--noise",
                                   std::to_string(config.sim.sonar_noise_cm),
                                   "--parent",  // it ends with this process, even one killed with -9
                                   std::to_string(getpid())};
  if (!config.sim.truth_path.empty()) {
    args.emplace_back("--truth");
    args.push_back(config.sim.truth_path);
  }
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int out[2];
  if (pipe2(out, O_CLOEXEC) != 0)
    throw std::runtime_error(std::string("pipe: ") + std::generic_category().message(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  // The board must hear SIGTERM: keel run blocks it in its threads, and a child inherits that.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, stops;
  sigemptyset(&none);
  sigemptyset(&stops);
  sigaddset(&stops, SIGTERM);
  sigaddset(&stops, SIGINT);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &stops);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  const int rc = posix_spawn(&child_, program.c_str(), &actions, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&actions);
  close(out[1]);
  if (rc != 0) {
    close(out[0]);
    child_ = -1;
    throw std::runtime_error("cannot start " + program + ": " + std::generic_category().message(rc));
  }
  const std::string path = readLine(out[0], 5000);
  close(out[0]);
  if (path.empty()) throw std::runtime_error(program + " printed no pseudo-terminal path (see its stderr)");
  openDevice(path);
  description_ = program + " on " + path;
}

void BoardLink::openDevice(const std::string& path) {
  fd_ = open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error("cannot open " + path + ": " + std::generic_category().message(errno));
  termios tio{};
  if (tcgetattr(fd_, &tio) == 0) {  // a tty: raw bytes, nothing buffered from before
    cfmakeraw(&tio);
    tcsetattr(fd_, TCSANOW, &tio);
    tcflush(fd_, TCIOFLUSH);
  }
}

BoardLink::~BoardLink() {
  if (fd_ >= 0 && !inprocess_) close(fd_);
  inprocess_.reset();
  if (child_ > 0) {
    kill(child_, SIGTERM);
    waitpid(child_, nullptr, 0);
  }
}

bool BoardLink::send(std::span<const std::uint8_t> frame) {
  std::lock_guard lock(send_mutex_);
  return write(fd_, frame.data(), frame.size()) == static_cast<ssize_t>(frame.size());
}

std::vector<std::uint8_t> BoardLink::receive() const {
  std::vector<std::uint8_t> bytes;
  std::uint8_t buf[512];
  for (ssize_t n; (n = read(fd_, buf, sizeof buf)) > 0;) bytes.insert(bytes.end(), buf, buf + n);
  return bytes;
}

}  // namespace keel::robot
