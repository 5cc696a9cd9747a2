// Composite profiles (OPRoS composite_component_profile): subcomponents, internal connections,
// exported ports in both spellings, nesting, reference cycles, and their error messages.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;

TEST(CompositeProfile, ReadsSubcomponentsConnectionsAndExportedPorts) {
  const auto result = load(dataPath("valid/SonarArray.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  EXPECT_EQ(result->root_kind, RootKind::Composite);
  EXPECT_EQ(result->rootPackage(), nullptr);
  const CompositeProfile& c = result->composites.at(keyOf("valid/SonarArray.xml"));
  EXPECT_EQ(c.name, "SonarArray");
  EXPECT_EQ(c.description, "Three sonars and a median voter (paper §5.1.4)");
  ASSERT_EQ(c.subcomponents.size(), 4u);
  EXPECT_EQ(c.subcomponents[3].reference, keyOf("valid/Voter.xml"));
  ASSERT_EQ(c.connections.size(), 3u);
  EXPECT_FALSE(c.connections[2].port_type_given);  // inferred from the ports
  EXPECT_EQ(c.connections[2].port_type, PortKind::Data);
  ASSERT_EQ(c.exported_ports.size(), 2u);
  EXPECT_EQ(c.exported_ports[0].name, "distance");  // attribute form
  EXPECT_EQ(c.exported_ports[0].inner.component, "voter");
  EXPECT_EQ(c.exported_ports[0].inner.port, "out");
  EXPECT_EQ(c.exported_ports[1].name, "threshold");  // OPRoS element form
  EXPECT_EQ(c.exported_ports[1].inner.component, "s1");
  EXPECT_EQ(c.exported_ports[1].inner.port, "threshold");
  EXPECT_EQ(result->components.size(), 2u);  // Sonar.xml once for s1..s3, Voter.xml
}

TEST(CompositeProfile, ConnectsThroughExportedPortsOfNestedComposites) {
  const auto result = load(dataPath("valid/composite_app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  EXPECT_EQ(result->composites.size(), 2u);
  const CompositeProfile& perception = result->composites.at(keyOf("valid/Perception.xml"));
  EXPECT_EQ(perception.subcomponents[0].reference, keyOf("valid/SonarArray.xml"));
  EXPECT_EQ(result->rootPackage()->connections[0].source.port, "range");
}

TEST(CompositeProfileErrors, RejectsAnExportOfAnUnknownSubcomponent) {
  EXPECT_THAT(problems("errors/composite/export_unknown_component.xml"),
              ElementsAre("errors/composite/export_unknown_component.xml:9: export_port 'out': no subcomponent 'votr' "
                          "(subcomponents: s1, voter)"));
}

TEST(CompositeProfileErrors, RejectsAnExportOfAnUnknownPort) {
  EXPECT_THAT(problems("errors/composite/export_unknown_port.xml"),
              ElementsAre("errors/composite/export_unknown_port.xml:9: export_port 'out': component 'voter' has no "
                          "port 'output' (ports: in1, in2, in3, out)"));
}

TEST(CompositeProfileErrors, RejectsTwoExportsWithOneName) {
  EXPECT_THAT(problems("errors/composite/export_duplicate_name.xml"),
              ElementsAre(
                  "errors/composite/export_duplicate_name.xml:10: duplicate export_port 'out' (first at line 9)"));
}

TEST(CompositeProfileErrors, RejectsAnExportMixingAttributesAndElements) {
  EXPECT_THAT(problems("errors/composite/export_mixed_forms.xml"),
              ElementsAre("errors/composite/export_mixed_forms.xml:9: <export_port> mixes attributes (name, component, "
                          "port) and child elements (export_port_name, component_name, port_name)"));
}

TEST(CompositeProfileErrors, RejectsAnOprosExportWithoutPortName) {
  EXPECT_THAT(problems("errors/composite/export_missing_port_name.xml"),
              ElementsAre("errors/composite/export_missing_port_name.xml:9: missing <port_name> in <export_port>"));
}

TEST(CompositeProfileErrors, RejectsAnExportWithoutPortAttribute) {
  EXPECT_THAT(problems("errors/composite/export_missing_attribute.xml"),
              ElementsAre(
                  "errors/composite/export_missing_attribute.xml:9: missing attribute 'port' of <export_port>"));
}

TEST(CompositeProfileErrors, RejectsACompositeIncludingItself) {
  EXPECT_THAT(problems("errors/composite/SelfComposite.xml"),
              ElementsAre("errors/composite/SelfComposite.xml:5: subcomponent 'me': circular reference: "
                          "errors/composite/SelfComposite.xml -> errors/composite/SelfComposite.xml"));
}

TEST(CompositeProfileErrors, RejectsCompositesIncludingEachOtherWithTheCycle) {
  EXPECT_THAT(problems("errors/composite/CycleA.xml"),
              ElementsAre("errors/composite/CycleB.xml:5: subcomponent 'a': circular reference: "
                          "errors/composite/CycleA.xml -> errors/composite/CycleB.xml -> errors/composite/CycleA.xml"));
}

TEST(CompositeProfileErrors, RejectsAConnectionToAPortTheCompositeDoesNotExport) {
  EXPECT_THAT(problems("errors/composite/connection_to_unexported_port.xml"),
              ElementsAre("errors/composite/connection_to_unexported_port.xml:9: port_connection: component 'array' "
                          "has no port 'alarm' (ports: distance, threshold)"));
}

}  // namespace
}  // namespace keel::profile::test
