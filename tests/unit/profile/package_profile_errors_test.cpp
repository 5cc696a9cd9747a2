// Every error message of a package profile (subcomponents, overrides, connections, tasks,
// coordination): the invalid fixture under data/errors/package and its exact diagnostic.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;

TEST(PackageProfileErrors, RejectsAMissingReferencedFileNamingTheSubcomponent) {
  EXPECT_THAT(problems("errors/package/missing_reference_file.xml"),
              ElementsAre("errors/package/missing_reference_file.xml:7: subcomponent 'sonar': cannot open 'Sonar.xml': "
                          "No such file or directory (nor in OPRoS's layouts: missing_reference_file/Sonar.xml, "
                          "sonar/Sonar.xml, missing_reference_file/Sonar/Sonar.xml, ../Sonar/profile/Sonar.xml, "
                          "../Sonar/Sonar.xml)"));
}

TEST(PackageProfileErrors, RejectsAReferenceToAPackageWhereAComponentIsExpected) {
  EXPECT_THAT(problems("errors/package/wrong_reference_kind.xml"),
              ElementsAre("errors/package/wrong_reference_kind.xml:7: subcomponent 'inner': '../../valid/app.xml' is a "
                          "<package_profile>, expected <component_profile>, <composite_component_profile> or "
                          "<ros2_node_profile>"));
}

TEST(PackageProfileErrors, RejectsADeclaredTypeThatDisagreesWithTheReferencedProfile) {
  EXPECT_THAT(problems("errors/package/declared_type_mismatch.xml"),
              ElementsAre("errors/package/declared_type_mismatch.xml:7: subcomponent 'sonar' has <type> composite but "
                          "'../../valid/Sonar.xml' is a <component_profile>"));
}

TEST(PackageProfileErrors, RejectsAnUnknownSubcomponentType) {
  EXPECT_THAT(problems("errors/package/bad_subcomponent_type.xml"),
              ElementsAre("errors/package/bad_subcomponent_type.xml:8: <type> of subcomponent 'sonar' must be one of "
                          "atomic or composite, got 'basic'"));
}

TEST(PackageProfileErrors, RejectsAnEmptyReference) {
  EXPECT_THAT(problems("errors/package/empty_reference.xml"),
              ElementsAre("errors/package/empty_reference.xml:7: subcomponent 'sonar': empty reference"));
}

TEST(PackageProfileErrors, RejectsASubcomponentWithoutReference) {
  EXPECT_THAT(problems("errors/package/missing_reference_element.xml"),
              ElementsAre(
                  "errors/package/missing_reference_element.xml:5: missing <reference> in subcomponent 'sonar'"));
}

TEST(PackageProfileErrors, RejectsTwoSubcomponentsWithOneName) {
  EXPECT_THAT(problems("errors/package/duplicate_subcomponent.xml"),
              ElementsAre(
                  "errors/package/duplicate_subcomponent.xml:9: duplicate subcomponent 'sonar' (first at line 5)"));
}

TEST(PackageProfileErrors, RejectsAPackageWithoutName) {
  EXPECT_THAT(problems("errors/package/missing_package_name.xml"),
              ElementsAre("errors/package/missing_package_name.xml:2: missing <name> in <package_profile>"));
}

TEST(PackageProfileErrors, RejectsAnOverrideOfAPropertyTheComponentDoesNotHave) {
  EXPECT_THAT(problems("errors/package/override_unknown_property.xml"),
              ElementsAre("errors/package/override_unknown_property.xml:9: subcomponent 'sonar': component 'Sonar' has "
                          "no property 'gian' (properties: gain, samples, enabled, frame, offsets)"));
}

// A property declared refers="ports" (the stock state estimator's `measurements`) names numeric
// output ports of the subcomponents beside it: each one that is not is said at the property.
TEST(PackageProfileErrors, RejectsAPortReferenceToAnythingButANumericOutputPortBesideIt) {
  const std::string f = "errors/package/refers_ports.xml";
  const std::string at = f + ":11: property 'measurements' of subcomponent 'estimator': ";
  EXPECT_THAT(problems(f),
              ElementsAre(at + "'near=sonar.threshold' names no output port 'threshold' of subcomponent 'sonar' (its "
                               "output ports: distance)",
                          at + "'sonar.range' names no output port 'range' of subcomponent 'sonar' (its output ports: "
                               "distance)",
                          at + "'ghost.out' names no subcomponent 'ghost' (subcomponents: sonar, labeller, estimator)",
                          at + "'labeller.label' is not numeric: port 'label' of subcomponent 'labeller' carries "
                               "'std::string'",
                          at + "'sonar' is not [name=]subcomponent.port"));
}

