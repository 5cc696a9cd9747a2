// keel bench ros2: its cells and its tables (driver.hpp, ros2.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <iostream>
#include <string>
#include <tuple>

#include "driver.hpp"
#include "ros2.hpp"

namespace keel::bench {

namespace {

const Row* find(const std::vector<Row>& rows, int load, const char* what) {
  for (const auto& r : rows)
    if (r.load == load && r.what == what && !r.skipped) return &r;
  return nullptr;
}

std::string cell(const Row* r) { return r ? fmt::format("{:.1f} / {:.1f}", r->s.p50_us, r->s.p99_us) : "–"; }

std::string ratio(const Row* a, const Row* b) {
  if (!a || !b || b->s.p50_us <= 0 || b->s.p99_us <= 0) return "–";
  return fmt::format("{:.2f} / {:.2f}", a->s.p50_us / b->s.p50_us, a->s.p99_us / b->s.p99_us);
}

std::string ms(const Row* r) { return r ? fmt::format("{:.0f} / {:.0f}", r->s.p50_us / 1e3, r->s.p99_us / 1e3) : "–"; }

void printRos2(const std::vector<Row>& rows, const std::vector<int>& loads, std::ostream& out) {
  out << "\nA supervised node's death, p50 / p99 µs (kill -9 → detected), beside the machine's floor (kill -9 → "
         "the pidfd readable) and a subscriber's deadline watch ("
      << kNodeDeadlineMs << " ms)\n\n";
  out << "| load % | keel: death | floor | keel ÷ floor | deadline only (ms) |\n|---|---|---|---|---|\n";
  for (int load : loads)
    out << fmt::format("| {} | {} | {} | {} | {} |\n", load, cell(find(rows, load, "death")),
                       cell(find(rows, load, "floor_death")),
                       ratio(find(rows, load, "death"), find(rows, load, "floor_death")),
                       ms(find(rows, load, "deadline_only")));
  out << "\nThe node back, p50 / p99 ms (kill -9 → its next life's first message): keel's restart beside a plain "
         "respawn loop\n\n";
  out << "| load % | keel: restart | respawn loop | keel ÷ respawn |\n|---|---|---|---|\n";
  for (int load : loads)
    out << fmt::format("| {} | {} | {} | {} |\n", load, ms(find(rows, load, "restart")),
                       ms(find(rows, load, "respawn")),
                       ratio(find(rows, load, "restart"), find(rows, load, "respawn")));
  out << "\nA lifecycle node back, p50 / p99 ms (kill -9 of the active → the first message again): its standby "
         "taking over beside a cold restart (start, configure, activate)\n\n";
  out << "| load % | keel: standby takes over | cold restart | cold ÷ takeover |\n|---|---|---|---|\n";
  for (int load : loads)
    out << fmt::format("| {} | {} | {} | {} |\n", load, cell(find(rows, load, "takeover")),
                       ms(find(rows, load, "cold")), ratio(find(rows, load, "cold"), find(rows, load, "takeover")));
}

}  // namespace

int ros2Benchmark(Options o, const Paths& paths) {
  if (o.which.empty()) o.which.assign(kRos2Cells.begin(), kRos2Cells.end());
  auto wants = [&](const char* w) { return std::find(o.which.begin(), o.which.end(), w) != o.which.end(); };
  const auto low = lowLatency(o.low_latency);
  const DdsEnvironment env;
  const std::string python = rclpyPython();
  if (python.empty()) {
    std::cerr << "keel bench ros2: no python with rclpy (set KEEL_RCLPY_PYTHON; scripts/peers.sh makes "
                 "tests/peers/venv)\n";
    return 2;
  }
  header(o, "ros2", "kills");
  const int deadline_kills = std::max(10, o.n / 5);
  std::cout << fmt::format("domain {}; python {}; the deadline_only cell: {} kills\n", env.domain(), python,
                           deadline_kills)
            << std::flush;
  std::vector<Row> rows;
  nlohmann::json idle, standby_cost;
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
    // The rows of the cells `cells` names that were asked for, at achieved load `busy` (%).
    auto emit = [&](std::initializer_list<std::pair<const char*, DdsCell*>> cells, double busy) {
      for (auto [what, c] : cells) {
        if (!wants(what)) continue;
        Row r = row(what);
        r.load_achieved = busy;
        fillRow(std::move(*c), r);
        report(r);
        rows.push_back(std::move(r));
      }
    };
    // keel's kills and the respawn loop's alternate in five chunks: the machine's drift over the
    // cell weighs on both alike.
    const bool keel = wants("death") || wants("restart"), loop = wants("floor_death") || wants("respawn");
    if (keel || loop) {
      const CpuMeter meter;
      Ros2Kills k, l;
      constexpr int kChunks = 5;
      auto add = [](DdsCell& to, DdsCell part) {
        to.latencies_ns.insert(to.latencies_ns.end(), part.latencies_ns.begin(), part.latencies_ns.end());
        to.failed += part.failed;
        addNote(to.error, part.error);
        addNote(to.note, part.note);
      };
      for (int chunk = 0; chunk < kChunks; ++chunk) {
        const int m = o.n / kChunks + (chunk < o.n % kChunks ? 1 : 0);
        if (m == 0) continue;
        if (keel) {
          Ros2Kills part = measureSupervised(paths, python, m);
          add(k.death, std::move(part.death));
          add(k.back, std::move(part.back));
        }
        if (loop) {
          Ros2Kills part = measureRespawnLoop(paths, python, m);
          add(l.death, std::move(part.death));
          add(l.back, std::move(part.back));
        }
      }
      emit({{"death", &k.death}, {"restart", &k.back}, {"floor_death", &l.death}, {"respawn", &l.back}},
           meter.busy() * 100);
    }
    // The standby's takeovers and the cold restarts alternate in chunks, as above.
    if (wants("takeover") || wants("cold")) {
      const CpuMeter meter;
      DdsCell take, cold;
      constexpr int kChunks = 5;
      for (int chunk = 0; chunk < kChunks; ++chunk) {
        const int m = o.n / kChunks + (chunk < o.n % kChunks ? 1 : 0);
        if (m == 0) continue;
        for (auto [what, to, standby] : {std::tuple{"takeover", &take, 1}, std::tuple{"cold", &cold, 0}}) {
          if (!wants(what)) continue;
          Ros2Kills part = measureManaged(paths, python, m, standby);
          to->latencies_ns.insert(to->latencies_ns.end(), part.back.latencies_ns.begin(), part.back.latencies_ns.end());
          to->failed += part.back.failed;
          addNote(to->error, part.back.error);
          addNote(to->note, part.back.note);
        }
      }
      emit({{"takeover", &take}, {"cold", &cold}}, meter.busy() * 100);
    }
    if (wants("standby_cost") && standby_cost.is_null() && load == 0) {  // measured without load
      const StandbyCost c = measureStandbyCost(paths, python);
      standby_cost = {{"cell", "standby_cost"},
                      {"window_s", kIdleWindow.count()},
                      {"standby_cpu_percent", std::round(c.standby_cpu_percent * 1000) / 1000},
                      {"active_cpu_percent", std::round(c.active_cpu_percent * 1000) / 1000},
                      {"standby_rss_mib", std::round(c.standby_rss_mib * 10) / 10},
                      {"active_rss_mib", std::round(c.active_rss_mib * 10) / 10}};
      if (!c.error.empty()) standby_cost["note"] = c.error;
      std::cerr << fmt::format(
          "keel-bench: standby_cost: the standby {:.3f} % of a CPU and {:.1f} MiB, the active {:.3f} % and {:.1f} "
          "MiB{}\n",
          c.standby_cpu_percent, c.standby_rss_mib, c.active_cpu_percent, c.active_rss_mib,
          c.error.empty() ? "" : ": " + c.error);
    }
    if (wants("deadline_only")) {
      Row r = row("deadline_only");
      const CpuMeter meter;
      fillRow(measureDeadlineOnly(paths, python, deadline_kills), r);
      r.load_achieved = meter.busy() * 100;
      report(r);
      rows.push_back(std::move(r));
    }
    if (wants("idle_cpu") && idle.is_null() && load == 0) {  // the nodes' idle: measured without load
      const IdleCpu c = measureIdleCpu(paths, python);
      idle = {{"cell", "idle_cpu"},
              {"nodes", kIdleNodes},
              {"window_s", kIdleWindow.count()},
              {"keel_cpu_percent", std::round(c.keel_percent * 1000) / 1000},
              {"nodes_cpu_percent", std::round(c.nodes_percent * 1000) / 1000}};
      if (!c.error.empty()) idle["note"] = c.error;
      std::cerr << fmt::format("keel-bench: idle_cpu: keel {:.3f} % of a CPU, the {} nodes {:.2f} %{}\n",
                               c.keel_percent, kIdleNodes, c.nodes_percent, c.error.empty() ? "" : ": " + c.error);
    }
  }
  printRos2(rows, o.loads, std::cout);
  if (!idle.is_null())
    std::cout << fmt::format(
        "\nkeel supervising {} idle nodes (a message a second each), over {} s: keel {:.3f} % of one CPU, the "
        "nodes themselves {:.2f} %{}\n",
        kIdleNodes, kIdleWindow.count(), idle["keel_cpu_percent"].get<double>(),
        idle["nodes_cpu_percent"].get<double>(),
        idle.contains("note") ? " (" + idle["note"].get<std::string>() + ")" : "");
  if (!standby_cost.is_null())
    std::cout << fmt::format(
        "\nA standby waiting, over {} s: {:.3f} % of one CPU and {:.1f} MiB resident; the active beside it (a "
        "message every 10 ms) {:.3f} % and {:.1f} MiB{}\n",
        kIdleWindow.count(), standby_cost["standby_cpu_percent"].get<double>(),
        standby_cost["standby_rss_mib"].get<double>(), standby_cost["active_cpu_percent"].get<double>(),
        standby_cost["active_rss_mib"].get<double>(),
        standby_cost.contains("note") ? " (" + standby_cost["note"].get<std::string>() + ")" : "");
  std::cout << "\nEvery cell (p50 / p99 / max µs; failed: trials that did not end within their bound)\n\n";
  printCells(rows, false, std::cout);
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : rows) {
    auto c = toJson(r, false);
    auto vs = [&](const char* other, const char* key) {
      const Row* b = find(rows, r.load, other);
      if (b && !r.skipped && b->s.p50_us > 0 && b->s.p99_us > 0)
        c[key] = {{"p50", std::round(r.s.p50_us / b->s.p50_us * 1000) / 1000},
                  {"p99", std::round(r.s.p99_us / b->s.p99_us * 1000) / 1000}};
    };
    if (r.what == "death") vs("floor_death", "vs_floor");
    if (r.what == "restart") vs("respawn", "vs_respawn");
    if (r.what == "cold") vs("takeover", "vs_takeover");
    j.push_back(std::move(c));
  }
  if (!idle.is_null()) j.push_back(idle);
  if (!standby_cost.is_null()) j.push_back(standby_cost);
  o.no_plot = true;  // tables only
  finish(o, paths, "ros2", j);
  return 0;
}

}  // namespace keel::bench
