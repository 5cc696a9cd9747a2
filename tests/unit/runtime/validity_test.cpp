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

// An injected value a port's type cannot hold saturates to the type's range (a plain cast of
// 1e300 to int is undefined; on x86 it gives INT_MIN).
TEST(NumericTraits, AValueTheTypeCannotHoldSaturates) {
  int i = 0;
  NumericTraits<int>::fill(i, 1e300);
  EXPECT_EQ(i, std::numeric_limits<int>::max());
  NumericTraits<int>::fill(i, -1e300);
  EXPECT_EQ(i, std::numeric_limits<int>::lowest());
  NumericTraits<int>::fill(i, std::nan(""));
  EXPECT_EQ(i, std::numeric_limits<int>::lowest());
  NumericTraits<int>::fill(i, -42.7);
  EXPECT_EQ(i, -42);
  std::uint16_t u = 0;
  NumericTraits<std::uint16_t>::fill(u, -1);
  EXPECT_EQ(u, 0);
  float f = 0;
  NumericTraits<float>::fill(f, 1e300);
  EXPECT_EQ(f, std::numeric_limits<float>::infinity());
  std::vector<std::int64_t> v;
  NumericTraits<std::vector<std::int64_t>>::fill(v, 1e300);
  EXPECT_EQ(v, std::vector<std::int64_t>{std::numeric_limits<std::int64_t>::max()});
  std::array<std::int8_t, 2> a{};
  NumericTraits<std::array<std::int8_t, 2>>::fill(a, 300);
  EXPECT_EQ(a, (std::array<std::int8_t, 2>{127, 127}));
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
