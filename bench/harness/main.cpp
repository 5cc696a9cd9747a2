// keel-bench: the harness behind `keel bench` (the keel command runs this program, found beside
// it). Three benchmarks, each over load levels and scheduling policies, each printing markdown
// tables and writing `--json FILE` (one object per cell) and a plot:
//   recovery   keel's reset, cold and preloaded replacement beside an Erlang/OTP supervisor and
//              a respawned process, and the machine's floor (a thread wake-up, a timer
//              wake-up), measured in the same run (the paper's Table 3)
//   detection  detected − injected per detector, beside the machine's floor for the same fault
//              (a bare signal handler, a bare catch) measured in the same run
//   scale      start-up, memory and diagnosis time against the number of components
//   isolation  components in processes of their own: a port across processes beside one in a
//              process and a raw CycloneDDS loopback, a standby's takeover beside a cold
//              respawn, each with the machine's floor; what a waiting standby costs
//   dds        keel's DDS ports: the round trip keel ↔ keel beside a plain CycloneDDS C program's
//              (and rclpy's), `remote` fault detection and failover across two hosts
//   ros2       a ROS 2 node keel supervises: its death seen beside the machine's floor and a
//              deadline watch, its restart beside a plain respawn loop, keel's CPU with idle nodes
//   guard      the regression guard CI runs: short cells of recovery, takeover and detection,
//              each within a bound of the machine's floor measured beside it (guard.hpp)
// `_load P` is the internal duty-cycle load and `_guard PID CMD...` what starts a load (load.hpp),
// both run by keel-bench itself. This file reads the command line; each benchmark's driver is a
// file of its own (driver.hpp).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <iostream>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>

#include "driver.hpp"
#include "guard.hpp"
#include "load.hpp"
#include "paths.hpp"
#include "runtime/injection.hpp"
#include "scale.hpp"

namespace keel::bench {
namespace {

void commonOptions(CLI::App& sub, Options& o, const std::string& items_help) {
  sub.add_option("--loads", o.loads, "load levels, % busy on every CPU (0: idle)")
      ->delimiter(',')
      ->check(CLI::Range(0, 100));
  sub.add_option("--n", o.n, "faults per cell (at least 1000 for the numbers we publish)")->check(CLI::PositiveNumber);
  sub.add_flag("--quick", o.quick, "20 faults per cell: a smoke test of the harness, not of the numbers");
  sub.add_option("--policy", o.policy, "scheduling policy of the measured threads")
      ->check(CLI::IsMember({"other", "fifo", "both"}));
  sub.add_option("--load-source", o.load_source, "auto: stress-ng when installed, else the internal duty-cycle load")
      ->check(CLI::IsMember({"auto", "stress-ng", "internal"}));
  sub.add_option("--only", o.which, items_help)->delimiter(',');
  sub.add_option("--json", o.json, "write every cell to FILE (a JSON array, one object per cell)");
  sub.add_option("--plot", o.plot, "the plot's file (default keel-bench-<benchmark>.svg)");
  sub.add_flag("--no-plot", o.no_plot, "no plot");
  sub.add_flag("--low-latency", o.low_latency, "hold /dev/cpu_dma_latency at 0 during the run (root)");
}

}  // namespace
}  // namespace keel::bench