TEST(PackageProfileErrors, RejectsAnOverrideValueThatDoesNotParseAsTheDeclaredType) {
  EXPECT_THAT(problems("errors/package/override_bad_value.xml"),
              ElementsAre("errors/package/override_bad_value.xml:9: property 'gain' of subcomponent 'sonar' must be a "
                          "finite double, got 'high'"));
}

TEST(PackageProfileErrors, RejectsAnOverrideTypeThatDisagreesWithTheDeclaration) {
  EXPECT_THAT(problems("errors/package/override_type_disagrees.xml"),
              ElementsAre("errors/package/override_type_disagrees.xml:9: property 'gain' of subcomponent 'sonar' has "
                          "type 'int' but component 'Sonar' declares it 'double'"));
}

TEST(PackageProfileErrors, RejectsAnOverrideWithAnUnknownType) {
  EXPECT_THAT(problems("errors/package/override_unknown_type.xml"),
              ElementsAre("errors/package/override_unknown_type.xml:9: property 'gain' of subcomponent 'sonar' has "
                          "unknown type 'real' (types: bool, int, double, string, double[])"));
}

TEST(PackageProfileErrors, RejectsTheSamePropertyOverriddenTwice) {
  EXPECT_THAT(problems("errors/package/override_duplicate.xml"),
              ElementsAre("errors/package/override_duplicate.xml:10: duplicate property 'gain' in subcomponent 'sonar' "
                          "(first at line 9)"));
}

TEST(PackageProfileErrors, RejectsAPropertyOverrideOnAComposite) {
  EXPECT_THAT(problems("errors/package/override_on_composite.xml"),
              ElementsAre("errors/package/override_on_composite.xml:9: subcomponent 'array': composite 'SonarArray' "
                          "has no property 'gain' (properties: none)"));
}

TEST(PackageProfileErrors, RejectsAConnectionToAnUnknownSubcomponent) {
  EXPECT_THAT(problems("errors/package/connection_unknown_component.xml"),
              ElementsAre("errors/package/connection_unknown_component.xml:19: port_connection: no subcomponent 'sonr' "
                          "(subcomponents: sonar, nav, map)"));
}

TEST(PackageProfileErrors, RejectsAConnectionToAnUnknownPortListingThePorts) {
  EXPECT_THAT(problems("errors/package/connection_unknown_port.xml"),
              ElementsAre("errors/package/connection_unknown_port.xml:19: port_connection: component 'sonar' has no "
                          "port 'distanse' (ports: distance, threshold, alarm)"));
}

TEST(PackageProfileErrors, RejectsAnUnknownPortType) {
  EXPECT_THAT(problems("errors/package/connection_bad_port_type.xml"),
              ElementsAre("errors/package/connection_bad_port_type.xml:19: port_type of <port_connection> must be one "
                          "of data, event or service, got 'stream'"));
}

TEST(PackageProfileErrors, RejectsPortsOfAnotherKindThanThePortType) {
  EXPECT_THAT(problems("errors/package/connection_kind_mismatch.xml"),
              ElementsAre("errors/package/connection_kind_mismatch.xml:19: port_connection: port 'sonar.alarm' is an "
                          "event port, but port_type is data",
                          "errors/package/connection_kind_mismatch.xml:19: port_connection: port 'nav.alarm' is an "
                          "event port, but port_type is data"));
}

TEST(PackageProfileErrors, RejectsAConnectionWithoutPortTypeBetweenPortsOfDifferentKinds) {
  EXPECT_THAT(problems("errors/package/connection_inferred_kinds_differ.xml"),
              ElementsAre("errors/package/connection_inferred_kinds_differ.xml:19: port_connection: 'sonar.alarm' is "
                          "an event port but 'nav.range' is a data port"));
}

TEST(PackageProfileErrors, RejectsAnInputPortAsSource) {
  EXPECT_THAT(problems("errors/package/connection_source_is_input.xml"),
              ElementsAre("errors/package/connection_source_is_input.xml:19: port_connection: source 'nav.range' is an "
                          "input data port of data_type 'double'; a source must be an output port"));
}

