// The simulated motion board (robot/motion_board): protocol framing and the decoder's resync,
// the physics (encoders, pose, motor inertia, deadman), sonar faults and noise, the Board behind
// its byte stream, and keel_motion_board served on a pseudo-terminal.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "robot/motion_board/board.hpp"
#include "robot/sim/sim_host.hpp"
#include "robot/sim/truth.hpp"
#include "robot/world/world.hpp"
#include "support/paths.hpp"

namespace keel::robot {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr double kDt = 0.001;

/// Steps `sim` for `seconds`, re-sending `command` every 100 ms if given (as a main board does).
void runFor(Simulator& sim, double seconds, const MotionCommand* command = nullptr) {
  const int steps = static_cast<int>(std::lround(seconds / kDt));
  for (int i = 0; i < steps; ++i) {
    if (command && i % 100 == 0) sim.command(*command);
    sim.step(kDt);
  }
}

std::vector<Frame> decodeAll(const Bytes& bytes) {
  Decoder decoder;
  return decoder.feed(bytes);
}

// ---- protocol ------------------------------------------------------------------------------

TEST(MotionBoardProtocol, EveryFrameTypeRoundTrips) {
  const std::vector<Frame> frames{
      MotionCommand{MotionType::Stop, 0},
      MotionCommand{MotionType::Forward, 120},
      MotionCommand{MotionType::Backward, -32768},
      MotionCommand{MotionType::TurnLeft, 40},
      MotionCommand{MotionType::TurnRight, 32767},
      StatusReport{-5, 2147483647, {3, 0, 3000, 65535}},
      StatusReport{std::numeric_limits<std::int32_t>::min(), 0, {}},
      FaultCommand{FaultKind::SensorUnplugged, 3, 0},
      FaultCommand{FaultKind::SensorStuck, 1, 150},
      FaultCommand{FaultKind::MotorPowerOff, 1, 0},
      FaultCommand{FaultKind::MotorPowerOn, 0, 0},
      FaultCommand{FaultKind::Noise, 0, 25},
      FaultCommand{FaultKind::SensorOk, 2, 0},
  };
  for (const Frame& frame : frames) {
    const Bytes bytes = encode(frame);
    ASSERT_EQ(bytes.front(), kStartByte);
    ASSERT_EQ(bytes[2] + kFrameOverhead, bytes.size());
    const auto decoded = decodeAll(bytes);
    ASSERT_EQ(decoded.size(), 1u);
    EXPECT_EQ(decoded[0], frame);
  }
}

TEST(MotionBoardProtocol, FieldsAreLittleEndianWithCrc8Smbus) {
  const Bytes bytes = encode(MotionCommand{MotionType::Forward, 0x0102});
  EXPECT_EQ(bytes, (Bytes{0xA5, 0x01, 0x03, 0x01, 0x02, 0x01, crc8(Bytes{0x01, 0x03, 0x01, 0x02, 0x01})}));
  EXPECT_EQ(crc8(Bytes{'1', '2', '3', '4', '5', '6', '7', '8', '9'}), 0xF4);  // CRC-8/SMBUS check value
}

TEST(MotionBoardProtocol, FramesSplitAcrossChunksAreReassembled) {
  const Bytes bytes = encode(StatusReport{1, 2, {3, 4, 5, 6}});
  Decoder decoder;
  std::vector<Frame> got;
  for (std::uint8_t b : bytes) {
    EXPECT_TRUE(got.empty());
    for (auto& f : decoder.feed(Bytes{b})) got.push_back(f);
  }
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0], (Frame{StatusReport{1, 2, {3, 4, 5, 6}}}));
}

