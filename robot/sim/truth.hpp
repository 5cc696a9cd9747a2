// The simulation's ground truth, shared between the process that simulates the robot
// (keel_motion_board, or an in-process simulator) and the components that stand for what a real
// robot gets from the physical world: the camera (it renders the view from the true pose) and
// the mission referee (collisions, clearance, goal). A small file in /dev/shm written by one
// simulator and read by any number of readers, never blocking either side (a seqlock).
// Thread-safety: one writer (any thread); readers on any thread or process.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

namespace keel::robot {

/// One instant of the simulated world.
struct TruthSample {
  double t_s = 0.0;  // simulated time
  double x_m = 0.0;
  double y_m = 0.0;
  double heading_rad = 0.0;
  double rpm_left = 0.0;  // true wheel speeds
  double rpm_right = 0.0;
  double clearance_m = 0.0;      // body to the nearest box now (0: touching or overlapping)
  double min_clearance_m = 0.0;  // smallest clearance so far
  double collisions = 0.0;       // collision episodes so far (the body entering a box)
  double deadman = 0.0;          // 1 while the deadman holds the motors
  double powered_left = 1.0;     // 0 while that driver has no power
  double powered_right = 1.0;
  double neutral_since_s = -1.0;  // since when the main board commands neutral (-1: it does not)
  double deadman_since_s = -1.0;  // since when the deadman holds the motors (-1: it does not)
  std::uint64_t steps = 0;        // simulation steps so far
};

/// The shared-memory path for a simulation named `name` ("robot" -> /dev/shm/keel-robot-<pid>
/// when owner_pid is the keel process, so several runs never meet).
std::string truthPath(const std::string& name, long owner_pid);

class TruthWriter {
 public:
  /// Creates (or truncates) the file and maps it; throws std::runtime_error with the reason.
  explicit TruthWriter(std::string path);
  ~TruthWriter();  // unmaps and removes the file
  TruthWriter(const TruthWriter&) = delete;
  TruthWriter& operator=(const TruthWriter&) = delete;

  void publish(const TruthSample& sample);
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  std::string path_;
  void* map_ = nullptr;
};

class TruthReader {
 public:
  explicit TruthReader(std::string path) : path_(std::move(path)) {}
  ~TruthReader();
  TruthReader(const TruthReader&) = delete;
  TruthReader& operator=(const TruthReader&) = delete;

  /// The latest consistent sample; nothing while the file does not exist yet or nothing has
  /// been published (the reader retries opening on each call until it succeeds).
  [[nodiscard]] std::optional<TruthSample> read();
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  std::string path_;
  void* map_ = nullptr;
};

}  // namespace keel::robot
