// keel bench isolation: its cells and its tables (driver.hpp).
#include <fmt/format.h>

#include <iostream>
#include <string>

#include "floor.hpp"
#include "isolation.hpp"
#include "peers.hpp"
#include "process_floor.hpp"

#include "driver.hpp"

namespace keel::bench {

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

int isolationBenchmark(Options o, const Paths& paths) {
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
  finish(o, paths, "isolation", j);
  return 0;
}

}  // namespace keel::bench
