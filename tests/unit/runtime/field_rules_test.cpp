// A port whose type is a message checks each value against its <validity field=".."> rules
// (runtime/field_rules.hpp), as a numeric port checks its <validity>: a violation is a `range`
// fault of the port's owner, whose detail names the field, the element of each array on the
// way, the value and the bounds, and the value goes nowhere. Ports wired by hand, faults caught
// by a recording sink; touches nothing else.
#include "runtime/field_rules.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "keel/component.hpp"
#include "keel/msg/keel_test_msgs/msg/detail/everything__fields.hpp"
#include "runtime/component_core.hpp"
#include "runtime/port_access.hpp"
#include "support/recording_hooks.hpp"

namespace keel {
namespace {

using msg::keel_test_msgs::Everything;

class Sender : public Component {
 public:
  OutputDataPort<Everything> out{this, "out"};
};
class Receiver : public Component {
 public:
  InputDataPort<Everything> in{this, "in"};
};

/// Keeps the details of the faults reported to it.
class Faults : public runtime::FaultSink {
 public:
  void report(Component&, const FaultEvent& fault) override {
    kinds.push_back(fault.kind);
    details.emplace_back(fault.detail.data());
  }
  void runPending(Component&) override {}
  void recovered(Component&, std::int64_t) override {}
  std::vector<FaultKind> kinds;
  std::vector<std::string> details;
};

/// A rule on `path` of Everything, as the engine makes it from a profile.
runtime::FieldRule rule(const std::string& path, std::vector<double> min, std::vector<double> max) {
  auto steps = runtime::resolveFieldPath(detail::MessageFieldsOf<Everything>::fields(), "keel_test_msgs/msg/Everything",
                                         path);
  if (!steps) throw std::runtime_error(steps.error().message);
  return {path, std::move(*steps), detail::ValidityRule{std::move(min), std::move(max)}};
}

class FieldRules : public ::testing::Test {
 protected:
  FieldRules() {
    test::wire(sender.out, receiver.in, keep);
    test::configureQueue(receiver.in, QueuePolicy::Fifo, 8);
    runtime::coreOf(sender).fault_sink = &faults;
    runtime::coreOf(receiver).fault_sink = &faults;
  }
  void onSend(std::vector<runtime::FieldRule> r) {
    rules.rules = std::move(r);
    detail::PortAccess::setFieldRules(sender.out, &rules);
  }

