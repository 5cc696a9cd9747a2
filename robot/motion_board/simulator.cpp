// Differential-drive physics of the simulated motion board. Motor speed follows its target
// with an exact first-order response over each step, so the result does not depend on how the
// caller slices time; encoders and pose integrate that response exactly per step.
#include "robot/motion_board/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace keel::robot {
namespace {

/// Body-frame mount of each sonar (SonarId order): offset forward, offset left, bearing. The
/// three front sonars sit side by side at the middle of the bumper (a few cm apart: at this
/// scale one point), looking ahead; the fourth looks back.
struct Mount {
  double forward;  // fraction of half length
  double left;     // fraction of half width
  double bearing_rad;
};
constexpr std::array<Mount, kSonarCount> kMounts{{
    {1.0, 0.0, 0.0},
    {1.0, 0.0, 0.0},
    {1.0, 0.0, 0.0},
    {-1.0, 0.0, std::numbers::pi},
}};

double normaliseAngle(double a) {
  a = std::remainder(a, 2 * std::numbers::pi);
  return a <= -std::numbers::pi ? a + 2 * std::numbers::pi : a;
}

}  // namespace

Simulator::Simulator(SimulatorConfig config)
    : config_(std::move(config)), rng_(config_.seed), pose_(config_.start),
      gyro_rng_(config_.seed ^ 0x9e3779b97f4a7c15ULL) {
  sampleSonars();
}

void Simulator::command(const MotionCommand& command) {
  if (command.type != MotionType::Stop) neutral_since_s_ = -1.0;
  else if (neutral_since_s_ < 0) neutral_since_s_ = time_s_;  // a repeated stop holds since the first
  command_ = command;
  last_command_s_ = time_s_;
  deadman_tripped_ = false;
}

void Simulator::applyFault(const FaultCommand& fault) {
  const std::size_t i = fault.index;
  switch (fault.kind) {
    case FaultKind::SensorUnplugged:
      if (i < kSonarCount) sensor_state_[i] = SensorState::Unplugged;
      break;
    case FaultKind::SensorStuck:
      if (i < kSonarCount) {
        sensor_state_[i] = SensorState::Stuck;
        stuck_cm_[i] = fault.value;
      }
      break;
    case FaultKind::SensorOk:
      if (i < kSonarCount) sensor_state_[i] = SensorState::Ok;
      break;
    case FaultKind::MotorPowerOff:
      if (i < 2) powered_[i] = false;
      break;
    case FaultKind::MotorPowerOn: powered_ = {true, true}; break;
    case FaultKind::Noise: noise_sigma_cm_ = fault.value / 10.0; break;
    case FaultKind::EncoderDead:
      if (i < 2 && !encoder_dead_[i]) {
        encoder_frozen_[i] = encoder(static_cast<Wheel>(i));
        encoder_dead_[i] = true;
      }
      break;
    case FaultKind::EncoderOk:
      if (i < 2) encoder_dead_[i] = false;
      break;
    case FaultKind::GyroDead:
      gyro_dead_ = true;
      gyro_mrad_s_ = 0;
      break;
    case FaultKind::GyroOk: gyro_dead_ = false; break;
  }
  sampleSonars();  // a fault shows in the very next status frame
}

std::array<double, 2> wheelTargets(const MotionCommand& command, double max_rpm) {
  const double p = std::clamp<double>(command.parameter, -max_rpm, max_rpm);
  switch (command.type) {
    case MotionType::Stop: return {0.0, 0.0};
    case MotionType::Forward: return {p, p};
    case MotionType::Backward: return {-p, -p};
    case MotionType::TurnLeft: return {-p / 2, p / 2};  // in place, counter-clockwise
    case MotionType::TurnRight: return {p / 2, -p / 2};
  }
  return {0.0, 0.0};
}

double Simulator::targetRpm(Wheel wheel) const {
  if (!powered_[index(wheel)] || deadman_tripped_) return 0.0;
  return wheelTargets(command_, config_.max_rpm)[index(wheel)];
}

void Simulator::checkDeadman() {
  if (config_.deadman_ms <= 0 || deadman_tripped_) return;
  if (time_s_ - last_command_s_ >= config_.deadman_ms / 1000.0) {
    deadman_tripped_ = true;
    deadman_since_s_ = time_s_;
  }
}

