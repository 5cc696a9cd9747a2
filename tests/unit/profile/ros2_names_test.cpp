// ROS 2's names as keel checks them (src/profile/ros2_names.hpp): node names and namespaces by
// rmw's rules, each broken rule named in rmw's words; parameter names, message field paths and
// environment variable names; topics' length.
#include <gtest/gtest.h>

#include <string>

#include "profile/ros2_names.hpp"

namespace keel::profile::detail {
namespace {

TEST(Ros2Names, AcceptsTheNamespacesAndNodeNamesRmwAccepts) {
  for (const char* ns : {"/", "/robot", "/robot/arm_2", "/_hidden", "/A/b9"}) EXPECT_EQ(namespaceProblem(ns), "") << ns;
  for (const char* name : {"wander", "_x", "Sonar2", "a_b_c"}) EXPECT_EQ(nodeNameProblem(name), "") << name;
  EXPECT_EQ(namespaceProblem("/" + std::string(244, 'a')), "");
  EXPECT_EQ(nodeNameProblem(std::string(255, 'a')), "");
}

TEST(Ros2Names, NamesTheNamespaceRuleBrokenInRmwsWords) {
  EXPECT_EQ(namespaceProblem(""), "namespace must not be empty");
  EXPECT_EQ(namespaceProblem("robot"), "namespace must be absolute, it must lead with a '/'");
  EXPECT_EQ(namespaceProblem("/robot/"), "namespace must not end with a '/', unless only a '/'");
  EXPECT_EQ(namespaceProblem("/ro-bot"),
            "namespace must not contain characters other than alphanumerics, '_', or '/' ('-')");
  EXPECT_EQ(namespaceProblem("/robot//arm"), "namespace must not contain repeated '/'");
  EXPECT_EQ(namespaceProblem("/robot/2arm/x"), "namespace must not have a token that starts with a number ('2arm')");
  EXPECT_EQ(namespaceProblem("/" + std::string(245, 'a')), "namespace should not exceed 245 characters (it has 246)");
}

TEST(Ros2Names, NamesTheNodeNameRuleBrokenInRmwsWords) {
  EXPECT_EQ(nodeNameProblem(""), "node name must not be empty");
  EXPECT_EQ(nodeNameProblem("my-node"), "node name must not contain characters other than alphanumerics or '_' ('-')");
  EXPECT_EQ(nodeNameProblem("9lives"), "node name must not start with a number");
  EXPECT_EQ(nodeNameProblem(std::string(256, 'a')), "node name length should not exceed 255 (it has 256)");
}

TEST(Ros2Names, ATopicLongerThanROS2sLongestIsRefused) {
  EXPECT_EQ(topicProblem("/" + std::string(246, 'a')), "");
  EXPECT_EQ(topicProblem(std::string(246, 'a')), "");  // relative: "/" + it
  EXPECT_EQ(topicProblem("/" + std::string(247, 'a')), "it is 248 characters long, and ROS 2's longest is 247");
}

TEST(Ros2Names, ParameterNamesAreDottedTokensNoneStartingWithADigit) {
  for (const char* name : {"speed", "planner.mode", "a_b.c_d.e9", "_private"})
    EXPECT_EQ(parameterNameProblem(name), "") << name;
  EXPECT_EQ(parameterNameProblem(""), "it is empty");
  EXPECT_EQ(parameterNameProblem("a..b"), "it has an empty token ('.' first, last or twice)");
  EXPECT_EQ(parameterNameProblem(".a"), "it has an empty token ('.' first, last or twice)");
  EXPECT_EQ(parameterNameProblem("a."), "it has an empty token ('.' first, last or twice)");
  EXPECT_EQ(parameterNameProblem("a.2b"), "its token '2b' starts with a digit");
  EXPECT_EQ(parameterNameProblem("max-speed"), "'-' is not allowed (letters, digits, '_' and '.' only)");
}

TEST(Ros2Names, FieldPathsAreDottedNames) {
  EXPECT_EQ(fieldPathProblem("linear.x"), "");
  EXPECT_EQ(fieldPathProblem("range"), "");
  EXPECT_EQ(fieldPathProblem("linear..x"), "it has an empty field name ('.' first, last or twice)");
  EXPECT_EQ(fieldPathProblem("ranges[0]"), "'[' is not allowed (letters, digits, '_' and '.' only)");
  EXPECT_EQ(fieldPathProblem("pose.1st"), "its field name '1st' starts with a digit");
}

TEST(Ros2Names, EnvironmentVariableNamesAreIdentifiers) {
  for (const char* name : {"PATH", "_X", "ros_home2"}) EXPECT_EQ(environmentNameProblem(name), "") << name;
  EXPECT_EQ(environmentNameProblem(""), "it is empty");
  EXPECT_EQ(environmentNameProblem("2X"), "it starts with a digit");
  EXPECT_EQ(environmentNameProblem("A=B"), "'=' is not allowed (letters, digits and '_' only)");
}

}  // namespace
}  // namespace keel::profile::detail
