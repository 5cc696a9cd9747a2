// Checkpoints of critical() memory (src/runtime/checkpoint.hpp): taken when due, restored on
// reset, copied into a replacement region by region.
#include "runtime/checkpoint.hpp"

#include <gtest/gtest.h>

#include <array>

namespace keel::runtime {
namespace {

struct State {
  int count = 0;
  std::array<double, 3> pose{};
};

class Holder : public Component {
 public:
  State state;
  int other = 0;
  void registerAll() {
    critical(state);
    critical(other);
  }
};

TEST(Checkpoint, RestoreBringsBackTheLastCopyAndNothingNewer) {
  Holder h;
  h.registerAll();
  auto& core = coreOf(h);
  EXPECT_EQ(restoreCheckpoint(core), 0) << "no checkpoint yet";
  h.state.count = 7;
  h.state.pose = {1, 2, 3};
  h.other = 11;
  takeCheckpoint(core, 1000);
  h.state.count = 99;  // after the checkpoint: lost by a restore
  h.state.pose[2] = -1;
  h.other = 0;
  EXPECT_EQ(restoreCheckpoint(core), 1000);
  EXPECT_EQ(h.state.count, 7);
  EXPECT_EQ(h.state.pose[2], 3);
  EXPECT_EQ(h.other, 11);
}

TEST(Checkpoint, APeriodicCheckpointIsTakenOnlyWhenDue) {
  Holder h;
  h.registerAll();
  auto& core = coreOf(h);
  core.checkpoints.period_ns = 100;
  checkpointIfDue(core, 0);
  EXPECT_EQ(core.checkpoints.count, 1u);
  h.state.count = 1;
  checkpointIfDue(core, 50);  // not due: the copy keeps 0
  EXPECT_EQ(core.checkpoints.count, 1u);
  checkpointIfDue(core, 100);
  EXPECT_EQ(core.checkpoints.count, 2u);
  h.state.count = 2;
  restoreCheckpoint(core);
  EXPECT_EQ(h.state.count, 1);
}

TEST(Checkpoint, WithoutAPeriodNoPeriodicCheckpointIsTaken) {
  Holder h;
  h.registerAll();
  checkpointIfDue(coreOf(h), 1'000'000);
  EXPECT_EQ(coreOf(h).checkpoints.count, 0u);
}

TEST(Checkpoint, AReplacementReceivesTheCheckpointRegionByRegion) {
  Holder failed, replacement;
  failed.registerAll();
  replacement.registerAll();
  failed.state.count = 42;
  failed.other = 5;
  takeCheckpoint(coreOf(failed), 1);
  failed.state.count = -1;  // torn or corrupted by the fault: not what is copied
  EXPECT_EQ(copyCheckpoint(coreOf(failed), coreOf(replacement)), 2u);
  EXPECT_EQ(replacement.state.count, 42);
  EXPECT_EQ(replacement.other, 5);
}

}  // namespace
}  // namespace keel::runtime
