// <process>: how the profile says it, how the plan groups instances into component processes,
// and what the plan refuses to split between processes (each with its file:line).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "plan/plan.hpp"
#include "unit/profile/profile_test_support.hpp"

namespace keel::plan {
namespace {

using profile::test::dataPath;
using profile::test::problems;
using profile::test::relative;
using ::testing::ElementsAre;

TEST(ProcessProfile, ReportsEachBadProcessElementWithItsLine) {
  EXPECT_THAT(problems("errors/process/bad_attributes.xml"),
              ElementsAre("errors/process/bad_attributes.xml:8: unknown attribute 'restart' of <process>",
                          "errors/process/bad_attributes.xml:8: standby of <process> of subcomponent 'sonar' must "
                          "be an integer from 0 to 8, got 'many'",
                          "errors/process/bad_attributes.xml:13: missing attribute 'name' of <process>",
                          "errors/process/bad_attributes.xml:18: <process> of subcomponent 'map': name 'maps and "
                          "more' is not a process name (1 to 64 letters, digits, '_', '-' or '.')"));
}

TEST(ProcessPlan, GroupsTheInstancesOfEachProcessAndLeavesTheRestInKeelRun) {
  auto set = profile::load(dataPath("process/app.xml"));
  ASSERT_TRUE(set.ok()) << profile::test::joined(set);
  auto plan = makePlan(*set);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  ASSERT_EQ(plan->processes.size(), 1u);
  EXPECT_EQ(plan->processes[0].name, "drivers");
  EXPECT_EQ(plan->processes[0].standby, 2);
  EXPECT_THAT(plan->processes[0].members, ElementsAre("sonar", "nav"));
  EXPECT_EQ(plan->find("sonar")->process, "drivers");
  EXPECT_EQ(plan->find("map")->process, "");
  EXPECT_EQ(relative(plan->processes[0].where.file), "process/app.xml");
  EXPECT_EQ(plan->processes[0].where.line, 9);
}

TEST(ProcessPlan, RefusesWhatCannotBeSplitBetweenProcesses) {
  auto set = profile::load(dataPath("process/crossings.xml"));
  ASSERT_TRUE(set.ok()) << profile::test::joined(set);
  auto plan = makePlan(*set);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(relative(plan.error().message),
            "process/crossings.xml:30: task 'control' runs 'sonar' (process 'sensing') and 'nav' (process "
            "'planning'): a task's members run in one process\n"
            "process/crossings.xml:24: port_connection nav.map -> map.map: a service call cannot cross processes "
            "('nav' runs in process 'planning', 'map' in process 'sensing'); put both in one <process>, or "
            "connect them by data or event ports\n"
            "process/crossings.xml:20: process 'sensing' has standby=\"2\" here but \"1\" at process/crossings.xml:10");
}

}  // namespace
}  // namespace keel::plan
