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
// `_load P` is the internal duty-cycle load (load.hpp), started by keel-bench itself.
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>
#include <string_view>
#include <thread>

#include "dds.hpp"
#include "detection.hpp"
#include "floor.hpp"
#include "isolation.hpp"
#include "load.hpp"
#include "paths.hpp"
#include "peers.hpp"
#include "process.hpp"
#include "process_floor.hpp"
#include "recovery.hpp"
#include "report.hpp"
#include "runtime/cpu_latency.hpp"
#include "scale.hpp"

namespace keel::bench {
namespace {

struct Options {
  std::vector<int> loads{10, 40, 60, 80};
  int n = 1000;
  bool quick = false;
  std::string policy = "both";  // other | fifo | both
  std::string load_source = "auto";
  std::vector<std::string> which;  // mechanisms or kinds
  std::string json;
  std::string plot;  // default: keel-bench-<what>.svg
  bool no_plot = false;
  bool low_latency = false;
};

/// SCHED_FIFO for a thread of this process: permitted, or why not (tried on a thread of its own).
std::optional<std::string> fifoRefused() {
  std::string why;
  std::thread([&why] { why = becomeFifo(); }).join();
  if (why.empty()) return std::nullopt;
  return why + ": run as root or with CAP_SYS_NICE / an RLIMIT_RTPRIO";
}

std::vector<bool> policiesOf(const Options& o) {
  std::vector<bool> out;
  if (o.policy != "fifo") out.push_back(false);
  if (o.policy != "other") out.push_back(true);
  return out;
}

LoadSource loadSourceOf(const std::string& s) {
  return s == "stress-ng" ? LoadSource::StressNg : s == "internal" ? LoadSource::Internal : LoadSource::Auto;
}

/// --low-latency: the runtime's own request (what `keel run --cpu-dma-latency 0` holds), for the
/// whole run; refused, the run stops rather than measure something else than asked.
runtime::CpuLatencyRequest lowLatency(bool on) {
  if (!on) return {};
  auto held = runtime::CpuLatencyRequest::hold(0);
  if (!held) throw std::runtime_error("--low-latency: " + held.error().message);
  return std::move(*held);
}

/// One benchmark's cells: for each load level (the load started once per level), each policy
/// and each item, `run` fills a Row's measurement; the load and policy columns are filled here.
using CellRunner = std::function<void(const std::string& item, bool fifo, Row& row)>;

std::vector<Row> runCells(const Options& o, const Paths& paths, const std::vector<std::string>& items,
                          const CellRunner& run) {
  std::vector<Row> rows;
  const auto refused = fifoRefused();
  const std::string self = paths.bin + "/keel-bench";
  for (int load : o.loads) {
    BackgroundLoad bg(load, loadSourceOf(o.load_source), self);
    for (bool fifo : policiesOf(o)) {
      for (const auto& item : items) {
        Row row;
        row.load = load;
        row.load_source = bg.source();
        row.what = item;
        row.policy = fifo ? "fifo" : "other";
        const CpuMeter meter;
        if (fifo && refused) {
          row.skipped = true;
          row.note = *refused;
        } else {
          run(item, fifo, row);
        }
        row.load_achieved = meter.busy() * 100;
        std::cerr << fmt::format("keel-bench: load {}% ({:.0f}% achieved), {} {}: ", load, row.load_achieved, item,
                                 row.policy)
                  << (row.skipped ? "skipped: " + row.note
                                  : fmt::format("n {} p50 {:.1f} µs p99 {:.1f} µs max {:.1f} µs", row.s.n, row.s.p50_us,
                                                row.s.p99_us, row.s.max_us))
                  << '\n';
        rows.push_back(std::move(row));
      }
    }
  }
  return rows;
}

void recoveryCell(const Paths& paths, int n, const std::string& log, const std::string& what, bool fifo, Row& row) {
  if (what == "floor_wake" || what == "floor_timer") {
    FloorResult f = what == "floor_wake" ? measureWakeFloor(n, fifo) : measureTimerFloor(n, fifo);
    row.s = summarise(std::move(f.latencies_ns));
    addNote(row.note, f.warnings);
    return;
  }
  if (what == "peer_erlang" || what == "peer_respawn") {
    PeerResult p = what == "peer_erlang" ? runErlangPeer(paths, n, fifo) : runRespawnPeer(paths, n, fifo);
    row.skipped = !p.skipped.empty();
    row.note = p.skipped;
    row.s = summarise(std::move(p.latencies_ns));
    row.failed = p.failed;
    return;
  }
  RecoveryCell c = measureRecovery(paths, what, fifo, n, log);
  if (!c.error.empty()) {
    row.skipped = true;
    row.note = c.error;
    return;
  }
  row.s = summarise(std::move(c.latencies_ns));
  row.failed = c.failed;
  if (c.unexpected) addNote(row.note, fmt::format("{} handled otherwise", c.unexpected));
  if (c.already_mapped) addNote(row.note, fmt::format("{} with the library already mapped", c.already_mapped));
  if (!c.to_client_ns.empty()) {
    const Summary to = summarise(std::move(c.to_client_ns));
    addNote(row.note,
            fmt::format("detection to a monitor client {:.0f} / {:.0f} µs (n {})", to.p50_us, to.p99_us, to.n));
  }
  if (!c.in_place_ns.empty()) {
    const Summary in = summarise(std::move(c.in_place_ns));
    addNote(row.note, fmt::format("in place {:.1f} / {:.1f} µs", in.p50_us, in.p99_us));
  }
  addNote(row.note, c.warnings);
}

/// The machine's floors for detection (floor.hpp), as cells of their own and inside keel's.
struct DetectionFloor {
  const char* name;
  const char* detector;
  FloorResult (*measure)(int n, bool fifo, int every);
};
constexpr DetectionFloor kDetectionFloors[] = {{"floor_signal", "bare handler", measureSignalFloor},
                                               {"floor_throw", "bare catch", measureThrowFloor}};

const DetectionFloor* floorNamed(std::string_view name) {
  for (const auto& f : kDetectionFloors)
    if (name == f.name) return &f;
  return nullptr;
}

/// The floor for the same fault as `kind`, if it has one: a bare handler for a signal, a bare
/// catch for a throw.
const DetectionFloor* floorFor(runtime::InjectKind kind) {
  if (detectorOf(kind) == "signal") return floorNamed("floor_signal");
  return kind == runtime::InjectKind::Throw ? floorNamed("floor_throw") : nullptr;
}

void detectionCell(int n, const std::string& what, bool fifo, Row& row) {
  if (const DetectionFloor* floor = floorNamed(what)) {
    FloorResult f = floor->measure(n, fifo, kDetectionCadence);
    row.detector = floor->detector;
    row.s = summarise(std::move(f.latencies_ns));
    addNote(row.note, f.warnings);
    return;
  }
  const auto kind = *runtime::parseInjectKind(what);
  row.detector = detectorOf(kind);
  if (kind == runtime::InjectKind::Hang)
    addNote(row.note, fmt::format("past the {} ms heartbeat timeout", kDetectionHeartbeatNs / 1'000'000));
  // A hang costs the heartbeat timeout per trial: half as many.
  const int total = kind == runtime::InjectKind::Hang ? std::max(1, n / 2) : n;
  // With a floor, keel's trials and the floor's alternate in chunks, so that the machine's drift
  // over the cell (2× over minutes on a shared VM) weighs on both alike.
  const DetectionFloor* floor = floorFor(kind);
  const int chunks = floor ? std::min(10, total) : 1;
  std::vector<std::int64_t> keel_ns, floor_ns;
  for (int i = 0; i < chunks; ++i) {
    const int m = total / chunks + (i < total % chunks ? 1 : 0);
    DetectionCell part = measureDetection(kind, fifo, m);
    keel_ns.insert(keel_ns.end(), part.latencies_ns.begin(), part.latencies_ns.end());
    row.failed += part.failed;
    addNote(row.note, part.warnings);
    if (!floor) continue;
    FloorResult f = floor->measure(m, fifo, kDetectionCadence);
    floor_ns.insert(floor_ns.end(), f.latencies_ns.begin(), f.latencies_ns.end());
    addNote(row.note, f.warnings);
  }
  row.s = summarise(std::move(keel_ns));
  row.floor = summarise(std::move(floor_ns));
}

/// Runs the plot script on the JSON; a missing python or matplotlib is said, not fatal.
void plot(const Paths& paths, const std::string& kind, const std::string& json, const std::string& svg) {
  const std::string python = ::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : findInPath("python3");
  const Captured ran = runCaptured({python, paths.plot, kind, json, svg}, false,
                                   std::chrono::steady_clock::now() + std::chrono::seconds(60));
  if (!ran.error.empty() || ran.status != 0) {
    std::cout << "\nplot: not written (" << paths.plot << ": "
              << (ran.error.empty() ? (ran.lines.empty() ? "failed" : ran.lines.back()) : ran.error)
              << "; it needs python3-matplotlib)\n";
    return;
  }
  std::cout << "\nplot: " << svg << '\n';
}

/// Writes the rows as a JSON array, one cell per line; returns the file written (a temporary
/// one when only the plot needs it).
std::string writeJson(const nlohmann::json& rows, const std::string& path) {
  std::ofstream out(path);
  out << "[\n";
  for (std::size_t i = 0; i < rows.size(); ++i) out << "  " << rows[i].dump() << (i + 1 < rows.size() ? ",\n" : "\n");
  out << "]\n";
  if (!out) throw std::runtime_error("cannot write " + path);
  return path;
}

void finish(const Options& o, const Paths& paths, const std::string& kind, nlohmann::json rows) {
  const std::string json = o.json.empty() ? fmt::format("/tmp/keel-bench-{}.{}.json", kind, ::getpid()) : o.json;
  writeJson(rows, json);
  if (!o.json.empty()) std::cout << "\njson: " << o.json << '\n';
  if (!o.no_plot) plot(paths, kind, json, o.plot.empty() ? "keel-bench-" + kind + ".svg" : o.plot);
  if (o.json.empty()) std::remove(json.c_str());
}

void header(const Options& o, const std::string& what, const char* trials = "faults") {
  std::cout << fmt::format("# keel bench {}: {} {} per cell{}, loads {}%, machine: {} CPUs{}\n", what, o.n, trials,
                           o.quick ? " (--quick)" : "", fmt::join(o.loads, "/"), std::thread::hardware_concurrency(),
                           o.low_latency ? ", /dev/cpu_dma_latency held at 0" : "")
            << std::flush;
}

int recovery(Options o, const Paths& paths) {
  if (o.which.empty())
    o.which = {"reset",       "replace_cold", "replace_preloaded", "reset_opros", "replace_preloaded_opros",
               "peer_erlang", "peer_respawn", "floor_wake",        "floor_timer"};
  const auto low = lowLatency(o.low_latency);
  header(o, "recovery");
  const std::string log = fmt::format("/tmp/keel-bench-recovery.{}.log", ::getpid());
  auto rows = runCells(o, paths, o.which,
                       [&](const std::string& w, bool fifo, Row& row) { recoveryCell(paths, o.n, log, w, fifo, row); });
  std::remove(log.c_str());
  printTable3(rows, std::cout);
  std::cout
      << "\nEvery cell (p50 / p99 / max over n faults; achieved: the machine's busy CPU time during the cell)\n\n";
  printCells(rows, false, std::cout);
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : rows) j.push_back(toJson(r, false));
  addPeerRatios(j);
  finish(o, paths, "recovery", std::move(j));
  return 0;
}

int detection(Options o, const Paths& paths) {
  if (o.which.empty()) {
    for (auto k : kDetectionKinds) o.which.emplace_back(runtime::toString(k));
    for (const auto& f : kDetectionFloors) o.which.emplace_back(f.name);
  }
  const auto low = lowLatency(o.low_latency);
  header(o, "detection");
  auto rows = runCells(o, paths, o.which,
                       [&](const std::string& w, bool fifo, Row& row) { detectionCell(o.n, w, fifo, row); });
  std::cout << "\nDetection latency, detected − injected (p50 / p99 / max µs)\n\n";
  printCells(rows, true, std::cout);
  printFloorRatios(rows, std::cout);
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : rows) j.push_back(toJson(r, true));
  finish(o, paths, "detection", std::move(j));
  return 0;
}

