// <validity field=".."> in a component profile's data port, read as a node profile's is (the
// fields themselves are checked where the message types are known: tests/unit/dds): several per
// port, each field once, beside at most one <validity> of the whole value.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;

TEST(FieldValidityProfile, AComponentsDataPortMayCheckFieldsOfItsMessage) {
  auto set = load(dataPath("fields/Teleop.xml"));
  ASSERT_TRUE(set.ok()) << joined(set);
  const ComponentProfile& c = set->components.begin()->second;
  ASSERT_EQ(c.data_ports.size(), 4u);
  const DataPort& cmd = c.data_ports[0];
  EXPECT_FALSE(cmd.validity);
  ASSERT_EQ(cmd.field_validity.size(), 2u);
  EXPECT_EQ(cmd.field_validity[0].field, "linear.x");
  EXPECT_THAT(cmd.field_validity[0].min, ElementsAre(-0.5));
  EXPECT_THAT(cmd.field_validity[0].max, ElementsAre(0.5));
  EXPECT_EQ(cmd.field_validity[0].where.line, 11);
  EXPECT_EQ(cmd.field_validity[1].field, "angular.z");
  EXPECT_THAT(cmd.field_validity[1].min, ElementsAre());
  EXPECT_EQ(c.data_ports[1].field_validity[0].field, "poses.position.z");
  const DataPort& speed = c.data_ports[3];
  ASSERT_TRUE(speed.validity);  // the whole value's, as before
  EXPECT_EQ(speed.validity->field, "");
  EXPECT_THAT(speed.validity->max, ElementsAre(2));
  EXPECT_THAT(speed.field_validity, ElementsAre());
}

TEST(FieldValidityProfile, EachFieldOnceTheWholeValueOnceAndAPathOfNames) {
  EXPECT_THAT(problems("errors/fields/parse.xml"),
              ElementsAre("errors/fields/parse.xml:12: duplicate <validity field=\"linear.x\"> in data port 'cmd' "
                          "(first at line 11)",
                          "errors/fields/parse.xml:13: field 'linear..y' of <validity> of data port 'cmd' is not a "
                          "field path (field names separated by '.', e.g. linear.x): it has an empty field name ('.' "
                          "first, last or twice)",
                          "errors/fields/parse.xml:20: duplicate <validity> in <data_port> (first at line 19); a "
                          "field's <validity> names it: <validity field=\"linear.x\">"));
}

}  // namespace
}  // namespace keel::profile::test