TEST(MotionBoardProtocol, DecoderResynchronisesAfterGarbageAndCountsBadChecksum) {
  std::mt19937_64 rng(7);
  Bytes stream;
  for (int i = 0; i < 64; ++i) stream.push_back(static_cast<std::uint8_t>(rng()));
  stream.push_back(kStartByte);  // a truncated header inside the garbage
  Bytes corrupt = encode(MotionCommand{MotionType::Forward, 100});
  corrupt.back() ^= 0x5A;
  stream.insert(stream.end(), corrupt.begin(), corrupt.end());
  const Bytes good = encode(MotionCommand{MotionType::TurnLeft, 30});
  stream.insert(stream.end(), good.begin(), good.end());

  Decoder decoder;
  const auto frames = decoder.feed(stream);

  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0], (Frame{MotionCommand{MotionType::TurnLeft, 30}}));
  EXPECT_EQ(decoder.stats().bad_checksum, 1u);
  EXPECT_EQ(decoder.stats().frames, 1u);
  EXPECT_GE(decoder.stats().skipped_bytes, 64u + corrupt.size());
}

TEST(MotionBoardProtocol, WrongLengthAndOutOfRangeFieldsAreRejectedAndCounted) {
  Bytes wrong_length = encode(MotionCommand{MotionType::Forward, 1});
  wrong_length[2] = 4;
  Bytes bad_type{0xA5, 0x01, 0x03, 0x07, 0x00, 0x00};  // motion_type 7, valid CRC
  bad_type.push_back(crc8(std::span(bad_type).subspan(1)));
  Bytes bad_sonar{0xA5, 0x02, 0x04, 0x01, 0x04, 0x00, 0x00};  // unplug sonar 4 of 0..3
  bad_sonar.push_back(crc8(std::span(bad_sonar).subspan(1)));

  Decoder decoder;
  EXPECT_TRUE(decoder.feed(wrong_length).empty());
  EXPECT_TRUE(decoder.feed(bad_type).empty());
  EXPECT_TRUE(decoder.feed(bad_sonar).empty());

  EXPECT_EQ(decoder.stats().bad_length, 1u);
  EXPECT_EQ(decoder.stats().bad_content, 2u);
  EXPECT_EQ(decoder.stats().frames, 0u);
}

TEST(MotionBoardProtocol, RandomChunksNeverCrashAndOnlyIntactFramesComeOut) {
  std::mt19937_64 rng(2024);
  auto byte = [&] { return static_cast<std::uint8_t>(rng()); };
  auto randomFrame = [&]() -> Frame {
    switch (rng() % 3) {
      case 0: return MotionCommand{static_cast<MotionType>(rng() % 5), static_cast<std::int16_t>(rng())};
      case 1:
        return StatusReport{static_cast<std::int32_t>(rng()),
                            static_cast<std::int32_t>(rng()),
                            {static_cast<std::uint16_t>(rng()), 0, 3, 3000}};
      default:
        return FaultCommand{static_cast<FaultKind>(1 + rng() % 6), static_cast<std::uint8_t>(rng() % 2),
                            static_cast<std::uint16_t>(rng())};
    }
  };
  Decoder decoder;
  std::vector<Frame> sent, received;
  std::uint64_t corrupted = 0;
  for (int chunk = 0; chunk < 10'000; ++chunk) {
    Bytes bytes(rng() % 48);
    for (auto& b : bytes) b = byte();
    if (rng() % 2 == 0) {  // half the chunks carry a frame, some of them with one byte damaged
      const Frame frame = randomFrame();
      Bytes encoded = encode(frame);
      if (rng() % 4 == 0) {
        encoded[1 + rng() % (encoded.size() - 1)] ^= static_cast<std::uint8_t>(1 + rng() % 255);
        ++corrupted;
      } else {
        sent.push_back(frame);
      }
      bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(rng() % (bytes.size() + 1)), encoded.begin(),
                   encoded.end());
    }
    for (auto& f : decoder.feed(bytes)) received.push_back(f);
  }
  // Every intact frame, in order, and nothing else: a damaged byte always fails CRC-8 (it
  // catches every error burst up to 8 bits), and random garbage never made a valid frame here.
  EXPECT_EQ(received, sent);
  EXPECT_GT(corrupted, 0u);
  const auto& s = decoder.stats();
  EXPECT_GT(s.bad_checksum + s.bad_length + s.unknown_type, 0u);
  EXPECT_EQ(s.frames, sent.size());
}

