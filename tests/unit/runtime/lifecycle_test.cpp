#include "keel/lifecycle.hpp"

#include <gtest/gtest.h>

namespace keel {
namespace {

TEST(Lifecycle, FollowsTheOprosTransitionTable) {
  EXPECT_TRUE(allowed(State::Created, Transition::Initialize));
  EXPECT_FALSE(allowed(State::Created, Transition::Start));
  EXPECT_TRUE(allowed(State::Ready, Transition::Start));
  EXPECT_TRUE(allowed(State::Active, Transition::Stop));
  EXPECT_FALSE(allowed(State::Active, Transition::Destroy));  // stop first
  EXPECT_TRUE(allowed(State::Inactive, Transition::Start));
  EXPECT_TRUE(allowed(State::Inactive, Transition::Destroy));
  EXPECT_FALSE(allowed(State::Destroyed, Transition::Start));
  EXPECT_FALSE(allowed(State::Destroyed, Transition::Initialize));
}

TEST(Lifecycle, ErrorIsLeftOnlyByRecoverOrDestroy) {
  EXPECT_TRUE(allowed(State::Error, Transition::Recover));
  EXPECT_TRUE(allowed(State::Error, Transition::Destroy));
  EXPECT_FALSE(allowed(State::Error, Transition::Start));
  EXPECT_FALSE(allowed(State::Error, Transition::Stop));
  EXPECT_FALSE(allowed(State::Error, Transition::Fault));
  EXPECT_EQ(target(Transition::Recover), State::Active);
}

TEST(Lifecycle, TransitionsLeadToTheirStates) {
  EXPECT_EQ(target(Transition::Initialize), State::Ready);
  EXPECT_EQ(target(Transition::Start), State::Active);
  EXPECT_EQ(target(Transition::Stop), State::Inactive);
  EXPECT_EQ(target(Transition::Destroy), State::Destroyed);
  EXPECT_EQ(target(Transition::Fault), State::Error);
}

}  // namespace
}  // namespace keel
