// The lexical rules of profile values (src/profile/values.hpp): numbers are strict (the whole
// text, finite unless allowed), words are case-insensitive, property types normalise.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

#include "profile/values.hpp"

namespace keel::profile::detail {
namespace {

using ::testing::ElementsAre;
using ::testing::Optional;

TEST(ProfileValues, ParsesAWholeDecimalNumberAroundWhitespace) {
  EXPECT_THAT(parseDouble(" 2.5\n"), Optional(2.5));
  EXPECT_THAT(parseDouble("1e3"), Optional(1000.0));
  EXPECT_THAT(parseDouble("+0.25"), Optional(0.25));
  EXPECT_THAT(parseDouble("-3"), Optional(-3.0));
}

TEST(ProfileValues, RejectsNumbersWithTrailingTextOrOtherSyntax) {
  EXPECT_EQ(parseDouble("10ms"), std::nullopt);
  EXPECT_EQ(parseDouble("1,5"), std::nullopt);
  EXPECT_EQ(parseDouble("0x10"), std::nullopt);
  EXPECT_EQ(parseDouble("++1"), std::nullopt);
  EXPECT_EQ(parseDouble("+-1"), std::nullopt);
  EXPECT_EQ(parseInt("+-1"), std::nullopt);
  EXPECT_EQ(parseDouble(""), std::nullopt);
  EXPECT_EQ(parseDouble("1e999"), std::nullopt);
}

TEST(ProfileValues, RejectsNanAlwaysAndInfinityUnlessAllowed) {
  EXPECT_EQ(parseDouble("nan"), std::nullopt);
  EXPECT_EQ(parseDouble("nan", true), std::nullopt);
  EXPECT_EQ(parseDouble("inf"), std::nullopt);
  EXPECT_THAT(parseDouble("-inf", true), Optional(-std::numeric_limits<double>::infinity()));
}

TEST(ProfileValues, ParsesIntegersStrictly) {
  EXPECT_THAT(parseInt(" 42 "), Optional(42));
  EXPECT_THAT(parseInt("-7"), Optional(-7));
  EXPECT_EQ(parseInt("1.0"), std::nullopt);
  EXPECT_EQ(parseInt("99999999999999999999"), std::nullopt);
  EXPECT_EQ(parseInt("12a"), std::nullopt);
}

TEST(ProfileValues, ParsesBooleansAsTrueFalseOneOrZero) {
  EXPECT_THAT(parseBool("TRUE"), Optional(true));
  EXPECT_THAT(parseBool("0"), Optional(false));
  EXPECT_EQ(parseBool("yes"), std::nullopt);
}

TEST(ProfileValues, SplitsNumberListsOnWhitespaceAndCommas) {
  EXPECT_THAT(parseDoubleList("1, 2\t3 ,4"), Optional(ElementsAre(1.0, 2.0, 3.0, 4.0)));
  EXPECT_THAT(parseDoubleList("  "), Optional(ElementsAre()));
  EXPECT_EQ(parseDoubleList("1 two"), std::nullopt);
}

TEST(ProfileValues, LooksUpWordsIgnoringCase) {
  const std::vector<std::pair<std::string_view, int>> table = {{"fifo", 1}, {"rr", 2}};
  EXPECT_THAT(parseWord(" FIFO ", table), Optional(1));
  EXPECT_EQ(parseWord("round", table), std::nullopt);
  EXPECT_EQ(wordList(table), "fifo or rr");
}

TEST(ProfileValues, NormalisesCppAndOprosPropertyTypes) {
  EXPECT_THAT(normalisePropertyType("long"), Optional(std::string("int")));
  EXPECT_THAT(normalisePropertyType("unsigned   short"), Optional(std::string("int")));
  EXPECT_THAT(normalisePropertyType("float"), Optional(std::string("double")));
  EXPECT_THAT(normalisePropertyType("std::string"), Optional(std::string("string")));
  EXPECT_THAT(normalisePropertyType("std::vector< double >"), Optional(std::string("double[]")));
  EXPECT_THAT(normalisePropertyType("double[]"), Optional(std::string("double[]")));
  EXPECT_EQ(normalisePropertyType("quaternion"), std::nullopt);
  EXPECT_TRUE(isUnsignedType("unsigned int"));
  EXPECT_FALSE(isUnsignedType("int"));
}

TEST(ProfileValues, ParsesPropertyValuesByNormalisedType) {
  EXPECT_EQ(parsePropertyValue("int", "12"), PropertyValue{std::int64_t{12}});
  EXPECT_EQ(parsePropertyValue("string", "  a b "), PropertyValue{std::string("a b")});
  EXPECT_EQ(parsePropertyValue("double[]", "1 2"), PropertyValue{(std::vector<double>{1, 2})});
  EXPECT_EQ(parsePropertyValue("double", "inf"), std::nullopt);
  EXPECT_EQ(parsePropertyValue("bool", "maybe"), std::nullopt);
}

}  // namespace
}  // namespace keel::profile::detail
