// What fuzz/dds_sample_fuzz.cpp and its seed writer (fuzz/dds_sample_seeds.cpp) share: the message
// types the target reads, each with the CycloneDDS sertype a keel reader of it deserializes with,
// and CycloneDDS's serialization of a C sample. The sertype is the one a topic made as keel's DDS
// layer makes it (dds_create_topic with idlc's descriptor and no QoS: plain CDR) holds; CycloneDDS
// 0.10 exports no getter for it, so it is taken from a sample written and read back once, in a
// participant of the process's own: domain 232, loopback only, no multicast, discovery tag
// "keel-fuzz" (it meets no other participant). Thread-safety: one caller at a time.
#pragma once

#include <dds/dds.h>
#include <dds/ddsi/ddsi_serdata.h>
#include <dds/ddsi/ddsi_sertype.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "dds/type_registry.hpp"
#include "keel/detail/dds_type.hpp"
#include "keel/msg/diagnostic_msgs/msg/detail/diagnostic_array__dds.hpp"
#include "keel/msg/geometry_msgs/msg/detail/twist__dds.hpp"
#include "keel/msg/keel_test_msgs/msg/detail/everything__dds.hpp"
#include "keel/msg/sensor_msgs/msg/detail/imu__dds.hpp"
#include "keel/msg/sensor_msgs/msg/detail/joint_state__dds.hpp"
#include "keel/msg/sensor_msgs/msg/detail/laser_scan__dds.hpp"
#include "keel/msg/std_msgs/msg/detail/float64_multi_array__dds.hpp"
#include "keel/msg/std_msgs/msg/detail/string__dds.hpp"

