// Connections between the applications of a system profile: endpoints "application.subcomponent"
// (a composite's exported ports included), checked exactly as a package's connections, and
// planned with the instances' absolute names; every error message with its exact diagnostic.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "plan/plan.hpp"
#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;

TEST(SystemConnections, AreReadWithApplicationQualifiedEndpoints) {
  const auto result = load(dataPath("system/connected.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  const auto& connections = result->system->connections;
  ASSERT_EQ(connections.size(), 2u);
  EXPECT_EQ(connections[0].source.component, "obstacle.array");  // a composite's exported port
  EXPECT_EQ(connections[0].source.port, "distance");
  EXPECT_EQ(connections[0].target.component, "navigation.nav");
  EXPECT_EQ(connections[0].port_type, PortKind::Data);
  EXPECT_EQ(connections[0].where.line, 13);
  EXPECT_FALSE(connections[1].port_type_given);
  EXPECT_EQ(connections[1].port_type, PortKind::Data);  // taken from the ports, as in a package
}

TEST(SystemConnections, ArePlannedBetweenAbsoluteInstanceNamesThroughExports) {
  const auto result = load(dataPath("system/connected.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  const auto plan = plan::makePlan(*result);
  ASSERT_TRUE(plan) << plan.error().message;
  std::vector<std::string> edges;
  for (const auto& c : plan->connections)
    edges.push_back(c.source.component + "." + c.source.port + " -> " + c.target.component + "." + c.target.port);
  EXPECT_THAT(edges,
              ElementsAre(
                  // the composite's own, prefixed with the application and the instance
                  "obstacle.array.s1.distance -> obstacle.array.voter.in1",
                  "obstacle.array.s2.distance -> obstacle.array.voter.in2",
                  "obstacle.array.s3.distance -> obstacle.array.voter.in3", "navigation.nav.map -> navigation.map.map",
                  // the system's: exported ports resolved to the inner ones
                  "obstacle.array.voter.out -> navigation.nav.range",
                  "navigation.nav.limit -> obstacle.sonar.threshold"));
}

TEST(SystemConnectionsErrors, AreCheckedAsAPackagesConnectionsAre) {
  EXPECT_THAT(
      problems("errors/system/connections.xml"),
      ElementsAre("errors/system/connections.xml:10: port_connection: no subcomponent 'navigation.navv' "
                  "(subcomponents: obstacle.array, obstacle.sonar, navigation.nav, navigation.map, odometry.odo)",
                  "errors/system/connections.xml:14: port_connection: component 'obstacle.array' has no port "
                  "'out' (ports: distance, threshold)",
                  "errors/system/connections.xml:18: port_connection: port 'obstacle.sonar.alarm' is an event "
                  "port, but port_type is data",
                  "errors/system/connections.xml:22: port_connection: 'obstacle.sonar.distance' is a data port "
                  "but 'navigation.nav.alarm' is an event port",
                  "errors/system/connections.xml:26: port_connection: source 'navigation.nav.range' is an input "
                  "data port of data_type 'double'; a source must be an output port",
                  "errors/system/connections.xml:30: port_connection: data types differ: 'odometry.odo.out' is "
                  "'float', 'navigation.nav.range' is 'double'",
                  "errors/system/connections.xml:38: duplicate port_connection 'obstacle.array.distance' -> "
                  "'navigation.nav.range' (first at line 34)"));
}

TEST(SystemConnectionsErrors, ToAnApplicationThatFailedToLoadAreNotCheckedAgain) {
  EXPECT_THAT(problems("errors/system/connection_to_unloaded_application.xml"),
              ElementsAre("errors/system/connection_to_unloaded_application.xml:6: application "
                          "'navigation': cannot open 'no_such_package.xml': No such file or directory"));
}

}  // namespace
}  // namespace keel::profile::test
