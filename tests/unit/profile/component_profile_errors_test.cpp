// Every error message of a component profile: the invalid fixture under
// data/errors/component and the exact `file:line: message` it must produce.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;

TEST(ComponentProfileErrors, RejectsAMisspeltElementNamingItsParent) {
  EXPECT_THAT(problems("errors/component/unknown_element.xml"),
              ElementsAre(
                  "errors/component/unknown_element.xml:5: unknown element <librry_name> in <execution_environment>"));
}

TEST(ComponentProfileErrors, RejectsAnUnknownAttribute) {
  EXPECT_THAT(problems("errors/component/unknown_attribute.xml"),
              ElementsAre("errors/component/unknown_attribute.xml:5: unknown attribute 'unit' of <property>"));
}

TEST(ComponentProfileErrors, RejectsASingletonElementGivenTwice) {
  EXPECT_THAT(
      problems("errors/component/duplicate_element.xml"),
      ElementsAre(
          "errors/component/duplicate_element.xml:5: duplicate <name> in <component_profile> (first at line 3)"));
}

TEST(ComponentProfileErrors, RejectsTextInAContainerElement) {
  EXPECT_THAT(problems("errors/component/stray_text.xml"),
              ElementsAre("errors/component/stray_text.xml:4: unexpected text 'oops' in <ports>"));
}

TEST(ComponentProfileErrors, RejectsAnElementInsideATextElement) {
  EXPECT_THAT(problems("errors/component/element_inside_leaf.xml"),
              ElementsAre("errors/component/element_inside_leaf.xml:4: unknown element <b> in <description>"));
}

TEST(ComponentProfileErrors, RejectsAProfileWithoutName) {
  EXPECT_THAT(problems("errors/component/missing_name.xml"),
              ElementsAre("errors/component/missing_name.xml:2: missing <name> in <component_profile>"));
}

TEST(ComponentProfileErrors, RejectsAZeroPeriod) {
  EXPECT_THAT(
      problems("errors/component/period_zero.xml"),
      ElementsAre(
          "errors/component/period_zero.xml:6: <period> of component 'Probe' must be a positive number, got '0'"));
}

TEST(ComponentProfileErrors, RejectsAPeriodWithUnits) {
  EXPECT_THAT(problems("errors/component/period_not_number.xml"),
              ElementsAre("errors/component/period_not_number.xml:5: <period> of component 'Probe' must be a positive "
                          "number, got '10ms'"));
}

TEST(ComponentProfileErrors, RejectsAnInfinitePeriod) {
  EXPECT_THAT(problems("errors/component/period_infinite.xml"),
              ElementsAre("errors/component/period_infinite.xml:5: <period> of component 'Probe' must be a positive "
                          "number, got 'inf'"));
}

TEST(ComponentProfileErrors, RejectsAnUnknownExecutionType) {
  EXPECT_THAT(problems("errors/component/bad_execution_type.xml"),
              ElementsAre("errors/component/bad_execution_type.xml:5: <type> of component 'Probe' must be one of "
                          "periodic, aperiodic or passive, got 'cyclic'"));
}

TEST(ComponentProfileErrors, RejectsAnUnknownSchedulingPolicy) {
  EXPECT_THAT(problems("errors/component/bad_policy.xml"),
              ElementsAre("errors/component/bad_policy.xml:5: <policy> of component 'Probe' must be one of other, fifo "
                          "or rr, got 'edf'"));
}

TEST(ComponentProfileErrors, ClampsAPriorityAbove99AsOPRoSDoes) {
  EXPECT_THAT(warnings("errors/component/priority_out_of_range.xml"),
              ElementsAre("errors/component/priority_out_of_range.xml:5: <priority> 120 of component 'Probe' clamped "
                          "to 99, as OPRoS does (priorities are 0 to 99)"));
}

TEST(ComponentProfileErrors, RejectsPriorityZeroWithFifoPolicy) {
  EXPECT_THAT(problems("errors/component/fifo_priority_zero.xml"),
              ElementsAre("errors/component/fifo_priority_zero.xml:5: <priority> of component 'Probe' must be from 1 "
                          "to 99 with policy fifo, got '0'"));
}

TEST(ComponentProfileErrors, RejectsRoundRobinPolicyWithoutPriority) {
  EXPECT_THAT(
      problems("errors/component/rr_without_priority.xml"),
      ElementsAre(
          "errors/component/rr_without_priority.xml:4: policy rr of component 'Probe' needs a priority from 1 to 99"));
}

TEST(ComponentProfileErrors, KeepsAsAStringAPropertyOfAnUnknownType) {
  EXPECT_THAT(warnings("errors/component/property_unknown_type.xml"),
              ElementsAre("errors/component/property_unknown_type.xml:5: property 'pose' of component 'Probe' has "
                          "unknown type 'quaternion' (types: bool, int, double, string, double[]): kept as a string, "
                          "as OPRoS does"));
}

