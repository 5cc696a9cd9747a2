// Every error message of a <ros2_node_profile> and of a package's node subcomponents: the
// invalid fixture under data/errors/node and its exact diagnostics, all of them, in order.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;

TEST(NodeProfileErrors, ANodeProfileNeedsANameACommandAndANode) {
  EXPECT_THAT(problems("errors/node/missing_everything.xml"),
              ElementsAre("errors/node/missing_everything.xml:2: missing <name> in <ros2_node_profile>",
                          "errors/node/missing_everything.xml:2: missing <command> in <ros2_node_profile>",
                          "errors/node/missing_everything.xml:2: missing <node> in <ros2_node_profile>"));
}

TEST(NodeProfileErrors, RejectsACommandThatNeedsAShellOrHasAnOpenQuote) {
  EXPECT_THAT(problems("errors/node/command_needs_shell.xml"),
              ElementsAre("errors/node/command_needs_shell.xml:5: <command> of node profile 'Cmd': unquoted '|' "
                          "(character 22) needs a shell, and keel starts the command without one (quote it to pass it "
                          "as it is)"));
  EXPECT_THAT(problems("errors/node/command_unterminated.xml"),
              ElementsAre("errors/node/command_unterminated.xml:5: <command> of node profile 'Cmd': the single quote "
                          "at character 12 is never closed"));
  EXPECT_THAT(problems("errors/node/command_empty.xml"),
              ElementsAre("errors/node/command_empty.xml:5: empty <command> in node profile 'Cmd'"));
}

TEST(NodeProfileErrors, RejectsAProgramThatIsNotThereSayingWhereItLooked) {
  EXPECT_THAT(problems("errors/node/command_not_on_path.xml"),
              ElementsAre("errors/node/command_not_on_path.xml:5: <command> of node profile 'Cmd': 'no_such_node' is "
                          "not an executable file in any directory of the PATH of its <environment> (line 4): "
                          "nowhere:/nonexistent"));
  EXPECT_THAT(problems("errors/node/command_missing_file.xml"),
              ElementsAre("errors/node/command_missing_file.xml:5: <command> of node profile 'Cmd': "
                          "'./nothing_here.py' does not exist (looked for errors/node/nothing_here.py)"));
  EXPECT_THAT(problems("errors/node/command_not_executable.xml"),
              ElementsAre("errors/node/command_not_executable.xml:5: <command> of node profile 'Cmd': "
                          "'../../node/not_executable.py' is not executable (node/not_executable.py): make it so "
                          "(chmod +x), or run it with its interpreter"));
  EXPECT_THAT(problems("errors/node/command_directory.xml"),
              ElementsAre("errors/node/command_directory.xml:5: <command> of node profile 'Cmd': '../../node/bin' is "
                          "not a regular file (node/bin)"));
}

TEST(NodeProfileErrors, RejectsANodeThatIsNotAFullyQualifiedNameNamingTheRuleBroken) {
  auto expect = [](const std::string& fixture, const std::string& node, const std::string& why) {
    EXPECT_THAT(problems("errors/node/" + fixture),
                ElementsAre("errors/node/" + fixture + ":5: <node> '" + node +
                            "' of node profile 'Named' is not a fully qualified node name: " + why));
  };
  expect("node_relative.xml", "wander",
         "it must lead with a '/' and the node's namespace ('/wander' in the root namespace)");
  expect("node_repeated_slash.xml", "/robot//wander", "namespace must not contain repeated '/'");
  expect("node_bad_namespace.xml", "/robot/2arm/wander",
         "namespace must not have a token that starts with a number ('2arm')");
  expect("node_bad_name.xml", "/robot/wander-1",
         "node name must not contain characters other than alphanumerics or '_' ('-')");
  expect("node_name_digit.xml", "/9wander", "node name must not start with a number");
  expect("node_trailing_slash.xml", "/robot/", "node name must not be empty");
  EXPECT_THAT(problems("errors/node/node_empty.xml"),
              ElementsAre("errors/node/node_empty.xml:5: empty <node> in node profile 'Named'"));
}