TEST(MotionBoardProtocol, FaultCommandsParseFromTheirTextForm) {
  EXPECT_EQ(parseFaultCommand("sensor_unplugged 2"), (FaultCommand{FaultKind::SensorUnplugged, 2, 0}));
  EXPECT_EQ(parseFaultCommand("sensor_stuck 1 150"), (FaultCommand{FaultKind::SensorStuck, 1, 150}));
  EXPECT_EQ(parseFaultCommand("motor_power_off left"), (FaultCommand{FaultKind::MotorPowerOff, 0, 0}));
  EXPECT_EQ(parseFaultCommand("motor_power_off right"), (FaultCommand{FaultKind::MotorPowerOff, 1, 0}));
  EXPECT_EQ(parseFaultCommand("motor_power_on"), (FaultCommand{FaultKind::MotorPowerOn, 0, 0}));
  EXPECT_EQ(parseFaultCommand("noise 2.5"), (FaultCommand{FaultKind::Noise, 0, 25}));
  for (const char* bad :
       {"sensor_unplugged 4", "sensor_stuck 1", "motor_power_off up", "noise -1", "motor_power_on now", "explode", ""})
    EXPECT_EQ(parseFaultCommand(bad), std::nullopt) << bad;
  for (const char* text : {"sensor_stuck 3 42", "motor_power_off right", "noise 2.5", "sensor_ok 0"})
    EXPECT_EQ(toString(*parseFaultCommand(text)), text);
}

// ---- physics -------------------------------------------------------------------------------

TEST(MotionBoardSimulator, ForwardAdvancesBothEncodersAtTheCommandedRate) {
  Simulator sim;
  const MotionCommand forward{MotionType::Forward, 60};  // 1 rev/s = 360 counts/s
  runFor(sim, 1.0, &forward);                            // past the motor lag (τ = 150 ms)
  const auto left0 = sim.encoder(Wheel::Left), right0 = sim.encoder(Wheel::Right);
  const double x0 = sim.pose().x_m;

  runFor(sim, 1.0, &forward);

  EXPECT_NEAR(sim.encoder(Wheel::Left) - left0, 360, 4);
  EXPECT_NEAR(sim.encoder(Wheel::Right) - right0, 360, 4);
  EXPECT_NEAR(sim.pose().x_m - x0, 2 * std::numbers::pi * 0.0325, 0.002);  // one wheel turn
  EXPECT_NEAR(sim.pose().y_m, 0.0, 1e-9);
  EXPECT_NEAR(sim.pose().heading_rad, 0.0, 1e-9);
}

TEST(MotionBoardSimulator, BackwardRunsTheEncodersDown) {
  Simulator sim;
  const MotionCommand backward{MotionType::Backward, 60};
  runFor(sim, 1.0, &backward);
  EXPECT_LT(sim.encoder(Wheel::Left), -200);
  EXPECT_LT(sim.encoder(Wheel::Right), -200);
  EXPECT_LT(sim.pose().x_m, -0.1);
}

TEST(MotionBoardSimulator, TurnsInPlaceInTheCommandedDirection) {
  Simulator left_sim, right_sim;
  const MotionCommand left{MotionType::TurnLeft, 40}, right{MotionType::TurnRight, 40};
  runFor(left_sim, 0.5, &left);
  runFor(right_sim, 0.5, &right);

  EXPECT_GT(left_sim.pose().heading_rad, 0.1);  // counter-clockwise
  EXPECT_LT(right_sim.pose().heading_rad, -0.1);
  EXPECT_NEAR(left_sim.pose().heading_rad, -right_sim.pose().heading_rad, 1e-9);
  EXPECT_NEAR(left_sim.pose().x_m, 0.0, 1e-9);  // in place
  EXPECT_GT(left_sim.encoder(Wheel::Right), 0);
  EXPECT_LT(left_sim.encoder(Wheel::Left), 0);
}

