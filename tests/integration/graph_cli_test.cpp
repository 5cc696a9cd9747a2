// `keel graph PROFILE.xml --fail COMPONENT`: the blast radius of a fault stop on the Fig. 7
// system profile (paper §5.2), its summary, the colours on the graph, and the application
// clusters of a system profile.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "support/paths.hpp"
#include "support/process.hpp"

namespace keel {
namespace {

std::string fig7() { return std::string(KEEL_TEST_PROFILES) + "/fig7/system.xml"; }

test::Ran graph(std::vector<std::string> args) {
  args.insert(args.begin(), {KEEL_CLI, "graph"});
  return test::runProcess(args);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(GraphCli, AConnectionCarryingAFieldIsLabelledWithIt) {
  auto r = graph({std::string(KEEL_PROFILE_TEST_DATA) + "/node/field_app.xml"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"wander\" -> \"nav\" [label=\"cmd.linear.x → range\", style=solid];")) << r.out;
}

TEST(GraphCli, AFaultOfOneOfBsPairStopsBAndCAndKeepsAAndDRunning) {
  auto r = graph({fig7(), "--fail", "B.b1"});

  ASSERT_EQ(r.status, 0) << r.err;
  const std::string summary =
      "fault at B.b1 (scope component): stops components [B.b1, B.b2, B.a1, C.a1, C.c1]; "
      "stops applications [B, C]; keeps running [A, D]";
  EXPECT_EQ(r.err, summary + "\n");
  EXPECT_EQ(r.out.rfind("digraph \"Fig7\" {\n  // keel graph --fail\n  // " + summary + "\n", 0), 0u) << r.out;
}

TEST(GraphCli, FigureSevenAppASurvivesTwoFaultyTypeBComponentsWhileBAndCStop) {
  auto r = graph({fig7(), "--fail", "A.b1", "--fail", "A.b2", "--fail", "B.b1"});

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err,
            "faults at A.b1 (scope component), A.b2 (scope component), B.b1 (scope component): "
            "stops components [A.b1, A.b2, B.b1, B.b2, B.a1, C.a1, C.c1]; stops applications [B, C]; "
            "keeps running [A, D]\n");
}

TEST(GraphCli, TheScopeDefaultsToTheComponentsFaultPolicy) {
  auto r = graph({fig7(), "--fail", "B.b2"});  // pair.xml: <dependency>executor</dependency>

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.rfind("fault at B.b2 (scope executor): stops components [B.b1, B.b2, B.a1, C.a1, C.c1];", 0), 0u)
      << r.err;
}

TEST(GraphCli, AnExplicitExecutorScopeStopsTheWholeTaskAndSoApplicationAAndD) {
  auto r = graph({fig7(), "--fail", "A.b1", "--scope", "executor"});

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err,
            "fault at A.b1 (scope executor): stops components [A.b1, A.b2, A.b3, A.a1, D.a1, D.c1]; "
            "stops applications [A, D]; keeps running [B, C]\n");
}

// The composite scope: the failed component's composite, whole, and nothing outside it; it is
// also what the policy of composite_stop.xml says.
TEST(GraphCli, ACompositeScopeStopsTheWholeCompositeAndNothingElse) {
  const std::string profile = std::string(KEEL_TEST_PROFILES) + "/composite_stop.xml";
  for (const auto& args : {std::vector<std::string>{profile, "--fail", "pair.crasher", "--scope", "composite"},
                           std::vector<std::string>{profile, "--fail", "pair.crasher"}}) {
    auto r = graph(args);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err,
              "fault at pair.crasher (scope composite): stops components [pair.crasher, pair.counter]; "
              "stops applications []; keeps running [composite_stop]\n");
  }
}

TEST(GraphCli, TheFailedComponentIsRedAndWhatItStopsIsFilled) {
  auto r = graph({fig7(), "--fail", "B.b1"});

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"B.b1\" [style=\"rounded,filled\", fillcolor=\"#e06666\""));
  EXPECT_TRUE(contains(r.out, "\"B.b2\" [style=\"rounded,filled\", fillcolor=\"#f6b26b\"]"));
  EXPECT_TRUE(contains(r.out, "label=\"B (stopped)\"; style=filled; fillcolor=gray90;"));
  EXPECT_TRUE(contains(r.out, "label=\"A\";\n")) << r.out;  // running: not marked
  EXPECT_TRUE(contains(r.out, "    \"A.b1\";\n")) << r.out;
}

TEST(GraphCli, AnUnknownComponentIsAnErrorListingTheComponents) {
  auto r = graph({fig7(), "--fail", "B.b9"});

  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(r.err,
            "keel graph: no component 'B.b9' in 'Fig7' (components: A.b1, A.b2, A.b3, A.a1, B.b1, B.b2, B.a1, "
            "C.a1, C.c1, D.a1, D.c1)\n");
}