TEST(NodeProfileErrors, RejectsBadEnvironmentVariablesParametersAndTimes) {
  const std::string f = "errors/node/environment.xml:";
  EXPECT_THAT(
      problems("errors/node/environment.xml"),
      ElementsAre(
          f + "7: missing attribute 'value' of <variable>",
          f + "8: name '1ST' of <variable> of node profile 'Env' is not an environment variable's name: it starts "
              "with a digit",
          f + "9: name 'A-B' of <variable> of node profile 'Env' is not an environment variable's name: '-' is not "
              "allowed (letters, digits and '_' only)",
          f + "10: <variable> ROS_DOMAIN_ID of node profile 'Env': keel sets it, to the DDS domain keel itself is on, "
              "so that keel sees the node",
          f + "12: duplicate <variable> 'HOME' in node profile 'Env' (first at line 11)",
          f + "13: unknown attribute 'type' of <variable>", f + "14: unknown element <var> in <environment>",
          f + "18: duplicate parameter 'speed' in node profile 'Env' (first at line 17)",
          f + "19: parameter name 'a..b' of node profile 'Env' is not a ROS 2 parameter name: it has an empty token "
              "('.' first, last or twice)",
          f + "20: parameter name '2fast' of node profile 'Env' is not a ROS 2 parameter name: its token '2fast' "
              "starts with a digit",
          f + "21: parameter name 'max-speed' of node profile 'Env' is not a ROS 2 parameter name: '-' is not allowed "
              "(letters, digits, '_' and '.' only)",
          f + "22: missing attribute 'name' of <parameter>", f + "23: unknown attribute 'type' of <parameter>",
          f + "25: timeout of <start> of node profile 'Env' must be a positive number, got '0'",
          f + "26: missing attribute 'grace' of <stop>", f + "27: <diagnostics> of node profile 'Env': empty name",
          f + "28: unknown element <colour> in <ros2_node_profile>", f + "29: unknown attribute 'state' of <lifecycle>",
          f + "29: transition_timeout of <lifecycle> of node profile 'Env' must be a positive number, got '0'"));
}

TEST(NodeProfileErrors, RejectsBadPortsEachWithItsLine) {
  const std::string f = "errors/node/ports.xml:";
  const std::string input =
      ": keel writes an input port's topic, so this would watch keel, not the node (deadline "
      "and liveliness watch a node's output ports)";
  EXPECT_THAT(
      problems("errors/node/ports.xml"),
      ElementsAre(
          f + "9: <usage> of data port 'cmd' must be one of input or output, got 'sideways'",
          f + "10: <data_type> 'geometry_msgs/Twist' of data port 'cmd' is not a ROS 2 message type: it must be "
              "written as ROS 2 writes it: package/msg/Name, e.g. std_msgs/msg/Float64",
          f + "11: <topic> 'cmd_vel' of data port 'cmd' is not a ROS 2 topic name: topic name must be absolute, it "
              "must lead with a '/' (a node resolves a relative name in its own namespace)",
          f + "12: <qos> of data port 'cmd' must be one of default, sensor_data, reliable or transient_local, got "
              "'best'",
          f + "13: <depth> of data port 'cmd' must be a positive integer, got '0'",
          f + "14: missing attribute 'field' of <validity>",
          f + "15: field 'linear..x' of <validity> of data port 'cmd' is not a field path (field names separated by "
              "'.', e.g. linear.x): it has an empty field name ('.' first, last or twice)",
          f + "16: unknown element <queue_size> in <data_port>",
          f + "22: <topic> '/sonar//a' of data port 'range' is not a ROS 2 topic name: it has an empty token ('//')",
          f + "23: <deadline> of data port 'range'" + input, f + "24: <liveliness> of data port 'range'" + input,
          f + "25: <validity field=\"range\"> of data port 'range': min 5 is greater than max 1",
          f + "26: duplicate <validity field=\"range\"> in data port 'range' (first at line 25)",
          f + "28: duplicate port 'cmd' in node profile 'Ports' (first at line 7)",
          f + "31: missing <usage> in data port 'other'", f + "31: missing <data_type> in data port 'other'",
          f + "31: missing <topic> in data port 'other'",
          f + "37: data ports 'twin' (line 34) and 'twin2' are both on topic '/same': a topic is one port of a node",
          f + "40: <event_port> in node profile 'Ports': only data ports are supported for nodes (a node's port is "
              "one of its topics)",
          f + "41: <service_port> in node profile 'Ports': only data ports are supported for nodes (a node's port is "
              "one of its topics)",
          f + "42: missing <name> in <data_port>"));
}

