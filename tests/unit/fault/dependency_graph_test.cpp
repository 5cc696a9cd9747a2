// The dependency graph (paper §5.2, Fig. 7): which applications a fault stops, through
// requirement groups with duplicates, application dependencies, package-level depends and the
// containment scope. Plans are built by hand, named as plan::makePlan names them ("app.x").
#include "fault/dependency_graph.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

namespace keel::fault {
namespace {

using profile::Scope;
using ::testing::ElementsAre;
using ::testing::IsEmpty;

struct AppSpec {
  std::string name;
  std::vector<std::string> components;  // unqualified
  std::vector<std::string> depends_on;
  std::vector<std::pair<std::vector<std::string>, int>> requires_;  // components, min_healthy
};

/// A system profile and its plan, as makePlan would make them.
struct System {
  plan::Plan plan;
  profile::ProfileSet set;

  explicit System(const std::vector<AppSpec>& apps) {
    plan.name = "test";
    set.root_kind = profile::RootKind::System;
    set.system.emplace();
    for (const auto& a : apps) {
      profile::Application app{a.name, a.name + ".xml", a.depends_on, {}, {}};
      for (const auto& [components, min] : a.requires_) app.requires_.push_back({components, min, {}});
      set.system->applications.push_back(app);
      for (const auto& c : a.components) {
        plan::PlannedInstance inst;
        inst.name = a.name + "." + c;
        inst.application = a.name;
        plan.instances.push_back(inst);
      }
    }
  }
  void task(const std::string& name, std::vector<std::string> members) {
    plan.executors.push_back({name, true, 5.0, 0, SchedPolicy::Other, std::move(members), {}});
  }
  void policy(const std::string& component, Scope scope) {
    auto& inst = *std::find_if(plan.instances.begin(), plan.instances.end(),
                               [&](const auto& i) { return i.name == component; });
    inst.policy.emplace();
    inst.policy->dependency = scope;
  }
  DependencyGraph graph() const {
    auto g = DependencyGraph::build(plan, set);
    EXPECT_TRUE(g) << g.error().message;
    return std::move(g.value());
  }
};

/// Fig. 7 as shipped in tests/integration/profiles/fig7: A needs one of its three type-B
/// components (b1..b3, one task) and a1; B needs both of its two (one task; b2's faults are
/// contained in the task) and a1; C depends on B, D on A; C and D need all of a1, c1.
System figureSeven() {
  System s({{"A", {"b1", "b2", "b3", "a1"}, {}, {{{"b1", "b2", "b3"}, 1}, {{"a1"}, 1}}},
            {"B", {"b1", "b2", "a1"}, {}, {{{"b1", "b2"}, 2}, {{"a1"}, 1}}},
            {"C", {"a1", "c1"}, {"B"}, {}},
            {"D", {"a1", "c1"}, {"A"}, {}}});
  s.task("A.sensors", {"A.b1", "A.b2", "A.b3"});
  s.task("B.pair", {"B.b1", "B.b2"});
  s.policy("B.b2", Scope::Executor);
  return s;
}

TEST(DependencyGraph, FigureSevenApplicationASurvivesTwoFaultyTypeBComponentsWhileBAndItsDependantCStop) {
  const auto graph = figureSeven().graph();

  const Impact impact = graph.impactOf({"A.b1", "A.b2", "B.b1"});

  EXPECT_THAT(impact.stopped_applications, ElementsAre("B", "C"));
  EXPECT_THAT(impact.running_applications, ElementsAre("A", "D"));
  EXPECT_THAT(impact.stopped_components, ElementsAre("A.b1", "A.b2", "B.b1", "B.b2", "B.a1", "C.a1", "C.c1"));
}

TEST(DependencyGraph, FigureSevenApplicationAStopsWhenItsLastTypeBComponentFailsAndTakesDWithIt) {
  const auto graph = figureSeven().graph();

  const Impact impact = graph.impactOf({"A.b1", "A.b2", "A.b3"});

  EXPECT_THAT(impact.stopped_applications, ElementsAre("A", "D"));
  EXPECT_THAT(impact.running_applications, ElementsAre("B", "C"));
  EXPECT_THAT(impact.stopped_components, ElementsAre("A.b1", "A.b2", "A.b3", "A.a1", "D.a1", "D.c1"));
}

TEST(DependencyGraph, AnApplicationWithoutRequiresNeedsEveryComponentButItsFaultDoesNotTravelUpstream) {
  const auto graph = figureSeven().graph();

  const Impact impact = graph.impactOf({"D.c1"});

  EXPECT_THAT(impact.stopped_applications, ElementsAre("D"));
  EXPECT_THAT(impact.stopped_components, ElementsAre("D.a1", "D.c1"));
}

TEST(DependencyGraph, NoFaultStopsNothing) {
  const auto graph = figureSeven().graph();

  const Impact impact = graph.impactOf({});

  EXPECT_THAT(impact.stopped_components, IsEmpty());
  EXPECT_THAT(impact.stopped_applications, IsEmpty());
  EXPECT_THAT(impact.running_applications, ElementsAre("A", "B", "C", "D"));
}

TEST(DependencyGraph, ApplicationDependenciesStopDependantsTransitively) {
  const auto graph = System({{"base", {"x"}, {}, {}},
                             {"middle", {"y"}, {"base"}, {}},
                             {"top", {"z"}, {"middle"}, {}},
                             {"other", {"w"}, {}, {}}})
                         .graph();

  const Impact impact = graph.impactOf({"base.x"});

  EXPECT_THAT(impact.stopped_applications, ElementsAre("base", "middle", "top"));
  EXPECT_THAT(impact.running_applications, ElementsAre("other"));
  EXPECT_THAT(impact.stopped_components, ElementsAre("base.x", "middle.y", "top.z"));
}

TEST(DependencyGraph, ComponentScopeIsTheComponentAlone) {
  const auto graph = figureSeven().graph();

  EXPECT_THAT(graph.scopeOf("A.b1", Scope::Component), ElementsAre("A.b1"));
  EXPECT_THAT(graph.blastRadius("A.b1", Scope::Component).stopped_components, ElementsAre("A.b1"));
}

TEST(DependencyGraph, ExecutorScopeStopsEveryMemberOfTheTaskAndWhatNeedsThem) {
  const auto graph = figureSeven().graph();

  EXPECT_THAT(graph.scopeOf("A.b2", Scope::Executor), ElementsAre("A.b1", "A.b2", "A.b3"));
  const Impact impact = graph.blastRadius("A.b2", Scope::Executor);

  EXPECT_THAT(impact.stopped_applications, ElementsAre("A", "D"));
  EXPECT_THAT(impact.running_applications, ElementsAre("B", "C"));
}

TEST(DependencyGraph, ExecutorScopeOfAComponentOnItsOwnExecutorOrNoneIsTheComponent) {
  System s = figureSeven();
  s.task("A.a1", {"A.a1"});  // its own executor, as makePlan gives it; C.a1 stays passive
  const auto graph = s.graph();

  EXPECT_THAT(graph.scopeOf("A.a1", Scope::Executor), ElementsAre("A.a1"));
  EXPECT_THAT(graph.scopeOf("C.a1", Scope::Executor), ElementsAre("C.a1"));
}

TEST(DependencyGraph, CompositeScopeIsTheInnermostCompositesMembersOrTheComponentAlone) {
  System s = figureSeven();
  // As makePlan records them: an outer composite "A.arm" holding "A.b1" and a nested "A.arm.hand"
  // (here "A.b2", "A.b3"), outer first.
  s.plan.composites.push_back({"A.arm", {"A.b1", "A.b2", "A.b3"}, {}});
  s.plan.composites.push_back({"A.arm.hand", {"A.b2", "A.b3"}, {}});
  const auto graph = s.graph();

  EXPECT_THAT(graph.scopeOf("A.b2", Scope::Composite), ElementsAre("A.b2", "A.b3"));
  EXPECT_THAT(graph.scopeOf("A.b1", Scope::Composite), ElementsAre("A.b1", "A.b2", "A.b3"));
  EXPECT_THAT(graph.scopeOf("A.a1", Scope::Composite), ElementsAre("A.a1"));
}

TEST(DependencyGraph, SystemScopeStopsEveryComponentAndEveryApplication) {
  const auto graph = figureSeven().graph();

  EXPECT_EQ(graph.scopeOf("D.c1", Scope::System).size(), graph.components().size());
  const Impact impact = graph.blastRadius("D.c1", Scope::System);

  EXPECT_EQ(impact.stopped_components, graph.components());
  EXPECT_THAT(impact.stopped_applications, ElementsAre("A", "B", "C", "D"));
  EXPECT_THAT(impact.running_applications, IsEmpty());
}

TEST(DependencyGraph, PolicyScopeIsTheFaultPolicysDependencyElseComponent) {
  const auto graph = figureSeven().graph();

  EXPECT_EQ(graph.policyScope("B.b2"), Scope::Executor);
  EXPECT_EQ(graph.policyScope("B.b1"), Scope::Component);
  EXPECT_EQ(graph.policyScope("no.such"), Scope::Component);
}

TEST(DependencyGraph, PackageDependsStopTheirSourcesTransitivelyButNotTheirTargets) {
  // "app" needs only `needed`; sensor <- filter <- planner through coordination/needs.
  System s({{"app", {"sensor", "filter", "planner", "needed"}, {}, {{{"needed"}, 1}}}});
  s.plan.depends.push_back({"app.filter", "app.sensor", {}});
  s.plan.depends.push_back({"app.planner", "app.filter", {}});
  const auto graph = s.graph();

  EXPECT_THAT(graph.impactOf({"app.sensor"}).stopped_components,
              ElementsAre("app.sensor", "app.filter", "app.planner"));
  EXPECT_THAT(graph.impactOf({"app.filter"}).stopped_components, ElementsAre("app.filter", "app.planner"));
  EXPECT_THAT(graph.impactOf({"app.sensor"}).running_applications, ElementsAre("app"));
}

TEST(DependencyGraph, PackageDependsCanStopARequiredComponentAndSoItsApplication) {
  System s({{"app", {"sensor", "planner"}, {}, {{{"planner"}, 1}}}, {"user", {"u"}, {"app"}, {}}});
  s.plan.depends.push_back({"app.planner", "app.sensor", {}});
  const auto graph = s.graph();

  const Impact impact = graph.impactOf({"app.sensor"});

  EXPECT_THAT(impact.stopped_applications, ElementsAre("app", "user"));
}

TEST(DependencyGraph, ARequiredCompositeIsOneEntryDownWhenAnyOfItsComponentsIsDown) {
  // "stereo" is a composite (flattened to app.stereo.left, app.stereo.right); one of
  // {stereo, lidar} must stay healthy.
  System s({{"app", {"stereo.left", "stereo.right", "lidar"}, {}, {{{"stereo", "lidar"}, 1}}}});
  const auto graph = s.graph();

  EXPECT_THAT(graph.impactOf({"app.stereo.left", "app.stereo.right"}).running_applications, ElementsAre("app"));
  EXPECT_THAT(graph.impactOf({"app.stereo.left", "app.lidar"}).stopped_applications, ElementsAre("app"));
}

TEST(DependencyGraph, APackageIsOneImplicitApplicationRunningWhileAnyComponentRuns) {
  plan::Plan plan;
  plan.name = "pipeline";
  for (const char* name : {"counter", "summer", "fault_manager"}) {
    plan::PlannedInstance inst;
    inst.name = name;
    plan.instances.push_back(inst);
  }
  profile::ProfileSet set;  // a package root: no system
  const auto graph = DependencyGraph::build(plan, set);
  ASSERT_TRUE(graph) << graph.error().message;

  EXPECT_THAT(graph->impactOf({}).running_applications, ElementsAre("pipeline"));
  const Impact one = graph->impactOf({"summer"});  // the others run on (decision 0004)
  EXPECT_THAT(one.stopped_applications, IsEmpty());
  EXPECT_THAT(one.stopped_components, ElementsAre("summer"));
  const Impact all = graph->impactOf({"summer", "counter"});
  EXPECT_THAT(all.stopped_applications, ElementsAre("pipeline"));
  EXPECT_THAT(all.stopped_components, ElementsAre("counter", "summer"));  // not the fault manager
  EXPECT_THAT(graph->impactOf({"fault_manager"}).running_applications, ElementsAre("pipeline"));
}

TEST(DependencyGraph, UnknownComponentsAreIgnoredAndHaveAnEmptyScope) {
  const auto graph = figureSeven().graph();

  EXPECT_FALSE(graph.contains("A.b9"));
  EXPECT_TRUE(graph.contains("A.b1"));
  EXPECT_THAT(graph.scopeOf("A.b9", Scope::System), IsEmpty());
  EXPECT_THAT(graph.impactOf({"A.b9"}).stopped_components, IsEmpty());
}

TEST(DependencyGraph, BuildRejectsARequirementThePlanDoesNotHave) {
  System s({{"app", {"x"}, {}, {{{"y"}, 1}}}});

  const auto graph = DependencyGraph::build(s.plan, s.set);

  ASSERT_FALSE(graph);
  EXPECT_EQ(graph.error().message, "application 'app' requires 'y', which is not in the plan");
}

TEST(DependencyGraph, BuildRejectsADependencyOnAnUnknownApplication) {
  System s({{"app", {"x"}, {"ghost"}, {}}});

  const auto graph = DependencyGraph::build(s.plan, s.set);

  ASSERT_FALSE(graph);
  EXPECT_EQ(graph.error().message, "application 'app' depends on unknown application 'ghost'");
}

TEST(DependencyGraph, CyclicApplicationDependenciesTheLoaderWouldRejectStillTerminateAndStopTogether) {
  const auto graph = System({{"p", {"x"}, {"q"}, {}}, {"q", {"y"}, {"p"}, {}}, {"r", {"z"}, {}, {}}}).graph();

  const Impact impact = graph.impactOf({"p.x"});

  EXPECT_THAT(impact.stopped_applications, ElementsAre("p", "q"));
  EXPECT_THAT(impact.running_applications, ElementsAre("r"));
}

// 100 applications of 10 components; each needs 4 of its c0..c4 and all of c5..c9; in chains
// of ten, application k depends on k-1.
TEST(DependencyGraph, AThousandComponentGraphGivesTheSameAnswerAsTheRulesByHand) {
  std::vector<AppSpec> apps;
  for (int k = 0; k < 100; ++k) {
    AppSpec a{"app" + std::to_string(k), {}, {}, {}};
    for (int c = 0; c < 10; ++c) a.components.push_back("c" + std::to_string(c));
    if (k % 10 != 0) a.depends_on.push_back("app" + std::to_string(k - 1));
    a.requires_.push_back({{"c0", "c1", "c2", "c3", "c4"}, 4});
    a.requires_.push_back({{"c5", "c6", "c7", "c8", "c9"}, 5});
    apps.push_back(a);
  }
  const auto graph = System(apps).graph();
  ASSERT_EQ(graph.components().size(), 1000u);

  // app0 loses two duplicates (chain app0..app9 stops); app50 loses one (keeps running);
  // app95 loses a component it needs (app95..app99 stop).
  const Impact impact = graph.impactOf({"app0.c0", "app0.c1", "app50.c2", "app95.c7"});

  std::vector<std::string> expected;
  expected.reserve(15);
  for (int k = 0; k < 10; ++k) expected.push_back("app" + std::to_string(k));
  for (int k = 95; k < 100; ++k) expected.push_back("app" + std::to_string(k));
  EXPECT_EQ(impact.stopped_applications, expected);
  EXPECT_EQ(impact.running_applications.size(), 85u);
  EXPECT_EQ(impact.stopped_components.size(), 151u);  // 15 applications, and app50.c2
  EXPECT_TRUE(std::find(impact.stopped_components.begin(), impact.stopped_components.end(), "app50.c2") !=
              impact.stopped_components.end());
}

}  // namespace
}  // namespace keel::fault
