// keel_motion_board: the simulated robot's motion board as a separate program behind a
// pseudo-terminal, driving the body in a world (--world, default the paper arena) and
// publishing the ground truth (--truth PATH) for the camera and the referee. Prints the slave
// path (one line on stdout), then serves the board in real time (robot/sim/board_server.hpp)
// until SIGINT/SIGTERM, or until the process named by --parent PID is gone: a main board
// killed with -9 does not leave its motion board running, nor, killed before it read the
// path, its truth file. Touches only its pty and the truth file.
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <thread>

#include "robot/sim/board_server.hpp"

namespace {

std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop.store(true); }

struct Options {
  keel::robot::SimHostConfig host;
  int period_ms = 20;
  long long parent = 0;  // --parent: serve while this process is our parent (0: for ever)
};

constexpr const char* kUsage =
    "use --seed N, --deadman-ms N, --period-ms N, --world NAME, --truth PATH, --noise CM, --parent PID";

bool parseInt(const char* text, long long min, long long& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtoll(text, &end, 10);
  return errno == 0 && end != text && *end == '\0' && out >= min;
}

bool parseNumberOption(const std::string& flag, const char* text, Options& options) {
  if (flag == "--noise") {
    char* end = nullptr;
    const double cm = std::strtod(text, &end);
    if (end == text || *end != '\0' || !(cm >= 0 && cm <= 1000)) {
      std::fprintf(stderr, "keel_motion_board: --noise needs a sigma in cm in [0, 1000]\n");
      return false;
    }
    options.host.sonar_noise_cm = cm;
    return true;
  }
  long long value = 0;
  const long long min = flag == "--period-ms" ? 1 : 0;
  const long long max = flag == "--seed" || flag == "--parent" ? std::numeric_limits<long long>::max() : 3'600'000;
  if (!parseInt(text, min, value) || value > max) {
    std::fprintf(stderr, "keel_motion_board: %s needs an integer in [%lld, %lld]\n", flag.c_str(), min, max);
    return false;
  }
  if (flag == "--seed") options.host.seed = static_cast<std::uint64_t>(value);
  else if (flag == "--deadman-ms") options.host.deadman_ms = static_cast<int>(value);
  else if (flag == "--parent") options.parent = value;
  else options.period_ms = static_cast<int>(value);
  return true;
}

bool parseOptions(int argc, char** argv, Options& options) {
  for (int i = 1; i < argc; i += 2) {
    const std::string flag = argv[i];
    const bool known = flag == "--seed" || flag == "--deadman-ms" || flag == "--period-ms" || flag == "--world" ||
                       flag == "--truth" || flag == "--noise" || flag == "--parent";
    if (!known) {
      std::fprintf(stderr, "keel_motion_board: unknown option %s (%s)\n", flag.c_str(), kUsage);
      return false;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "keel_motion_board: %s needs a value (%s)\n", flag.c_str(), kUsage);
      return false;
    }
    if (flag == "--world") options.host.world = argv[i + 1];
    else if (flag == "--truth") options.host.truth_path = argv[i + 1];
    else if (!parseNumberOption(flag, argv[i + 1], options)) return false;
  }
  return true;
}

/// Opens a raw pty; returns the master fd and holds the slave open (so the master never sees a
/// hang-up while the main board reconnects), or -1 with a message on stderr.
int openPty(std::string& slave_path, int& slave_fd) {
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  char name[128];
  if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0 || ptsname_r(master, name, sizeof name) != 0) {
    std::perror("keel_motion_board: pseudo-terminal");
    return -1;
  }
  slave_path = name;
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
  // A starter killed before it read our path closed its pipe: the write fails (below) instead
  // of the SIGPIPE killing us with the truth file left behind.
  std::signal(SIGPIPE, SIG_IGN);

  std::unique_ptr<keel::robot::SimHost> host;
  try {
    host = std::make_unique<keel::robot::SimHost>(options.host);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "keel_motion_board: %s\n", e.what());
    return 2;
  }
  std::string slave_path;
  int slave_fd = -1;
  const int master = openPty(slave_path, slave_fd);
  if (master < 0) return 1;
  if (std::printf("%s\n", slave_path.c_str()) < 0 || std::fflush(stdout) != 0) {
    std::perror("keel_motion_board: nobody reads the pseudo-terminal's path");
    close(slave_fd);
    close(master);
    return 1;  // the truth file goes with the host
  }

  // The parent's death reparents us: watched every 20 ms by a thread of its own, so the board's
  // loop stays as it is in-process. A parent already gone before we looked is caught too.
  std::thread watch;
  if (options.parent > 0) {
    watch = std::thread([parent = static_cast<pid_t>(options.parent)] {
      while (!g_stop.load()) {
        if (getppid() != parent) g_stop.store(true);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    });
  }
  keel::robot::serveBoard(master, *host, options.period_ms, g_stop);
  g_stop.store(true);
  if (watch.joinable()) watch.join();
  close(slave_fd);
  close(master);
  return 0;
}