TEST(PackageProfileErrors, RejectsAnOutputPortAsTarget) {
  EXPECT_THAT(problems("errors/package/connection_target_is_output.xml"),
              ElementsAre("errors/package/connection_target_is_output.xml:19: port_connection: target 'nav.limit' is "
                          "an output data port of data_type 'double'; a target must be an input port"));
}

TEST(PackageProfileErrors, RejectsAServiceConnectionFromProvidedToRequired) {
  EXPECT_THAT(problems("errors/package/connection_service_reversed.xml"),
              ElementsAre("errors/package/connection_service_reversed.xml:19: port_connection: source 'map.map' is a "
                          "provided service port of type 'MapService'; a source must be a required service port",
                          "errors/package/connection_service_reversed.xml:19: port_connection: target 'nav.map' is a "
                          "required service port of type 'MapService'; a target must be a provided service port"));
}

TEST(PackageProfileErrors, RejectsDifferentDataTypesAtTheTwoEnds) {
  EXPECT_THAT(problems("errors/package/connection_data_types_differ.xml"),
              ElementsAre("errors/package/connection_data_types_differ.xml:23: port_connection: data types differ: "
                          "'voter.out' is 'float', 'sonar.threshold' is 'double'"));
}

TEST(PackageProfileErrors, RejectsDifferentServiceTypesAtTheTwoEnds) {
  EXPECT_THAT(problems("errors/package/connection_service_types_differ.xml"),
              ElementsAre("errors/package/connection_service_types_differ.xml:23: port_connection: service types "
                          "differ: 'nav.map' is 'MapService', 'planner.plan' is 'PlanService'"));
}

TEST(PackageProfileErrors, RejectsARequiredServicePortBoundToTwoProviders) {
  EXPECT_THAT(problems("errors/package/connection_required_twice.xml"),
              ElementsAre("errors/package/connection_required_twice.xml:27: port_connection: required service port "
                          "'nav.map' is already connected to 'map.map' (line 23)"));
}

TEST(PackageProfileErrors, RejectsTheSameConnectionListedTwice) {
  EXPECT_THAT(problems("errors/package/connection_duplicate.xml"),
              ElementsAre("errors/package/connection_duplicate.xml:23: duplicate port_connection 'sonar.distance' -> "
                          "'nav.range' (first at line 19)"));
}

TEST(PackageProfileErrors, RejectsAConnectionWithoutTarget) {
  EXPECT_THAT(problems("errors/package/connection_missing_target.xml"),
              ElementsAre("errors/package/connection_missing_target.xml:19: missing <target> in <port_connection>"));
}

TEST(PackageProfileErrors, RejectsAnEndpointWithoutPortName) {
  EXPECT_THAT(problems("errors/package/connection_missing_port_name.xml"),
              ElementsAre(
                  "errors/package/connection_missing_port_name.xml:20: missing attribute 'port_name' of <source>"));
}

TEST(PackageProfileErrors, RejectsATaskMemberThatIsNoSubcomponent) {
  EXPECT_THAT(problems("errors/package/task_unknown_member.xml"),
              ElementsAre("errors/package/task_unknown_member.xml:19: task 'control': no subcomponent 'snoar' "
                          "(subcomponents: sonar, nav, map)"));
}

TEST(PackageProfileErrors, RejectsASubcomponentInTwoTasks) {
  EXPECT_THAT(problems("errors/package/task_member_in_two_tasks.xml"),
              ElementsAre("errors/package/task_member_in_two_tasks.xml:22: task 'slow': subcomponent 'sonar' is "
                          "already in task 'fast' (line 19)"));
}

TEST(PackageProfileErrors, RejectsATaskListingAMemberTwice) {
  EXPECT_THAT(problems("errors/package/task_member_twice.xml"),
              ElementsAre("errors/package/task_member_twice.xml:19: task 'control' lists member 'sonar' twice"));
}

TEST(PackageProfileErrors, RejectsAPassiveComponentAsTaskMember) {
  EXPECT_THAT(problems("errors/package/task_passive_member.xml"),
              ElementsAre("errors/package/task_passive_member.xml:19: task 'control': subcomponent 'map' is passive "
                          "(component 'MapServer') and cannot be a task member"));
}