TEST(NodeProfileErrors, RejectsBadEmergencyCommands) {
  const std::string f = "errors/node/emergency.xml:";
  const std::string of = " of <publish> of <emergency> of node profile 'Halt'";
  EXPECT_THAT(
      problems("errors/node/emergency.xml"),
      ElementsAre(f + "8: duplicate <stop> in <emergency> (first at line 7)",
                  f + "9: type 'std_msgs/msg/Bool'" + of +
                      ": data port 'cmd' on topic '/cmd_vel' has data_type 'geometry_msgs/msg/Twist'",
                  f + "10: topic 'cmd'" + of +
                      " is not a ROS 2 topic name: topic name must be absolute, it must lead with a '/' (a node "
                      "resolves a relative name in its own namespace)",
                  f + "11: type 'Twist'" + of +
                      " is not a ROS 2 message type: it must be written as ROS 2 writes it: package/msg/Name, e.g. "
                      "std_msgs/msg/Float64",
                  f + "12: rate" + of + " (Hz) must be a positive number, got '0'",
                  f + "14: duplicate <publish topic=\"/c\"> in <emergency> of node profile 'Halt' (first at line 13)",
                  f + "15: missing attribute 'topic' of <publish>", f + "16: unknown attribute 'hz' of <publish>",
                  f + "17: duplicate <stop> in <emergency> (first at line 7)"));
}

TEST(NodeProfileErrors, RejectsNodeSubcomponentsUsedAsComponentsAndTheReverse) {
  const std::string f = "errors/node/package.xml:";
  const std::string attach =
      " is not a ROS 2 node (keel attaches to a node someone else started; its reference must "
      "be a <ros2_node_profile>)";
  EXPECT_THAT(
      problems("errors/node/package.xml"),
      ElementsAre(
          f + "5: subcomponent 'pkg': '../../valid/app.xml' is a <package_profile>, expected <component_profile>, "
              "<composite_component_profile> or <ros2_node_profile>",
          f + "6: <attach/> of subcomponent 'sonar': component 'RangeSensor'" + attach,
          f + "7: subcomponent 'sonar': alternative 'Wander' is a ROS 2 node, but 'RangeSensor' is a component: only a "
              "node's alternative may be a <ros2_node_profile>",
          f + "8: <attach/> of subcomponent 'array': composite 'SonarArray'" + attach,
          f + "13: <process> of subcomponent 'wander': a ROS 2 node is a process of its own, and with <attach/> "
              "someone else starts it",
          f + "14: subcomponent 'wander': alternative 'Planner' is a component, but 'Wander' is a ROS 2 node: a node's "
              "alternative is another <ros2_node_profile>",
          f + "17: subcomponent 'watcher' has <type> atomic but '../../node/minimal.xml' is a <ros2_node_profile>",
          f + "18: unexpected text 'now' in <attach>",
          f + "18: subcomponents 'watcher' (line 17) and 'calm' are both ROS 2 node '/minimal' (one node, one "
              "subcomponent)",
          f + "21: port_connection: data types differ: 'wander.cmd' is 'geometry_msgs/msg/Twist', 'nav.range' is "
              "'double'",
          f + "27: task 'control': subcomponent 'wander' is a ROS 2 node (node profile 'Wander') and cannot be a task "
              "member: it runs in a process of its own"));
}

TEST(NodeProfileErrors, ANodesAlternativeMustBeTheSameNodeToTheGraph) {
  // It takes the role's name, topics and status: each difference is an error at <alternative>.
  const std::string f = "errors/node/alternative.xml:8: subcomponent 'wander': alternative 'WanderElsewhere'";
  EXPECT_THAT(problems("errors/node/alternative.xml"),
              ElementsAre(f + " is node '/robot/wander_backup', not '/robot/wander': it takes the node's place in the "
                              "ROS 2 graph, under its name",
                          f + ": its <diagnostics name> is none, the node's \"wander: status\": keel reads one status "
                              "for the role",
                          f + ": port 'cmd' is on topic '/backup/cmd_vel', the node's on '/cmd_vel': it takes the "
                              "node's place on its topics",
                          f + ": port 'range' is on topic '/sonar/b', the node's on '/sonar/a': it takes the node's "
                              "place on its topics"));
}

TEST(NodeProfileErrors, AConnectionCarriesAFieldOfItsSourceToADoubleInput) {
  // The first connection is right: wander.cmd's linear.x to nav's double input.
  const std::string f = "errors/node/field.xml:";
  EXPECT_THAT(problems("errors/node/field.xml"),
              ElementsAre(f + "14: field of <target>: a connection carries a field of its source's messages",
                          f + "16: port_connection: field 'linear.x' of source 'wander.cmd' is a number, but target "
                              "'planner.cmd' is 'geometry_msgs/msg/Twist' (a field goes to a 'double' input)",
                          f + "20: empty field of <source>: a dotted path to a number of the port's messages"));
}

}  // namespace
}  // namespace keel::profile::test
