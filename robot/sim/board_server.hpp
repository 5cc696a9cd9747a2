// Serves a SimHost on a byte stream in real time: every period it reads the main board's bytes
// that arrived, steps the simulation by the period and writes one status frame. Used by
// keel_motion_board (on a pseudo-terminal) and by InProcessBoard (on a socket pair), so both
// speak exactly the same bytes. Also the in-process board itself.
// Thread-safety: serveBoard runs on its caller's thread; InProcessBoard owns one thread.
#pragma once

#include <atomic>
#include <memory>
#include <thread>

#include "robot/sim/sim_host.hpp"

namespace keel::robot {

/// Runs until `stop` becomes true (checked at least every period). Status frames that cannot be
/// written (nobody reading, buffer full) are dropped, as on a real UART.
void serveBoard(int fd, SimHost& host, int period_ms, const std::atomic<bool>& stop);

/// The simulated motion board on a thread of this process, behind a socket pair: the main
/// board's end is fd(). Same simulation, same bytes, same timing as keel_motion_board.
class InProcessBoard {
 public:
  /// Throws what SimHost throws, or std::runtime_error when the socket pair fails.
  InProcessBoard(const SimHostConfig& config, int period_ms);
  ~InProcessBoard();  // stops the thread, closes both ends
  InProcessBoard(const InProcessBoard&) = delete;
  InProcessBoard& operator=(const InProcessBoard&) = delete;

  [[nodiscard]] int fd() const { return main_fd_; }

 private:
  std::unique_ptr<SimHost> host_;
  int main_fd_ = -1;
  int board_fd_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace keel::robot
