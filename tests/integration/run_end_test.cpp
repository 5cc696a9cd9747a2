// A component ends the run (RunControl::endRun): `keel run` stops at once as if its duration had
// elapsed (exit 0), prints who ended it, and the fault log's last record is the one the
// component asked for, written after every component stopped.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>

#include "log/schema.hpp"
#include "support/env.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"

namespace keel {
namespace {

std::string profile(const std::string& name) { return std::string(KEEL_TEST_PROFILES) + "/" + name; }

class RunEnd : public ::testing::Test {
 protected:
  keel::test::ScopedEnv component_path_{"KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS};
  void TearDown() override { std::filesystem::remove(log_); }

  test::Ran run(const std::string& name, const std::string& duration) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = test::runProcess({KEEL_CLI, "run", profile(name), "--duration", duration, "--log", log_});
    took_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }

  std::string log_ = (std::filesystem::temp_directory_path() /
                      ("keel_run_end_test_" + std::to_string(::getpid()) + ".jsonl"))
                         .string();
  double took_s_ = 0;
};

TEST_F(RunEnd, AComponentEndsTheRunLongBeforeItsDuration) {
  auto r = run("finish/mission.xml", "30");

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_LT(took_s_, 10.0);  // 20 executions of 5 ms, not 30 s
  EXPECT_NE(r.out.find("\nended by finisher: done after 20 executions\n"), std::string::npos) << r.out;
  auto log = test::readLog(log_);
  ASSERT_FALSE(log.empty());
  bool stopping = false;
  for (const auto& e : test::eventsOf(log, "engine"))
    if (e["phase"] == "stopping") stopping = e["reason"] == "ended by finisher";
  EXPECT_TRUE(stopping);
  const auto& last = log.back();
  EXPECT_EQ(last["event"], "mission");
  EXPECT_EQ(last["component"], "finisher");
  EXPECT_EQ(last["goal_reached"], true);
  EXPECT_EQ(last["collisions"], 0);
  EXPECT_EQ(last["executions"], 20);
  EXPECT_TRUE(last.contains("t_ns"));
  EXPECT_EQ(last.size(), 6u) << last.dump();
  // every component stopped and was destroyed before it
  EXPECT_EQ(test::statesOf(log, "counter").back(), "Destroyed");
  EXPECT_EQ(log[log.size() - 2]["phase"], "stopped");
}

TEST_F(RunEnd, OnlyTheFirstCallCounts) {
  auto r = run("finish/mission.xml", "30");

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.find("a second call"), std::string::npos) << r.out;
  auto log = test::readLog(log_);
  EXPECT_TRUE(test::eventsOf(log, "ignored").empty());
  const auto requested = test::eventsOf(log, "end_requested");
  ASSERT_EQ(requested.size(), 1u);
  EXPECT_EQ(requested[0]["component"], "finisher");
  EXPECT_EQ(requested[0]["summary"], "done after 20 executions");
}

TEST_F(RunEnd, AComponentMayEndTheRunFromOnStopWhenTheDurationEndedIt) {
  auto r = run("finish/on_stop.xml", "0.3");

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\nended by finisher: stopped after "), std::string::npos) << r.out;
  auto log = test::readLog(log_);
  ASSERT_FALSE(log.empty());
  for (const auto& e : test::eventsOf(log, "engine")) {
    if (e["phase"] == "stopping") {
      EXPECT_EQ(e["reason"], "duration");
    }
  }
  const auto& last = log.back();
  EXPECT_EQ(last["event"], "mission");
  EXPECT_EQ(last["component"], "finisher");
  EXPECT_EQ(last["goal_reached"], false);
  EXPECT_GT(last["executions"].get<int>(), 10);  // about 60 in 0.3 s
}

TEST_F(RunEnd, MalformedFieldsGiveAFieldsErrorInsteadOfACrash) {
  auto r = run("finish/malformed.xml", "30");

  ASSERT_EQ(r.status, 0) << r.err;
  const auto log = test::readLog(log_);
  ASSERT_FALSE(log.empty());
  const auto& last = log.back();
  EXPECT_EQ(last["event"], "mission");
  EXPECT_EQ(last["component"], "finisher");
  EXPECT_FALSE(last.contains("goal_reached"));
  ASSERT_TRUE(last.contains(log::schema::field::kFieldsError)) << last.dump();
  EXPECT_EQ(last[log::schema::field::kFieldsError].get<std::string>().rfind(
                "fields_json '\"goal_reached\":tru,\"executions\":5' is not the members of a JSON object: ", 0),
            0u)
      << last.dump();
}

TEST_F(RunEnd, ARunNobodyEndsHasNoEndLine) {
  auto r = run("pipeline.xml", "0.2");

  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.find("ended by"), std::string::npos) << r.out;
  EXPECT_TRUE(test::eventsOf(test::readLog(log_), "end_requested").empty());
}

}  // namespace
}  // namespace keel
