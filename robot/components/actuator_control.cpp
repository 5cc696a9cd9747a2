// ActuatorControl; see actuator_control.hpp.
#include "robot/components/actuator_control.hpp"

#include <unistd.h>

#include <cmath>

#include "robot/motion_board/simulator.hpp"
#include "robot/sim/truth.hpp"

namespace keel::robot {
namespace {

MotionCommand toMotion(const std::array<double, 2>& c) {
  const long type = std::lround(c[0]);
  MotionCommand m;
  m.type = type >= 0 && type <= 4 ? static_cast<MotionType>(type) : MotionType::Stop;
  m.parameter = static_cast<std::int16_t>(std::lround(std::fmax(-32768.0, std::fmin(32767.0, c[1]))));
  return m;
}

}  // namespace

ReturnCode ActuatorControl::onInitialize() {
  BoardLinkConfig config;
  config.device = property<std::string>("device", "spawn");
  config.program = property<std::string>("board_program", "");
  config.sim.world = property<std::string>("world", "paper");
  config.sim.seed = static_cast<std::uint64_t>(property<std::int64_t>("seed", 1));
  config.sim.deadman_ms = static_cast<int>(property<std::int64_t>("deadman_ms", 300));
  config.sim.sonar_noise_cm = property<double>("sonar_noise_cm", 0.0);
  config.period_ms = static_cast<int>(property<std::int64_t>("frame_period_ms", 20));
  if (config.device == "spawn" || config.device == "inprocess")
    config.sim.truth_path = truthPath(property<std::string>("sim", "robot"), getpid());
  frame_s_ = config.period_ms / 1000.0;
  resend_ = std::chrono::milliseconds(property<std::int64_t>("resend_ms", 100));
  if (config.period_ms < 1) rejectProperty("frame_period_ms", "must be >= 1");
  if (config.sim.seed == 0) rejectProperty("seed", "must be >= 1");
  try {
    link_ = std::make_unique<BoardLink>(config);
  } catch (const std::exception& e) {
    rejectProperty("device", std::string("'") + config.device + "': motion board: " + e.what());
  }
  return ReturnCode::Ok;
}

ReturnCode ActuatorControl::onStart() {
  wanted_ = MotionCommand{};
  return sendMotion(MotionCommand{}) ? ReturnCode::Ok : ReturnCode::CallApiError;
}

ReturnCode ActuatorControl::onExecute() {
  for (const Frame& f : decoder_.feed(link_->receive()))
    if (const auto* s = std::get_if<StatusReport>(&f)) onStatus(*s);
  while (std::optional<std::array<double, 2>> c = command.pop()) wanted_ = toMotion(*c);
  const MotionCommand next = emergencyLatched() ? MotionCommand{} : wanted_;  // latched: neutral
  if (!(next == in_effect_) || std::chrono::steady_clock::now() - sent_at_ >= resend_) {
    if (!sendMotion(next)) return ReturnCode::CallApiError;
  }
  return ReturnCode::Ok;
}

void ActuatorControl::onStatus(const StatusReport& s) {
  sonars.push({static_cast<double>(s.sonar_cm[0]), static_cast<double>(s.sonar_cm[1]),
               static_cast<double>(s.sonar_cm[2]), static_cast<double>(s.sonar_cm[3])});
  encoders.push({static_cast<double>(s.left_encoder), static_cast<double>(s.right_encoder)});
  gyro.push(static_cast<double>(s.yaw_rate_mrad_s));
  left_setpoint.push(static_cast<double>(s.setpoint_rpm[0]));
  right_setpoint.push(static_cast<double>(s.setpoint_rpm[1]));
  if (last_status_) {
    // Encoders wrap at 32 bits: the difference in unsigned arithmetic is right across a wrap.
    const auto dl = static_cast<std::int32_t>(static_cast<std::uint32_t>(s.left_encoder) -
                                              static_cast<std::uint32_t>(last_status_->left_encoder));
    const auto dr = static_cast<std::int32_t>(static_cast<std::uint32_t>(s.right_encoder) -
                                              static_cast<std::uint32_t>(last_status_->right_encoder));
    const double per_count = 60.0 / (counts_per_rev_ * frame_s_);
    left_rpm.push(dl * per_count);
    right_rpm.push(dr * per_count);
    wheel_targets.push(wheelTargets(in_effect_, max_rpm_));
  }
  last_status_ = s;
}

bool ActuatorControl::sendMotion(const MotionCommand& c) {
  sent_at_ = std::chrono::steady_clock::now();
  in_effect_ = c;
  return link_->send(encode(c));
}

ReturnCode ActuatorControl::onStop() {
  wanted_ = MotionCommand{};
  return sendMotion(MotionCommand{}) ? ReturnCode::Ok : ReturnCode::CallApiError;
}

ReturnCode ActuatorControl::onReset() {
  last_status_.reset();  // the rpm estimate restarts from the next two frames
  decoder_ = Decoder{};
  wanted_ = MotionCommand{};
  return ReturnCode::Ok;
}

ReturnCode ActuatorControl::onDestroy() {
  if (link_) (void)link_->send(encode(MotionCommand{}));
  link_.reset();
  return ReturnCode::Ok;
}

ReturnCode ActuatorControl::onEmergencyStop() {
  // Straight to the board, whatever thread this runs on: the motors go to neutral now.
  return link_ && link_->send(encode(MotionCommand{})) ? ReturnCode::Ok : ReturnCode::CallApiError;
}

ReturnCode ActuatorControl::onHardwareFault(std::string_view command_text) {
  const std::optional<FaultCommand> fault = parseFaultCommand(command_text);
  if (!fault) return ReturnCode::BadInput;
  return link_ && link_->send(encode(*fault)) ? ReturnCode::Ok : ReturnCode::CallApiError;
}

std::vector<std::string> ActuatorControl::simulatedFaults() const {
  // A sonar that reads 0 is a range fault of its sensor component; a wheel without power is
  // seen by its encoder monitor and stops the robot; noise is what the voter masks. Not offered:
  // a stuck sonar reads plausibly, and two of them, which a random campaign would pick sooner or
  // later, outvote the third: a common-mode fault beyond the 2-of-3 voter the robot relies on.
  return {"sensor_unplugged 0",   "sensor_unplugged 1",    "sensor_unplugged 2",
          "motor_power_off left", "motor_power_off right", "noise 2"};
}

}  // namespace keel::robot