TEST(MotionBoardSimulator, LeftDriverPowerOffDecaysTheLeftWheelWhileTheRightHolds) {
  Simulator sim;
  const MotionCommand forward{MotionType::Forward, 100};
  runFor(sim, 1.0, &forward);
  ASSERT_NEAR(sim.wheelRpm(Wheel::Left), 100, 1);

  sim.applyFault(*parseFaultCommand("motor_power_off left"));
  runFor(sim, 0.05, &forward);
  EXPECT_GT(sim.wheelRpm(Wheel::Left), 50);  // inertia: not at once (paper Fig. 6)
  EXPECT_LT(sim.wheelRpm(Wheel::Left), 95);  // but already falling
  runFor(sim, 0.95, &forward);
  EXPECT_LT(sim.wheelRpm(Wheel::Left), 5);
  EXPECT_NEAR(sim.wheelRpm(Wheel::Right), 100, 1);
  EXPECT_GT(sim.pose().heading_rad, 0.1);  // the right wheel drives it round to the left

  sim.applyFault(*parseFaultCommand("motor_power_on"));
  runFor(sim, 1.0, &forward);
  EXPECT_NEAR(sim.wheelRpm(Wheel::Left), 100, 1);
}

TEST(MotionBoardSimulator, DeadmanStopsTheMotorsWhenCommandsStop) {
  Simulator sim;  // deadman 300 ms
  const MotionCommand forward{MotionType::Forward, 100};
  runFor(sim, 1.0, &forward);  // re-sent every 100 ms: keeps running
  ASSERT_FALSE(sim.deadmanTripped());
  ASSERT_EQ(sim.targetRpm(Wheel::Left), 100);

  sim.command(forward);  // the last one
  runFor(sim, 0.25);     // silence, inside the window
  EXPECT_FALSE(sim.deadmanTripped());
  EXPECT_EQ(sim.targetRpm(Wheel::Right), 100);
  runFor(sim, 1.25);  // silence past it
  EXPECT_TRUE(sim.deadmanTripped());
  EXPECT_EQ(sim.targetRpm(Wheel::Left), 0);
  EXPECT_LT(std::abs(sim.wheelRpm(Wheel::Left)), 1);
  EXPECT_LT(std::abs(sim.wheelRpm(Wheel::Right)), 1);

  sim.command(forward);  // a new command re-arms it
  EXPECT_FALSE(sim.deadmanTripped());
  EXPECT_EQ(sim.targetRpm(Wheel::Left), 100);
}

// The referee's collision count comes from here: driven straight into obstacle A, the body
// touches it once — one episode however long it keeps pushing — and the clearance falls to 0.
TEST(SimHost, CountsOneCollisionPerEpisodeOfTheBodyInAnObstacle) {
  SimHost host(SimHostConfig{});
  const MotionCommand forward{MotionType::Forward, 200};
  EXPECT_GT(host.truth().clearance_m, 0.2);                         // clear of everything at the start
  for (int i = 0; i < 1000 && host.truth().collisions == 0; ++i) {  // 20 s at most
    if (i % 5 == 0) host.onBytes(encode(forward));
    (void)host.step(0.020);
  }
  ASSERT_EQ(host.truth().collisions, 1.0) << "never hit obstacle A";
  EXPECT_EQ(host.truth().clearance_m, 0.0);
  EXPECT_EQ(host.truth().min_clearance_m, 0.0);
  for (int i = 0; i < 50; ++i) {  // pushing on: the same episode
    if (i % 5 == 0) host.onBytes(encode(forward));
    (void)host.step(0.020);
  }
  EXPECT_EQ(host.truth().collisions, 1.0);
}

// What holds the motors, for the referee: the main board's stop (held since the first of a
// repeated stop) or the deadman (since it tripped), each -1 while it does not.
TEST(MotionBoardSimulator, TellsSinceWhenAStopCommandAndSinceWhenTheDeadmanHoldTheMotors) {
  Simulator sim;  // deadman 300 ms
  EXPECT_EQ(sim.neutralSinceS(), -1.0) << "nothing commanded yet";
  const MotionCommand forward{MotionType::Forward, 100}, stop{MotionType::Stop, 0};
  runFor(sim, 1.0, &forward);
  EXPECT_EQ(sim.neutralSinceS(), -1.0);
  EXPECT_EQ(sim.deadmanSinceS(), -1.0);

  const double stopped_at = sim.timeS();
  runFor(sim, 0.2, &stop);  // sent at once, then again after 100 ms: held since the first
  EXPECT_DOUBLE_EQ(sim.neutralSinceS(), stopped_at);
  EXPECT_EQ(sim.deadmanSinceS(), -1.0);
  runFor(sim, 0.5);  // silence: the deadman trips too, after the stop
  EXPECT_DOUBLE_EQ(sim.neutralSinceS(), stopped_at);
  EXPECT_GT(sim.deadmanSinceS(), stopped_at + 0.29);

  sim.command(forward);
  EXPECT_EQ(sim.neutralSinceS(), -1.0);
  EXPECT_EQ(sim.deadmanSinceS(), -1.0);
  runFor(sim, 0.5);  // silent while moving: only the deadman holds the motors
  EXPECT_EQ(sim.neutralSinceS(), -1.0);
  EXPECT_GT(sim.deadmanSinceS(), 0.0);
}

