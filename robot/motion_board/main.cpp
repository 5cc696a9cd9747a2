// keel_motion_board: the simulated motion board as a separate program behind a pseudo-terminal.
// Prints the slave path (one line on stdout), then every --period-ms reads main-board bytes
// (motion and fault commands), steps the simulation and writes one status frame, until
// SIGINT/SIGTERM. Touches only its own pty; status frames nobody reads are dropped.
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>

#include "robot/motion_board/board.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void onSignal(int) { g_stop = 1; }

struct Options {
  keel::robot::SimulatorConfig sim;
  int period_ms = 20;
};

bool parseInt(const char* text, long long min, long long& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtoll(text, &end, 10);
  return errno == 0 && end != text && *end == '\0' && out >= min;
}

bool parseOptions(int argc, char** argv, Options& options) {
  for (int i = 1; i < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag != "--seed" && flag != "--deadman-ms" && flag != "--period-ms") {
      std::fprintf(stderr, "keel_motion_board: unknown option %s "
                           "(use --seed N, --deadman-ms N, --period-ms N)\n", flag.c_str());
      return false;
    }
    long long value = 0;
    const long long min = flag == "--period-ms" ? 1 : 0;
    const long long max = flag == "--seed" ? std::numeric_limits<long long>::max() : 3'600'000;
    if (i + 1 >= argc || !parseInt(argv[i + 1], min, value) || value > max) {
      std::fprintf(stderr, "keel_motion_board: %s needs an integer in [%lld, %lld]\n", flag.c_str(), min, max);
      return false;
    }
    if (flag == "--seed") options.sim.seed = static_cast<std::uint64_t>(value);
    else if (flag == "--deadman-ms") options.sim.deadman_ms = static_cast<int>(value);
    else options.period_ms = static_cast<int>(value);
  }
  return true;
}

/// Opens a raw pty; returns the master fd and holds the slave open (so the master never sees a
/// hang-up while the main board reconnects), or -1 with a message on stderr.
int openPty(std::string& slave_path, int& slave_fd) {
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0 || ptsname(master) == nullptr) {
    std::perror("keel_motion_board: pseudo-terminal");
    return -1;
  }
  slave_path = ptsname(master);
  slave_fd = open(slave_path.c_str(), O_RDWR | O_NOCTTY);
  termios tio{};
  if (slave_fd < 0 || tcgetattr(slave_fd, &tio) != 0) {
    std::perror("keel_motion_board: slave");
    return -1;
  }
  cfmakeraw(&tio);
  tcsetattr(slave_fd, TCSANOW, &tio);
  fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);
  return master;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parseOptions(argc, argv, options)) return 2;
  struct sigaction sa {};
  sa.sa_handler = onSignal;  // no SA_RESTART: poll returns at once on a signal
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);

  std::string slave_path;
  int slave_fd = -1;
  const int master = openPty(slave_path, slave_fd);
  if (master < 0) return 1;
  std::printf("%s\n", slave_path.c_str());
  std::fflush(stdout);

  keel::robot::Board board(options.sim);
  const auto period = std::chrono::milliseconds(options.period_ms);
  auto next = std::chrono::steady_clock::now() + period;
  std::array<std::uint8_t, 256> buffer{};
  while (!g_stop) {
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next - std::chrono::steady_clock::now());
    pollfd pfd{master, POLLIN, 0};
    if (poll(&pfd, 1, static_cast<int>(std::max<long long>(wait.count(), 0))) > 0 && (pfd.revents & POLLIN)) {
      const ssize_t n = read(master, buffer.data(), buffer.size());
      if (n > 0) board.onBytes(std::span(buffer.data(), static_cast<std::size_t>(n)));
    }
    const auto now = std::chrono::steady_clock::now();
    if (now < next) continue;
    const auto frame = board.step(options.period_ms / 1000.0);
    if (write(master, frame.data(), frame.size()) < 0) { /* nobody reading: drop the frame */ }
    next += period;
    if (now - next > 10 * period) next = now + period;  // fell far behind (stopped?): resync
  }
  close(slave_fd);
  close(master);
  return 0;
}