void isolationCell(const Paths& paths, int n, const std::string& what, bool fifo, Row& row) {
  if (what == "floor_robust") {
    FloorResult f = measureRobustFloor(n, fifo, 1);
    row.s = summarise(std::move(f.latencies_ns));
    addNote(row.note, f.warnings);
    addNote(row.note, "the dying process has 1 thread");
    return;
  }
  if (what == "port_dds") {
    const DdsResult d = runDdsPeer(n, fifo);
    row.skipped = !d.skipped.empty();
    row.note = d.skipped.empty() ? d.detail : d.skipped;
    row.s = {d.samples, d.p50_us, d.p99_us, d.max_us};
    return;
  }
  IsolationCell c;
  std::vector<std::int64_t> floor_ns;
  auto addFloor = [&](FloorResult f) {
    floor_ns.insert(floor_ns.end(), f.latencies_ns.begin(), f.latencies_ns.end());
    addNote(row.note, f.warnings);
  };
  if (what == "takeover") {
    c = measureTakeover(paths, true, fifo, n,
                        [&](int m, int threads) { addFloor(measureRobustFloor(m, fifo, threads)); });
    addNote(row.note,
            fmt::format("floor: the dying process has {} threads, as keel's component process", c.host_threads));
  } else if (what == "respawn") {
    c = measureTakeover(paths, false, fifo, n);
  } else {
    c = measurePort(paths, what == "port_process", fifo, n);
    addFloor(what == "port_process" ? measureProcessWakeFloor(n, fifo) : measureWakeFloor(n, fifo));
  }
  if (!c.detected_to_step_ns.empty()) {  // takeover, respawn: the part of it keel's log times
    const Summary in = summarise(std::move(c.detected_to_step_ns));
    addNote(row.note, fmt::format("detected → first step {:.1f} / {:.1f} µs", in.p50_us, in.p99_us));
  }
  if (!c.error.empty()) {
    row.skipped = c.latencies_ns.empty();
    addNote(row.note, c.error);
  }
  row.s = summarise(std::move(c.latencies_ns));
  row.floor = summarise(std::move(floor_ns));
  row.failed = c.unexpected;
  addNote(row.note, c.warnings);
}

