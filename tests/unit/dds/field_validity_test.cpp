// <validity field=".."> checked at load against the message types keel has (dds/field_validity.hpp):
// each rule that names no numeric field of its port's message is a `file:line` error saying
// which fields there are, from keel validate's check of the profiles (without --load) and from
// the engine (keel run, keel validate --load), for components' ports and nodes'. Fixtures under
// tests/unit/profile/data/fields and errors/fields; the component class is linked into this binary.
#include "dds/field_validity.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "engine/engine.hpp"
#include "keel/component.hpp"
#include "keel/msg/geometry_msgs/msg/pose_array.hpp"
#include "keel/msg/geometry_msgs/msg/pose_with_covariance_stamped.hpp"
#include "keel/msg/geometry_msgs/msg/twist.hpp"
#include "unit/profile/profile_test_support.hpp"

namespace keel {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

// The class of fields/Teleop.xml and errors/fields/Teleop.xml (their library is not there: the
// engine finds the class in this program).
class FieldTeleop : public Component {
 public:
  OutputDataPort<msg::geometry_msgs::Twist> cmd{this, "cmd"};
  InputDataPort<msg::geometry_msgs::PoseArray> poses{this, "poses"};
  InputDataPort<msg::geometry_msgs::PoseWithCovarianceStamped> pose{this, "pose"};
  OutputDataPort<double> speed{this, "speed"};
};

/// Each problem of the rules of `fixture`'s component, as keel validate prints them.
std::vector<std::string> problems(const std::string& fixture, bool unknown_ok) {
  auto set = profile::load(profile::test::dataPath(fixture));
  if (!set) throw std::runtime_error(profile::test::joined(set));
  std::vector<std::string> out;
  for (const auto& [path, component] : set->components)
    for (const auto& port : component.data_ports)
      if (auto r = dds::resolveFieldRules(port, "", unknown_ok); !r) {
        const std::string text = profile::test::relative(r.error().message);
        for (std::size_t start = 0; start < text.size();) {
          const std::size_t end = text.find('\n', start);
          out.push_back(text.substr(start, end - start));
          start = end + 1;
        }
      }
  return out;
}

/// The engine's error for `fixture` (keel validate --load), or "" when it loads.
std::string engineError(const std::string& fixture) {
  auto set = profile::load(profile::test::dataPath(fixture));
  if (!set) throw std::runtime_error(profile::test::joined(set));
  engine::EngineOptions eo;
  eo.check_only = true;
  eo.search_path = {};
  eo.warn = [](const std::string&) {};
  auto engine = engine::Engine::create(std::move(*set), eo);
  return engine ? std::string() : profile::test::relative(engine.error().message);
}

TEST(FieldValidity, ARuleNamingANumericFieldOfTheMessageLoads) {
  EXPECT_THAT(problems("fields/Teleop.xml", false), ElementsAre());
  EXPECT_EQ(engineError("fields/Teleop.xml"), "");
}

TEST(FieldValidity, APathThatNamesNoNumericFieldIsAnErrorAtItsLineSayingWhichFieldsThereAre) {
  EXPECT_THAT(
      problems("errors/fields/Teleop.xml", true),
      ElementsAre("errors/fields/Teleop.xml:11: <validity field=\"linear.w\"> of data port 'cmd': "
                  "geometry_msgs/msg/Vector3 (the type of 'linear') has no field 'w': its fields are x, y, z",
                  "errors/fields/Teleop.xml:12: <validity field=\"angular\"> of data port 'cmd': 'angular' is a "
                  "message (geometry_msgs/msg/Vector3), not a number: name one of its numeric fields (angular.x, "
                  "angular.y, angular.z)",
                  "errors/fields/Teleop.xml:18: <validity field=\"header.frame_id\"> of data port 'pose': "
                  "'header.frame_id' is a string: only numbers and arrays of numbers can be range-checked (the "
                  "numeric fields of 'header': header.stamp.sec, header.stamp.nanosec)",
                  "errors/fields/Teleop.xml:19: <validity field=\"pose.covariance\"> of data port 'pose': 3 bounds, "
                  "one per element, but 'pose.covariance' always has 36 elements (one bound applies to every "
                  "element)",
                  "errors/fields/Teleop.xml:20: <validity field=\"pose.pose.position.x\"> of data port 'pose': 2 "
                  "bounds, one per element, but 'pose.pose.position.x' always has 1 element (one bound applies to "
                  "every element)"));
}

TEST(FieldValidity, APortWhoseTypeIsNoMessageHasNoFields) {
  const auto all = problems("errors/fields/Teleop.xml", false);
  EXPECT_THAT(all.back(),
              "errors/fields/Teleop.xml:26: <validity field=\"x\"> of data port 'speed': its type "
              "'double' is not a ROS 2 message keel has (a keel::msg type: docs/messages.md), so it has "
              "no fields to check");
}

TEST(FieldValidity, TheEngineRefusesAComponentsBadRuleNamingTheComponent) {
  const std::string error = engineError("errors/fields/Teleop.xml");
  EXPECT_THAT(error,
              HasSubstr("errors/fields/Teleop.xml:11: component 'FieldTeleop': <validity field=\"linear.w\"> "
                        "of data port 'cmd': geometry_msgs/msg/Vector3 (the type of 'linear') has no field 'w'"));
  EXPECT_THAT(error, HasSubstr("errors/fields/Teleop.xml:26: component 'FieldTeleop': <validity field=\"x\"> of data "
                               "port 'speed': its type 'double' is not a ROS 2 message keel has"));
}

TEST(FieldValidity, TheEngineRefusesANodesBadRuleAndAnUnknownMessageType) {
  EXPECT_THAT(problems("errors/fields/wander.xml", true),
              ElementsAre("errors/fields/wander.xml:12: <validity field=\"liner.x\"> of data port 'cmd': "
                          "geometry_msgs/msg/Twist has no field 'liner': its fields are linear, angular (did you mean "
                          "'linear'?)"));
  const std::string error = engineError("errors/fields/app.xml");
  EXPECT_THAT(error, HasSubstr("errors/fields/wander.xml:12: node 'wander': <validity field=\"liner.x\"> of data port "
                               "'cmd': geometry_msgs/msg/Twist has no field 'liner'"));
  EXPECT_THAT(error, HasSubstr("errors/fields/wander.xml:19: node 'wander': <validity field=\"a.b\"> of data port "
                               "'odd': its type 'no_msgs/msg/Odd' is not a ROS 2 message keel has"));
}

}  // namespace
}  // namespace keel

KEEL_REGISTER_COMPONENT_AS(keel::FieldTeleop, "FieldTeleop")
