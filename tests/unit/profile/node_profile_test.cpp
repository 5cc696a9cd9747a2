// <ros2_node_profile> (docs/profiles.md#ros-2-node-profile): a full profile read into every
// field, the defaults, the node as the passive component keel's engine sees, the program found
// on the node's own PATH, and a package whose subcomponents are nodes (started and attached),
// connected to components.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "profile_test_support.hpp"
#include "support/env.hpp"

namespace keel::profile::test {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;

std::string nodeDir() { return fs::path(keyOf("node/wander.xml")).parent_path().string(); }

TEST(NodeProfile, AFullProfileIsReadIntoEveryField) {
  auto set = load(dataPath("node/wander.xml"));
  ASSERT_TRUE(set.ok()) << joined(set);
  EXPECT_EQ(set->root_kind, RootKind::Node);
  EXPECT_THAT(set->warnings, ElementsAre());
  ASSERT_EQ(set->nodes.count(keyOf("node/wander.xml")), 1u);
  const NodeProfile& n = set->nodes.at(keyOf("node/wander.xml"));
  EXPECT_EQ(n.file, keyOf("node/wander.xml"));
  EXPECT_EQ(n.name, "Wander");
  EXPECT_EQ(n.description, "Drives around, avoiding what the sonar sees");
  EXPECT_EQ(n.where.line, 2);
  EXPECT_THAT(n.command, ElementsAre("wander_node", "--speed", "0.2", "a b", "c \"d\"", "e f"));
  EXPECT_EQ(n.executable, nodeDir() + "/bin/wander_node");  // PATH's "bin" is the profile's folder's
  EXPECT_EQ(n.command_where.line, 5);
  EXPECT_EQ(n.node_namespace, "/robot");
  EXPECT_EQ(n.node_name, "wander");
  EXPECT_EQ(n.fullName(), "/robot/wander");
  EXPECT_EQ(n.node_where.line, 6);
  ASSERT_EQ(n.environment.size(), 3u);
  EXPECT_EQ(n.environment[0].name, "PYTHONUNBUFFERED");
  EXPECT_EQ(n.environment[0].value, "1");
  EXPECT_EQ(n.environment[1].name, "PATH");
  EXPECT_EQ(n.environment[2].value, " two words ");  // a value as written
  EXPECT_EQ(n.environment[2].where.line, 10);
  ASSERT_EQ(n.parameters.size(), 3u);
  EXPECT_EQ(n.parameters[0].name, "speed");
  EXPECT_EQ(n.parameters[0].value, "0.2");
  EXPECT_EQ(n.parameters[1].name, "planner.mode");
  EXPECT_EQ(n.parameters[1].value, "careful");  // trimmed
  EXPECT_EQ(n.parameters[2].value, "");         // an empty string
  EXPECT_EQ(n.parameters[2].where.line, 15);
  EXPECT_EQ(n.start_timeout_ms, 5000.0);
  EXPECT_EQ(n.stop_grace_ms, 1500.5);
  EXPECT_EQ(n.diagnostics_name, "wander: status");
  ASSERT_TRUE(n.lifecycle);
  EXPECT_EQ(n.lifecycle->transition_timeout_ms, 2500.0);

  ASSERT_EQ(n.topics.size(), 2u);
  EXPECT_EQ(n.topics[0].port, "cmd");
  EXPECT_EQ(n.topics[0].topic, "/cmd_vel");
  EXPECT_EQ(n.topics[0].qos, DdsQos::Reliable);
  EXPECT_EQ(n.topics[0].depth, 5u);
  EXPECT_EQ(n.topics[0].deadline_ms, 300.0);
  EXPECT_EQ(n.topics[0].liveliness_ms, 600.0);
  EXPECT_EQ(n.topics[0].where.line, 21);
  EXPECT_EQ(n.topics[1].port, "range");
  EXPECT_EQ(n.topics[1].topic, "/sonar/a");
  EXPECT_EQ(n.topics[1].qos, DdsQos::SensorData);
  EXPECT_FALSE(n.topics[1].depth);
  EXPECT_FALSE(n.topics[1].deadline_ms);
  EXPECT_FALSE(n.topics[1].liveliness_ms);

  ASSERT_TRUE(n.emergency);
  EXPECT_TRUE(n.emergency->stop);
  EXPECT_EQ(n.emergency->where.line, 42);
  ASSERT_EQ(n.emergency->publish.size(), 2u);
  EXPECT_EQ(n.emergency->publish[0].topic, "/cmd_vel");
  EXPECT_EQ(n.emergency->publish[0].type, "geometry_msgs/msg/Twist");
  EXPECT_EQ(n.emergency->publish[0].rate_hz, 20.0);
  EXPECT_EQ(n.emergency->publish[1].topic, "/led");
  EXPECT_EQ(n.emergency->publish[1].rate_hz, 10.0);  // the default
  EXPECT_EQ(n.emergency->publish[1].where.line, 45);
}

TEST(NodeProfile, TheNodeIsAPassiveComponentWithItsPortsUnderItsPathToo) {
  auto set = load(dataPath("node/wander.xml"));
  ASSERT_TRUE(set.ok()) << joined(set);
  const ComponentProfile& c = set->nodes.at(keyOf("node/wander.xml")).component;
  EXPECT_EQ(c.file, keyOf("node/wander.xml"));
  EXPECT_EQ(c.name, "Wander");
  EXPECT_EQ(c.description, "Drives around, avoiding what the sonar sees");
  EXPECT_EQ(c.where.line, 2);
  EXPECT_EQ(c.execution.type, ExecutionType::Passive);
  EXPECT_EQ(c.library_name, "");
  EXPECT_THAT(c.properties, ElementsAre());
  EXPECT_THAT(c.event_ports, ElementsAre());
  EXPECT_THAT(c.service_ports, ElementsAre());
  ASSERT_EQ(c.data_ports.size(), 2u);
  const DataPort& cmd = c.data_ports[0];
  EXPECT_EQ(cmd.name, "cmd");
  EXPECT_EQ(cmd.usage, PortDirection::Output);
  EXPECT_EQ(cmd.data_type, "geometry_msgs/msg/Twist");
  EXPECT_EQ(cmd.where.line, 21);
  EXPECT_FALSE(cmd.validity);  // a node's port's rules are per field
  ASSERT_EQ(cmd.field_validity.size(), 2u);
  EXPECT_EQ(cmd.field_validity[0].field, "linear.x");
  EXPECT_THAT(cmd.field_validity[0].min, ElementsAre(-0.5));
  EXPECT_THAT(cmd.field_validity[0].max, ElementsAre(0.5));
  EXPECT_EQ(cmd.field_validity[0].where.line, 30);
  EXPECT_EQ(cmd.field_validity[1].field, "angular.z");
  EXPECT_THAT(cmd.field_validity[1].min, ElementsAre());
  EXPECT_THAT(cmd.field_validity[1].max, ElementsAre(1.5));
  EXPECT_EQ(c.data_ports[1].name, "range");
  EXPECT_EQ(c.data_ports[1].usage, PortDirection::Input);
  EXPECT_EQ(c.data_ports[1].data_type, "sensor_msgs/msg/Range");
  EXPECT_THAT(c.data_ports[1].field_validity, ElementsAre());

  ASSERT_EQ(set->components.count(keyOf("node/wander.xml")), 1u);
  const ComponentProfile& copy = set->components.at(keyOf("node/wander.xml"));
  EXPECT_EQ(copy.name, "Wander");
  ASSERT_EQ(copy.data_ports.size(), 2u);
  EXPECT_EQ(copy.data_ports[0].field_validity.size(), 2u);
}

TEST(NodeProfile, AMinimalProfileTakesTheDefaults) {
  auto set = load(dataPath("node/minimal.xml"));
  ASSERT_TRUE(set.ok()) << joined(set);
  const NodeProfile& n = set->nodes.at(keyOf("node/minimal.xml"));
  EXPECT_THAT(n.command, ElementsAre("./wander.py"));
  EXPECT_EQ(n.executable, nodeDir() + "/wander.py");  // from the profile's folder
  EXPECT_EQ(n.node_namespace, "/");
  EXPECT_EQ(n.node_name, "minimal");
  EXPECT_EQ(n.fullName(), "/minimal");
  EXPECT_EQ(n.description, "");
  EXPECT_THAT(n.environment, ElementsAre());
  EXPECT_THAT(n.parameters, ElementsAre());
  EXPECT_EQ(n.start_timeout_ms, 10000.0);
  EXPECT_EQ(n.stop_grace_ms, 2000.0);
  EXPECT_EQ(n.diagnostics_name, "");
  EXPECT_FALSE(n.lifecycle);
  EXPECT_THAT(n.topics, ElementsAre());
  EXPECT_FALSE(n.emergency);
  EXPECT_THAT(n.component.data_ports, ElementsAre());
}

TEST(NodeProfile, AnEmergencyThatDoesNothingIsAWarning) {
  EXPECT_THAT(warnings("node/empty_emergency.xml"),
              ElementsAre("node/empty_emergency.xml:6: <emergency> of node profile 'Calm' has neither <stop/> nor "
                          "<publish>: it does nothing"));
}

/// A node profile written in a scratch folder with a program on a PATH of its own.
class NodeProfilePath : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("keel_node_profile_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "tools");
    const fs::path exe = dir_ / "tools" / "my_node";
    std::ofstream(exe) << "#!/bin/sh\nexit 0\n";
    fs::permissions(exe, fs::perms(0755));
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Loads a node profile whose <environment> is `environment`, running `my_node`.
  Result<ProfileSet, Diagnostics> loadWith(const std::string& environment) {
    const fs::path profile = dir_ / "node.xml";
    std::ofstream(profile) << "<ros2_node_profile>\n  <name>Mine</name>\n  <command>my_node --fast</command>\n"
                           << "  <node>/mine</node>\n  <environment>" << environment << "</environment>\n"
                           << "</ros2_node_profile>\n";
    return load(profile.string());
  }
  std::string key() const { return fs::weakly_canonical(dir_ / "node.xml").string(); }

  fs::path dir_;
};

TEST_F(NodeProfilePath, TheProgramIsFoundOnThePathTheEnvironmentSets) {
  auto set = loadWith(R"(<variable name="PATH" value="/nonexistent:)" + (dir_ / "tools").string() + R"("/>)");
  ASSERT_TRUE(set.ok()) << joined(set);
  EXPECT_EQ(set->nodes.at(key()).executable, (dir_ / "tools" / "my_node").string());
  EXPECT_THAT(set->nodes.at(key()).command, ElementsAre("my_node", "--fast"));
}

TEST_F(NodeProfilePath, WithoutAPathOfItsOwnTheProgramIsFoundOnKeelsPath) {
  auto set = [&] {
    const keel::test::ScopedEnv keel_path("PATH", (dir_ / "tools").string());
    return loadWith("");
  }();
  ASSERT_TRUE(set.ok()) << joined(set);
  EXPECT_EQ(set->nodes.at(key()).executable, (dir_ / "tools" / "my_node").string());
}

TEST_F(NodeProfilePath, AProgramNotOnTheNodesPathIsAnErrorSayingWhereItLooked) {
  auto set = loadWith(R"(<variable name="PATH" value="/usr/bin:/bin"/>)");
  ASSERT_FALSE(set.ok());
  ASSERT_EQ(set.error().size(), 1u);
  EXPECT_EQ(set.error()[0].where.line, 3);
  EXPECT_EQ(set.error()[0].message,
            "<command> of node profile 'Mine': 'my_node' is not an executable file in any directory of the PATH of "
            "its <environment> (line 5): /usr/bin:/bin");
}

TEST(NodeProfile, APackagesSubcomponentsMayBeNodesStartedOrAttachedAndConnectedToComponents) {
  auto set = load(dataPath("node/app.xml"));
  ASSERT_TRUE(set.ok()) << joined(set);
  EXPECT_THAT(set->warnings, ElementsAre());  // a node's remote rule is not a <dds>'s
  const PackageProfile& pkg = set->packages.at(keyOf("node/app.xml"));
  ASSERT_EQ(pkg.subcomponents.size(), 4u);
  const Subcomponent& wander = pkg.subcomponents[2];
  EXPECT_EQ(wander.reference, keyOf("node/wander.xml"));
  EXPECT_FALSE(wander.attach);
  ASSERT_TRUE(wander.fault_policy && wander.fault_policy->alternative);
  EXPECT_EQ(wander.fault_policy->alternative->reference, keyOf("node/wander_backup.xml"));
  const Subcomponent& watcher = pkg.subcomponents[3];
  EXPECT_EQ(watcher.reference, keyOf("node/minimal.xml"));
  ASSERT_TRUE(watcher.attach);
  EXPECT_EQ(watcher.attach->line, 18);
  EXPECT_EQ(set->nodes.size(), 3u);  // wander, its alternative, and the attached one
  EXPECT_EQ(set->components.count(keyOf("node/wander_backup.xml")), 1u);
  ASSERT_EQ(pkg.connections.size(), 2u);
  EXPECT_EQ(pkg.connections[1].port_type, PortKind::Data);  // taken from the node's port and the sonar's
}

}  // namespace
}  // namespace keel::profile::test