TEST(ComponentProfileErrors, KeepsAsAStringADoublePropertyThatIsNotANumber) {
  EXPECT_THAT(warnings("errors/component/property_bad_double.xml"),
              ElementsAre("errors/component/property_bad_double.xml:5: property 'gain' of component 'Probe' must be a "
                          "finite double, got 'abc': kept as a string, as OPRoS does (it ignores a property's type); a "
                          "component that reads it typed fails to start"));
}

TEST(ComponentProfileErrors, KeepsAsAStringAnIntPropertyWithAFraction) {
  EXPECT_THAT(warnings("errors/component/property_bad_int.xml"),
              ElementsAre("errors/component/property_bad_int.xml:5: property 'count' of component 'Probe' must be an "
                          "int, got '1.5': kept as a string, as OPRoS does (it ignores a property's type); a component "
                          "that reads it typed fails to start"));
}

TEST(ComponentProfileErrors, KeepsAsAStringABoolPropertyThatIsNotTrueOrFalse) {
  EXPECT_THAT(warnings("errors/component/property_bad_bool.xml"),
              ElementsAre("errors/component/property_bad_bool.xml:5: property 'enabled' of component 'Probe' must be a "
                          "bool (true, false, 1 or 0), got 'yes': kept as a string, as OPRoS does (it ignores a "
                          "property's type); a component that reads it typed fails to start"));
}

TEST(ComponentProfileErrors, KeepsAsAStringADoubleArrayPropertyWithAWord) {
  EXPECT_THAT(warnings("errors/component/property_bad_list.xml"),
              ElementsAre(
                  "errors/component/property_bad_list.xml:5: property 'weights' of component 'Probe' must be a "
                  "double[] (finite numbers separated by spaces or commas), got '1, two, 3': kept as a string, as "
                  "OPRoS does (it ignores a property's type); a component that reads it typed fails to start"));
}

TEST(ComponentProfileErrors, KeepsAsAStringANegativeUnsignedProperty) {
  EXPECT_THAT(warnings("errors/component/property_negative_unsigned.xml"),
              ElementsAre("errors/component/property_negative_unsigned.xml:5: property 'samples' of component 'Probe' "
                          "must be a non-negative unsigned int, got '-1': kept as a string, as OPRoS does (it ignores "
                          "a property's type); a component that reads it typed fails to start"));
}

TEST(ComponentProfileErrors, ReadsAPropertyWithoutTypeAsAStringAsOPRoSDoes) {
  const auto set = load(dataPath("errors/component/property_missing_type.xml"));
  ASSERT_TRUE(set.ok()) << joined(set);
  EXPECT_TRUE(set->warnings.empty());
  const auto& props = set->components.at(keyOf("errors/component/property_missing_type.xml")).properties;
  ASSERT_EQ(props.size(), 1U);
  EXPECT_EQ(props[0].type, "string");
  EXPECT_EQ(std::get<std::string>(props[0].value), "1");
}

TEST(ComponentProfileErrors, RejectsTwoPropertiesWithOneName) {
  EXPECT_THAT(problems("errors/component/property_duplicate.xml"),
              ElementsAre("errors/component/property_duplicate.xml:6: duplicate property 'gain' in component 'Probe' "
                          "(first at line 5)"));
}

TEST(ComponentProfileErrors, RejectsANegativeQueueSize) {
  EXPECT_THAT(problems("errors/component/queue_size_negative.xml"),
              ElementsAre("errors/component/queue_size_negative.xml:9: <queue_size> of data port 'range' must be a "
                          "positive integer, got '-3'"));
}

TEST(ComponentProfileErrors, DropsADataPortOfAnUnknownUsageAsOPRoSDoes) {
  EXPECT_THAT(warnings("errors/component/bad_usage.xml"),
              ElementsAre("errors/component/bad_usage.xml:7: data port 'range' dropped: <usage> 'in' is neither input "
                          "nor output (OPRoS's engine drops such ports too)"));
  const auto set = load(dataPath("errors/component/bad_usage.xml"));
  ASSERT_TRUE(set.ok());
  EXPECT_TRUE(set->components.at(keyOf("errors/component/bad_usage.xml")).data_ports.empty());
}

TEST(ComponentProfileErrors, RejectsAnUnknownQueueingPolicy) {
  EXPECT_THAT(problems("errors/component/bad_queueing_policy.xml"),
              ElementsAre("errors/component/bad_queueing_policy.xml:9: <queueing_policy> of data port 'range' must be "
                          "one of FIFO, UFIFO, LIFO or LAST, got 'RING'"));
}

TEST(ComponentProfileErrors, RejectsBothQueueingPolicySpellingsOnOnePort) {
  EXPECT_THAT(problems("errors/component/both_queueing_spellings.xml"),
              ElementsAre("errors/component/both_queueing_spellings.xml:10: <queueing_policy> and "
                          "<queuing_policy> in data port 'range': one queue policy (line 9)"));
}

