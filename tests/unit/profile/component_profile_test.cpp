// Valid component profiles read into model.hpp's structs: execution, properties of every type,
// ports with their defaults and validity, and plain OPRoS profiles.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;

const ComponentProfile& onlyComponent(const ProfileSet& set) { return set.components.begin()->second; }

const Property* findProperty(const ComponentProfile& c, const std::string& name) {
  for (const Property& p : c.properties) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

TEST(ComponentProfile, ReadsIdentityAndExecutionSemantics) {
  const auto result = load(dataPath("valid/Sonar.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  EXPECT_EQ(result->root_kind, RootKind::Component);
  EXPECT_EQ(result->root, keyOf("valid/Sonar.xml"));
  ASSERT_EQ(result->components.size(), 1u);
  const ComponentProfile& c = onlyComponent(*result);
  EXPECT_EQ(c.file, keyOf("valid/Sonar.xml"));
  EXPECT_EQ(c.name, "Sonar");
  EXPECT_EQ(c.description, "Ultrasonic range sensor (paper §5.1.2)");
  EXPECT_EQ(c.library_name, "libsonar.so");
  EXPECT_EQ(c.execution.type, ExecutionType::Periodic);  // written "Periodic"
  EXPECT_DOUBLE_EQ(c.execution.period_ms, 0.5);          // sub-millisecond periods allowed
  EXPECT_EQ(c.execution.priority, 20);
  EXPECT_EQ(c.execution.policy, SchedPolicy::Fifo);  // written "SCHED_FIFO"
  EXPECT_EQ(c.where.line, 2);
  EXPECT_EQ(relative(c.where.file), "valid/Sonar.xml");
}

TEST(ComponentProfile, TypesPropertiesAndNormalisesTheirTypeNames) {
  const auto result = load(dataPath("valid/Sonar.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const ComponentProfile& c = onlyComponent(*result);

  ASSERT_EQ(c.properties.size(), 5u);
  EXPECT_EQ(findProperty(c, "gain")->type, "double");
  EXPECT_DOUBLE_EQ(std::get<double>(findProperty(c, "gain")->value), 1.5);
  EXPECT_EQ(findProperty(c, "samples")->type, "int");  // "unsigned short"
  EXPECT_EQ(std::get<std::int64_t>(findProperty(c, "samples")->value), 4);
  EXPECT_EQ(std::get<bool>(findProperty(c, "enabled")->value), true);
  EXPECT_EQ(findProperty(c, "frame")->type, "string");  // "std::string", value trimmed
  EXPECT_EQ(std::get<std::string>(findProperty(c, "frame")->value), "base_link");
  EXPECT_EQ(findProperty(c, "offsets")->type, "double[]");  // "std::vector<double>"
  EXPECT_THAT(std::get<std::vector<double>>(findProperty(c, "offsets")->value), ElementsAre(0.1, 0.2, 0.3));
  EXPECT_EQ(findProperty(c, "gain")->where.line, 15);
}

TEST(ComponentProfile, ReadsDataAndEventPortsWithDefaultsAndValidity) {
  const auto result = load(dataPath("valid/Sonar.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const ComponentProfile& c = onlyComponent(*result);

  ASSERT_EQ(c.data_ports.size(), 2u);
  const DataPort& distance = c.data_ports[0];
  EXPECT_EQ(distance.name, "distance");
  EXPECT_EQ(distance.usage, PortDirection::Output);
  EXPECT_EQ(distance.data_type, "double");
  EXPECT_EQ(distance.queue_policy, QueuePolicy::Fifo);  // default
  EXPECT_EQ(distance.queue_size, 10u);                  // default
  ASSERT_TRUE(distance.validity.has_value());
  EXPECT_THAT(distance.validity->min, ElementsAre(3.0));
  EXPECT_THAT(distance.validity->max, ElementsAre(3000.0));
  const DataPort& threshold = c.data_ports[1];
  EXPECT_EQ(threshold.usage, PortDirection::Input);      // written "Input"
  EXPECT_EQ(threshold.queue_policy, QueuePolicy::Last);  // <queuing_policy>last</queuing_policy>
  EXPECT_EQ(threshold.queue_size, 1u);
  EXPECT_FALSE(threshold.validity.has_value());
  ASSERT_EQ(c.event_ports.size(), 1u);
  EXPECT_EQ(c.event_ports[0].name, "alarm");
  EXPECT_EQ(c.event_ports[0].data_type, "keel::Event");
  EXPECT_EQ(c.event_ports[0].queue_size, 64u);  // default
  EXPECT_TRUE(c.service_ports.empty());
}

TEST(ComponentProfile, ReadsServicePortsAndElementWiseValidityWithInfiniteBounds) {
  const auto result = load(dataPath("valid/Nav.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const ComponentProfile& c = onlyComponent(*result);

  const Validity& v = *c.data_ports[0].validity;
  EXPECT_THAT(v.min, ElementsAre(0.0, -1.0, -std::numeric_limits<double>::infinity()));
  EXPECT_THAT(v.max, ElementsAre(10.0, 1.0, std::numeric_limits<double>::infinity()));
  EXPECT_EQ(c.data_ports[0].queue_size, 8u);
  EXPECT_EQ(c.event_ports[0].queue_size, 16u);
  ASSERT_EQ(c.service_ports.size(), 1u);
  EXPECT_EQ(c.service_ports[0].name, "map");
  EXPECT_EQ(c.service_ports[0].type, "MapService");
  EXPECT_EQ(c.service_ports[0].usage, ServiceUsage::Required);
  EXPECT_DOUBLE_EQ(c.service_ports[0].timeout_ms, 250.0);
}

TEST(ComponentProfile, AppliesExecutionDefaultsWhenSemanticsAreLeftOut) {
  const auto result = load(dataPath("valid/MapServer.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const ComponentProfile& c = onlyComponent(*result);

  EXPECT_EQ(c.execution.type, ExecutionType::Passive);
  EXPECT_DOUBLE_EQ(c.execution.period_ms, 100.0);
  EXPECT_EQ(c.execution.priority, 0);
  EXPECT_EQ(c.execution.policy, SchedPolicy::Other);
  EXPECT_DOUBLE_EQ(c.service_ports[0].timeout_ms, 1000.0);
  EXPECT_TRUE(c.library_name.empty());
  EXPECT_TRUE(c.properties.empty());
}

TEST(ComponentProfile, LoadsAPlainOprosProfileIgnoringItsToolElements) {
  const auto result = load(dataPath("opros/LaserScannerComp.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const ComponentProfile& c = onlyComponent(*result);

  EXPECT_EQ(c.name, "LaserScannerComp");
  EXPECT_EQ(c.library_name, "LaserScannerComp.dll");
  EXPECT_DOUBLE_EQ(c.execution.period_ms, 200.0);
  EXPECT_EQ(c.execution.priority, 5);
  EXPECT_EQ(c.properties.size(), 4u);
  ASSERT_EQ(c.data_ports.size(), 1u);
  EXPECT_EQ(c.data_ports[0].data_type, "vector<double>");
  ASSERT_EQ(c.service_ports.size(), 1u);
  EXPECT_EQ(c.service_ports[0].usage, ServiceUsage::Provided);
}

TEST(ComponentProfile, LoadsAnOprosProfileWithQueuingPolicySpelling) {
  const auto result = load(dataPath("opros/Brightness.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const ComponentProfile& c = onlyComponent(*result);

  ASSERT_EQ(c.data_ports.size(), 2u);
  EXPECT_EQ(c.data_ports[1].name, "ImageIn");
  EXPECT_EQ(c.data_ports[1].queue_policy, QueuePolicy::Last);
  EXPECT_EQ(c.data_ports[1].queue_size, 1u);
}

}  // namespace
}  // namespace keel::profile::test