int isolation(Options o, const Paths& paths) {
  const std::vector<std::string> all{"port_process", "port_thread", "port_dds", "takeover",
                                     "floor_robust", "respawn",     "standby"};
  if (o.which.empty()) o.which = all;
  const bool standby = std::find(o.which.begin(), o.which.end(), "standby") != o.which.end();
  std::erase(o.which, "standby");
  const auto low = lowLatency(o.low_latency);
  header(o, "isolation", "trials");
  auto rows = runCells(o, paths, o.which,
                       [&](const std::string& w, bool fifo, Row& row) { isolationCell(paths, o.n, w, fifo, row); });
  printIsolation(rows, std::cout);
  std::cout << "\nEvery cell (p50 / p99 / max; failed: kills handled otherwise than the cell measures)\n\n";
  printCells(rows, false, std::cout);
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : rows) j.push_back(toJson(r, false));
  if (standby) {
    const StandbyCost c = measureStandbyCost(paths, 5.0);
    if (!c.error.empty()) {
      std::cout << "\nA waiting standby: not measured (" << c.error << ")\n";
    } else {
      std::cout << fmt::format(
          "\nA waiting standby beside its active process, idle, over {:.0f} s (CPU in ticks of 1/{} s, every "
          "thread)\n\n| process | CPU ticks | context switches | RSS kB | PSS kB | anonymous kB |\n"
          "|---|---|---|---|---|---|\n"
          "| active (a 1 kHz component) | {} | {} | {} | {} | {} |\n| standby | {} | {} | {} | {} | {} |\n",
          c.seconds, c.tick_hz, c.active_cpu_ticks, c.active_switches, c.active_rss_kb, c.active_pss_kb,
          c.active_anon_kb, c.standby_cpu_ticks, c.standby_switches, c.standby_rss_kb, c.standby_pss_kb,
          c.standby_anon_kb);
      j.push_back({{"mechanism", "standby_cost"},
                   {"seconds", c.seconds},
                   {"tick_hz", c.tick_hz},
                   {"active",
                    {{"cpu_ticks", c.active_cpu_ticks},
                     {"switches", c.active_switches},
                     {"rss_kb", c.active_rss_kb},
                     {"pss_kb", c.active_pss_kb},
                     {"anon_kb", c.active_anon_kb}}},
                   {"standby",
                    {{"cpu_ticks", c.standby_cpu_ticks},
                     {"switches", c.standby_switches},
                     {"rss_kb", c.standby_rss_kb},
                     {"pss_kb", c.standby_pss_kb},
                     {"anon_kb", c.standby_anon_kb}}}});
    }
  }
  o.no_plot = true;  // tables only
  finish(o, paths, "isolation", std::move(j));
  return 0;
}