namespace keel::fuzz {

[[noreturn]] inline void fail(const char* what, const char* detail) {
  std::fprintf(stderr, "dds_sample: %s%s\n", what, detail);
  std::abort();
}

/// The participant every sertype lives in; made once, never deleted (the sertypes need it).
inline dds_entity_t participant() {
  static const dds_entity_t made = [] {
    constexpr dds_domainid_t kDomain = 232;
    const char* config =
        "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/>"
        "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><Tag>keel-fuzz</Tag>"
        "<ParticipantIndex>none</ParticipantIndex></Discovery></Domain></CycloneDDS>";
    if (const dds_entity_t domain = dds_create_domain(kDomain, config); domain < 0) {
      fail("no CycloneDDS domain: ", dds_strretcode(domain));
    }
    const dds_entity_t pp = dds_create_participant(kDomain, nullptr, nullptr);
    if (pp < 0) fail("no CycloneDDS participant: ", dds_strretcode(pp));
    return pp;
  }();
  return made;
}

/// The sertype of a reader of the registered type `ros_name`, as keel's DDS layer makes it: a
/// default C sample written by a writer of the same topic and taken back as serdata, whose type
/// it is. Referenced once more, so that it outlives the writer and reader deleted here.
inline const ddsi_sertype* readerSertype(const keel::detail::DdsType& type, const void* zero_sample) {
  const auto& desc = *static_cast<const dds_topic_descriptor_t*>(type.descriptor);
  std::string name = std::string("keel_fuzz_") + type.ros_name;
  for (char& c : name) c = c == '/' ? '_' : c;
  const dds_entity_t topic = dds_create_topic(participant(), &desc, name.c_str(), nullptr, nullptr);
  if (topic < 0) fail("no topic: ", dds_strretcode(topic));
  const dds_entity_t reader = dds_create_reader(participant(), topic, nullptr, nullptr);
  const dds_entity_t writer = dds_create_writer(participant(), topic, nullptr, nullptr);
  if (reader < 0 || writer < 0) fail("no reader or writer for ", type.ros_name);
  if (dds_write(writer, zero_sample) != DDS_RETCODE_OK) fail("cannot write ", type.ros_name);
  ddsi_serdata* taken = nullptr;
  dds_sample_info_t info;
  if (dds_takecdr(reader, &taken, 1, &info, 0) != 1) fail("nothing taken back of ", type.ros_name);
  const ddsi_sertype* sertype = ddsi_sertype_ref(taken->type);
  ddsi_serdata_unref(taken);
  dds_delete(writer);
  dds_delete(reader);
  return sertype;
}

/// CycloneDDS's serialization of the C sample `sample` by `sertype` (what its writer puts on the
/// wire, the 4-byte CDR header first); empty if CycloneDDS refuses the sample.
inline std::vector<std::uint8_t> serialize(const ddsi_sertype* sertype, const void* sample) {
  ddsi_serdata* d = ddsi_serdata_from_sample(sertype, SDK_DATA, sample);
  if (d == nullptr) return {};
  std::vector<std::uint8_t> bytes(ddsi_serdata_size(d));
  ddsi_serdata_to_ser(d, 0, bytes.size(), bytes.data());
  ddsi_serdata_unref(d);
  return bytes;
}

/// One message type the target reads: its registration (the receive path keel's DDS layer calls),
/// its reader's sertype, and the round trip through keel's conversions.
struct SampleType {
  const keel::detail::DdsType* type;
  const ddsi_sertype* sertype;
  /// keel's receive path on a C sample (the registration's deliver into a connection), then
  /// keel's toDds of what arrived; the serialization of that (empty if CycloneDDS refuses it).
  std::vector<std::uint8_t> (*round_trip)(const SampleType&, const void* sample);
};

template <class T>
struct Captured final : keel::detail::Sink<T> {
  void deliver(const T& value) override { values.push_back(value); }
  std::vector<T> values;
};

template <class T, class C>
std::vector<std::uint8_t> roundTrip(const SampleType& t, const void* sample) {
  Captured<T> input;
  keel::detail::Connection<T> connection(&input);
  t.type->deliver(sample, connection);
  if (input.values.size() != 1) fail("a sample delivered is not one value: ", t.type->ros_name);
  C back{};
  keel::detail::DdsScratch scratch;
  keel::msg::dds::toDds(input.values[0], back, scratch);
  return serialize(t.sertype, &back);
}

template <class T, class C>
SampleType sampleType(const char* ros_name) {
  const keel::detail::DdsType* type = keel::dds::findType(ros_name);
  if (type == nullptr) fail("not registered: ", ros_name);
  C zero{};
  return {type, readerSertype(*type, &zero), &roundTrip<T, C>};
}

namespace msg = keel::msg;

/// The types, in the order the input's first byte selects them (byte % size).
inline const std::vector<SampleType>& sampleTypes() {
  static const std::vector<SampleType> types{
      sampleType<msg::sensor_msgs::LaserScan, sensor_msgs_msg_dds__LaserScan_>("sensor_msgs/msg/LaserScan"),
      sampleType<msg::std_msgs::String, std_msgs_msg_dds__String_>("std_msgs/msg/String"),
      sampleType<msg::diagnostic_msgs::DiagnosticArray, diagnostic_msgs_msg_dds__DiagnosticArray_>(
          "diagnostic_msgs/msg/DiagnosticArray"),
      sampleType<msg::geometry_msgs::Twist, geometry_msgs_msg_dds__Twist_>("geometry_msgs/msg/Twist"),
      sampleType<msg::keel_test_msgs::Everything, keel_test_msgs_msg_dds__Everything_>("keel_test_msgs/msg/Everything"),
      sampleType<msg::sensor_msgs::JointState, sensor_msgs_msg_dds__JointState_>("sensor_msgs/msg/JointState"),
      sampleType<msg::sensor_msgs::Imu, sensor_msgs_msg_dds__Imu_>("sensor_msgs/msg/Imu"),
      sampleType<msg::std_msgs::Float64MultiArray, std_msgs_msg_dds__Float64MultiArray_>(
          "std_msgs/msg/Float64MultiArray"),
  };
  return types;
}

}  // namespace keel::fuzz