int main(int argc, char** argv) try {
  using namespace keel::bench;
  if (argc == 3 && std::string(argv[1]) == "_load") {
    int percent = 0;
    const std::string_view arg(argv[2]);
    if (std::from_chars(arg.data(), arg.data() + arg.size(), percent).ec != std::errc() || percent < 0 || percent > 100)
      return 2;
    return runInternalLoad(percent);
  }
  if (argc >= 2 && std::string(argv[1]) == "_guard") return runGuarded(argc, argv);
  CLI::App app{"keel bench: recovery and detection latency under CPU load beside peers, and scale"};
  app.require_subcommand(1);
  Options o;
  auto* rec = app.add_subcommand("recovery", "recovery latency per mechanism, keel beside its peers (Table 3)");
  commonOptions(*rec, o,
                "mechanisms: reset,replace_cold,replace_preloaded,reset_opros,replace_preloaded_opros (the same with a "
                "victim written against the OPRoS API),reset_hang (not by default),peer_erlang,peer_respawn,"
                "floor_wake,floor_timer; reset_monitored (not by default): reset with keel run --monitor's monitor "
                "and a client of it subscribed to everything");
  auto* det = app.add_subcommand("detection", "detection latency per detector");
  commonOptions(*det, o,
                "injected kinds: segfault,divide_by_zero,abort,throw,error_code,out_of_range,hang; the machine's "
                "floor: floor_signal,floor_throw");
  auto* iso = app.add_subcommand("isolation", "components in processes of their own: ports, takeover, standby cost");
  commonOptions(*iso, o,
                "cells: port_process,port_thread,port_dds,takeover,floor_robust,respawn,standby (a waiting "
                "standby's cost, once)");
  auto* dds_cmd = app.add_subcommand("dds",
                                     "DDS ports: round trip beside CycloneDDS and rclpy, remote faults, failover");
  commonOptions(*dds_cmd, o,
                "cells: roundtrip_keel,roundtrip_raw (a plain CycloneDDS C program),roundtrip_rclpy,remote,failover "
                "(root: two network namespaces)");
  auto* ros2_cmd = app.add_subcommand(
      "ros2",
      "ROS 2 nodes under keel: a kill seen, beside the floor and a deadline; restart beside a respawn loop; a "
      "lifecycle node's standby taking over beside a cold restart");
  commonOptions(*ros2_cmd, o,
                "cells: death,floor_death (the machine's: the pidfd of the killed node),restart,respawn (a plain "
                "respawn loop),deadline_only,idle_cpu (once, without load),takeover (a lifecycle node's standby),cold "
                "(the same node restarted),standby_cost (once, without load)");
  GuardOptions g;
  auto* guard = app.add_subcommand(
      "guard", "the regression guard: recovery, takeover and detection within a bound of the floor beside them");
  guard->add_option("--n", g.n, "faults per cell")->check(CLI::PositiveNumber);
  guard->add_option("--attempts", g.attempts, "a check fails only when every attempt is above its bound")
      ->check(CLI::PositiveNumber);
  guard->add_option("--only", g.only, "benchmarks: recovery,isolation,detection")
      ->delimiter(',')
      ->check(CLI::IsMember({"recovery", "isolation", "detection"}));
  guard->add_option("--json", g.json, "write every check and its attempts to FILE");
  std::vector<int> sizes{1, 10, 100, 1000};
  int trials = 5;
  auto* sca = app.add_subcommand("scale", "start-up, memory and diagnosis against the number of components");
  sca->add_option("--sizes", sizes, "numbers of components")->delimiter(',')->check(CLI::PositiveNumber);
  sca->add_option("--trials", trials, "trials per size")->check(CLI::PositiveNumber);
  sca->add_flag("--quick", o.quick, "one trial per size");
  sca->add_option("--json", o.json, "write every row to FILE (a JSON array)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (o.quick) o.n = 20;
  const Paths paths = findPaths();
  const std::vector<std::string> mechanisms{
      "reset",       "replace_cold", "replace_preloaded", "reset_opros", "replace_preloaded_opros", "reset_hang",
      "peer_erlang", "peer_respawn", "floor_wake",        "floor_timer", "reset_monitored"};
  const std::vector<std::string> cells{"port_process", "port_thread", "port_dds", "takeover",
                                       "floor_robust", "respawn",     "standby"};
  if (iso->parsed() && !iso->count("--loads")) o.loads = {0, 80};  // its goals' two: idle, and 80 % loaded
  if (dds_cmd->parsed() && !dds_cmd->count("--loads")) o.loads = {0};
  if (ros2_cmd->parsed() && !ros2_cmd->count("--loads")) o.loads = {0, 80};  // its goals' two
  if (ros2_cmd->parsed() && !ros2_cmd->count("--n") && !o.quick) o.n = 100;  // a kill is a node's start: ~0.5 s
  if (ros2_cmd->parsed() && o.policy == "fifo") {
    std::cerr << "keel bench ros2: --policy fifo: its cells run under SCHED_OTHER only\n";
    return 2;
  }
  if (dds_cmd->parsed() && o.policy == "fifo") {
    std::cerr << "keel bench dds: --policy fifo: its cells run under SCHED_OTHER only\n";
    return 2;
  }
  for (const auto& w : o.which) {
    const bool ok = dds_cmd->parsed()    ? std::find(kDdsCells.begin(), kDdsCells.end(), w) != kDdsCells.end()
                    : ros2_cmd->parsed() ? std::find(kRos2Cells.begin(), kRos2Cells.end(), w) != kRos2Cells.end()
                    : iso->parsed()      ? std::find(cells.begin(), cells.end(), w) != cells.end()
                    : rec->parsed()      ? std::find(mechanisms.begin(), mechanisms.end(), w) != mechanisms.end()
                                         : keel::runtime::parseInjectKind(w).has_value() || isDetectionFloor(w);
    if (!ok) {
      std::cerr << "keel bench: --only: unknown '" << w << "'\n";
      return 2;
    }
  }
  if (rec->parsed()) return recoveryBenchmark(o, paths);
  if (det->parsed()) return detectionBenchmark(o, paths);
  if (iso->parsed()) return isolationBenchmark(o, paths);
  if (dds_cmd->parsed()) return ddsBenchmark(o, paths);
  if (ros2_cmd->parsed()) return ros2Benchmark(o, paths);
  if (guard->parsed()) return guardBenchmark(g, paths);
  std::cout << fmt::format("# keel bench scale: sizes {}, {} trial(s) each, machine: {} CPUs\n\n",
                           fmt::join(sizes, "/"), o.quick ? 1 : trials, std::thread::hardware_concurrency())
            << std::flush;
  const auto rows = measureScale(paths, sizes, o.quick ? 1 : trials);
  printScale(rows, std::cout);
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : rows) j.push_back(toJson(r));
  if (!o.json.empty()) {
    writeJson(j, o.json);
    std::cout << "\njson: " << o.json << '\n';
  }
  return 0;
} catch (const std::exception& e) {
  std::cerr << "keel bench: " << e.what() << '\n';
  return 1;
} catch (...) {
  std::cerr << "keel bench: unknown exception\n";
  return 1;
}