/// One DDS cell's result in its row: a cell with no sample is skipped, with the reason.
void ddsRow(DdsCell c, Row& row) {
  row.skipped = c.latencies_ns.empty() && !c.error.empty();
  row.s = summarise(std::move(c.latencies_ns));
  row.failed = c.failed;
  addNote(row.note, c.error);
  addNote(row.note, c.note);
}

const std::vector<std::string> kDdsCells{"roundtrip_keel", "roundtrip_raw", "roundtrip_rclpy", "remote", "failover"};

int dds(Options o, const Paths& paths) {
  if (o.which.empty()) o.which = kDdsCells;
  auto wants = [&](const char* w) { return std::find(o.which.begin(), o.which.end(), w) != o.which.end(); };
  const auto low = lowLatency(o.low_latency);
  const DdsEnvironment env;
  header(o, "dds", "trials");
  std::cout << fmt::format("domain {}; the remote and failover cells: max(10, n/{}) and max(10, n/{}) kills\n",
                           env.domain(), 5, 20)
            << std::flush;
  const int kills_remote = std::max(10, o.n / 5), kills_failover = std::max(10, o.n / 20);
  std::vector<Row> rows;
  const std::string self = paths.bin + "/keel-bench";
  for (int load : o.loads) {
    BackgroundLoad bg(load, loadSourceOf(o.load_source), self);
    auto row = [&](const std::string& what) {
      Row r;
      r.load = load;
      r.load_source = bg.source();
      r.what = what;
      r.policy = "other";
      return r;
    };
    auto report = [](const Row& r) {
      std::cerr << fmt::format("keel-bench: load {}% ({:.0f}% achieved), {}: ", r.load, r.load_achieved, r.what)
                << (r.skipped ? "skipped: " + r.note
                              : fmt::format("n {} p50 {:.1f} µs p99 {:.1f} µs max {:.1f} µs", r.s.n, r.s.p50_us,
                                            r.s.p99_us, r.s.max_us))
                << '\n';
    };
    // keel's round trip and the C program's alternate in five chunks: the machine's drift over
    // the cell weighs on both alike.
    std::vector<Row> pair;
    for (const char* w : {"roundtrip_keel", "roundtrip_raw"})
      if (wants(w)) pair.push_back(row(w));
    if (!pair.empty()) {
      const CpuMeter meter;
      std::vector<DdsCell> got(pair.size());
      constexpr int kChunks = 5;
      for (int chunk = 0; chunk < kChunks; ++chunk) {
        const int m = o.n / kChunks + (chunk < o.n % kChunks ? 1 : 0);
        for (std::size_t i = 0; i < pair.size(); ++i) {
          DdsCell part = pair[i].what == "roundtrip_keel" ? measureKeelRoundTrip(paths, m)
                                                          : measureRawRoundTrip(paths, m);
          got[i].latencies_ns.insert(got[i].latencies_ns.end(), part.latencies_ns.begin(), part.latencies_ns.end());
          got[i].failed += part.failed;
          addNote(got[i].error, part.error);
          got[i].note = part.note;
        }
      }
      for (std::size_t i = 0; i < pair.size(); ++i) {
        pair[i].load_achieved = meter.busy() * 100;
        ddsRow(std::move(got[i]), pair[i]);
        report(pair[i]);
        rows.push_back(std::move(pair[i]));
      }
    }
    for (const char* w : {"roundtrip_rclpy", "remote", "failover"}) {
      if (!wants(w)) continue;
      Row r = row(w);
      const CpuMeter meter;
      const std::string what = w;
      ddsRow(what == "roundtrip_rclpy" ? measureRclpyRoundTrip(paths, o.n)
             : what == "remote"        ? measureRemoteDetection(paths, kills_remote)
                                       : measureFailover(paths, kills_failover),
             r);
      r.load_achieved = meter.busy() * 100;
      report(r);
      rows.push_back(std::move(r));
    }
  }
  printDds(rows, kRemoteDeadlineMs, kFailoverLeaseMs, std::cout);
  std::cout << "\nEvery cell (p50 / p99 / max µs; failed: trials that did not end within their bound)\n\n";
  printCells(rows, false, std::cout);
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : rows) {
    auto cell = toJson(r, false);
    if (r.what == "remote") cell["goal_p99_us"] = (kRemoteDeadlineMs + 10) * 1000;
    if (r.what == "failover") cell["goal_p99_us"] = (kFailoverLeaseMs + 10) * 1000;
    if (r.what == "roundtrip_keel") {
      for (const auto& raw : rows)
        if (raw.what == "roundtrip_raw" && raw.load == r.load && raw.s.n > 0 && r.s.n > 0)
          cell["vs_raw"] = {{"p50", std::round(r.s.p50_us / raw.s.p50_us * 1000) / 1000},
                            {"p99", std::round(r.s.p99_us / raw.s.p99_us * 1000) / 1000}};
    }
    j.push_back(std::move(cell));
  }
  o.no_plot = true;  // tables only
  finish(o, paths, "dds", std::move(j));
  return 0;
}

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

