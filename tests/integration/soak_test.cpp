// keel soak as a user runs it (docs/soak.md): a healthy application passes with every injected
// fault accounted for and its log whole; one that leaks descriptors and memory run after run
// fails, naming the growth; an application that does not load is an error before anything runs.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include "log/schema.hpp"
#include "support/env.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"
#include "support/temp_log.hpp"

namespace keel {
namespace {

namespace ev = log::schema::event;
namespace fd = log::schema::field;

std::string profile(const std::string& name) { return std::string(KEEL_TEST_PROFILES) + "/soak/" + name; }

class Soak : public ::testing::Test {
 protected:
  keel::test::ScopedEnv component_path_{"KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS};
  void TearDown() override { std::filesystem::remove(log_); }
  std::string log_ = test::tempPath("keel_soak_test");
};

/// The number in `out`'s table row for `kind`, column `column` (0: injected, 1: handled).
int tableCell(const std::string& out, const std::string& kind, int column) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex("\n  " + kind + " +([0-9]+) +([0-9]+) +([0-9]+) +([0-9]+)\n"))) return -1;
  return std::stoi(m[1 + column]);
}

TEST_F(Soak, AHealthyApplicationPassesWithEveryInjectedFaultAccountedForAndItsLogWhole) {
  // 15 s of runs of 3 s, a fault every 60 ms on average; its resources are not judged in so
  // short a soak (the warm-up outlasts it): this is about the faults and the log.
  auto r = test::runProcess({KEEL_CLI, "soak", profile("steady.xml"), "--minutes", "0.25", "--round", "3",
                             "--fault-every", "60", "--seed", "3", "--warmup", "600", "--log", log_});
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("keel soak: ok, no violation"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(not checked: the soak ended within its 600 s warm-up)"), std::string::npos) << r.out;
  for (const char* kind : {"segfault", "throw", "error_code", "hang", "stall_heartbeat", "out_of_range", "kill"}) {
    EXPECT_GT(tableCell(r.out, kind, 0), 0) << kind << " never injected:\n" << r.out;
    EXPECT_GT(tableCell(r.out, kind, 1), 0) << kind << " never handled:\n" << r.out;
  }
  // The log holds every round, one after the other, each a whole run.
  const auto log = test::readLog(log_);
  int loads = 0, stopped = 0;
  for (const auto& rec : test::eventsOf(log, ev::kEngine)) {
    loads += rec.value(fd::kPhase, "") == "load";
    stopped += rec.value(fd::kPhase, "") == "stopped";
  }
  EXPECT_GE(loads, 4);
  EXPECT_EQ(loads, stopped);
  EXPECT_NE(r.out.find(std::to_string(loads) + " round(s)"), std::string::npos) << r.out;
  EXPECT_GT(test::eventsOf(log, ev::kRecovered).size(), 10u);
  // The counter's process injects its own faults, from the same scenario: its records carry its pid.
  int in_process = 0;
  for (const auto& rec : test::eventsOf(log, ev::kDetected))
    in_process += rec.contains(fd::kPid) && rec.value(fd::kComponent, "") == "counter";
  EXPECT_GT(in_process, 0) << "no fault injected inside the counter's process";
}

TEST_F(Soak, AnApplicationThatLeaksEachRunFailsNamingTheGrowthOfDescriptorsAndMemory) {
  auto r = test::runProcess({KEEL_CLI, "soak", profile("leaking.xml"), "--minutes", "0.2", "--round", "2",
                             "--fault-every", "200", "--warmup", "3", "--log", log_});
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("violation: open descriptors grew from [0-9]+ after the warm-up "
                                                  "to [0-9]+ \\(> 5 %\\)")))
      << r.out;
  // Under ASan, whose own bookkeeping grows, the heap in use is judged instead of resident memory.
  EXPECT_TRUE(std::regex_search(r.out, std::regex("violation: (resident memory|heap in use) grew from [0-9.]+ MB "
                                                  "after the warm-up to [0-9.]+ MB \\(> 5 %\\)")))
      << r.out;
}

TEST_F(Soak, AnApplicationThatDoesNotLoadIsAnErrorAtItsLineBeforeAnythingRuns) {
  auto r = test::runProcess(
      {KEEL_CLI, "soak", std::string(KEEL_TEST_PROFILES) + "/wrong_type.xml", "--minutes", "0.1", "--log", log_});
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_TRUE(
      std::regex_search(r.err, std::regex("keel soak: .*CounterDouble\\.xml:9: .*port 'count' carries 'double'")))
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(log_));
}

}  // namespace
}  // namespace keel