// ---- sonars --------------------------------------------------------------------------------

TEST(MotionBoardSimulator, SonarsReadTheRayCastClampedToTheValidRange) {
  SimulatorConfig config;
  double range = 120.4;
  config.ray_cast = [&](double, double, double) { return range; };
  Simulator sim(config);
  sim.step(kDt);
  EXPECT_EQ(sim.sonarCm(SonarId::FrontA), 120);
  range = 1.0;
  sim.step(kDt);
  EXPECT_EQ(sim.sonarCm(SonarId::FrontB), 3);
  range = 1e9;
  sim.step(kDt);
  EXPECT_EQ(sim.sonarCm(SonarId::Back), 3000);
  EXPECT_EQ(Simulator{}.sonarCm(SonarId::FrontC), 3000);  // default: free space
}

TEST(MotionBoardSimulator, TheThreeFrontSonarsLookAheadFromTheNoseAndTheFourthBack) {
  SimulatorConfig config;  // a wall at x = 1 m straight ahead only
  config.ray_cast = [](double x, double, double heading) {
    return std::abs(heading) < 1e-9 ? (1.0 - x) * 100 : kFreeSpaceCm;
  };
  Simulator sim(config);
  for (SonarId front : {SonarId::FrontA, SonarId::FrontB, SonarId::FrontC})
    EXPECT_EQ(sim.sonarCm(front), std::lround((1.0 - 0.105) * 100));
  EXPECT_EQ(sim.sonarCm(SonarId::Back), 3000);
}

TEST(MotionBoardSimulator, ASonarAnswersWithTheNearestEchoWithinItsBeam) {
  auto echoAt = [](double bearing_lo, double bearing_hi) {
    SimulatorConfig config;  // something 50 cm away, seen only between two bearings
    config.ray_cast = [=](double, double, double heading) {
      return heading >= bearing_lo && heading <= bearing_hi ? 50.0 : kFreeSpaceCm;
    };
    return Simulator(config).sonarCm(SonarId::FrontB);
  };
  EXPECT_EQ(echoAt(0.15, 0.20), 50);    // inside the ±15° beam, off its axis
  EXPECT_EQ(echoAt(-0.20, -0.15), 50);  // the other side
  EXPECT_EQ(echoAt(0.30, 0.40), 3000);  // outside the beam
  SimulatorConfig narrow;
  narrow.sonar_half_angle_rad = 0.0;  // a single ray
  narrow.ray_cast = [](double, double, double heading) { return heading > 0.1 ? 50.0 : kFreeSpaceCm; };
  EXPECT_EQ(Simulator(narrow).sonarCm(SonarId::FrontB), 3000);
}

TEST(MotionBoardSimulator, UnpluggedSonarReadsZeroAndStuckSonarReadsItsValue) {
  SimulatorConfig config;
  config.ray_cast = [](double, double, double) { return 200.0; };
  Simulator sim(config);
  sim.applyFault(*parseFaultCommand("sensor_unplugged 1"));
  sim.applyFault(*parseFaultCommand("sensor_stuck 2 77"));
  runFor(sim, 0.1);

  EXPECT_EQ(sim.status().sonar_cm, (std::array<std::uint16_t, 4>{200, 0, 77, 200}));

  sim.applyFault(*parseFaultCommand("sensor_ok 1"));
  sim.applyFault(*parseFaultCommand("sensor_ok 2"));
  EXPECT_EQ(sim.status().sonar_cm, (std::array<std::uint16_t, 4>{200, 200, 200, 200}));
}

