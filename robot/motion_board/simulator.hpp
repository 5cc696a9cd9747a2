// The motion board's physics: a deterministic differential-drive body (210 × 140 mm) with
// first-order motor inertia, wheel encoders, four sonars fed by a pluggable ray cast, a deadman,
// and the hardware faults of the paper's experiments (unplugged/stuck sonar, driver power off).
// Called by Board (behind the byte protocol) and directly by tests. Touches no I/O or clock:
// time advances only through step(), randomness only through the seeded generator.
// Thread-safety: none; one owner.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <random>

#include "robot/motion_board/protocol.hpp"

namespace keel::robot {

inline constexpr double kMinRangeCm = 3.0;
inline constexpr double kMaxRangeCm = 3000.0;
inline constexpr double kFreeSpaceCm = 3000.0;

/// World frame: metres, heading in radians, 0 = +x, counter-clockwise positive.
struct Pose {
  double x_m = 0.0;
  double y_m = 0.0;
  double heading_rad = 0.0;
};

enum class Wheel : std::uint8_t { Left = 0, Right = 1 };

/// Distance in cm from a sensor at (x_m, y_m) looking along heading_rad to the first obstacle.
using RayCast = std::function<double(double x_m, double y_m, double heading_rad)>;

/// The wheel targets (left, right rpm) a motion command asks for, clamped to ±max_rpm, as the
/// motion board applies them (docs/motion_board_protocol.md); the main board's reference model
/// uses the same mapping.
std::array<double, 2> wheelTargets(const MotionCommand& command, double max_rpm);

struct SimulatorConfig {
  std::uint64_t seed = 1;
  int deadman_ms = 300;                  // 0 disables the deadman
  double motor_time_constant_s = 0.150;  // first-order lag, also the coast-down when unpowered
  double wheel_radius_m = 0.0325;        // 65 mm wheels
  double track_width_m = 0.140;          // wheel to wheel across the 140 mm body
  double body_length_m = 0.210;          // front/back sonars sit at ± half of it
  int counts_per_revolution = 360;
  double max_rpm = 300.0;              // commands are clamped to ± this
  double gyro_noise_rad_s = 0.005;     // the gyro's white noise (sigma), on its own seeded generator
  double sonar_half_angle_rad = 0.26;  // ±15° beam; 0 = a single ray
  int sonar_beam_rays = 7;             // rays spread across the beam (at least 2 when > 0)
  Pose start{};
  RayCast ray_cast;  // empty: free space, every ray reads kFreeSpaceCm
};

class Simulator {
 public:
  explicit Simulator(SimulatorConfig config = {});

  /// A command from the main board; restarts the deadman window.
  void command(const MotionCommand& command);
  void applyFault(const FaultCommand& fault);
  /// Advances time by dt_s (> 0): deadman, motors, encoders, pose, then one sonar sample.
  void step(double dt_s);

  [[nodiscard]] double timeS() const { return time_s_; }
  [[nodiscard]] const Pose& pose() const { return pose_; }
  [[nodiscard]] double wheelRpm(Wheel wheel) const { return rpm_[index(wheel)]; }
  /// What the driver is asked for after the deadman and driver power are applied.
  [[nodiscard]] double targetRpm(Wheel wheel) const;
  [[nodiscard]] std::int32_t encoder(Wheel wheel) const;
  /// The robot's true yaw rate (rad/s, counter-clockwise positive) at the end of the last step.
  [[nodiscard]] double yawRate() const;
  /// What the gyro reads, mrad/s: the yaw rate with its noise, 0 while it is dead.
  [[nodiscard]] std::int16_t gyroMradS() const { return gyro_mrad_s_; }
  [[nodiscard]] std::uint16_t sonarCm(SonarId id) const { return sonar_cm_[static_cast<std::size_t>(id)]; }
  [[nodiscard]] StatusReport status() const;
  [[nodiscard]] bool deadmanTripped() const { return deadman_tripped_; }
  /// Since when (simulated s) the command in effect is a stop, i.e. the main board holds the
  /// motors in neutral; -1 while it asks for motion, or has sent nothing yet.
  [[nodiscard]] double neutralSinceS() const { return neutral_since_s_; }
  /// Since when the deadman holds the motors (no command for deadman_ms); -1 while it does not.
  [[nodiscard]] double deadmanSinceS() const { return deadman_tripped_ ? deadman_since_s_ : -1.0; }
  [[nodiscard]] bool motorPowered(Wheel wheel) const { return powered_[index(wheel)]; }

 private:
  enum class SensorState : std::uint8_t { Ok, Unplugged, Stuck };

  static std::size_t index(Wheel wheel) { return static_cast<std::size_t>(wheel); }
  void checkDeadman();
  void sampleSonars();
  double rawRangeCm(std::size_t sonar) const;

  SimulatorConfig config_;
  std::mt19937_64 rng_;
  double time_s_ = 0.0;
  double last_command_s_ = 0.0;
  bool deadman_tripped_ = false;
  double deadman_since_s_ = -1.0;
  double neutral_since_s_ = -1.0;
  MotionCommand command_{};
  Pose pose_{};
  std::array<double, 2> rpm_{};
  std::array<double, 2> encoder_counts_{};  // fractional; reported floored and wrapped
  std::array<bool, 2> powered_{true, true};
  std::array<bool, 2> encoder_dead_{};
  std::array<std::int32_t, 2> encoder_frozen_{};  // a dead encoder's reading: its last count
  bool gyro_dead_ = false;
  std::mt19937_64 gyro_rng_;  // the gyro's own: its noise leaves the sonars' draws as they were
  std::int16_t gyro_mrad_s_ = 0;
  std::array<SensorState, kSonarCount> sensor_state_{};
  std::array<std::uint16_t, kSonarCount> stuck_cm_{};
  std::array<std::uint16_t, kSonarCount> sonar_cm_{};
  double noise_sigma_cm_ = 0.0;
};

}  // namespace keel::robot
