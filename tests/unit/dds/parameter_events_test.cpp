// /parameter_events as keel run reads it (src/dds/parameter_events): what an event says of its
// node's parameters, typed; and, through CycloneDDS in a random domain pinned to the loopback,
// that the events of the nodes keel runs reach the watch and those of other nodes do not.
#include "dds/parameter_events.hpp"

#include <dds/dds.h>
#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

#include "dds/dds_ports.hpp"
#include "dds/type_registry.hpp"
#include "keel/detail/connection.hpp"
#include "keel/msg/rcl_interfaces/msg/parameter_event.hpp"
#include "keel/msg/rcl_interfaces/msg/parameter_type.hpp"
#include "support/env.hpp"

namespace keel::dds {
namespace {

using msg::rcl_interfaces::Parameter;
using msg::rcl_interfaces::ParameterEvent;
using msg::rcl_interfaces::ParameterType;
using profile::ParameterValue;

Parameter parameter(const std::string& name, std::uint8_t type) {
  Parameter p;
  p.name = name;
  p.value.type = type;
  return p;
}

TEST(ParameterEvents, AnEventsNewAndChangedValuesAreTypedAndItsDeletionsNamed) {
  ParameterEvent e;
  e.node = "/demo/talker";
  Parameter b = parameter("b", ParameterType::PARAMETER_BOOL);
  b.value.bool_value = true;
  Parameter i = parameter("i", ParameterType::PARAMETER_INTEGER);
  i.value.integer_value = -4;
  Parameter d = parameter("d", ParameterType::PARAMETER_DOUBLE);
  d.value.double_value = 2.5;
  Parameter s = parameter("s", ParameterType::PARAMETER_STRING);
  s.value.string_value = "yes";
  Parameter sa = parameter("sa", ParameterType::PARAMETER_STRING_ARRAY);
  sa.value.string_array_value = {"a", "b"};
  Parameter ba = parameter("ba", ParameterType::PARAMETER_BOOL_ARRAY);
  ba.value.bool_array_value = {true, false};
  Parameter ia = parameter("ia", ParameterType::PARAMETER_INTEGER_ARRAY);
  ia.value.integer_array_value = {1, 2};
  Parameter da = parameter("da", ParameterType::PARAMETER_DOUBLE_ARRAY);
  da.value.double_array_value = {0.5};
  Parameter bytes = parameter("bytes", ParameterType::PARAMETER_BYTE_ARRAY);
  bytes.value.byte_array_value = {1, 2};
  e.new_parameters = {b, i, d, bytes};
  e.changed_parameters = {s, sa, ba, ia, da, parameter("unset", ParameterType::PARAMETER_NOT_SET)};
  e.deleted_parameters = {parameter("gone", ParameterType::PARAMETER_NOT_SET)};
  std::vector<std::string> skipped;
  const profile::ParameterUpdate u = updateOf(e, skipped);
  const std::vector<std::pair<std::string, ParameterValue>> set = {{"b", true},
                                                                   {"i", std::int64_t{-4}},
                                                                   {"d", 2.5},
                                                                   {"s", std::string("yes")},
                                                                   {"sa", std::vector<std::string>{"a", "b"}},
                                                                   {"ba", std::vector<bool>{true, false}},
                                                                   {"ia", std::vector<std::int64_t>{1, 2}},
                                                                   {"da", std::vector<double>{0.5}}};
  EXPECT_EQ(u.set, set);
  EXPECT_EQ(u.deleted, (std::vector<std::string>{"unset", "gone"}));
  EXPECT_EQ(skipped, std::vector<std::string>{"bytes"});  // a params file cannot hold a byte array
}

constexpr const char* kLoopbackOnly =
    "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/>"
    "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>"
    "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>100</MaxAutoParticipantIndex>"
    "</Discovery></Domain></CycloneDDS>";

struct Heard final : ParameterWatch {
  std::mutex mutex;
  std::vector<std::pair<std::string, profile::ParameterUpdate>> updates;
  void parametersChanged(const std::string& instance, const profile::ParameterUpdate& update) override {
    std::lock_guard lock(mutex);
    updates.emplace_back(instance, update);
  }
  std::size_t count() {
    std::lock_guard lock(mutex);
    return updates.size();
  }
};

TEST(ParameterEvents, TheEventsOfTheWatchedNodesReachTheWatchAndOthersDoNot) {
  test::ScopedEnv loopback("CYCLONEDDS_URI", kLoopbackOnly);
  std::random_device rd;
  const dds_entity_t participant = dds_create_participant(static_cast<dds_domainid_t>(101 + rd() % 100), nullptr,
                                                          nullptr);
  ASSERT_GT(participant, 0) << dds_strretcode(participant);
  Heard heard;
  std::vector<std::string> warnings;
  {
    ParameterEvents events(heard, [&](const std::string& m) { warnings.push_back(m); });
    ASSERT_TRUE(events.open(participant, {{"talker", "/demo/talker", {}, {}}}));
    // A writer as rclcpp's and rclpy's: reliable, volatile, keep last 1000.
    const detail::DdsType* type = findType("rcl_interfaces/msg/ParameterEvent");
    ASSERT_NE(type, nullptr);
    const dds_entity_t topic = dds_create_topic(participant,
                                                static_cast<const dds_topic_descriptor_t*>(type->descriptor),
                                                "rt/parameter_events", nullptr, nullptr);
    ASSERT_GT(topic, 0) << dds_strretcode(topic);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1000);
    const dds_entity_t writer = dds_create_writer(participant, topic, qos, nullptr);
    dds_delete_qos(qos);
    ASSERT_GT(writer, 0) << dds_strretcode(writer);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    dds_publication_matched_status_t matched{};
    while (dds_get_publication_matched_status(writer, &matched) == 0 && matched.current_count == 0 &&
           std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_EQ(matched.current_count, 1u);
    auto outlet = type->make_outlet(writer);
    auto& send = static_cast<detail::Connection<ParameterEvent>&>(outlet->connection());

    ParameterEvent other;
    other.node = "/demo/other";
    Parameter s = parameter("greeting", ParameterType::PARAMETER_STRING);
    s.value.string_value = "not mine";
    other.changed_parameters = {s};
    send.send(other);
    ParameterEvent mine;
    mine.node = "/demo/talker";
    s.value.string_value = "changed";
    mine.changed_parameters = {s};
    Parameter bytes = parameter("blob", ParameterType::PARAMETER_BYTE_ARRAY);
    mine.new_parameters = {bytes};
    send.send(mine);
    while (heard.count() == 0 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    events.close();
  }
  dds_delete(participant);
  // In order, one writer: the other node's event came first, and was not told.
  ASSERT_EQ(heard.updates.size(), 1u);
  EXPECT_EQ(heard.updates[0].first, "talker");
  const profile::ParameterUpdate expected{{{"greeting", std::string("changed")}}, {}};
  EXPECT_EQ(heard.updates[0].second, expected);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("node '/demo/talker': parameter 'blob' is a byte array"), std::string::npos)
      << warnings[0];
}

}  // namespace
}  // namespace keel::dds
