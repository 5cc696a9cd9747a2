// `keel bench scale` (bench/harness/scale.cpp): the generated profiles load and really run the
// number of components asked for, the system's applications form the chain the diagnosis
// walks, and a quick measurement gives one sane row per size with the keys of its JSON. No
// timing goals: only that every figure was measured.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <set>
#include <sstream>

#include "engine/engine.hpp"
#include "profile/loader.hpp"
#include "scale.hpp"

namespace keel::bench {
namespace {

namespace fs = std::filesystem;

/// A temporary directory for generated profiles, removed at the end of the test.
class ScaleProfiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "keel_scale_test.XXXXXX").string();
    ASSERT_NE(mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::unique_ptr<engine::Engine> run(const std::string& profile) {
    auto set = profile::load(profile);
    if (!set) {
      for (const auto& d : set.error()) ADD_FAILURE() << d.str();
      return nullptr;
    }
    engine::EngineOptions opts;
    opts.search_path = {paths_.components};
    auto engine = engine::Engine::create(std::move(*set), std::move(opts));
    if (!engine) {
      ADD_FAILURE() << engine.error().message;
      return nullptr;
    }
    if (auto r = (*engine)->start(); !r) {
      ADD_FAILURE() << r.error().message;
      return nullptr;
    }
    return std::move(*engine);
  }

  Paths paths_ = findPaths();
  std::string dir_;
};

TEST_F(ScaleProfiles, ThePackageRunsEveryComponentOnTasksOfTen) {
  const std::string package = writeScalePackage(dir_, paths_, 25);

  auto engine = run(package);

  ASSERT_NE(engine, nullptr);
  EXPECT_EQ(engine->instances().size(), 25u);
  ASSERT_NE(engine->find("c24"), nullptr);
  EXPECT_EQ(engine->find("c24")->state(), State::Active);
  EXPECT_EQ(engine->find("c25"), nullptr);
  EXPECT_EQ(engine->executors().size(), 3u);  // 10 + 10 + 5
  for (const auto& inst : engine->instances()) EXPECT_EQ(inst.serving()->state(), State::Active) << inst.plan->name;
}

TEST_F(ScaleProfiles, TheSystemChainsItsApplicationsSoAFaultOfTheFirstStopsAll) {
  const std::string system = writeScaleSystem(dir_, paths_, 25);

  auto engine = run(system);

  ASSERT_NE(engine, nullptr);
  EXPECT_EQ(engine->instances().size(), 25u);
  ASSERT_NE(engine->find("a2.c4"), nullptr);  // the last application has the 5 left over
  EXPECT_EQ(engine->find("a2.c5"), nullptr);
  EXPECT_EQ(engine->find("a2.c4")->state(), State::Active);
  ASSERT_NE(engine->graph(), nullptr);
  const fault::Impact impact = engine->graph()->blastRadius("a0.c0", profile::Scope::Component);
  EXPECT_EQ(impact.stopped_components.size(), 25u);
  EXPECT_EQ(impact.stopped_applications, (std::vector<std::string>{"a0", "a1", "a2"}));
  // A fault of the last application stops it alone: the chain goes one way.
  EXPECT_EQ(engine->graph()->blastRadius("a2.c0", profile::Scope::Component).stopped_applications,
            (std::vector<std::string>{"a2"}));
}

TEST(Scale, AQuickRunGivesOneMeasuredRowPerSize) {
  const auto rows = measureScale(findPaths(), {1, 10}, 1);

  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].components, 1);
  EXPECT_EQ(rows[1].components, 10);
  EXPECT_EQ(rows[0].graph_nodes, 2);   // 1 component + 1 application
  EXPECT_EQ(rows[1].graph_nodes, 11);  // 10 components + 1 application
  for (const auto& r : rows) {
    SCOPED_TRACE(r.components);
    EXPECT_EQ(r.error, "");
    EXPECT_EQ(r.trials, 1);
    EXPECT_GT(r.startup_ms, 0);
    EXPECT_GT(r.load_ms, 0);
    EXPECT_GT(r.create_ms, 0);
    EXPECT_GT(r.start_ms, 0);
    EXPECT_GE(r.startup_ms, r.start_ms);
    EXPECT_GT(r.memory_kib, 0);
    EXPECT_DOUBLE_EQ(r.memory_kib_per_component, r.memory_kib / r.components);
    EXPECT_EQ(r.faults, 1);
    EXPECT_EQ(r.failed, 0);
    EXPECT_GT(r.diagnosis_p50_us, 0);
    EXPECT_GE(r.diagnosis_p99_us, r.diagnosis_p50_us);
    EXPECT_GT(r.graph_walk_p50_us, 0);
    EXPECT_GE(r.graph_walk_p99_us, r.graph_walk_p50_us);
  }
}

TEST(Scale, EachRowPrintsAsATableLineAndAJsonObjectWithItsFields) {
  ScaleRow r;
  r.components = 100;
  r.applications = 10;
  r.graph_nodes = 110;
  r.startup_ms = 12.5;
  r.diagnosis_p50_us = 40;
  r.diagnosis_p99_us = 90;
  r.trials = 5;

  const nlohmann::json j = toJson(r);
  std::ostringstream table;
  printScale({r, r}, table);

  for (const char* key : {"components", "applications", "graph_nodes", "startup_ms", "load_ms", "create_ms", "start_ms",
                          "memory_kib", "memory_kib_per_component", "diagnosis_p50_us", "diagnosis_p99_us",
                          "graph_walk_p50_us", "graph_walk_p99_us", "faults", "failed", "trials"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["components"], 100);
  EXPECT_EQ(j["graph_nodes"], 110);
  EXPECT_DOUBLE_EQ(j["startup_ms"].get<double>(), 12.5);
  EXPECT_FALSE(j.contains("error"));
  const std::string text = table.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 4);  // header, rule, two rows
  EXPECT_NE(text.find("| 100 | 10 | 110 | 12.5 |"), std::string::npos) << text;
}

}  // namespace
}  // namespace keel::bench
