// Fault injection's runtime side (src/runtime/injection): what an armed injection does to a
// component depending on its state.
#include "runtime/injection.hpp"

#include <gtest/gtest.h>

#include "runtime/component_core.hpp"
#include "runtime/invoke.hpp"

namespace keel {
namespace {

class Idle : public Component {};

// A component that is not running has no heartbeat to stall: a stall armed then would be
// recorded as manifested and never detected (keel soak met it on components a fault stop had
// stopped). It is refused, and the caller says so.
TEST(Injection, AStallIsArmedOnlyOnAComponentThatIsRunning) {
  Idle c;
  const runtime::InjectArgs args{"", 0.0, 100'000'000};
  EXPECT_FALSE(runtime::arm(c, runtime::InjectKind::StallHeartbeat, 7, args)) << "Created";
  ASSERT_TRUE(runtime::transition(c, Transition::Initialize));
  EXPECT_FALSE(runtime::arm(c, runtime::InjectKind::StallHeartbeat, 7, args)) << "Ready";
  EXPECT_EQ(runtime::coreOf(c).injection.injected_id.load(), 0u);
  ASSERT_TRUE(runtime::transition(c, Transition::Start));
  EXPECT_TRUE(runtime::arm(c, runtime::InjectKind::StallHeartbeat, 7, args)) << "Active";
  EXPECT_EQ(runtime::coreOf(c).injection.injected_id.load(), 7u);
  ASSERT_TRUE(runtime::transition(c, Transition::Stop));
  runtime::coreOf(c).injection.injected_id.store(0);
  EXPECT_FALSE(runtime::arm(c, runtime::InjectKind::StallHeartbeat, 8, args)) << "Inactive";
  EXPECT_EQ(runtime::coreOf(c).injection.injected_id.load(), 0u);
}

}  // namespace
}  // namespace keel
