// OPRoS's execution types in the plan (docs/opros.md#what-means-what): periodic-shared
// components of one period and priority share one executor, in load order; periodic and
// periodic-exclusive ones have their own; a task may not take a periodic-exclusive one.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "plan/plan.hpp"
#include "support/paths.hpp"
#include "unit/profile/profile_test_support.hpp"

namespace keel::plan {
namespace {

using profile::test::dataPath;
using profile::test::relative;
using ::testing::ElementsAre;

/// The plan of fixture `path` with the profiles it points into; one that does not load fails
/// with its diagnostics.
Result<PlannedProfiles> planOf(const std::string& path) {
  auto set = profile::load(dataPath(path));
  if (!set.ok()) return fail("does not load:\n" + profile::test::joined(set));
  return planProfiles(std::move(*set));
}

const PlannedExecutor* executorOf(const Plan& plan, const std::string& instance) {
  for (const auto& ex : plan.executors)
    for (const auto& m : ex.members)
      if (m == instance) return &ex;
  return nullptr;
}

TEST(OprosExecution, PeriodicSharedComponentsOfOnePeriodAndPriorityShareAnExecutor) {
  auto planned = planOf("opros_dialect/shared/app.xml");
  ASSERT_TRUE(planned.ok()) << planned.error().message;
  const Plan* plan = &planned->plan;
  const PlannedExecutor* shared = executorOf(*plan, "a");
  ASSERT_NE(shared, nullptr);
  EXPECT_EQ(shared->name, "periodic-shared-50ms-p10");
  EXPECT_THAT(shared->members, ElementsAre("b", "a", "a2")) << "in load order";
  EXPECT_DOUBLE_EQ(shared->period_ms, 50);
  EXPECT_EQ(shared->priority, 10);
  const PlannedExecutor* other = executorOf(*plan, "c");
  ASSERT_NE(other, nullptr);
  EXPECT_EQ(other->name, "periodic-shared-20ms-p10") << "another period, another executor";
  EXPECT_THAT(other->members, ElementsAre("c"));
  for (const char* own : {"d", "e"}) {
    const PlannedExecutor* ex = executorOf(*plan, own);
    ASSERT_NE(ex, nullptr) << own;
    EXPECT_THAT(ex->members, ElementsAre(own)) << "periodic and periodic-exclusive: a thread of its own";
  }
  EXPECT_EQ(plan->executors.size(), 4U);
}

TEST(OprosExecution, DependsIsTheExecutionOrderAndNeedsTheStopDependency) {
  auto planned = planOf("valid/app.xml");
  ASSERT_TRUE(planned.ok()) << planned.error().message;
  const Plan* plan = &planned->plan;
  ASSERT_EQ(plan->execution_order.size(), 1U);
  EXPECT_EQ(plan->execution_order[0].source, "nav");
  EXPECT_EQ(plan->execution_order[0].target, "sonar");
  ASSERT_EQ(plan->depends.size(), 1U) << "the fault manager's dependency graph: <needs>";
  EXPECT_EQ(plan->depends[0].source, "nav");
  EXPECT_EQ(plan->depends[0].target, "map");
}

TEST(OprosExecution, ACompositesCoordinationIsPlannedAndAnEdgeToItReachesEachMember) {
  for (const char* root : {"opros_dialect/shared/composite.xml", "opros_dialect/shared/with_composite.xml"}) {
    auto planned = planOf(root);
    ASSERT_TRUE(planned.ok()) << planned.error().message;
    const Plan* plan = &planned->plan;
    const std::string pair = std::string(root).ends_with("with_composite.xml") ? "pair." : "";
    std::vector<std::string> order, needs;
    for (const auto& d : plan->execution_order) order.push_back(d.source + "->" + d.target);
    for (const auto& d : plan->depends) needs.push_back(d.source + "->" + d.target);
    if (pair.empty()) {
      EXPECT_THAT(order, ElementsAre("d->e")) << root;
    } else {
      EXPECT_THAT(order, ElementsAre("pair.d->pair.e", "a->pair.e", "a->pair.d")) << root;
    }
    EXPECT_THAT(needs, ElementsAre(fmt::format("{0}e->{0}d", pair))) << root;
  }
}

TEST(OprosExecution, AnExecutionOrderOnAPassiveComponentIsAWarning) {
  const auto set = profile::load(std::string(KEEL_TEST_PROFILES) + "/execution_order.xml");
  ASSERT_TRUE(set.ok()) << profile::test::joined(set);
  ASSERT_EQ(set->warnings.size(), 1U);
  EXPECT_EQ(set->warnings[0].where.line, 17);
  EXPECT_EQ(set->warnings[0].message,
            "depends: 'server' is passive and never executes, so 'stuck', which executes after it, never executes "
            "either (OPRoS's execution order; <needs> is keel's stop dependency)");
}

TEST(OprosExecution, AnExecutionOrderStaysInKeelRunsOwnProcess) {
  auto planned = planOf("opros_dialect/shared/order_across_processes.xml");
  ASSERT_FALSE(planned.ok());
  EXPECT_EQ(relative(planned.error().message),
            "opros_dialect/shared/order_across_processes.xml:9: depends d -> e: OPRoS's execution order is kept "
            "within keel run's own process ('d' runs in keel run's own process, 'e' in process 'drivers')");
}

TEST(OprosExecution, ATaskMayNotTakeAPeriodicExclusiveComponent) {
  auto planned = planOf("opros_dialect/shared/exclusive_in_task.xml");
  ASSERT_FALSE(planned.ok());
  EXPECT_EQ(relative(planned.error().message),
            "opros_dialect/shared/exclusive_in_task.xml:9: task 'control' names 'd', whose component 'D' is "
            "periodic-exclusive (a thread of its own, as OPRoS runs it): take it out of the task, or make it "
            "periodic");
}

}  // namespace
}  // namespace keel::plan
