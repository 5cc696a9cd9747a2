// keel's message types through CycloneDDS itself: a value converted with toDds, written by a
// DDS writer, serialized to CDR by CycloneDDS with idlc's descriptor, taken by a reader of the same
// participant and converted back with fromDds, is equal to itself; and the same through the
// registration libkeel holds for each shipped type (the DDS layer's path). Makes a DDS participant
// in a random domain, pinned to the loopback interface with multicast off (CYCLONEDDS_URI), on
// topics of a name of its own; touches nothing else.
#include <dds/dds.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "dds/type_registry.hpp"
#include "keel/detail/connection.hpp"
#include "keel/msg/diagnostic_msgs/msg/detail/diagnostic_array__dds.hpp"
#include "keel/msg/geometry_msgs/msg/detail/pose_stamped__dds.hpp"
#include "keel/msg/keel_test_msgs/msg/detail/everything__dds.hpp"
#include "keel/msg/sensor_msgs/msg/detail/imu__dds.hpp"
#include "keel/msg/sensor_msgs/msg/detail/joint_state__dds.hpp"
#include "keel/msg/sensor_msgs/msg/detail/laser_scan__dds.hpp"
#include "keel/msg/std_msgs/msg/detail/empty__dds.hpp"
#include "keel/msg/std_msgs/msg/detail/string__dds.hpp"
#include "support/env.hpp"
#include "unit/msgs/sample_values.hpp"

// idlc's descriptor of keel's test message, compiled here as keel_msggen.py's registering source
// compiles it (the shipped messages' descriptors are libkeel's; keel_test_msgs' objects are not
// linked: this binary has one registration of each type, libkeel's).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-enum-enum-conversion"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#undef dds_alignof
#define dds_alignof alignof
#include "keel_test_msgs/msg/Everything_.c"  // NOLINT(bugprone-suspicious-include): idlc's C, above
#pragma GCC diagnostic pop

namespace {

namespace msg = keel::msg;

constexpr const char* kLoopbackOnly =
    "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/>"
    "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>"
    "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>100</MaxAutoParticipantIndex>"
    "</Discovery></Domain></CycloneDDS>";

class CycloneRoundTrip : public ::testing::Test {
 protected:
  void SetUp() override {
    loopback_.emplace("CYCLONEDDS_URI", kLoopbackOnly);
    std::random_device rd;
    const auto domain = static_cast<dds_domainid_t>(101 + rd() % 100);
    participant_ = dds_create_participant(domain, nullptr, nullptr);
    ASSERT_GT(participant_, 0) << dds_strretcode(participant_);
    prefix_ = "keel_msgs_test_" + std::to_string(getpid()) + "_" + std::to_string(rd());
  }
  void TearDown() override {
    if (participant_ > 0) dds_delete(participant_);
  }

  struct Endpoints {
    dds_entity_t reader = 0;
    dds_entity_t writer = 0;
  };

  /// A reader and a writer on a topic of its own with the type `desc` describes.
  Endpoints endpoints(const dds_topic_descriptor_t& desc) {
    std::string name = prefix_ + "_" + desc.m_typename;  // "pkg::msg::dds_::Name_": ':' is no topic character
    for (char& ch : name) ch = ch == ':' ? '_' : ch;
    const dds_entity_t topic = dds_create_topic(participant_, &desc, name.c_str(), nullptr, nullptr);
    EXPECT_GT(topic, 0) << dds_strretcode(topic);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
    Endpoints e{dds_create_reader(participant_, topic, qos, nullptr),
                dds_create_writer(participant_, topic, qos, nullptr)};
    dds_delete_qos(qos);
    EXPECT_GT(e.reader, 0) << dds_strretcode(e.reader);
    EXPECT_GT(e.writer, 0) << dds_strretcode(e.writer);
    return e;
  }

  /// Waits for the sample `reader` has, takes it and hands it to `use` (a `const void*`).
  template <class Use>
  void takeOne(dds_entity_t reader, Use use) {
    const dds_entity_t waitset = dds_create_waitset(participant_);
    const dds_entity_t ready = dds_create_readcondition(reader, DDS_ANY_STATE);
    dds_waitset_attach(waitset, ready, 0);
    EXPECT_GT(dds_waitset_wait(waitset, nullptr, 0, DDS_SECS(10)), 0) << "no sample within 10 s";
    void* samples[1] = {nullptr};
    dds_sample_info_t info[1];
    const dds_return_t n = dds_take(reader, samples, info, 1, 1);
    EXPECT_EQ(n, 1) << dds_strretcode(n);
    if (n == 1 && info[0].valid_data) use(static_cast<const void*>(samples[0]));
    if (n > 0) dds_return_loan(reader, samples, n);
    dds_delete(waitset);
  }

