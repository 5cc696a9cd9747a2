// Encoding and decoding of motion-board frames (little-endian fields, CRC-8/SMBUS), and the
// text form of fault commands. Pure code: no I/O, no globals.
#include "robot/motion_board/protocol.hpp"

#include <cmath>
#include <sstream>

namespace keel::robot {
namespace {

constexpr std::size_t kMotionLength = 3;   // motion_type u8, parameter i16
constexpr std::size_t kFaultLength = 4;    // kind u8, index u8, value u16
constexpr std::size_t kStatusLength = 22;  // left i32, right i32, 4 × sonar u16, gyro i16, 2 × setpoint i16

std::optional<std::size_t> payloadLength(std::uint8_t type) {
  switch (static_cast<FrameType>(type)) {
    case FrameType::MotionCommand: return kMotionLength;
    case FrameType::Fault: return kFaultLength;
    case FrameType::Status: return kStatusLength;
  }
  return std::nullopt;
}

void put16(std::vector<std::uint8_t>& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v & 0xFF));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
}

void put32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

std::uint16_t get16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }

std::uint32_t get32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

FrameType typeOf(const Frame& frame) {
  if (std::holds_alternative<MotionCommand>(frame)) return FrameType::MotionCommand;
  if (std::holds_alternative<FaultCommand>(frame)) return FrameType::Fault;
  return FrameType::Status;
}

void putPayload(std::vector<std::uint8_t>& out, const Frame& frame) {
  if (const auto* m = std::get_if<MotionCommand>(&frame)) {
    out.push_back(static_cast<std::uint8_t>(m->type));
    put16(out, static_cast<std::uint16_t>(m->parameter));
  } else if (const auto* f = std::get_if<FaultCommand>(&frame)) {
    out.push_back(static_cast<std::uint8_t>(f->kind));
    out.push_back(f->index);
    put16(out, f->value);
  } else {
    const auto& s = std::get<StatusReport>(frame);
    put32(out, static_cast<std::uint32_t>(s.left_encoder));
    put32(out, static_cast<std::uint32_t>(s.right_encoder));
    for (std::uint16_t cm : s.sonar_cm) put16(out, cm);
    put16(out, static_cast<std::uint16_t>(s.yaw_rate_mrad_s));
    for (std::int16_t rpm : s.setpoint_rpm) put16(out, static_cast<std::uint16_t>(rpm));
  }
}

bool validFault(const FaultCommand& f) {
  switch (f.kind) {
    case FaultKind::SensorUnplugged:
    case FaultKind::SensorStuck:
    case FaultKind::SensorOk: return f.index < kSonarCount;
    case FaultKind::MotorPowerOff:
    case FaultKind::EncoderDead:
    case FaultKind::EncoderOk: return f.index < 2;
    case FaultKind::MotorPowerOn:
    case FaultKind::Noise:
    case FaultKind::GyroDead:
    case FaultKind::GyroOk: return true;
  }
  return false;
}

/// The frame a checked payload holds, or nullopt if a field is out of range.
std::optional<Frame> parsePayload(FrameType type, const std::uint8_t* p) {
  switch (type) {
    case FrameType::MotionCommand:
      if (p[0] > static_cast<std::uint8_t>(MotionType::TurnRight)) return std::nullopt;
      return MotionCommand{static_cast<MotionType>(p[0]), static_cast<std::int16_t>(get16(p + 1))};
    case FrameType::Fault: {
      FaultCommand f{static_cast<FaultKind>(p[0]), p[1], get16(p + 2)};
      if (!validFault(f)) return std::nullopt;
      return f;
    }
    case FrameType::Status: {
      StatusReport s;
      s.left_encoder = static_cast<std::int32_t>(get32(p));
      s.right_encoder = static_cast<std::int32_t>(get32(p + 4));
      for (std::size_t i = 0; i < kSonarCount; ++i) s.sonar_cm[i] = get16(p + 8 + 2 * i);
      s.yaw_rate_mrad_s = static_cast<std::int16_t>(get16(p + 16));
      for (std::size_t i = 0; i < 2; ++i) s.setpoint_rpm[i] = static_cast<std::int16_t>(get16(p + 18 + 2 * i));
      return s;
    }
  }
  return std::nullopt;
}

}  // namespace

std::uint8_t crc8(std::span<const std::uint8_t> bytes) {
  std::uint8_t crc = 0;
  for (std::uint8_t byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) crc = static_cast<std::uint8_t>((crc & 0x80) ? (crc << 1) ^ 0x07 : crc << 1);
  }
  return crc;
}

std::vector<std::uint8_t> encode(const Frame& frame) {
  std::vector<std::uint8_t> out{kStartByte, static_cast<std::uint8_t>(typeOf(frame)), 0};
  putPayload(out, frame);
  out[2] = static_cast<std::uint8_t>(out.size() - 3);
  out.push_back(crc8(std::span(out).subspan(1)));
  return out;
}