  Sender sender;
  Receiver receiver;
  Faults faults;
  detail::FieldRules rules;
  std::vector<std::unique_ptr<detail::ConnectionBase>> keep;
};

TEST_F(FieldRules, AValueWithinEveryRuleIsSent) {
  onSend({rule("twist.linear.x", {-1}, {1}), rule("parts.xyz", {0}, {10})});
  Everything m;
  m.twist.linear.x = 1;  // bounds are inclusive
  m.parts.resize(2);
  m.parts[1].xyz = {10, 0, 5};
  sender.out.push(m);
  EXPECT_TRUE(faults.details.empty());
  EXPECT_EQ(receiver.in.pop(), m);
}

TEST_F(FieldRules, ANestedFieldOutOfItsBoundsIsARangeFaultNamingItAndIsNotSent) {
  onSend({rule("i32", {}, {100}), rule("twist.linear.x", {-0.5}, {0.5})});
  Everything m;
  m.twist.linear.x = 0.75;
  sender.out.push(m);
  ASSERT_EQ(faults.details.size(), 1u);
  EXPECT_EQ(faults.kinds[0], FaultKind::Range);
  EXPECT_EQ(faults.details[0], "value 0.75 pushed on port 'out' field 'twist.linear.x' outside [-0.5, 0.5]");
  EXPECT_TRUE(receiver.in.empty());
}

TEST_F(FieldRules, AnElementOfAnArrayOfMessagesIsNamedByItsIndexAtEachLevel) {
  onSend({rule("parts.xyz", {0}, {10})});
  Everything m;
  m.parts.resize(3);
  m.parts[2].xyz = {1, 2, -3};
  sender.out.push(m);
  ASSERT_EQ(faults.details.size(), 1u);
  EXPECT_EQ(faults.details[0], "value -3 pushed on port 'out' field 'parts[2].xyz[2]' outside [0, 10]");
}

TEST_F(FieldRules, NaNAndInfinityViolateEveryRule) {
  onSend({rule("values", {}, {}), rule("f32", {}, {})});
  Everything m;
  m.values = {1, std::numeric_limits<double>::quiet_NaN()};
  sender.out.push(m);
  m.values = {};
  m.f32 = std::numeric_limits<float>::infinity();
  sender.out.push(m);
  ASSERT_EQ(faults.details.size(), 2u);
  EXPECT_EQ(faults.details[0], "value nan pushed on port 'out' field 'values[1]' outside [-inf, inf]");
  EXPECT_EQ(faults.details[1], "value inf pushed on port 'out' field 'f32' outside [-inf, inf]");
  EXPECT_TRUE(receiver.in.empty());
}

TEST_F(FieldRules, SeveralBoundsApplyElementByElementAndFixTheNumberOfElements) {
  onSend({rule("values", {0, 10}, {5, 20})});
  Everything m;
  m.values = {4, 15};
  sender.out.push(m);
  EXPECT_TRUE(faults.details.empty());
  m.values = {4, 25};
  sender.out.push(m);
  m.values = {4, 15, 1};
  sender.out.push(m);
  m.values = {9, 15, 1};  // the wrong size is said, not the first value out of bounds
  sender.out.push(m);
  ASSERT_EQ(faults.details.size(), 3u);
  EXPECT_EQ(faults.details[0], "value 25 pushed on port 'out' field 'values[1]' outside [10, 20]");
  EXPECT_EQ(faults.details[1], "pushed on port 'out' field 'values': 3 elements, validity expects 2");
  EXPECT_EQ(faults.details[2], "pushed on port 'out' field 'values': 3 elements, validity expects 2");
  ASSERT_FALSE(receiver.in.empty());  // only the first was sent
  EXPECT_EQ(receiver.in.pop()->values, (std::vector<double>{4, 15}));
  EXPECT_TRUE(receiver.in.empty());
}

TEST_F(FieldRules, AnInputPortChecksWhatItReceivesAsAFaultOfItsOwner) {
  detail::FieldRules on_receive{{rule("quad", {0}, {1})}};
  detail::PortAccess::setFieldRules(receiver.in, &on_receive);
  Everything m;
  m.quad = {0, 1, 2, 0};
  sender.out.push(m);
  ASSERT_EQ(faults.details.size(), 1u);
  EXPECT_EQ(faults.details[0], "value 2 received on port 'in' field 'quad[2]' outside [0, 1]");
  EXPECT_TRUE(receiver.in.empty());
}

// A connection carrying one field (<source field="..">): the field's number of each value sent
// goes to a double port of the sender's, after the rules, and not for a value they stopped.
class Numbers : public Component {
 public:
  InputDataPort<double> in{this, "in"};
};

TEST_F(FieldRules, ATapSendsTheFieldsNumberOfEachValueThatPassedTheRules) {
  auto steps = runtime::resolveFieldTap(detail::MessageFieldsOf<Everything>::fields(), "keel_test_msgs/msg/Everything",
                                        "twist.linear.x");
  ASSERT_TRUE(steps) << steps.error().message;
  OutputDataPort<double> field{&sender, "out.twist.linear.x"};
  Numbers numbers;
  test::wire(field, numbers.in, keep);
  test::configureQueue(numbers.in, QueuePolicy::Fifo, 8);
  rules.taps.push_back({std::move(*steps), &field});
  onSend({rule("i32", {}, {100})});
  Everything m;
  m.twist.linear.x = 0.25;
  sender.out.push(m);
  m.twist.linear.x = -3;
  m.i32 = 101;  // against the rule: neither the value nor its field goes anywhere
  sender.out.push(m);
  m.i32 = 0;
  sender.out.push(m);
  EXPECT_EQ(numbers.in.pop(), 0.25);
  EXPECT_EQ(numbers.in.pop(), -3.0);
  EXPECT_TRUE(numbers.in.empty());
  EXPECT_EQ(faults.details.size(), 1u);
}

TEST(FieldTap, NamesOneNumberOfEachMessageNoArrayOnTheWay) {
  const auto fields = detail::MessageFieldsOf<Everything>::fields();
  const std::string type = "keel_test_msgs/msg/Everything";
  EXPECT_TRUE(runtime::resolveFieldTap(fields, type, "i32"));
  auto array = runtime::resolveFieldTap(fields, type, "quad");
  ASSERT_FALSE(array);
  EXPECT_EQ(array.error().message, "'quad' is an array (float32[4]): a connection carries one number of each message");
  auto through = runtime::resolveFieldTap(fields, type, "parts.xyz");
  ASSERT_FALSE(through);
  EXPECT_EQ(through.error().message.substr(0, 30), "'parts' is an array (keel_test");
  EXPECT_FALSE(runtime::resolveFieldTap(fields, type, "twist"));  // a message, not a number
  EXPECT_FALSE(runtime::resolveFieldTap(fields, type, "nothing"));
}

}  // namespace
}  // namespace keel
