// The real-time loop of the simulated motion board, shared by the program and the in-process
// board.
#include "robot/sim/board_server.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace keel::robot {

void serveBoard(int fd, SimHost& host, int period_ms, const std::atomic<bool>& stop) {
  const auto period = std::chrono::milliseconds(period_ms);
  auto next = std::chrono::steady_clock::now() + period;
  std::array<std::uint8_t, 256> buffer{};
  while (!stop.load(std::memory_order_acquire)) {
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next - std::chrono::steady_clock::now());
    pollfd pfd{fd, POLLIN, 0};
    if (poll(&pfd, 1, static_cast<int>(std::clamp<long long>(wait.count(), 0, period_ms))) > 0 &&
        (pfd.revents & POLLIN)) {
      const ssize_t n = read(fd, buffer.data(), buffer.size());
      if (n > 0) host.onBytes(std::span(buffer.data(), static_cast<std::size_t>(n)));
    }
    const auto now = std::chrono::steady_clock::now();
    if (now < next) continue;
    const auto frame = host.step(period_ms / 1000.0);
    if (write(fd, frame.data(), frame.size()) < 0) { /* nobody reading: drop the frame */
    }
    next += period;
    if (now - next > 10 * period) next = now + period;  // fell far behind (stopped?): resync
  }
}

InProcessBoard::InProcessBoard(const SimHostConfig& config, int period_ms) : host_(std::make_unique<SimHost>(config)) {
  int fds[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
    throw std::runtime_error(std::string("socketpair: ") + std::generic_category().message(errno));
  main_fd_ = fds[0];
  board_fd_ = fds[1];
  fcntl(board_fd_, F_SETFL, fcntl(board_fd_, F_GETFL) | O_NONBLOCK);
  thread_ = std::thread([this, period_ms] {
    pthread_setname_np(pthread_self(), "sim-board");
    serveBoard(board_fd_, *host_, period_ms, stop_);
  });
}

InProcessBoard::~InProcessBoard() {
  stop_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  close(main_fd_);
  close(board_fd_);
}

}  // namespace keel::robot