  /// `value` written and taken back on a topic of type C (descriptor `desc`).
  template <class C, class T>
  T throughDds(const dds_topic_descriptor_t& desc, const T& value) {
    const Endpoints e = endpoints(desc);
    C sample{};
    keel::detail::DdsScratch scratch;
    keel::msg::dds::toDds(value, sample, scratch);
    const dds_return_t written = dds_write(e.writer, &sample);
    EXPECT_EQ(written, DDS_RETCODE_OK) << dds_strretcode(written);
    T back{};
    takeOne(e.reader, [&](const void* taken) { keel::msg::dds::fromDds(*static_cast<const C*>(taken), back); });
    return back;
  }

  std::optional<keel::test::ScopedEnv> loopback_;  // CycloneDDS's configuration, for the test
  dds_entity_t participant_ = 0;
  std::string prefix_;
};

TEST_F(CycloneRoundTrip, StringAndEmptyComeBackEqual) {
  msg::std_msgs::String s;
  s.data = "hello, ROS 2 — ünïcödé";
  EXPECT_EQ((throughDds<std_msgs_msg_dds__String_>(std_msgs_msg_dds__String__desc, s)), s);
  EXPECT_EQ((throughDds<std_msgs_msg_dds__Empty_>(std_msgs_msg_dds__Empty__desc, msg::std_msgs::Empty{})),
            msg::std_msgs::Empty{});
}

TEST_F(CycloneRoundTrip, SensorMessagesComeBackEqual) {
  const auto scan = keel::test::laserScan(1000);
  EXPECT_EQ((throughDds<sensor_msgs_msg_dds__LaserScan_>(sensor_msgs_msg_dds__LaserScan__desc, scan)), scan);
  const auto joints = keel::test::jointState();
  EXPECT_EQ((throughDds<sensor_msgs_msg_dds__JointState_>(sensor_msgs_msg_dds__JointState__desc, joints)), joints);
  const auto imu = keel::test::imu();
  EXPECT_EQ((throughDds<sensor_msgs_msg_dds__Imu_>(sensor_msgs_msg_dds__Imu__desc, imu)), imu);
  const auto pose = keel::test::poseStamped();
  EXPECT_EQ((throughDds<geometry_msgs_msg_dds__PoseStamped_>(geometry_msgs_msg_dds__PoseStamped__desc, pose)), pose);
}

TEST_F(CycloneRoundTrip, DiagnosticArrayComesBackEqual) {
  const auto diagnostics = keel::test::diagnosticArray();
  EXPECT_EQ((throughDds<diagnostic_msgs_msg_dds__DiagnosticArray_>(diagnostic_msgs_msg_dds__DiagnosticArray__desc,
                                                                   diagnostics)),
            diagnostics);
}

TEST_F(CycloneRoundTrip, EveryKindOfFieldComesBackEqual) {
  const auto e = keel::test::everything();
  EXPECT_EQ((throughDds<keel_test_msgs_msg_dds__Everything_>(keel_test_msgs_msg_dds__Everything__desc, e)), e);
}

/// What an input port's connection would get.
template <class T>
struct Captured final : keel::detail::Sink<T> {
  void deliver(const T& value) override { values.push_back(value); }
  std::vector<T> values;
};

TEST_F(CycloneRoundTrip, ARegisteredTypeWritesThroughItsOutletAndDeliversToAConnection) {
  using Scan = msg::sensor_msgs::LaserScan;
  const keel::detail::DdsType* type = keel::dds::findType("sensor_msgs/msg/LaserScan");
  ASSERT_NE(type, nullptr);
  const Endpoints e = endpoints(*static_cast<const dds_topic_descriptor_t*>(type->descriptor));
  const auto scan = keel::test::laserScan(500);
  auto outlet = type->make_outlet(e.writer);
  static_cast<keel::detail::Connection<Scan>&>(outlet->connection()).send(scan);
  Captured<Scan> input;
  keel::detail::Connection<Scan> connection(&input);
  takeOne(e.reader, [&](const void* taken) { type->deliver(taken, connection); });
  ASSERT_EQ(input.values.size(), 1u);
  EXPECT_EQ(input.values[0], scan);
}

}  // namespace
