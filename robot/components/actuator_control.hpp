// ActuatorControl: the test robot's actuator component (paper Fig. 5), the only one that talks
// to the motion board, over its serial protocol (docs/motion_board_protocol.md). Each cycle it
// reads the board's status frames — publishing the raw sonar ranges, each wheel's rpm measured
// from the encoders and the wheel targets in effect (for the reference model) — and sends the
// planner's latest command, re-sent before the board's deadman expires. onStop and
// onEmergencyStop put the motors in neutral (stop); while an emergency is latched no other
// command is sent. Hardware faults from a fault scenario go to the board (onHardwareFault).
// Thread-safety: a component; onHardwareFault and onEmergencyStop may run on other threads
// (the link's send is locked; the latch is the framework's).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <keel/component.hpp>
#include <keel/hardware_driver.hpp>

#include "robot/components/board_link.hpp"
#include "robot/components/robot_types.hpp"
#include "robot/motion_board/protocol.hpp"

namespace keel::robot {

class ActuatorControl : public Component, public HardwareDriver {
 public:
  /// The planner's command: {motion_type, parameter} as in the protocol's motion frame.
  InputDataPort<std::array<double, 2>> command{this, "command"};
  /// The four sonar readings of the newest status frame, in cm (0: unplugged).
  OutputDataPort<std::array<double, 4>> sonars{this, "sonars"};
  /// Wheel speeds measured from the encoders, one sample per status frame.
  OutputDataPort<double> left_rpm{this, "left_rpm"};
  OutputDataPort<double> right_rpm{this, "right_rpm"};
  /// The (left, right) wheel targets the command in effect asked for, one per status frame.
  OutputDataPort<std::array<double, 2>> wheel_targets{this, "wheel_targets"};
  /// The raw odometry of every status frame, for the sensors' own components (WheelEncoder,
  /// RateGyro): the (left, right) encoder counts, and the gyro's reading in mrad/s.
  OutputDataPort<std::array<double, 2>> encoders{this, "encoders"};
  OutputDataPort<double> gyro{this, "gyro"};
  /// The wheel speeds the board drove toward during each frame (its setpoints, rpm, as it
  /// reports them): a model's inputs, frame for frame.
  OutputDataPort<double> left_setpoint{this, "left_setpoint"};
  OutputDataPort<double> right_setpoint{this, "right_setpoint"};

  ReturnCode onInitialize() override;
  ReturnCode onStart() override;
  ReturnCode onExecute() override;
  ReturnCode onStop() override;
  ReturnCode onReset() override;
  ReturnCode onDestroy() override;
  ReturnCode onEmergencyStop() override;
  ReturnCode onHardwareFault(std::string_view command_text) override;
  std::vector<std::string> simulatedFaults() const override;

 private:
  void onStatus(const StatusReport& status);
  bool sendMotion(const MotionCommand& c);

  std::unique_ptr<BoardLink> link_;
  Decoder decoder_;
  double frame_s_ = 0.02;
  std::chrono::milliseconds resend_{100};
  double max_rpm_ = 300.0;
  int counts_per_rev_ = 360;
  std::optional<StatusReport> last_status_;
  MotionCommand in_effect_{};
  MotionCommand wanted_{};
  std::chrono::steady_clock::time_point sent_at_{};
};

}  // namespace keel::robot
