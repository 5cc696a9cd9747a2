#include "keel/detail/validity.hpp"

#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <vector>

namespace keel::detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(ValidityRule, AcceptsValuesWithinBoundsInclusive) {
  ValidityRule r{{3}, {3000}};
  Violation v;
  EXPECT_TRUE(r.check(3.0, v));
  EXPECT_TRUE(r.check(3000.0, v));
  EXPECT_TRUE(r.check(150, v));  // integers too
}

TEST(ValidityRule, RejectsOutOfBoundsNaNAndInfinity) {
  ValidityRule r{{3}, {3000}};
  Violation v;
  EXPECT_FALSE(r.check(0.0, v));
  EXPECT_EQ(v.value, 0.0);
  EXPECT_EQ(v.min, 3.0);
  EXPECT_EQ(v.max, 3000.0);
  EXPECT_FALSE(r.check(kNaN, v));
  EXPECT_FALSE(r.check(kInf, v));
  ValidityRule open_above{{0}, {}};
  EXPECT_FALSE(open_above.check(kInf, v)) << "infinity is never a reading";
  EXPECT_TRUE(open_above.check(1e300, v));
}

TEST(ValidityRule, OneBoundAppliesToEveryElementOfAnArray) {
  ValidityRule r{{0}, {10}};
  Violation v;
  EXPECT_TRUE(r.check(std::vector<double>{1, 2, 3}, v));
  EXPECT_FALSE(r.check(std::vector<double>{1, 12, 3}, v));
  EXPECT_EQ(v.index, 1u);
  EXPECT_TRUE(v.array);
  EXPECT_FALSE(r.check(std::array<float, 2>{1.0f, -1.0f}, v));
  EXPECT_EQ(v.index, 1u);
}

TEST(ValidityRule, SeveralBoundsApplyElementWiseAndFixTheLength) {
  ValidityRule r{{0, 10}, {5, 20}};
  Violation v;
  EXPECT_TRUE(r.check(std::vector<double>{4, 15}, v));
  EXPECT_FALSE(r.check(std::vector<double>{6, 15}, v));
  EXPECT_EQ(v.index, 0u);
  EXPECT_FALSE(r.check(std::vector<double>{4, 15, 1}, v));
  EXPECT_EQ(v.size_expected, 2u);
  EXPECT_EQ(v.size_got, 3u);
}

TEST(NumericTraits, KnowsWhichTypesCanBeChecked) {
  EXPECT_TRUE(NumericTraits<double>::numeric);
  EXPECT_TRUE(NumericTraits<int>::numeric);
  EXPECT_TRUE((NumericTraits<std::array<float, 3>>::numeric));
  EXPECT_TRUE(NumericTraits<std::vector<double>>::numeric);
  EXPECT_FALSE(NumericTraits<bool>::numeric);
  EXPECT_FALSE(NumericTraits<std::string>::numeric);
  EXPECT_FALSE(NumericTraits<std::vector<std::string>>::numeric);
}

}  // namespace
}  // namespace keel::detail
