// Valid package (application) profiles: subcomponents with typed overrides, connections,
// tasks, coordination, referenced files loaded once, and a plain OPRoS application profile.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;
using ::testing::Pair;
using ::testing::UnorderedElementsAre;

std::vector<std::string> keys(const std::map<std::string, ComponentProfile>& components) {
  std::vector<std::string> out;
  out.reserve(components.size());
  for (const auto& [path, c] : components) out.push_back(path);
  return out;
}

TEST(PackageProfile, ReadsSubcomponentsWithAbsoluteReferences) {
  const auto result = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  ASSERT_NE(result->rootPackage(), nullptr);
  const PackageProfile& pkg = *result->rootPackage();
  EXPECT_EQ(pkg.name, "Navigation");
  EXPECT_EQ(pkg.description, "Target following with obstacle avoidance");
  EXPECT_EQ(pkg.file, keyOf("valid/app.xml"));
  ASSERT_EQ(pkg.subcomponents.size(), 3u);
  EXPECT_EQ(pkg.subcomponents[0].name, "sonar");
  EXPECT_EQ(pkg.subcomponents[0].reference, keyOf("valid/Sonar.xml"));
  EXPECT_EQ(pkg.subcomponents[1].reference, keyOf("valid/Nav.xml"));  // written "./Nav.xml"
  EXPECT_EQ(pkg.subcomponents[2].where.line, 31);
  EXPECT_THAT(keys(result->components),
              UnorderedElementsAre(keyOf("valid/Sonar.xml"), keyOf("valid/Nav.xml"), keyOf("valid/MapServer.xml"),
                                   keyOf("valid/SonarBackup.xml")));
}

TEST(PackageProfile, TypesPropertyOverridesAgainstTheComponentProfile) {
  const auto result = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const Subcomponent& sonar = result->rootPackage()->subcomponents[0];

  ASSERT_EQ(sonar.property_overrides.size(), 2u);
  const Property& gain = sonar.property_overrides.at("gain");
  EXPECT_EQ(gain.type, "double");  // from Sonar.xml, written "2"
  EXPECT_DOUBLE_EQ(std::get<double>(gain.value), 2.0);
  const Property& offsets = sonar.property_overrides.at("offsets");
  EXPECT_EQ(offsets.type, "double[]");
  EXPECT_THAT(std::get<std::vector<double>>(offsets.value), ElementsAre(1.0, 2.0));
  EXPECT_TRUE(result->rootPackage()->subcomponents[1].property_overrides.empty());
}

TEST(PackageProfile, ReadsConnectionsOfEveryPortType) {
  const auto result = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const auto& cs = result->rootPackage()->connections;

  ASSERT_EQ(cs.size(), 4u);
  EXPECT_EQ(cs[0].port_type, PortKind::Data);
  EXPECT_EQ(cs[0].source.component, "sonar");
  EXPECT_EQ(cs[0].source.port, "distance");
  EXPECT_EQ(cs[0].target.component, "nav");
  EXPECT_EQ(cs[0].target.port, "range");
  EXPECT_TRUE(cs[0].port_type_given);
  EXPECT_EQ(cs[2].port_type, PortKind::Event);
  EXPECT_EQ(cs[3].port_type, PortKind::Service);
  EXPECT_EQ(cs[3].where.line, 49);
}

TEST(PackageProfile, ReadsTasksWithMembersInOrder) {
  const auto result = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const auto& tasks = result->rootPackage()->tasks;

  ASSERT_EQ(tasks.size(), 1u);
  EXPECT_EQ(tasks[0].name, "control");
  EXPECT_DOUBLE_EQ(tasks[0].period_ms, 10.0);
  EXPECT_EQ(tasks[0].priority, 30);
  EXPECT_EQ(tasks[0].policy, SchedPolicy::Fifo);
  EXPECT_THAT(tasks[0].members, ElementsAre("sonar", "nav"));  // attribute and text forms
}

TEST(PackageProfile, ReadsTheExecutionOrderAndTheStopDependencies) {
  const auto result = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const Coordination& c = result->rootPackage()->coordination;

  ASSERT_EQ(c.depends.size(), 1u);  // OPRoS's execution order
  EXPECT_EQ(c.depends[0].source, "nav");
  EXPECT_EQ(c.depends[0].target, "sonar");
  ASSERT_EQ(c.needs.size(), 1u);  // keel's stop dependency
  EXPECT_EQ(c.needs[0].source, "nav");
  EXPECT_EQ(c.needs[0].target, "map");
}

TEST(PackageProfile, LoadsAFileReferencedSeveralTimesOnce) {
  const auto result = load(dataPath("system/robot.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  EXPECT_EQ(result->rootPackage()->subcomponents.size(), 5u);
  EXPECT_THAT(keys(result->components),
              UnorderedElementsAre(keyOf("valid/Sonar.xml"), keyOf("valid/Nav.xml"), keyOf("valid/MapServer.xml")));
}

TEST(PackageProfile, AcceptsFanInToAnInputAndFanOutFromAnOutput) {
  const auto result = load(dataPath("system/robot.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  int into_range = 0, from_limit = 0;
  for (const Connection& c : result->rootPackage()->connections) {
    into_range += c.target.component == "nav" && c.target.port == "range";
    from_limit += c.source.component == "nav" && c.source.port == "limit";
  }
  EXPECT_EQ(into_range, 3);
  EXPECT_EQ(from_limit, 2);
}

TEST(PackageProfile, LoadsAPlainOprosApplicationProfileInferringThePortType) {
  const auto result = load(dataPath("opros/VisionApp.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  EXPECT_EQ(result->root_kind, RootKind::Package);
  const PackageProfile& pkg = *result->rootPackage();
  EXPECT_EQ(pkg.name, "VisionApp");
  ASSERT_EQ(pkg.connections.size(), 1u);
  EXPECT_FALSE(pkg.connections[0].port_type_given);
  EXPECT_EQ(pkg.connections[0].port_type, PortKind::Data);
  EXPECT_EQ(result->components.size(), 1u);  // Brightness.xml, referenced twice
}

TEST(PackageProfile, KeepsDeclarationLinesForLaterStages) {
  const auto result = load(dataPath("valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  const PackageProfile& pkg = *result->rootPackage();

  EXPECT_EQ(relative(pkg.where.file), "valid/app.xml");
  EXPECT_EQ(pkg.where.line, 2);
  EXPECT_EQ(pkg.tasks[0].where.line, 55);
  EXPECT_THAT(std::vector<int>({pkg.coordination.depends[0].where.line, pkg.coordination.needs[0].where.line}),
              ElementsAre(61, 62));
  EXPECT_THAT(pkg.subcomponents[0].property_overrides,
              ::testing::Contains(
                  Pair("gain", ::testing::Field(&Property::where, ::testing::Field(&Where::line, 11)))));
}

}  // namespace
}  // namespace keel::profile::test
