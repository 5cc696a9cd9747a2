// The parameter values a node is restarted with (src/supervision/node_parameters): the profile's
// values typed as rcl types a `-p`, overlaid by /parameter_events, and the params file of the
// restart, whose values rcl must read back with their types (a string that looks like a bool or
// a number stays a string; a double stays a double).
#include "supervision/node_parameters.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace keel::supervision {
namespace {

using profile::ParameterValue;
using Strings = std::vector<std::string>;

TEST(NodeParameters, AProfileValueIsTypedAsRclTypesAMinusPValue) {
  EXPECT_EQ(rosValueOf("hi"), ParameterValue(std::string("hi")));
  EXPECT_EQ(rosValueOf("hi there"), ParameterValue(std::string("hi there")));
  EXPECT_EQ(rosValueOf("yes"), ParameterValue(true));
  EXPECT_EQ(rosValueOf("Off"), ParameterValue(false));
  EXPECT_EQ(rosValueOf("7"), ParameterValue(std::int64_t{7}));
  EXPECT_EQ(rosValueOf("0x10"), ParameterValue(std::int64_t{16}));  // strtoll, base 0
  EXPECT_EQ(rosValueOf("-3"), ParameterValue(std::int64_t{-3}));
  EXPECT_EQ(rosValueOf("0.2"), ParameterValue(0.2));
  EXPECT_EQ(rosValueOf("1.5e3"), ParameterValue(1500.0));
  EXPECT_EQ(rosValueOf("1."), ParameterValue(1.0));
  EXPECT_EQ(rosValueOf(".inf"), ParameterValue(HUGE_VAL));
  EXPECT_TRUE(std::isnan(std::get<double>(*rosValueOf(".nan"))));
  EXPECT_EQ(rosValueOf("1_000"), ParameterValue(std::string("1_000")));
  EXPECT_EQ(rosValueOf("'yes'"), ParameterValue(std::string("yes")));
  EXPECT_EQ(rosValueOf("'it''s'"), ParameterValue(std::string("it's")));
  EXPECT_EQ(rosValueOf(R"("1.0\n\u00e9")"), ParameterValue(std::string("1.0\n\xc3\xa9")));
  EXPECT_EQ(rosValueOf("[1, 2]"), ParameterValue(std::vector<std::int64_t>{1, 2}));
  EXPECT_EQ(rosValueOf("[a, 'b, c']"), ParameterValue(Strings{"a", "b, c"}));
  EXPECT_EQ(rosValueOf("[yes, no]"), ParameterValue(std::vector<bool>{true, false}));
  EXPECT_EQ(rosValueOf("[1.5, 2.5]"), ParameterValue(std::vector<double>{1.5, 2.5}));
  // What rcl gives no value, or refuses.
  EXPECT_EQ(rosValueOf(""), std::nullopt);
  EXPECT_EQ(rosValueOf("[]"), std::nullopt);
  EXPECT_EQ(rosValueOf("[1, 2.0]"), std::nullopt);
  EXPECT_EQ(rosValueOf("{a: 1}"), std::nullopt);
  EXPECT_EQ(rosValueOf("'open"), std::nullopt);
}

TEST(NodeParameters, EachTypeIsWrittenSoThatRclReadsItBackAsItWas) {
  EXPECT_EQ(yamlOf(true), "true");
  EXPECT_EQ(yamlOf(std::int64_t{-5}), "-5");
  EXPECT_EQ(yamlOf(1.0), "1.0");  // a decimal point: a double, not an integer
  EXPECT_EQ(yamlOf(0.1), "0.1");
  EXPECT_EQ(yamlOf(1e20), "1e+20");
  EXPECT_EQ(yamlOf(-HUGE_VAL), "-.inf");
  EXPECT_EQ(yamlOf(std::nan("")), ".nan");
  // Strings quoted, whatever they look like.
  EXPECT_EQ(yamlOf(std::string("yes")), R"("yes")");
  EXPECT_EQ(yamlOf(std::string("1.0")), R"("1.0")");
  EXPECT_EQ(yamlOf(std::string(": x")), R"(": x")");
  EXPECT_EQ(yamlOf(std::string("")), R"("")");
  EXPECT_EQ(yamlOf(std::string("# not a comment")), R"("# not a comment")");
  EXPECT_EQ(yamlOf(std::string("say \"hi\"\\ \n\ttab")), R"("say \"hi\"\\ \n\ttab")");
  EXPECT_EQ(yamlOf(std::string("caf\xc3\xa9")), "\"caf\xc3\xa9\"");             // UTF-8 as it is
  EXPECT_EQ(yamlOf(std::string("bell\x07 bad\xff")), R"("bell\x07 bad\xFF")");  // what YAML cannot hold
  EXPECT_EQ(yamlOf(std::vector<bool>{true, false}), "[true, false]");
  EXPECT_EQ(yamlOf(std::vector<std::int64_t>{1, 2}), "[1, 2]");
  EXPECT_EQ(yamlOf(std::vector<double>{1, 2.5}), "[1.0, 2.5]");
  EXPECT_EQ(yamlOf(Strings{"yes", "", "a, b"}), R"(["yes", "", "a, b"])");
  EXPECT_EQ(yamlOf(Strings{}), "");  // rcl cannot type it: left out
}

TEST(NodeParameters, WhatIsWrittenReadsBackAsTheSameTypeAndValue) {
  for (const ParameterValue& v :
       {ParameterValue(true), ParameterValue(std::int64_t{-9'223'372'036'854'775'807}), ParameterValue(3.0),
        ParameterValue(1e-7), ParameterValue(std::string("no")), ParameterValue(std::string("0x10")),
        ParameterValue(std::string("'q' \"d\"")), ParameterValue(std::string("[1, 2]")),
        ParameterValue(std::vector<double>{0.0, -1.0}), ParameterValue(Strings{"on", "1", "'"})})
    EXPECT_EQ(rosValueOf(yamlOf(v)), v) << yamlOf(v);
}

TEST(NodeParameters, AnUpdateSetsNewAndChangedValuesAndErasesDeletedOnes) {
  ParameterMap values = typedParameters({{"greeting", "hi", {}}, {"speed", "0.2", {}}, {"mode", "fast", {}}});
  EXPECT_EQ(values.at("speed"), ParameterValue(0.2));
  overlay(values, {{{"greeting", std::string("changed")}, {"count", std::int64_t{3}}}, {"mode"}});
  const ParameterMap expected = {{"greeting", std::string("changed")}, {"speed", 0.2}, {"count", std::int64_t{3}}};
  EXPECT_EQ(values, expected);
  overlay(values, {{}, {"no_such_parameter"}});
  EXPECT_EQ(values, expected);
}

TEST(NodeParameters, TheParamsFileNamesTheNodeAndHoldsEveryValueTyped) {
  const ParameterMap values = {{"greeting", std::string("yes")},
                               {"speed", 2.0},
                               {"limits", std::vector<std::int64_t>{1, 2}},
                               {"empty", Strings{}},
                               {"odd name", true}};
  EXPECT_EQ(paramsFileText("/demo/talker", values),
            "# keel run: the parameters of /demo/talker as it last had them, for its restart\n"
            "/demo/talker:\n"
            "  ros__parameters:\n"
            "    greeting: \"yes\"\n"
            "    limits: [1, 2]\n"
            "    \"odd name\": true\n"
            "    speed: 2.0\n");
  const auto path = std::filesystem::temp_directory_path() / ("keel_params_" + std::to_string(::getpid()) + ".yaml");
  ASSERT_TRUE(writeParamsFile(path.string(), "/demo/talker", values));
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), paramsFileText("/demo/talker", values));
  std::filesystem::remove(path);
  EXPECT_FALSE(writeParamsFile("/no/such/folder/p.yaml", "/demo/talker", values));
}

}  // namespace
}  // namespace keel::supervision
