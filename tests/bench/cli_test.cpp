// `keel bench ... --quick` end to end, as CI runs it: a smoke test of the harness (every cell
// present, measured or skipped with a reason, the JSON and the plot written), not of the numbers.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/env.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"

namespace {

namespace fs = std::filesystem;
using keel::test::runProcess;

// NOLINTNEXTLINE(bugprone-exception-escape): its implicit moves, nlohmann::json's, never throw
struct QuickRun {
  keel::test::Ran ran;
  nlohmann::json cells;
  bool plotted = false;
};

QuickRun quick(const std::vector<std::string>& args) {
  const fs::path dir = fs::temp_directory_path() / ("keel_bench_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string json = (dir / "cells.json").string(), svg = (dir / "plot.svg").string();
  std::vector<std::string> argv{KEEL_CLI, "bench"};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.insert(argv.end(), {"--quick", "--json", json});
  if (args[0] != "scale") argv.insert(argv.end(), {"--plot", svg});
  QuickRun r;
  r.ran = runProcess(argv);
  r.cells = nlohmann::json::parse(keel::test::slurp(json), nullptr, false);
  r.plotted = fs::exists(svg) && fs::file_size(svg) > 1000;
  fs::remove_all(dir);
  return r;
}

/// Every measured cell has its faults, and sane percentiles; a skipped one says why.
void expectCellsSound(const nlohmann::json& cells, const char* what_key) {
  for (const auto& c : cells) {
    for (const char* k : {"load", "load_achieved", "load_source", "policy", "n", "p50_us", "p99_us", "max_us"})
      ASSERT_TRUE(c.contains(k)) << k << " missing in " << c.dump();
    ASSERT_TRUE(c.contains(what_key)) << c.dump();
    if (c.value("skipped", false)) {
      EXPECT_FALSE(c.value("note", "").empty()) << "skipped without a reason: " << c.dump();
      continue;
    }
    EXPECT_GE(c["n"].get<int>() + c["failed"].get<int>(), 10) << c.dump();  // 20 per cell; hangs 10
    EXPECT_GT(c["p50_us"].get<double>(), 0) << c.dump();
    EXPECT_LE(c["p50_us"].get<double>(), c["p99_us"].get<double>()) << c.dump();
    EXPECT_LE(c["p99_us"].get<double>(), c["max_us"].get<double>()) << c.dump();
  }
}

TEST(BenchCli, QuickRecoveryMeasuresEveryMechanismAndPeerAtEveryLoadAndPolicy) {
  const auto r = quick({"recovery"});
  ASSERT_EQ(r.ran.status, 0) << r.ran.err;
  ASSERT_TRUE(r.cells.is_array()) << r.ran.out;
  EXPECT_EQ(r.cells.size(), 4u * 9u * 2u);  // loads 10/40/60/80 × 7 mechanisms and 2 floors × other/fifo
  std::set<std::string> mechanisms;
  std::set<int> loads;
  for (const auto& c : r.cells) {
    mechanisms.insert(c["mechanism"].get<std::string>());
    loads.insert(c["load"].get<int>());
  }
  EXPECT_EQ(mechanisms, (std::set<std::string>{"reset", "replace_cold", "replace_preloaded", "reset_opros",
                                               "replace_preloaded_opros", "peer_erlang", "peer_respawn", "floor_wake",
                                               "floor_timer"}));
  EXPECT_EQ(loads, (std::set<int>{10, 40, 60, 80}));
  expectCellsSound(r.cells, "mechanism");
  // keel's own mechanisms and the floors always run (SCHED_OTHER needs no privilege); keel
  // recovers every fault.
  for (const auto& c : r.cells)
    if (c["policy"] == "other" && c["mechanism"].get<std::string>().rfind("peer_", 0) != 0) {
      EXPECT_EQ(c["n"], 20) << c.dump();
      EXPECT_EQ(c["failed"], 0) << c.dump();
    }
  EXPECT_NE(r.ran.out.find("paper, Linux-Pentium4"), std::string::npos) << r.ran.out;
  // The OPRoS victim beside keel's: each *_opros cell ÷ its keel twin.
  EXPECT_NE(r.ran.out.find("| load | reset_opros ÷ reset | replace_preloaded_opros ÷ replace_preloaded |"),
            std::string::npos)
      << r.ran.out;
  EXPECT_TRUE(r.plotted) << r.ran.out;
}

/// The lines of `text` that start with `prefix`, in order.
std::vector<std::string> linesStartingWith(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
  return out;
}

// The paper's Table 3 as `keel bench recovery` gives it, on its shape only (not its numbers):
// the table has a row per load, ascending whatever order the loads were given in, each with the
// paper's Linux-Pentium4 figure for that load beside keel's columns, then keel ÷ peer per load;
// the JSON has a cell per load and mechanism in the order measured, keel's carrying their ratio
// to the peer of the same load.
TEST(BenchCli, QuickRecoveryGivesTable3WithARowPerLoadThePapersColumnAndKeelToPeerRatios) {
  const auto r = quick({"recovery", "--loads", "80,10", "--policy", "other", "--only",
                        "reset,replace_preloaded,peer_respawn", "--no-plot"});
  ASSERT_EQ(r.ran.status, 0) << r.ran.err;
  const std::string& out = r.ran.out;
  ASSERT_NE(out.find("(the paper's Table 3: without (with) preloading)"), std::string::npos) << out;
  const auto header = linesStartingWith(out, "| load (achieved) |");
  ASSERT_EQ(header.size(), 1u) << out;
  EXPECT_EQ(header[0], "| load (achieved) | reset | replace_preloaded | peer_respawn | paper, Linux-Pentium4 |");
  const auto rows = linesStartingWith(out, "| ~");
  ASSERT_EQ(rows.size(), 4u) << "a row per load in the table, and in the ratios below it: " << out;
  EXPECT_EQ(rows[0].rfind("| ~10% (", 0), 0u) << rows[0];
  EXPECT_TRUE(rows[0].ends_with("| 20 ms (< 1 ms) |")) << rows[0];
  EXPECT_EQ(rows[1].rfind("| ~80% (", 0), 0u) << rows[1];
  EXPECT_TRUE(rows[1].ends_with("| > 100 ms (< 20 ms) |")) << rows[1];
  EXPECT_EQ(std::count(rows[0].begin(), rows[0].end(), '|'), 6) << "load, 3 mechanisms, the paper: " << rows[0];
  const auto ratios_header = linesStartingWith(out,
                                               "| load | reset ÷ peer_respawn | replace_preloaded ÷ peer_respawn |");
  EXPECT_EQ(ratios_header.size(), 1u) << out;
  EXPECT_EQ(rows[2].rfind("| ~10% |", 0), 0u) << rows[2];
  EXPECT_EQ(rows[3].rfind("| ~80% |", 0), 0u) << rows[3];
  for (std::size_t i = 2; i < 4; ++i) EXPECT_EQ(rows[i].find("—"), std::string::npos) << "a ratio missing: " << rows[i];

  ASSERT_TRUE(r.cells.is_array()) << out;
  ASSERT_EQ(r.cells.size(), 6u) << r.cells.dump();
  const std::vector<std::string> mechanisms{"reset", "replace_preloaded", "peer_respawn"};
  for (std::size_t i = 0; i < r.cells.size(); ++i) {
    const auto& c = r.cells[i];
    SCOPED_TRACE(c.dump());
    EXPECT_EQ(c["load"], i < 3 ? 80 : 10);  // measured in the order asked
    EXPECT_EQ(c["mechanism"], mechanisms[i % 3]);
    EXPECT_EQ(c["policy"], "other");
    EXPECT_FALSE(c.value("skipped", false));
    EXPECT_GT(c["n"].get<int>(), 0);
    if (c["mechanism"] == "peer_respawn") {
      EXPECT_FALSE(c.contains("vs_peer_respawn")) << "a peer has no ratio to itself";
      continue;
    }
    ASSERT_TRUE(c.contains("vs_peer_respawn"));
    for (const char* p : {"p50", "p99"}) {
      const double ratio = c["vs_peer_respawn"][p].get<double>();
      EXPECT_GT(ratio, 0.0) << p;
      EXPECT_NEAR(ratio,
                  c[std::string(p) + "_us"].get<double>() /
                      r.cells[i - i % 3 + 2][std::string(p) + "_us"].get<double>(),
                  0.01 + ratio * 0.01)
          << p << ": keel ÷ the peer of the same load";
    }
  }
  expectCellsSound(r.cells, "mechanism");
}

// The monitor's cost on recovery (docs/performance.md, "The live monitor"): reset measured
// beside itself watched by keel run --monitor's monitor with a client subscribed to everything.
TEST(BenchCli, QuickRecoveryMeasuresResetWithTheMonitorWatchingBesidePlainReset) {
  const auto r = quick({"recovery", "--loads", "0", "--policy", "other", "--only", "reset,reset_monitored"});
  ASSERT_EQ(r.ran.status, 0) << r.ran.err;
  ASSERT_EQ(r.cells.size(), 2u) << r.ran.out;
  EXPECT_EQ(r.cells[1]["mechanism"], "reset_monitored");
  EXPECT_NE(r.cells[1].value("note", "").find("detection to a monitor client"), std::string::npos)
      << "every detection timed to the client: " << r.cells[1].dump();
  EXPECT_NE(r.cells[1].value("note", "").find("(n 20)"), std::string::npos) << r.cells[1].dump();
  expectCellsSound(r.cells, "mechanism");
  for (const auto& c : r.cells) {
    EXPECT_FALSE(c.value("skipped", false)) << c.dump();
    EXPECT_EQ(c["n"], 20) << c.dump();
    EXPECT_EQ(c["failed"], 0) << c.dump();
  }
}

TEST(BenchCli, QuickDetectionMeasuresEveryDetectorAtEveryLoad) {
  const auto r = quick({"detection", "--loads", "10,80", "--policy", "other"});
  ASSERT_EQ(r.ran.status, 0) << r.ran.err;
  ASSERT_TRUE(r.cells.is_array()) << r.ran.out;
  EXPECT_EQ(r.cells.size(), 2u * (7u + 2u));  // seven kinds and the two floors, per load
  std::set<std::string> detectors;
  int beside_floor = 0;
  for (const auto& c : r.cells) {
    detectors.insert(c["detector"].get<std::string>());
    EXPECT_EQ(c["failed"], 0) << c.dump();
    // Each injection detected once, as itself: a late cycle's heartbeat fault on a loaded
    // machine neither replaces one nor leaves the victim stopped for the next.
    EXPECT_EQ(c["n"], c["kind"] == "hang" ? 10 : 20) << c.dump();
    beside_floor += c.contains("vs_floor");
  }
  EXPECT_EQ(detectors, (std::set<std::string>{"signal", "exception", "error_code", "range", "watchdog", "bare handler",
                                              "bare catch"}));
  EXPECT_EQ(beside_floor, 2 * 4) << "segfault, divide_by_zero, abort and throw, at each load";
  for (const auto& c : r.cells) {
    if (c.contains("vs_floor")) {
      EXPECT_GT(c["floor_p50_us"].get<double>(), 0) << c.dump();
    }
  }
  EXPECT_NE(r.ran.out.find("keel ÷ the machine's floor"), std::string::npos) << r.ran.out;
  expectCellsSound(r.cells, "kind");
  EXPECT_TRUE(r.plotted) << r.ran.out;
}

TEST(BenchCli, QuickIsolationMeasuresPortsTakeoverRespawnBesideTheirFloorsAndAWaitingStandby) {
  const auto r = quick({"isolation", "--loads", "0", "--policy", "other"});
  ASSERT_EQ(r.ran.status, 0) << r.ran.err;
  ASSERT_TRUE(r.cells.is_array()) << r.ran.out;
  nlohmann::json cells = nlohmann::json::array(), standby;
  std::map<std::string, nlohmann::json> by;
  for (const auto& c : r.cells) {
    if (c.value("mechanism", "") == "standby_cost") {
      standby = c;
      continue;
    }
    cells.push_back(c);
    by[c["mechanism"].get<std::string>()] = c;
  }
  expectCellsSound(cells, "mechanism");
  ASSERT_EQ(by.size(), 6u) << r.ran.out;
  for (const char* keel : {"port_process", "port_thread", "takeover", "respawn"}) {
    ASSERT_TRUE(by.count(keel)) << keel;
    EXPECT_FALSE(by[keel].value("skipped", false)) << by[keel].dump();
    EXPECT_EQ(by[keel]["n"].get<int>() + by[keel]["failed"].get<int>(), 20) << by[keel].dump();
    // A takeover may become a respawn when a busy machine had its new standby late: rare.
    EXPECT_LE(by[keel]["failed"].get<int>(), std::string(keel) == "takeover" ? 2 : 0)
        << "a kill handled otherwise than the cell measures: " << by[keel].dump();
  }
  for (const char* with_floor : {"port_process", "port_thread", "takeover"})
    EXPECT_GT(by[with_floor].value("floor_p50_us", 0.0), 0) << by[with_floor].dump();
  // A standby takes over well before a cold respawn has even loaded.
  EXPECT_LT(by["takeover"]["p50_us"].get<double>(), by["respawn"]["p50_us"].get<double>());
  ASSERT_TRUE(standby.is_object()) << r.ran.out;
  EXPECT_GT(standby["active"]["cpu_ticks"].get<long>(), standby["standby"]["cpu_ticks"].get<long>());
  EXPECT_LE(standby["standby"]["cpu_ticks"].get<long>(), 1) << "a waiting standby costs no CPU";
  for (const char* p : {"active", "standby"}) EXPECT_GT(standby[p].value("anon_kb", 0L), 0) << standby.dump();
  EXPECT_NE(r.ran.out.find("Takeover (p50 / p99"), std::string::npos) << r.ran.out;
}

/// A ROS domain no other test of this machine holds (tests/dds/domains.py's flocks), -1 when
/// none is free; `lock` is set to its lock file, which holds it until closed.
int holdRosDomain(int& lock) {
  for (int d = 1; d <= 100; ++d) {
    const int fd = ::open(("/tmp/keel-ros-domain-" + std::to_string(d)).c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0666);
    if (fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) == 0) {
      lock = fd;
      return d;
    }
    if (fd >= 0) ::close(fd);
  }
  return -1;
}

// keel's DDS ports beside a plain CycloneDDS program and rclpy, and the faults from the network
// against the times they cannot beat: a deadline's fault is not seen long before the deadline
// has passed since the kill, a standby not heard before the primary's lease could expire.
TEST(BenchCli, QuickDdsMeasuresRoundTripsBesideCycloneDdsAndRclpyRemoteFaultsAndFailover) {
  int lock = -1;
  const int domain = holdRosDomain(lock);
  ASSERT_GE(domain, 0) << "every ROS domain 1-100 is held";
  QuickRun r;
  {
    const keel::test::ScopedEnv ros_domain("ROS_DOMAIN_ID", std::to_string(domain));
    const keel::test::ScopedEnv rclpy("KEEL_RCLPY_PYTHON", ::access(KEEL_RCLPY_PYTHON, X_OK) == 0
                                                               ? std::optional<std::string>(KEEL_RCLPY_PYTHON)
                                                               : std::nullopt);
    r = quick({"dds"});
  }
  ::close(lock);
  ASSERT_EQ(r.ran.status, 0) << r.ran.err;
  ASSERT_TRUE(r.cells.is_array()) << r.ran.out;
  expectCellsSound(r.cells, "mechanism");
  std::map<std::string, nlohmann::json> by;
  for (const auto& c : r.cells) by[c["mechanism"].get<std::string>()] = c;
  ASSERT_EQ(by.size(), 5u) << r.ran.out;
  for (const char* measured : {"roundtrip_keel", "roundtrip_raw", "remote"}) {
    EXPECT_FALSE(by[measured].value("skipped", false)) << by[measured].dump();
    EXPECT_EQ(by[measured]["failed"].get<int>(), 0) << by[measured].dump();
  }
  EXPECT_EQ(by["roundtrip_keel"]["n"].get<int>(), 20) << by["roundtrip_keel"].dump();
  EXPECT_TRUE(by["roundtrip_keel"].contains("vs_raw")) << by["roundtrip_keel"].dump();
  EXPECT_EQ(by["remote"]["n"].get<int>(), 10) << by["remote"].dump();
  // The deadline counts from the writer's last sample, at most a period (1 ms) and its lateness
  // before the kill.
  EXPECT_GE(by["remote"]["p50_us"].get<double>(), 40'000)
      << "a fault long before the deadline: " << by["remote"].dump();
  EXPECT_EQ(by["remote"]["goal_p99_us"].get<int>(), 60'000);
  if (::access(KEEL_RCLPY_PYTHON, X_OK) == 0) {
    EXPECT_FALSE(by["roundtrip_rclpy"].value("skipped", false)) << by["roundtrip_rclpy"].dump();
  }
  if (::geteuid() == 0) {  // two network namespaces
    EXPECT_FALSE(by["failover"].value("skipped", false)) << by["failover"].dump();
    EXPECT_EQ(by["failover"]["failed"].get<int>(), 0) << by["failover"].dump();
    EXPECT_GE(by["failover"]["p50_us"].get<double>(), 100'000) << "heard before the lease: " << by["failover"].dump();
  }
  EXPECT_NE(r.ran.out.find("keel ÷ CycloneDDS"), std::string::npos) << r.ran.out;
}

// A supervised rclpy node's death and restart beside the machine's floor and a respawn loop, a
// deadline watch, keel's CPU with idle nodes, and a lifecycle node's standby taking over beside
// its cold restart: every cell measured, none of its kills lost; a death seen by keel long before
// the deadline that a subscriber alone would wait for.
TEST(BenchCli, Ros2MeasuresANodesDeathAndRestartBesideTheFloorARespawnLoopAndADeadline) {
  if (::access(KEEL_RCLPY_PYTHON, X_OK) != 0) GTEST_SKIP() << "no rclpy venv (scripts/peers.sh python)";
  int lock = -1;
  const int domain = holdRosDomain(lock);
  ASSERT_GE(domain, 0) << "every ROS domain 1-100 is held";
  const fs::path dir = fs::temp_directory_path() / ("keel_bench_ros2_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string json = (dir / "cells.json").string();
  keel::test::Ran ran;
  {
    const keel::test::ScopedEnv ros_domain("ROS_DOMAIN_ID", std::to_string(domain));
    const keel::test::ScopedEnv rclpy("KEEL_RCLPY_PYTHON", std::string(KEEL_RCLPY_PYTHON));
    ran = runProcess({KEEL_CLI, "bench", "ros2", "--n", "4", "--loads", "0", "--json", json});
  }
  ::close(lock);
  const auto cells = nlohmann::json::parse(keel::test::slurp(json), nullptr, false);
  fs::remove_all(dir);
  ASSERT_EQ(ran.status, 0) << ran.err;
  ASSERT_TRUE(cells.is_array()) << ran.out;
  std::map<std::string, nlohmann::json> by;
  for (const auto& c : cells) by[c.value("mechanism", c.value("cell", ""))] = c;
  for (const char* kills : {"death", "floor_death", "restart", "respawn"}) {
    ASSERT_TRUE(by.contains(kills)) << kills << " missing: " << ran.out;
    EXPECT_FALSE(by[kills].value("skipped", false)) << by[kills].dump();
    EXPECT_EQ(by[kills]["n"].get<int>(), 4) << by[kills].dump();
    EXPECT_EQ(by[kills]["failed"].get<int>(), 0) << by[kills].dump();
  }
  EXPECT_TRUE(by["death"].contains("vs_floor")) << by["death"].dump();
  EXPECT_TRUE(by["restart"].contains("vs_respawn")) << by["restart"].dump();
  ASSERT_TRUE(by.contains("deadline_only")) << ran.out;
  EXPECT_EQ(by["deadline_only"]["n"].get<int>(), 10) << by["deadline_only"].dump();
  // The deadline counts from the node's last sample (every 10 ms) before the kill.
  EXPECT_GE(by["deadline_only"]["p50_us"].get<double>(), 250'000) << by["deadline_only"].dump();
  EXPECT_LT(by["death"]["p50_us"].get<double>(), 250'000) << "keel saw the death no sooner than a deadline";
  ASSERT_TRUE(by.contains("idle_cpu")) << ran.out;
  EXPECT_FALSE(by["idle_cpu"].contains("note")) << by["idle_cpu"].dump();
  EXPECT_GT(by["idle_cpu"]["nodes_cpu_percent"].get<double>(), 0) << by["idle_cpu"].dump();
  EXPECT_NE(ran.out.find("keel ÷ respawn"), std::string::npos) << ran.out;
  // The lifecycle node: its standby taking over beside its cold restart, and what a standby costs.
  for (const char* kills : {"takeover", "cold"}) {
    ASSERT_TRUE(by.contains(kills)) << kills << " missing: " << ran.out;
    EXPECT_EQ(by[kills]["n"].get<int>(), 4) << by[kills].dump();
    EXPECT_EQ(by[kills]["failed"].get<int>(), 0) << by[kills].dump();
  }
  EXPECT_LT(by["takeover"]["p50_us"].get<double>(), by["cold"]["p50_us"].get<double>())
      << "a standby took over no sooner than a cold restart";
  ASSERT_TRUE(by.contains("standby_cost")) << ran.out;
  EXPECT_GT(by["standby_cost"]["standby_rss_mib"].get<double>(), 0) << by["standby_cost"].dump();
  EXPECT_GT(by["standby_cost"]["active_rss_mib"].get<double>(), 0) << by["standby_cost"].dump();
  EXPECT_NE(ran.out.find("cold ÷ takeover"), std::string::npos) << ran.out;
}

TEST(BenchCli, QuickScaleHasARowPerSize) {
  const auto r = quick({"scale", "--sizes", "1,10,100"});
  ASSERT_EQ(r.ran.status, 0) << r.ran.err;
  ASSERT_TRUE(r.cells.is_array()) << r.ran.out;
  ASSERT_EQ(r.cells.size(), 3u);
  EXPECT_EQ(r.cells[2]["components"], 100);
  EXPECT_GT(r.cells[2]["startup_ms"].get<double>(), 0);
}

TEST(BenchCli, AnUnknownMechanismIsRefusedBeforeAnythingRuns) {
  const auto r = runProcess({KEEL_CLI, "bench", "recovery", "--only", "reboot"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown 'reboot'"), std::string::npos) << r.err;
  const auto none = runProcess({KEEL_CLI, "bench"});
  EXPECT_NE(none.status, 0);
}

}  // namespace

namespace {

// A keel whose keel-bench is missing (only the keel target built, or the file removed) names
// the file it looked for; it does not blame a configuration it was not built with.
TEST(BenchCli, AKeelWithoutItsHarnessBesideItNamesTheMissingFile) {
  const fs::path dir = fs::temp_directory_path() / ("keel_bench_alone_" + std::to_string(::getpid()));
  fs::create_directories(dir / "bin");
  const fs::path keel = dir / "bin" / "keel";
  fs::copy_file(KEEL_CLI, keel, fs::copy_options::overwrite_existing);
  fs::create_directory_symlink(fs::path(KEEL_CLI).parent_path().parent_path() / "lib", dir / "lib");  // its RPATH
  const auto r = runProcess({keel.string(), "bench", "recovery", "--quick"});
  fs::remove_all(dir);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("keel bench: its harness " + (dir / "bin" / "keel-bench").string() + " is missing"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("KEEL_BUILD_BENCH"), std::string::npos) << r.err;
}

}  // namespace
