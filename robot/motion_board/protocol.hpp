// The byte protocol between the main board and the motion board of the test robot (paper
// Table 3; docs/motion_board_protocol.md): the frame types, their encoding, and an incremental
// decoder that resynchronises after garbage. Used by the motion-board simulator (Board) and by
// whatever speaks to it (the actuator component, the test harness). Touches no I/O.
// Thread-safety: free functions are pure; a Decoder is confined to one thread.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace keel::robot {

/// Every frame: kStartByte, type, length, payload[length], CRC-8 over type..payload.
inline constexpr std::uint8_t kStartByte = 0xA5;
inline constexpr std::size_t kFrameOverhead = 4;  // start, type, length, checksum

enum class FrameType : std::uint8_t {
  MotionCommand = 0x01,  // main → motion: what the wheels should do
  Fault = 0x02,          // test harness → motion: inject a hardware fault (simulator only)
  Status = 0x81,         // motion → main: encoders, sonars, gyro and setpoints, once per period
};

/// Table 3 `motion_type`.
enum class MotionType : std::uint8_t { Stop = 0, Forward = 1, Backward = 2, TurnLeft = 3, TurnRight = 4 };

struct MotionCommand {
  MotionType type = MotionType::Stop;
  /// rpm of both wheels (Forward/Backward), or right − left rpm difference (turns, in place).
  std::int16_t parameter = 0;
  bool operator==(const MotionCommand&) const = default;
};

/// Sonar order in a status frame and in fault indices: a triple-redundant forward rangefinder
/// (three sonars side by side on the front bumper, for the voting experiment) and one looking
/// back (docs/motion_board_protocol.md).
enum class SonarId : std::uint8_t { FrontA = 0, FrontB = 1, FrontC = 2, Back = 3 };
inline constexpr std::size_t kSonarCount = 4;

struct StatusReport {
  std::int32_t left_encoder = 0;                      // counts, wrapping
  std::int32_t right_encoder = 0;                     // counts, wrapping
  std::array<std::uint16_t, kSonarCount> sonar_cm{};  // 3..3000, 0 = unplugged / no echo
  std::int16_t yaw_rate_mrad_s = 0;                   // the gyro: mrad/s, counter-clockwise positive
  /// The (left, right) wheel speeds the board drove toward during the period, rpm: the command's,
  /// or 0 while its deadman holds the motors. A driver without power does not change them.
  std::array<std::int16_t, 2> setpoint_rpm{};
  bool operator==(const StatusReport&) const = default;
};

/// Hardware faults the simulator takes on command (never sent by the main board).
enum class FaultKind : std::uint8_t {
  SensorUnplugged = 1,  // index = sonar; it reads 0
  SensorStuck = 2,      // index = sonar, value = the reading in cm it is stuck at
  MotorPowerOff = 3,    // index = 0 left, 1 right; the wheel coasts down
  MotorPowerOn = 4,     // both drivers powered again (index ignored)
  Noise = 5,            // value = Gaussian sigma in mm (tenths of a cm) on every healthy sonar
  SensorOk = 6,         // index = sonar; clears unplugged / stuck
  EncoderDead = 7,      // index = 0 left, 1 right; its count stops: it reads 0 rpm while the wheel turns
  EncoderOk = 8,        // index = 0 left, 1 right; counts again
  GyroDead = 9,         // it reads 0 (index ignored)
  GyroOk = 10,          // it reads the yaw rate again (index ignored)
};

struct FaultCommand {
  FaultKind kind = FaultKind::MotorPowerOn;
  std::uint8_t index = 0;
  std::uint16_t value = 0;
  bool operator==(const FaultCommand&) const = default;
};

using Frame = std::variant<MotionCommand, StatusReport, FaultCommand>;

/// CRC-8, polynomial 0x07, initial value 0x00, no reflection, no final xor (CRC-8/SMBUS).
[[nodiscard]] std::uint8_t crc8(std::span<const std::uint8_t> bytes);

/// The complete frame, start byte to checksum.
[[nodiscard]] std::vector<std::uint8_t> encode(const Frame& frame);

/// The harness's text form: `sensor_unplugged 1`, `sensor_stuck 2 150`, `sensor_ok 1`,
/// `motor_power_off left|right`, `motor_power_on`, `noise 2.5` (sigma in cm),
/// `encoder_dead left|right`, `encoder_ok left|right`, `gyro_dead`, `gyro_ok`. nullopt if invalid.
[[nodiscard]] std::optional<FaultCommand> parseFaultCommand(std::string_view text);
[[nodiscard]] std::string toString(const FaultCommand& fault);

struct DecoderStats {
  std::uint64_t frames = 0;         // accepted
  std::uint64_t bad_checksum = 0;   // a well-formed header whose CRC did not match
  std::uint64_t bad_length = 0;     // known type, wrong length byte
  std::uint64_t unknown_type = 0;   // start byte followed by a type we do not know
  std::uint64_t bad_content = 0;    // valid CRC but a field out of range (e.g. motion_type 7)
  std::uint64_t skipped_bytes = 0;  // bytes that were not part of an accepted frame
};

/// Incremental decoder: feed any chunks, get whole frames back. After a rejected header or
/// checksum it drops the start byte only and rescans, so a good frame right after garbage is
/// never lost. Buffers at most one frame's worth of bytes.
class Decoder {
 public:
  [[nodiscard]] std::vector<Frame> feed(std::span<const std::uint8_t> bytes);
  [[nodiscard]] const DecoderStats& stats() const { return stats_; }

 private:
  std::vector<std::uint8_t> buffer_;
  DecoderStats stats_;
};

}  // namespace keel::robot