std::vector<Frame> Decoder::feed(std::span<const std::uint8_t> bytes) {
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  std::vector<Frame> frames;
  std::size_t pos = 0;
  auto reject = [&](std::uint64_t& counter) {
    ++counter;
    ++stats_.skipped_bytes;
    ++pos;  // drop the start byte only; rescan what followed it
  };
  for (;;) {
    while (pos < buffer_.size() && buffer_[pos] != kStartByte) {
      ++pos;
      ++stats_.skipped_bytes;
    }
    const std::size_t avail = buffer_.size() - pos;
    if (avail < 2) break;
    const auto length = payloadLength(buffer_[pos + 1]);
    if (!length) {
      reject(stats_.unknown_type);
      continue;
    }
    if (avail < 3) break;
    if (buffer_[pos + 2] != *length) {
      reject(stats_.bad_length);
      continue;
    }
    if (avail < kFrameOverhead + *length) break;
    const std::uint8_t expected = crc8(std::span(buffer_).subspan(pos + 1, 2 + *length));
    if (buffer_[pos + 3 + *length] != expected) {
      reject(stats_.bad_checksum);
      continue;
    }
    auto frame = parsePayload(static_cast<FrameType>(buffer_[pos + 1]), &buffer_[pos + 3]);
    if (!frame) {
      reject(stats_.bad_content);
      continue;
    }
    frames.push_back(*frame);
    ++stats_.frames;
    pos += kFrameOverhead + *length;
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(pos));
  return frames;
}

std::optional<FaultCommand> parseFaultCommand(std::string_view text) {
  std::istringstream in{std::string(text)};
  std::string verb;
  in >> verb;
  auto sonarIndex = [&]() -> std::optional<std::uint8_t> {
    int i = -1;
    if (!(in >> i) || i < 0 || i >= static_cast<int>(kSonarCount)) return std::nullopt;
    return static_cast<std::uint8_t>(i);
  };
  std::optional<FaultCommand> out;
  if (verb == "sensor_unplugged" || verb == "sensor_ok") {
    if (auto i = sonarIndex())
      out = FaultCommand{verb == "sensor_ok" ? FaultKind::SensorOk : FaultKind::SensorUnplugged, *i, 0};
  } else if (verb == "sensor_stuck") {
    auto i = sonarIndex();
    long value = -1;
    if (i && (in >> value) && value >= 0 && value <= 0xFFFF)
      out = FaultCommand{FaultKind::SensorStuck, *i, static_cast<std::uint16_t>(value)};
  } else if (verb == "motor_power_off" || verb == "encoder_dead" || verb == "encoder_ok") {
    std::string side;
    in >> side;
    const FaultKind kind = verb == "motor_power_off" ? FaultKind::MotorPowerOff
                           : verb == "encoder_dead"  ? FaultKind::EncoderDead
                                                     : FaultKind::EncoderOk;
    if (side == "left" || side == "right") out = FaultCommand{kind, static_cast<std::uint8_t>(side == "right"), 0};
  } else if (verb == "gyro_dead" || verb == "gyro_ok") {
    out = FaultCommand{verb == "gyro_dead" ? FaultKind::GyroDead : FaultKind::GyroOk, 0, 0};
  } else if (verb == "motor_power_on") {
    out = FaultCommand{FaultKind::MotorPowerOn, 0, 0};
  } else if (verb == "noise") {
    double sigma_cm = -1;
    if ((in >> sigma_cm) && sigma_cm >= 0 && sigma_cm * 10 <= 0xFFFF)
      out = FaultCommand{FaultKind::Noise, 0, static_cast<std::uint16_t>(std::lround(sigma_cm * 10))};
  }
  std::string rest;
  if (out && (in >> rest)) return std::nullopt;  // trailing words
  return out;
}

std::string toString(const FaultCommand& fault) {
  const std::string index = std::to_string(fault.index);
  switch (fault.kind) {
    case FaultKind::SensorUnplugged: return "sensor_unplugged " + index;
    case FaultKind::SensorStuck: return "sensor_stuck " + index + " " + std::to_string(fault.value);
    case FaultKind::SensorOk: return "sensor_ok " + index;
    case FaultKind::MotorPowerOff: return fault.index == 0 ? "motor_power_off left" : "motor_power_off right";
    case FaultKind::MotorPowerOn: return "motor_power_on";
    case FaultKind::EncoderDead: return fault.index == 0 ? "encoder_dead left" : "encoder_dead right";
    case FaultKind::EncoderOk: return fault.index == 0 ? "encoder_ok left" : "encoder_ok right";
    case FaultKind::GyroDead: return "gyro_dead";
    case FaultKind::GyroOk: return "gyro_ok";
    case FaultKind::Noise: {
      std::ostringstream out;
      out << "noise " << fault.value / 10.0;
      return out.str();
    }
  }
  return "unknown_fault " + std::to_string(static_cast<int>(fault.kind));
}

}  // namespace keel::robot