TEST(GraphCli, ApplicationsAreClustersWhoseDependencyEdgesJoinDeclaredNodes) {
  auto r = graph({fig7()});

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_TRUE(contains(r.out, "\"app:A\" [shape=folder, label=\"A\\n1 of {b1, b2, b3}\\nall of {a1}\"];")) << r.out;
  EXPECT_TRUE(contains(r.out, "\"app:C\" -> \"app:B\" [label=\"depends_on\""));
  EXPECT_TRUE(contains(r.out, "\"app:D\" -> \"app:A\" [label=\"depends_on\""));
  // Every edge joins nodes declared in the graph.
  std::set<std::string> declared;
  std::vector<std::pair<std::string, std::string>> edges;
  const std::regex node_re(R"re(^\s*"([^"]+)"\s*(\[|;))re");
  const std::regex edge_re(R"re(^\s*"([^"]+)" -> "([^"]+)")re");
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_search(line, m, edge_re)) edges.emplace_back(m[1], m[2]);
    else if (std::regex_search(line, m, node_re)) declared.insert(m[1]);
  }
  ASSERT_EQ(edges.size(), 11u);  // 7 connections, 2 depends, 2 depends_on
  for (const auto& [from, to] : edges) {
    EXPECT_TRUE(declared.count(from)) << from;
    EXPECT_TRUE(declared.count(to)) << to;
  }
}

// docs/fault-diagnosis.md shows `$ keel graph ... > somewhere` followed by the summary line;
// each must be what keel prints.
TEST(GraphCli, TheSummariesInTheFaultDiagnosisDocAreWhatKeelPrints) {
  const std::string profiles = KEEL_TEST_PROFILES;
  const std::string root = profiles.substr(0, profiles.size() - std::string("tests/integration/profiles").size());
  std::istringstream doc(test::slurp(root + "docs/fault-diagnosis.md"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(doc, line);) lines.push_back(line);
  int checked = 0;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
    if (lines[i].rfind("$ keel graph ", 0) != 0 || contains(lines[i], "|")) continue;
    std::vector<std::string> args;
    std::istringstream words(lines[i].substr(std::string("$ keel graph ").size()));
    for (std::string w; words >> w && w != ">";)
      args.push_back(w.rfind("tests/integration/profiles", 0) == 0 ? root + w : w);
    auto r = graph(args);
    EXPECT_EQ(r.status, 0) << lines[i] << '\n' << r.err;
    EXPECT_EQ(r.err, lines[i + 1] + "\n") << lines[i];
    ++checked;
  }
  EXPECT_EQ(checked, 5);
}

// A ROS 2 node is drawn as one (an ellipse, its ROS 2 name), and its fault stop stops what
// <needs> it, as a component's does.
TEST(GraphCli, ANodeIsDrawnWithItsRosNameAndItsFaultStopsWhatNeedsIt) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("keel_graph_node_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "planner.xml") << R"(<?xml version="1.0"?>
<ros2_node_profile><name>Planner</name><command>sh -c "sleep 100"</command><node>/nav/planner</node>
  <ports><data_port><name>plan</name><usage>output</usage><data_type>std_msgs/msg/String</data_type>
    <topic>/nav/plan</topic></data_port></ports></ros2_node_profile>
)";
  std::ofstream(dir / "follower.xml") << R"(<?xml version="1.0"?>
<ros2_node_profile><name>Follower</name><command>sh -c "sleep 100"</command><node>/nav/follower</node>
</ros2_node_profile>
)";
  std::ofstream(dir / "app.xml") << R"(<?xml version="1.0"?>
<package_profile><name>nav</name><subcomponents>
  <subcomponent><name>planner</name><reference>planner.xml</reference>
    <fault_policy><severity>stop</severity></fault_policy></subcomponent>
  <subcomponent><name>follower</name><reference>follower.xml</reference><attach/></subcomponent>
</subcomponents><coordination><needs source="follower" target="planner"/></coordination></package_profile>
)";
  auto r = graph({(dir / "app.xml").string(), "--fail", "planner"});
  std::filesystem::remove_all(dir);

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err,
            "fault at planner (scope component): stops components [planner, follower]; "
            "stops applications [nav]; keeps running []\n");
  EXPECT_TRUE(contains(r.out, R"x(shape=ellipse, label="planner\n/nav/planner (ROS 2 node)")x")) << r.out;
  EXPECT_TRUE(contains(r.out, R"x(label="follower\n/nav/follower (ROS 2 node, attached)")x")) << r.out;
}

TEST(GraphCli, AFaultInAPackageStopsItsScopeAndTheImplicitApplicationRunsOn) {
  auto r = graph({std::string(KEEL_TEST_PROFILES) + "/crash.xml", "--fail", "summer"});

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err,
            "fault at summer (scope component): stops components [summer]; "
            "stops applications []; keeps running [crash]\n");
}

}  // namespace
}  // namespace keel