TEST(PackageProfileErrors, RejectsTwoTasksWithOneName) {
  EXPECT_THAT(problems("errors/package/task_duplicate_name.xml"),
              ElementsAre("errors/package/task_duplicate_name.xml:22: duplicate task 'control' (first at line 19)"));
}

TEST(PackageProfileErrors, RejectsATaskWithoutMembers) {
  EXPECT_THAT(problems("errors/package/task_without_members.xml"),
              ElementsAre("errors/package/task_without_members.xml:19: task 'control' has no <member>"));
}

TEST(PackageProfileErrors, RejectsANegativeTaskPeriod) {
  EXPECT_THAT(
      problems("errors/package/task_bad_period.xml"),
      ElementsAre(
          "errors/package/task_bad_period.xml:19: period of task 'control' must be a positive number, got '-10'"));
}

TEST(PackageProfileErrors, RejectsATaskWithoutPeriod) {
  EXPECT_THAT(problems("errors/package/task_missing_period.xml"),
              ElementsAre("errors/package/task_missing_period.xml:19: missing attribute 'period' of <task>"));
}

TEST(PackageProfileErrors, RejectsAFifoTaskWithoutPriority) {
  EXPECT_THAT(problems("errors/package/task_fifo_without_priority.xml"),
              ElementsAre("errors/package/task_fifo_without_priority.xml:19: policy fifo of task 'control' needs a "
                          "priority from 1 to 99"));
}

TEST(PackageProfileErrors, RejectsAnUnknownTaskPolicy) {
  EXPECT_THAT(problems("errors/package/task_bad_policy.xml"),
              ElementsAre("errors/package/task_bad_policy.xml:19: policy of task 'control' must be one of other, fifo "
                          "or rr, got 'deadline'"));
}

TEST(PackageProfileErrors, RejectsAMisspeltTaskAttribute) {
  EXPECT_THAT(problems("errors/package/task_unknown_attribute.xml"),
              ElementsAre("errors/package/task_unknown_attribute.xml:19: unknown attribute 'peroid' of <task>",
                          "errors/package/task_unknown_attribute.xml:19: missing attribute 'period' of <task>"));
}

TEST(PackageProfileErrors, RejectsAMemberNamedBothAsAttributeAndText) {
  EXPECT_THAT(problems("errors/package/task_member_both_forms.xml"),
              ElementsAre("errors/package/task_member_both_forms.xml:20: <member> of task 'control' names a component "
                          "both as attribute and as text"));
}

TEST(PackageProfileErrors, RejectsAnEmptyMember) {
  EXPECT_THAT(problems("errors/package/task_empty_member.xml"),
              ElementsAre("errors/package/task_empty_member.xml:20: <member> of task 'control' names no component"));
}

TEST(PackageProfileErrors, RejectsADependencyOnAnUnknownSubcomponent) {
  EXPECT_THAT(
      problems("errors/package/depends_unknown.xml"),
      ElementsAre(
          "errors/package/depends_unknown.xml:19: depends: no subcomponent 'sonra' (subcomponents: sonar, nav, map)"));
}

TEST(PackageProfileErrors, RejectsASelfDependency) {
  EXPECT_THAT(problems("errors/package/depends_self.xml"),
              ElementsAre("errors/package/depends_self.xml:19: depends: subcomponent 'nav' cannot depend on itself"));
}

TEST(PackageProfileErrors, RejectsADependencyListedTwice) {
  EXPECT_THAT(problems("errors/package/depends_duplicate.xml"),
              ElementsAre(
                  "errors/package/depends_duplicate.xml:20: duplicate depends 'nav' -> 'sonar' (first at line 19)"));
}

TEST(PackageProfileErrors, RejectsCircularDependenciesWithTheCycle) {
  EXPECT_THAT(problems("errors/package/depends_cycle.xml"),
              ElementsAre("errors/package/depends_cycle.xml:19: circular dependency: sonar -> map -> nav -> sonar"));
}

TEST(PackageProfileErrors, RejectsADependsWithoutTarget) {
  EXPECT_THAT(problems("errors/package/depends_missing_target.xml"),
              ElementsAre("errors/package/depends_missing_target.xml:19: missing attribute 'target' of <depends>"));
}

}  // namespace
}  // namespace keel::profile::test