TEST(ComponentProfileErrors, RejectsADataPortWithoutUsage) {
  EXPECT_THAT(problems("errors/component/missing_usage.xml"),
              ElementsAre("errors/component/missing_usage.xml:5: missing <usage> in data port 'range'"));
}

TEST(ComponentProfileErrors, RejectsADataPortWithoutDataType) {
  EXPECT_THAT(problems("errors/component/missing_data_type.xml"),
              ElementsAre("errors/component/missing_data_type.xml:5: missing <data_type> in data port 'range'"));
}

TEST(ComponentProfileErrors, RejectsAPortWithoutName) {
  EXPECT_THAT(problems("errors/component/port_without_name.xml"),
              ElementsAre("errors/component/port_without_name.xml:5: missing <name> in <data_port>"));
}

TEST(ComponentProfileErrors, RejectsAValidityBoundThatIsNotANumber) {
  EXPECT_THAT(problems("errors/component/validity_not_number.xml"),
              ElementsAre("errors/component/validity_not_number.xml:10: <min> of data port 'range' must be a number or "
                          "a list of numbers, got 'low'"));
}

TEST(ComponentProfileErrors, RejectsANanValidityBound) {
  EXPECT_THAT(problems("errors/component/validity_nan.xml"),
              ElementsAre("errors/component/validity_nan.xml:10: <max> of data port 'range' must be a number or a list "
                          "of numbers, got 'nan'"));
}

TEST(ComponentProfileErrors, RejectsValidityMinAboveMax) {
  EXPECT_THAT(problems("errors/component/validity_min_above_max.xml"),
              ElementsAre("errors/component/validity_min_above_max.xml:9: <validity> of data port 'range': min 10 is "
                          "greater than max 3"));
}

TEST(ComponentProfileErrors, RejectsValidityBoundsCrossingElementWise) {
  EXPECT_THAT(problems("errors/component/validity_elementwise.xml"),
              ElementsAre("errors/component/validity_elementwise.xml:9: <validity> of data port 'range': min[1] 5 is "
                          "greater than max[1] 2"));
}

TEST(ComponentProfileErrors, RejectsValidityBoundListsOfDifferentLengths) {
  EXPECT_THAT(problems("errors/component/validity_sizes_differ.xml"),
              ElementsAre("errors/component/validity_sizes_differ.xml:9: <validity> of data port 'range': <min> has 3 "
                          "values but <max> has 2"));
}

TEST(ComponentProfileErrors, RejectsTwoPortsWithOneNameAcrossKinds) {
  EXPECT_THAT(
      problems("errors/component/duplicate_port.xml"),
      ElementsAre(
          "errors/component/duplicate_port.xml:10: duplicate port 'range' in component 'Probe' (first at line 5)"));
}

TEST(ComponentProfileErrors, RejectsAZeroEventQueueSize) {
  EXPECT_THAT(problems("errors/component/event_queue_size.xml"),
              ElementsAre("errors/component/event_queue_size.xml:8: <queue_size> of event port 'alarm' must be a "
                          "positive integer, got '0'"));
}

TEST(ComponentProfileErrors, RejectsANegativeServiceTimeout) {
  EXPECT_THAT(problems("errors/component/service_bad_timeout.xml"),
              ElementsAre("errors/component/service_bad_timeout.xml:9: <timeout> of service port 'map' must be a "
                          "positive number, got '-5'"));
}

TEST(ComponentProfileErrors, RejectsAServicePortUsedAsOutput) {
  EXPECT_THAT(problems("errors/component/service_bad_usage.xml"),
              ElementsAre("errors/component/service_bad_usage.xml:8: <usage> of service port 'map' must be one of "
                          "provided or required, got 'output'"));
}

TEST(ComponentProfileErrors, RejectsAServicePortWithoutType) {
  EXPECT_THAT(problems("errors/component/service_missing_type.xml"),
              ElementsAre("errors/component/service_missing_type.xml:5: missing <type> in service port 'map'"));
}

TEST(ComponentProfileErrors, ReportsEveryProblemOfTheFileNotJustTheFirst) {
  EXPECT_THAT(
      problems("errors/component/many_problems.xml"),
      ElementsAre(
          "errors/component/many_problems.xml:5: <type> of component 'Probe' must be one of periodic, aperiodic or "
          "passive, got 'cyclic'",
          "errors/component/many_problems.xml:6: <period> of component 'Probe' must be a positive number, got '-1'",
          "errors/component/many_problems.xml:16: <queue_size> of data port 'range' must be a positive integer, got "
          "'0'",
          "errors/component/many_problems.xml:19: unknown element <extra> in <component_profile>"));
}

}  // namespace
}  // namespace keel::profile::test