std::vector<std::uint16_t> noisyFrontReadings(std::uint64_t seed) {
  SimulatorConfig config;
  config.seed = seed;
  config.ray_cast = [](double, double, double) { return 100.0; };
  Simulator sim(config);
  sim.applyFault(*parseFaultCommand("noise 2"));
  std::vector<std::uint16_t> readings;
  for (int i = 0; i < 200; ++i) {
    sim.step(kDt);
    readings.push_back(sim.sonarCm(SonarId::FrontA));
  }
  return readings;
}

TEST(MotionBoardSimulator, NoiseVariesReadingsButSeededRunsAreIdentical) {
  const auto a = noisyFrontReadings(11), b = noisyFrontReadings(11), c = noisyFrontReadings(12);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  const auto [lo, hi] = std::minmax_element(a.begin(), a.end());
  EXPECT_LT(*lo, 100);
  EXPECT_GT(*hi, 100);
  double mean = 0;
  for (auto v : a) mean += v;
  EXPECT_NEAR(mean / a.size(), 100, 1.0);  // σ/√200 ≈ 0.14 cm: 7σ of slack
}

// ---- the board behind its byte stream ------------------------------------------------------

TEST(MotionBoardBoard, CommandBytesInStatusFramesOut) {
  Board board;
  Bytes in{0x00, 0x13, 0xA5};  // line noise first
  const Bytes cmd = encode(MotionCommand{MotionType::Forward, 60});
  in.insert(in.end(), cmd.begin(), cmd.end());
  const Bytes fault = encode(*parseFaultCommand("sensor_unplugged 3"));
  in.insert(in.end(), fault.begin(), fault.end());
  board.onBytes(in);

  Decoder main_board;
  std::vector<StatusReport> reports;
  for (int i = 0; i < 10; ++i)  // 200 ms at 20 ms per frame, inside the deadman
    for (auto& f : main_board.feed(board.step(0.02))) reports.push_back(std::get<StatusReport>(f));

  ASSERT_EQ(reports.size(), 10u);
  EXPECT_GT(reports.back().left_encoder, reports.front().left_encoder);
  EXPECT_GT(reports.back().right_encoder, 0);
  EXPECT_EQ(reports.back().sonar_cm[3], 0);
  EXPECT_EQ(reports.back().sonar_cm[0], 3000);
  EXPECT_EQ(board.decoderStats().frames, 2u);
}

// ---- keel_motion_board on a pseudo-terminal ------------------------------------------------

/// keel_motion_board as a child process; stopped with SIGTERM on destruction.
class BoardProcess {
 public:
  explicit BoardProcess(const std::string& truth = "") {
    int out[2];
    if (pipe(out) != 0) return;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, out[0]);
    std::vector<char*> argv = {const_cast<char*>(KEEL_MOTION_BOARD), const_cast<char*>("--seed"),
                               const_cast<char*>("3")};
    if (!truth.empty()) {
      argv.push_back(const_cast<char*>("--truth"));
      argv.push_back(const_cast<char*>(truth.c_str()));
    }
    argv.push_back(nullptr);
    if (posix_spawn(&pid_, KEEL_MOTION_BOARD, &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
    close(out[1]);
    stdout_ = out[0];
  }
  ~BoardProcess() {
    if (stdout_ >= 0) close(stdout_);
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }
  BoardProcess(const BoardProcess&) = delete;
  BoardProcess& operator=(const BoardProcess&) = delete;
  BoardProcess(BoardProcess&&) = delete;
  BoardProcess& operator=(BoardProcess&&) = delete;
  /// One line of the child's stdout, or "" if none within `timeout`.
  std::string readLine(std::chrono::milliseconds timeout) {
    std::string line;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    char c = 0;
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd pfd{stdout_, POLLIN, 0};
      if (poll(&pfd, 1, 100) <= 0) continue;
      if (read(stdout_, &c, 1) != 1) break;
      if (c == '\n') return line;
      line += c;
    }
    return "";
  }
  /// SIGTERM and the exit status (-1 if it did not exit normally).
  int terminate() {
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  int stdout_ = -1;
};

TEST(MotionBoardProcess, ServesTheProtocolOnAPseudoTerminalAndPublishesTheTruth) {
  const std::string truth_path = truthPath("board-test", getpid());
  BoardProcess process(truth_path);
  ASSERT_GT(process.pid(), 0);
  const std::string path = process.readLine(std::chrono::seconds(2));
  ASSERT_EQ(path.rfind("/dev/pts/", 0), 0u) << path;
  const int fd = open(path.c_str(), O_RDWR | O_NOCTTY);
  ASSERT_GE(fd, 0);
  tcflush(fd, TCIFLUSH);  // status frames written before we came

  const Bytes cmd = encode(MotionCommand{MotionType::Forward, 120});
  ASSERT_EQ(write(fd, cmd.data(), cmd.size()), static_cast<ssize_t>(cmd.size()));
  Decoder decoder;
  std::vector<StatusReport> reports;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < deadline &&
         (reports.size() < 2 || reports.back().left_encoder <= reports.front().left_encoder ||
          reports.back().right_encoder <= reports.front().right_encoder)) {
    pollfd pfd{fd, POLLIN, 0};
    if (poll(&pfd, 1, 50) <= 0) continue;
    std::uint8_t buf[256];
    const ssize_t n = read(fd, buf, sizeof buf);
    if (n <= 0) continue;
    for (auto& f : decoder.feed(std::span(buf, static_cast<std::size_t>(n))))
      if (auto* s = std::get_if<StatusReport>(&f)) reports.push_back(*s);
  }
  close(fd);

