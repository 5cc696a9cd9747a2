// The actuator's serial link to the motion board: a pseudo-terminal or serial device opened by
// path, a keel_motion_board child process it starts itself (its pty), or the simulated board on
// a thread of this process (a socket pair). Either way: a non-blocking byte stream.
// Called by ActuatorControl. Thread-safety: send() may be called from any thread (a mutex keeps
// frames whole); receive() from one thread.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "robot/sim/board_server.hpp"

namespace keel::robot {

struct BoardLinkConfig {
  std::string device = "spawn";  // "spawn", "inprocess" or a device path
  std::string program;           // spawn: keel_motion_board ("" = next to this executable)
  SimHostConfig sim;             // spawn / inprocess: the simulation
  int period_ms = 20;            // spawn / inprocess: the board's status period
};

class BoardLink {
 public:
  /// Opens the link; throws std::runtime_error with the reason.
  explicit BoardLink(const BoardLinkConfig& config);
  ~BoardLink();  // closes the link; stops a child board (SIGTERM, then waits)
  BoardLink(const BoardLink&) = delete;
  BoardLink& operator=(const BoardLink&) = delete;

  /// Writes one whole frame; false when the link refused it.
  bool send(std::span<const std::uint8_t> frame);
  /// Whatever bytes arrived (possibly none); never blocks.
  std::vector<std::uint8_t> receive() const;
  [[nodiscard]] const std::string& description() const { return description_; }

 private:
  void spawn(const BoardLinkConfig& config);
  void openDevice(const std::string& path);

  int fd_ = -1;
  pid_t child_ = -1;
  std::unique_ptr<InProcessBoard> inprocess_;
  std::mutex send_mutex_;
  std::string description_;
};

}  // namespace keel::robot
