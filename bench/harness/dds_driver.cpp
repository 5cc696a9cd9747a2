// keel bench dds: its cells and its tables (driver.hpp).
#include <fmt/format.h>

#include <iostream>
#include <string>

#include "dds.hpp"

#include "driver.hpp"

namespace keel::bench {

int ddsBenchmark(Options o, const Paths& paths) {
  if (o.which.empty()) o.which.assign(kDdsCells.begin(), kDdsCells.end());
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
        fillRow(std::move(got[i]), pair[i]);
        report(pair[i]);
        rows.push_back(std::move(pair[i]));
      }
    }
    for (const char* w : {"roundtrip_rclpy", "remote", "failover"}) {
      if (!wants(w)) continue;
      Row r = row(w);
      const CpuMeter meter;
      const std::string what = w;
      fillRow(what == "roundtrip_rclpy" ? measureRclpyRoundTrip(paths, o.n)
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
  finish(o, paths, "dds", j);
  return 0;
}

}  // namespace keel::bench