void Simulator::step(double dt_s) {
  if (!(dt_s > 0.0)) return;
  time_s_ += dt_s;
  checkDeadman();
  const double decay = std::exp(-dt_s / config_.motor_time_constant_s);
  std::array<double, 2> distance_m{};
  for (Wheel wheel : {Wheel::Left, Wheel::Right}) {
    const std::size_t w = index(wheel);
    const double target = targetRpm(wheel);
    // ∫ rpm dt over the step for rpm(t) = target + (rpm0 − target)·e^(−t/τ).
    const double rev = (target * dt_s + (rpm_[w] - target) * config_.motor_time_constant_s * (1 - decay)) / 60.0;
    rpm_[w] = target + (rpm_[w] - target) * decay;
    encoder_counts_[w] += rev * config_.counts_per_revolution;
    distance_m[w] = rev * 2 * std::numbers::pi * config_.wheel_radius_m;
  }
  const double d = (distance_m[0] + distance_m[1]) / 2;
  const double dtheta = (distance_m[1] - distance_m[0]) / config_.track_width_m;
  const double mid = pose_.heading_rad + dtheta / 2;
  pose_.x_m += d * std::cos(mid);
  pose_.y_m += d * std::sin(mid);
  pose_.heading_rad = normaliseAngle(pose_.heading_rad + dtheta);
  std::normal_distribution<double> noise(0.0, config_.gyro_noise_rad_s);
  const double gyro = yawRate() + (config_.gyro_noise_rad_s > 0 ? noise(gyro_rng_) : 0.0);
  const long mrad_s = std::clamp(std::lround(gyro * 1000), -32767L, 32767L);
  gyro_mrad_s_ = gyro_dead_ ? std::int16_t{0} : static_cast<std::int16_t>(mrad_s);
  sampleSonars();
}

double Simulator::yawRate() const {
  const double to_m_s = 2 * std::numbers::pi * config_.wheel_radius_m / 60.0;  // rpm → m/s at the rim
  return (rpm_[1] - rpm_[0]) * to_m_s / config_.track_width_m;
}

std::int32_t Simulator::encoder(Wheel wheel) const {
  if (encoder_dead_[index(wheel)]) return encoder_frozen_[index(wheel)];
  const auto counts = static_cast<std::int64_t>(std::floor(encoder_counts_[index(wheel)]));
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(counts));  // a 32-bit counter wraps
}

StatusReport Simulator::status() const {
  StatusReport s{encoder(Wheel::Left), encoder(Wheel::Right), sonar_cm_};
  s.yaw_rate_mrad_s = gyro_mrad_s_;
  // The board's setpoints: its own, whether or not a driver has power.
  const std::array<double, 2> wanted = deadman_tripped_ ? std::array<double, 2>{}
                                                        : wheelTargets(command_, config_.max_rpm);
  for (std::size_t w = 0; w < 2; ++w) s.setpoint_rpm[w] = static_cast<std::int16_t>(std::lround(wanted[w]));
  return s;
}

double Simulator::rawRangeCm(std::size_t sonar) const {
  const Mount& m = kMounts[sonar];
  const double fwd = m.forward * config_.body_length_m / 2;
  const double left = m.left * config_.track_width_m / 2;
  const double c = std::cos(pose_.heading_rad), s = std::sin(pose_.heading_rad);
  const double x = pose_.x_m + c * fwd - s * left;
  const double y = pose_.y_m + s * fwd + c * left;
  const double heading = normaliseAngle(pose_.heading_rad + m.bearing_rad);
  if (!config_.ray_cast) return kFreeSpaceCm;
  // A sonar answers with its nearest echo within its beam: the minimum over rays spread evenly
  // across the cone (one ray when the cone is 0).
  const int rays = config_.sonar_half_angle_rad > 0 ? std::max(config_.sonar_beam_rays, 2) : 1;
  double nearest = kFreeSpaceCm;
  for (int k = 0; k < rays; ++k) {
    const double offset = rays == 1 ? 0.0 : config_.sonar_half_angle_rad * (2.0 * k / (rays - 1) - 1.0);
    nearest = std::min(nearest, config_.ray_cast(x, y, normaliseAngle(heading + offset)));
  }
  return nearest;
}

void Simulator::sampleSonars() {
  for (std::size_t i = 0; i < kSonarCount; ++i) {
    switch (sensor_state_[i]) {
      case SensorState::Unplugged: sonar_cm_[i] = 0; break;
      case SensorState::Stuck: sonar_cm_[i] = stuck_cm_[i]; break;
      case SensorState::Ok: {
        double cm = rawRangeCm(i);
        if (noise_sigma_cm_ > 0) cm += std::normal_distribution<double>(0.0, noise_sigma_cm_)(rng_);
        if (!std::isfinite(cm)) cm = kMaxRangeCm;
        sonar_cm_[i] = static_cast<std::uint16_t>(std::lround(std::clamp(cm, kMinRangeCm, kMaxRangeCm)));
        break;
      }
    }
  }
}

}  // namespace keel::robot
