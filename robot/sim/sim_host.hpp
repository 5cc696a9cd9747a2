// The simulated robot in its world: the motion board (behind its byte stream) driving a body in
// a World whose sonars it ray-casts, with the ground truth (pose, collisions, clearance)
// published for the camera and the referee. keel_motion_board serves it on a pseudo-terminal;
// the actuator component can also run it in-process (robot/sim/inprocess_board.hpp).
// Touches no clock: time advances by step(). Thread-safety: none; one owner.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "robot/motion_board/board.hpp"
#include "robot/sim/truth.hpp"
#include "robot/world/world.hpp"

namespace keel::robot {

struct SimHostConfig {
  std::string world = "paper";  // a name worldByName() knows
  std::uint64_t seed = 1;
  int deadman_ms = 300;
  double sonar_noise_cm = 0.0;  // Gaussian sigma on every healthy sonar from the start
  std::string truth_path;       // empty: no ground truth published
};

/// The worlds the simulator knows by name: "paper" (World::paperArena()). Nothing otherwise.
std::optional<World> worldByName(const std::string& name);
/// Their names, for error messages ("paper").
std::string worldNames();

class SimHost {
 public:
  /// Throws std::invalid_argument for an unknown world, std::runtime_error when the truth
  /// file cannot be created.
  explicit SimHost(const SimHostConfig& config);

  /// Main-board bytes (motion and fault commands).
  void onBytes(std::span<const std::uint8_t> bytes) { board_.onBytes(bytes); }
  /// Advances by dt_s, tracks collisions, publishes the truth; returns the status frame.
  [[nodiscard]] std::vector<std::uint8_t> step(double dt_s);

  [[nodiscard]] const TruthSample& truth() const { return truth_; }
  [[nodiscard]] const World& world() const { return world_; }
  [[nodiscard]] const Board& board() const { return board_; }

 private:
  void observe();

  World world_;
  Board board_;
  std::unique_ptr<TruthWriter> writer_;
  TruthSample truth_;
  bool in_collision_ = false;
};

}  // namespace keel::robot
