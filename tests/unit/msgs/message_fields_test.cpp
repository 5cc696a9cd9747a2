// The table of fields keel_msggen.py generates for each message (keel/detail/message_fields.hpp),
// against hand-built values of keel's test message (tests/unit/msgs/keel_test_msgs) and shipped
// ones: each field's kind, its visitors, paths resolved through nested messages, fixed arrays,
// sequences and arrays of messages, and what a path cannot name. Touches nothing.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <vector>

#include "dds/type_registry.hpp"
#include "keel/msg/geometry_msgs/msg/detail/pose_array__fields.hpp"
#include "keel/msg/geometry_msgs/msg/detail/twist__fields.hpp"
#include "keel/msg/keel_test_msgs/msg/detail/everything__fields.hpp"
#include "keel/msg/keel_test_msgs/msg/detail/nothing__fields.hpp"
#include "runtime/field_rules.hpp"

namespace keel::detail {
namespace {

using msg::keel_test_msgs::Everything;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

const MessageField& field(std::span<const MessageField> fields, std::string_view name) {
  for (const MessageField& f : fields)
    if (f.name == name) return f;
  throw std::runtime_error("no field " + std::string(name));
}

std::span<const MessageField> everything() { return MessageFieldsOf<Everything>::fields(); }

std::vector<double> numbers(const MessageField& f, const void* message) {
  std::vector<double> out;
  EXPECT_TRUE(f.numbers(message, &out, [](void* c, double x) {
    static_cast<std::vector<double>*>(c)->push_back(x);
    return true;
  }));
  return out;
}

std::vector<const void*> messages(const MessageField& f, const void* message) {
  std::vector<const void*> out;
  EXPECT_TRUE(f.messages(message, &out, [](void* c, const void* m) {
    static_cast<std::vector<const void*>*>(c)->push_back(m);
    return true;
  }));
  return out;
}

/// The names along a resolved path, or its error.
std::string resolved(std::span<const MessageField> fields, std::string_view type, std::string_view path) {
  auto steps = runtime::resolveFieldPath(fields, type, path);
  if (!steps) return "error: " + steps.error().message;
  std::string out;
  for (const MessageField* f : *steps) out += (out.empty() ? "" : "/") + std::string(f->name);
  return out;
}

TEST(MessageFields, EachFieldIsListedInTheMsgsOrderWithItsKindAndType) {
  std::vector<std::string> names;
  for (const MessageField& f : everything()) names.emplace_back(f.name);
  EXPECT_EQ(names.front(), "header");
  EXPECT_EQ(names.back(), "module");
  EXPECT_EQ(names.size(), 39u);
  EXPECT_EQ(field(everything(), "twist").kind, FieldKind::Message);
  EXPECT_STREQ(field(everything(), "twist").type, "geometry_msgs/msg/Twist");
  EXPECT_STREQ(field(everything(), "few_parts").type, "keel_test_msgs/msg/Part[<=2]");
  EXPECT_TRUE(field(everything(), "parts").array);
  EXPECT_EQ(field(everything(), "i8").kind, FieldKind::Number);
  EXPECT_EQ(field(everything(), "c").kind, FieldKind::Number);  // char is a uint8
  EXPECT_EQ(field(everything(), "flag").kind, FieldKind::Bool);
  EXPECT_EQ(field(everything(), "flags").kind, FieldKind::Bool);
  EXPECT_EQ(field(everything(), "short_text").kind, FieldKind::String);
  EXPECT_STREQ(field(everything(), "short_texts").type, "string<=3[]");
  EXPECT_EQ(field(everything(), "quad").numbers != nullptr, true);
  EXPECT_EQ(field(everything(), "text").numbers, nullptr);
  EXPECT_EQ(field(everything(), "twist").nested().size(), 2u);
  EXPECT_TRUE(MessageFieldsOf<msg::keel_test_msgs::Nothing>::fields().empty());
}

TEST(MessageFields, NumbersAreVisitedOneByOneAndArraysElementByElement) {
  Everything m;
  m.i32 = -7;
  m.u64 = 12;
  m.class_ = 3;  // a C++ keyword: its .msg name is the table's
  m.values = {1.5, 2.5, 3.5};
  m.quad = {1, 2, 3, 4};
  m.bytes = {};
  EXPECT_THAT(numbers(field(everything(), "i32"), &m), ElementsAre(-7));
  EXPECT_THAT(numbers(field(everything(), "u64"), &m), ElementsAre(12));
  EXPECT_THAT(numbers(field(everything(), "class"), &m), ElementsAre(3));
  EXPECT_THAT(numbers(field(everything(), "values"), &m), ElementsAre(1.5, 2.5, 3.5));
  EXPECT_THAT(numbers(field(everything(), "quad"), &m), ElementsAre(1, 2, 3, 4));
  EXPECT_THAT(numbers(field(everything(), "bytes"), &m), ElementsAre());
}

TEST(MessageFields, MessagesAreVisitedByAddressAndArraysOfThemElementByElement) {
  Everything m;
  m.parts.resize(3);
  EXPECT_THAT(messages(field(everything(), "twist"), &m), ElementsAre(&m.twist));
  EXPECT_THAT(messages(field(everything(), "pair"), &m), ElementsAre(m.pair.data(), m.pair.data() + 1));
  EXPECT_THAT(messages(field(everything(), "parts"), &m),
              ElementsAre(m.parts.data(), m.parts.data() + 1, m.parts.data() + 2));
  m.parts[1].xyz = {4, 5, 6};
  const MessageField& xyz = field(field(everything(), "parts").nested(), "xyz");
  EXPECT_THAT(numbers(xyz, &m.parts[1]), ElementsAre(4, 5, 6));
}

TEST(MessageFields, AVisitorThatReturnsFalseStopsTheVisit) {
  Everything m;
  m.values = {1, 2, 3};
  int seen = 0;
  EXPECT_FALSE(
      field(everything(), "values").numbers(&m, &seen, [](void* c, double) { return ++*static_cast<int*>(c) < 2; }));
  EXPECT_EQ(seen, 2);
}

TEST(MessageFields, TheRegistryCarriesEachShippedTypesTable) {
  const DdsType* twist = dds::findType("geometry_msgs/msg/Twist");
  ASSERT_NE(twist, nullptr);
  ASSERT_EQ(twist->fields.size(), 2u);
  EXPECT_STREQ(twist->fields[0].name, "linear");
  EXPECT_STREQ(twist->fields[1].nested()[2].name, "z");
  const DdsType* empty = dds::findType("std_msgs/msg/Empty");
  ASSERT_NE(empty, nullptr);
  EXPECT_TRUE(empty->fields.empty());
}

TEST(MessageFields, APathResolvesThroughNestedMessagesArraysAndSequences) {
  const std::string_view type = "keel_test_msgs/msg/Everything";
  EXPECT_EQ(resolved(everything(), type, "twist.linear.x"), "twist/linear/x");
  EXPECT_EQ(resolved(everything(), type, "header.stamp.sec"), "header/stamp/sec");
  EXPECT_EQ(resolved(everything(), type, "part.xyz"), "part/xyz");    // a fixed array
  EXPECT_EQ(resolved(everything(), type, "values"), "values");        // a sequence
  EXPECT_EQ(resolved(everything(), type, "parts.xyz"), "parts/xyz");  // through a sequence of messages
  EXPECT_EQ(resolved(everything(), type, "few_parts.xyz"), "few_parts/xyz");
  EXPECT_EQ(resolved(everything(), type, "class"), "class");  // the .msg's name, not C++'s
  const auto poses = MessageFieldsOf<msg::geometry_msgs::PoseArray>::fields();
  EXPECT_EQ(resolved(poses, "geometry_msgs/msg/PoseArray", "poses.position.x"), "poses/position/x");
}

TEST(MessageFields, APathToAStringOrABoolIsRefusedNamingTheNumericFieldsBeside) {
  const std::string_view type = "keel_test_msgs/msg/Everything";
  EXPECT_EQ(resolved(everything(), type, "header.frame_id"),
            "error: 'header.frame_id' is a string: only numbers and arrays of numbers can be range-checked (the "
            "numeric fields of 'header': header.stamp.sec, header.stamp.nanosec)");
  EXPECT_THAT(resolved(everything(), type, "flag"), HasSubstr("error: 'flag' is a bool: only numbers"));
  EXPECT_THAT(resolved(everything(), type, "short_texts"), HasSubstr("error: 'short_texts' is a string<=3[]: only"));
  EXPECT_THAT(resolved(everything(), type, "part.name"), HasSubstr("error: 'part.name' is a string: only"));
}

TEST(MessageFields, AFieldThatIsNotThereIsRefusedWithTheFieldsThatAreAndTheNearest) {
  const auto twist = MessageFieldsOf<msg::geometry_msgs::Twist>::fields();
  const std::string_view type = "geometry_msgs/msg/Twist";
  EXPECT_EQ(resolved(twist, type, "linear.w"),
            "error: geometry_msgs/msg/Vector3 (the type of 'linear') has no field 'w': its fields are x, y, z");
  EXPECT_EQ(resolved(twist, type, "linear.xx"),
            "error: geometry_msgs/msg/Vector3 (the type of 'linear') has no field 'xx': its fields are x, y, z (did "
            "you mean 'linear.x'?)");
  EXPECT_EQ(resolved(twist, type, "liner.x"),
            "error: geometry_msgs/msg/Twist has no field 'liner': its fields are linear, angular (did you mean "
            "'linear'?)");
  EXPECT_EQ(resolved(twist, type, "angular"),
            "error: 'angular' is a message (geometry_msgs/msg/Vector3), not a number: name one of its numeric fields "
            "(angular.x, angular.y, angular.z)");
  EXPECT_EQ(resolved(twist, type, "linear.x.y"),
            "error: 'linear.x' is a float64, which has no fields: 'linear.x.y' names nothing");
}

TEST(MessageFields, EveryNumericPathOfATypeIsListedDepthFirst) {
  EXPECT_THAT(runtime::numericFieldPaths(MessageFieldsOf<msg::geometry_msgs::Twist>::fields()),
              ElementsAre("linear.x", "linear.y", "linear.z", "angular.x", "angular.y", "angular.z"));
  const auto paths = runtime::numericFieldPaths(everything());
  EXPECT_THAT(paths, ::testing::Contains("parts.xyz"));
  EXPECT_THAT(paths, ::testing::Not(::testing::Contains("text")));
  EXPECT_THAT(paths, ::testing::Not(::testing::Contains("flags")));
}

}  // namespace
}  // namespace keel::detail
