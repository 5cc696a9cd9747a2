// The pieces of `keel bench` that its numbers rest on: percentiles, the background load (it
// really loads the machine, and goes away), the JSON cells and the Table 3 rendering.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "floor.hpp"
#include "load.hpp"
#include "process.hpp"
#include "report.hpp"
#include "runtime/guard.hpp"
#include "stats.hpp"
#include "support/env.hpp"
#include "support/paths.hpp"

namespace keel::bench {
namespace {

TEST(BenchStats, PercentilesAreNearestRankInMicroseconds) {
  std::vector<std::int64_t> ns;
  for (std::int64_t i = 1; i <= 100; ++i) ns.push_back(i * 1000);  // 1..100 µs, shuffled below
  std::reverse(ns.begin(), ns.end());
  const Summary s = summarise(ns);
  EXPECT_EQ(s.n, 100u);
  EXPECT_DOUBLE_EQ(s.p50_us, 51.0);  // rank round(0.5 × 99) = 50 (0-based)
  EXPECT_DOUBLE_EQ(s.p99_us, 99.0);
  EXPECT_DOUBLE_EQ(s.max_us, 100.0);
  EXPECT_EQ(summarise({}).n, 0u);
}

// A child gets the harness's environment with its own changes (the DDS benchmark's keel runs
// their CycloneDDS configuration, a failover host none), and the harness's stays as it was.
TEST(BenchProcess, ASpawnedChildGetsTheEnvironmentChangesAndTheHarnessKeepsItsOwn) {
  const keel::test::ScopedEnv kept("KEEL_BENCH_TEST_KEPT", "kept");
  const keel::test::ScopedEnv removed("KEEL_BENCH_TEST_REMOVED", "here");
  const keel::test::ScopedEnv changed("KEEL_BENCH_TEST_CHANGED", "before");
  keel::bench::Pipe out;
  ASSERT_TRUE(out.open());
  auto child = keel::bench::Process::spawn(
      {"/bin/sh", "-c",
       R"(echo "$KEEL_BENCH_TEST_KEPT ${KEEL_BENCH_TEST_REMOVED-unset} $KEEL_BENCH_TEST_CHANGED $KEEL_BENCH_TEST_ADDED")"},
      {.out = out.write.get()}, false, true,
      {{"KEEL_BENCH_TEST_REMOVED", std::nullopt},
       {"KEEL_BENCH_TEST_CHANGED", "after"},
       {"KEEL_BENCH_TEST_ADDED", "added"}});
  ASSERT_TRUE(child.ok()) << child.error().message;
  out.write.reset();
  keel::bench::LineReader lines(out.read.get());
  EXPECT_EQ(lines.next(std::chrono::steady_clock::now() + std::chrono::seconds(10)).value_or(""),
            "kept unset after added");
  EXPECT_STREQ(std::getenv("KEEL_BENCH_TEST_REMOVED"), "here");
  EXPECT_STREQ(std::getenv("KEEL_BENCH_TEST_CHANGED"), "before");
  EXPECT_EQ(std::getenv("KEEL_BENCH_TEST_ADDED"), nullptr);
}

TEST(BenchLoad, TheInternalLoadKeepsTheCpusBusyAndIsReapedWhenDestroyed) {
  pid_t pid = -1;
  double busy = 0;
  {
    BackgroundLoad load(60, LoadSource::Internal, KEEL_BENCH);
    EXPECT_EQ(load.source(), "internal");
    pid = load.pid();
    ASSERT_GT(pid, 0);
    const CpuMeter meter;
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    busy = meter.busy();
  }
  // 60% asked on every CPU: whatever else runs only adds to it.
  EXPECT_GT(busy, 0.40);
  EXPECT_NE(::kill(pid, 0), 0) << "the load's process is still there after its destructor";
}

/// Whether `pid` still runs (a zombie waiting for its reaper does not).
bool runs(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return false;
  const auto state = line.rfind(") ");
  return state != std::string::npos && line[state + 2] != 'Z';
}

// keel-bench killed with kill -9 (or crashed) while a load runs: the load goes with it, instead
// of loading the machine for the hours of its timeout.
TEST(BenchLoad, TheLoadEndsWhenKeelBenchIsKilled) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const pid_t bench = ::fork();
  if (bench == 0) {  // stands for keel-bench: starts a load, says its pid, waits to be killed
    ::close(fds[0]);
    BackgroundLoad load(30, LoadSource::Internal, KEEL_BENCH);
    const pid_t pid = load.pid();
    if (::write(fds[1], &pid, sizeof pid) != sizeof pid) ::_exit(1);
    for (;;) ::pause();
  }
  ::close(fds[1]);
  pid_t load = -1;
  ASSERT_EQ(::read(fds[0], &load, sizeof load), static_cast<ssize_t>(sizeof load));
  ::close(fds[0]);
  ASSERT_TRUE(runs(load));
  ::kill(bench, SIGKILL);
  ::waitpid(bench, nullptr, 0);
  bool gone = false;
  for (int i = 0; i < 100 && !gone; ++i) {  // 5 s
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    gone = !runs(load);
  }
  EXPECT_TRUE(gone) << "the load (pid " << load << ") outlived keel-bench";
  if (!gone) ::kill(load, SIGKILL);
}

TEST(BenchLoad, NoLoadStartsNothing) {
  BackgroundLoad none(0, LoadSource::Auto, KEEL_BENCH);
  EXPECT_EQ(none.source(), "none");
  EXPECT_EQ(none.pid(), -1);
}

Row row(int load, const std::string& what, const std::string& policy, double p50, double p99) {
  Row r;
  r.load = load;
  r.load_achieved = load + 3;
  r.load_source = "internal";
  r.what = what;
  r.policy = policy;
  r.s = {1000, p50, p99, p99 * 2};
  return r;
}

TEST(BenchReport, NotesAreJoinedOnceEach) {
  std::string notes;
  addNote(notes, "SCHED_FIFO not permitted");
  addNote(notes, "");
  addNote(notes, "in place 1.0 / 2.0 µs");
  addNote(notes, "SCHED_FIFO not permitted");  // an engine warns once per executor
  EXPECT_EQ(notes, "SCHED_FIFO not permitted; in place 1.0 / 2.0 µs");
}

TEST(BenchReport, ACellAsJsonHasTheIssuesKeys) {
  const auto j = toJson(row(40, "reset", "fifo", 10, 20), false);
  for (const char* k :
       {"load", "load_achieved", "load_source", "mechanism", "policy", "n", "p50_us", "p99_us", "max_us"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_EQ(j["load"], 40);
  EXPECT_EQ(j["mechanism"], "reset");
  EXPECT_EQ(j["n"], 1000);
  EXPECT_DOUBLE_EQ(j["p99_us"].get<double>(), 20.0);
  const auto d = toJson(row(40, "segfault", "other", 1, 2), true);
  EXPECT_EQ(d["kind"], "segfault");
  EXPECT_FALSE(d.contains("mechanism"));
}

TEST(BenchReport, KeelCellsGetTheirRatioToEachPeerOfTheSameLoadAndPolicy) {
  nlohmann::json rows = nlohmann::json::array(
      {toJson(row(10, "reset", "other", 10, 20), false), toJson(row(10, "peer_erlang", "other", 40, 100), false),
       toJson(row(80, "peer_erlang", "other", 1, 1), false), toJson(row(10, "peer_respawn", "fifo", 1, 1), false),
       toJson(row(10, "floor_wake", "other", 5, 50), false)});
  addPeerRatios(rows);
  ASSERT_TRUE(rows[0].contains("vs_peer_erlang"));
  EXPECT_DOUBLE_EQ(rows[0]["vs_peer_erlang"]["p50"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(rows[0]["vs_peer_erlang"]["p99"].get<double>(), 0.2);
  EXPECT_FALSE(rows[0].contains("vs_peer_respawn"));  // that peer ran under the other policy only
  EXPECT_FALSE(rows[1].contains("vs_peer_erlang"));   // peers get no ratio
  EXPECT_FALSE(rows[4].contains("vs_peer_erlang"));   // nor does the machine's floor
}

// The detection floors catch every fault they cause, with a plausible latency, and the signal
// floor leaves the process's SIGSEGV action as it found it (keel's guard needs it back).
TEST(BenchFloor, TheBareSignalAndThrowFloorsCatchEveryFaultAndRestoreTheSignalAction) {
  runtime::installSignalHandlers();  // what the detection cells measured before find in place
  struct sigaction before {
  }, after{};
  ::sigaction(SIGSEGV, nullptr, &before);
  const FloorResult sig = measureSignalFloor(15, false);
  ::sigaction(SIGSEGV, nullptr, &after);
  EXPECT_EQ(after.sa_sigaction, before.sa_sigaction);
  EXPECT_EQ(after.sa_flags, before.sa_flags);
  const FloorResult thr = measureThrowFloor(15, false);
  for (const auto* f : {&sig, &thr}) {
    ASSERT_EQ(f->latencies_ns.size(), 15u);
    for (std::int64_t ns : f->latencies_ns) {
      EXPECT_GT(ns, 0);
      EXPECT_LT(ns, 1'000'000'000) << "a fault caught a second later was not caught where it struck";
    }
  }
}

TEST(BenchReport, ADetectionCellWithItsFloorCarriesTheFloorAndTheRatio) {
  Row seg = row(0, "segfault", "other", 6, 30);
  seg.floor = {1000, 3, 20, 40};
  const auto j = toJson(seg, true);
  EXPECT_DOUBLE_EQ(j["floor_p50_us"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["floor_p99_us"].get<double>(), 20.0);
  EXPECT_DOUBLE_EQ(j["vs_floor"]["p50"].get<double>(), 2.0);  // keel ÷ floor
  EXPECT_DOUBLE_EQ(j["vs_floor"]["p99"].get<double>(), 1.5);
  const auto range = toJson(row(0, "out_of_range", "other", 0.2, 1), true);
  EXPECT_FALSE(range.contains("vs_floor"));  // a range check has no floor of its own
  EXPECT_FALSE(range.contains("floor_p99_us"));

  Row thr = row(80, "throw", "fifo", 4, 20);
  thr.floor = {1000, 4, 40, 80};
  std::ostringstream out;
  printFloorRatios({seg, row(0, "out_of_range", "other", 0.2, 1), thr}, out);
  EXPECT_NE(out.str().find("| segfault | throw |"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("| 0% | other | 2 / 1.5 | — |"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("| 80% | fifo | — | 1 / 0.5 |"), std::string::npos) << out.str();
  std::ostringstream none;
  printFloorRatios({row(0, "segfault", "other", 6, 30)}, none);
  EXPECT_EQ(none.str(), "") << "no floor measured, no table";
}

TEST(BenchReport, Table3HasALineperLoadWithThePapersColumnAndTheRatios) {
  std::vector<Row> rows{row(10, "reset", "other", 10, 20), row(10, "peer_erlang", "other", 40, 100),
                        row(80, "reset", "other", 12, 30), row(80, "peer_erlang", "other", 50, 150)};
  Row skipped = row(80, "replace_cold", "other", 0, 0);
  skipped.skipped = true;
  skipped.s = {};
  rows.push_back(skipped);
  std::ostringstream out;
  printTable3(rows, out);
  const std::string t = out.str();
  EXPECT_NE(t.find("| ~10% (13%) | 10.0 / 20.0 | 40.0 / 100.0 |"), std::string::npos) << t;
  // The paper's figure on the row of its own load, last.
  auto rowOf = [&](const std::string& head) {
    const auto at = t.find(head);
    return at == std::string::npos ? std::string() : t.substr(at, t.find('\n', at) - at);
  };
  EXPECT_TRUE(rowOf("| ~10% (").ends_with("| 20 ms (< 1 ms) |")) << t;
  EXPECT_TRUE(rowOf("| ~80% (").ends_with("| > 100 ms (< 20 ms) |")) << t;
  EXPECT_NE(t.find("skipped"), std::string::npos) << t;
  EXPECT_NE(t.find("| ~10% | 0.25 / 0.2 |"), std::string::npos) << t;  // reset ÷ erlang
}

}  // namespace
}  // namespace keel::bench