int main(int argc, char** argv) {
  using namespace keel::bench;
  if (argc == 3 && std::string(argv[1]) == "_load") return runInternalLoad(std::atoi(argv[2]));
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
  try {
    const std::vector<std::string> mechanisms{
        "reset",       "replace_cold", "replace_preloaded", "reset_opros", "replace_preloaded_opros", "reset_hang",
        "peer_erlang", "peer_respawn", "floor_wake",        "floor_timer", "reset_monitored"};
    const std::vector<std::string> cells{"port_process", "port_thread", "port_dds", "takeover",
                                         "floor_robust", "respawn",     "standby"};
    if (iso->parsed() && !iso->count("--loads")) o.loads = {0, 80};  // the two: idle, and 80 % loaded
    if (dds_cmd->parsed() && !dds_cmd->count("--loads")) o.loads = {0};
    if (dds_cmd->parsed() && o.policy == "fifo") {
      std::cerr << "keel bench dds: --policy fifo: its cells run under SCHED_OTHER only\n";
      return 2;
    }
    for (const auto& w : o.which) {
      const bool ok = dds_cmd->parsed() ? std::find(kDdsCells.begin(), kDdsCells.end(), w) != kDdsCells.end()
                      : iso->parsed()   ? std::find(cells.begin(), cells.end(), w) != cells.end()
                      : rec->parsed()   ? std::find(mechanisms.begin(), mechanisms.end(), w) != mechanisms.end()
                                        : keel::runtime::parseInjectKind(w).has_value() || floorNamed(w);
      if (!ok) {
        std::cerr << "keel bench: --only: unknown '" << w << "'\n";
        return 2;
      }
    }
    if (rec->parsed()) return recovery(o, paths);
    if (det->parsed()) return detection(o, paths);
    if (iso->parsed()) return isolation(o, paths);
    if (dds_cmd->parsed()) return dds(o, paths);
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
  }
}
