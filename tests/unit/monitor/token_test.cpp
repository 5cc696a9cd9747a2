#include "monitor/token.hpp"

#include <gtest/gtest.h>

#include <set>

namespace keel::monitor {
namespace {

TEST(MonitorToken, IsThirtyTwoHexDigitsAndNewEachTime) {
  std::set<std::string> seen;
  for (int i = 0; i < 100; ++i) {
    auto token = newToken();
    ASSERT_TRUE(token) << token.error().message;
    EXPECT_EQ(token->size(), 32U);
    EXPECT_EQ(token->find_first_not_of("0123456789abcdef"), std::string::npos) << *token;
    seen.insert(*token);
  }
  EXPECT_EQ(seen.size(), 100U);
}

TEST(MonitorToken, MatchesOnlyItselfAndNeverAnEmptyToken) {
  EXPECT_TRUE(tokenMatches("0123abcd", "0123abcd"));
  EXPECT_FALSE(tokenMatches("0123abcd", "0123abce"));
  EXPECT_FALSE(tokenMatches("0123abcd", "0123abc"));
  EXPECT_FALSE(tokenMatches("0123abcd", ""));
  EXPECT_FALSE(tokenMatches("", ""));
}

}  // namespace
}  // namespace keel::monitor
