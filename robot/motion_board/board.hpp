// The simulated motion board behind its byte stream: main-board bytes in (onBytes), one status
// frame out per step. keel_motion_board runs it behind a pseudo-terminal in real time; tests run
// it in-process with the same bytes. Touches no I/O or clock itself.
// Thread-safety: none; one owner.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "robot/motion_board/protocol.hpp"
#include "robot/motion_board/simulator.hpp"

namespace keel::robot {

class Board {
 public:
  explicit Board(SimulatorConfig config = {}) : simulator_(std::move(config)) {}

  /// Decodes whatever arrived: motion commands go to the simulator (restarting the deadman),
  /// fault commands are applied, status frames (never sent by a main board) are ignored.
  void onBytes(std::span<const std::uint8_t> bytes);
  /// A hardware fault applied directly (the simulator's own options, e.g. noise from start).
  void applyFault(const FaultCommand& fault) { simulator_.applyFault(fault); }
  /// Advances the simulation by dt_s and returns the encoded status frame of this step.
  [[nodiscard]] std::vector<std::uint8_t> step(double dt_s);

  [[nodiscard]] const Simulator& simulator() const { return simulator_; }
  [[nodiscard]] const DecoderStats& decoderStats() const { return decoder_.stats(); }

 private:
  Simulator simulator_;
  Decoder decoder_;
};

}  // namespace keel::robot
