// Board: the protocol decoder wired to the simulator; see board.hpp.
#include "robot/motion_board/board.hpp"

namespace keel::robot {

void Board::onBytes(std::span<const std::uint8_t> bytes) {
  for (const Frame& frame : decoder_.feed(bytes)) {
    if (const auto* motion = std::get_if<MotionCommand>(&frame)) {
      simulator_.command(*motion);
    } else if (const auto* fault = std::get_if<FaultCommand>(&frame)) {
      simulator_.applyFault(*fault);
    }
  }
}

std::vector<std::uint8_t> Board::step(double dt_s) {
  simulator_.step(dt_s);
  return encode(simulator_.status());
}

}  // namespace keel::robot