  ASSERT_GE(reports.size(), 2u);
  EXPECT_GT(reports.back().left_encoder, reports.front().left_encoder);
  EXPECT_GT(reports.back().right_encoder, reports.front().right_encoder);
  // The paper arena: the front sonars see obstacle A ahead, the back one the west wall.
  const World arena = World::paperArena();
  EXPECT_LT(reports.back().sonar_cm[0], 100.0 * (3.5 - 0.12 - 0.505));
  EXPECT_NEAR(reports.back().sonar_cm[3], 100.0 * (arena.start().x_m - 0.105), 15.0);
  EXPECT_EQ(decoder.stats().bad_checksum, 0u);
  TruthReader truth(truth_path);
  const auto sample = truth.read();
  ASSERT_TRUE(sample.has_value());
  EXPECT_GT(sample->x_m, arena.start().x_m);  // it drove forward
  EXPECT_EQ(sample->collisions, 0.0);
  EXPECT_GT(sample->rpm_left, 0.0);
  EXPECT_EQ(process.terminate(), 0);                  // SIGTERM is a clean exit
  EXPECT_FALSE(std::filesystem::exists(truth_path));  // the board removes its truth file
}

// keel run killed between starting its board and reading the pseudo-terminal's path (the kill -9
// campaign's moments during startup): the board finds nobody to tell the path to. It must not
// die of the SIGPIPE with its truth file left in /dev/shm, but leave as it does when its parent
// is gone.
TEST(MotionBoardProcess, ABoardWhoseStarterIsGoneBeforeItSaysItsPathLeavesNoTruthFile) {
  const std::string truth_path = truthPath("board-orphan-test", getpid());
  int out[2];
  ASSERT_EQ(pipe(out), 0);
  close(out[0]);  // no reader: the path goes nowhere
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  std::vector<char*> argv = {const_cast<char*>(KEEL_MOTION_BOARD), const_cast<char*>("--truth"),
                             const_cast<char*>(truth_path.c_str()), nullptr};
  pid_t pid = -1;
  ASSERT_EQ(posix_spawn(&pid, KEEL_MOTION_BOARD, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  close(out[1]);
  int status = 0;
  for (int i = 0; i < 500 && waitpid(pid, &status, WNOHANG) == 0; ++i) usleep(10'000);  // 5 s
  if (kill(pid, 0) == 0) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    ADD_FAILURE() << "the board kept running without anyone to serve";
  }
  EXPECT_FALSE(WIFSIGNALED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  EXPECT_FALSE(std::filesystem::exists(truth_path)) << "left in /dev/shm";
  std::filesystem::remove(truth_path);
}

}  // namespace
}  // namespace keel::robot
