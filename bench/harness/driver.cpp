#include "driver.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <thread>

#include "process.hpp"

namespace keel::bench {

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

runtime::CpuLatencyRequest lowLatency(bool on) {
  if (!on) return {};
  auto held = runtime::CpuLatencyRequest::hold(0);
  if (!held) throw std::runtime_error("--low-latency: " + held.error().message);
  return std::move(*held);
}

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

/// Runs the plot script on the JSON; a missing python or matplotlib is said, not fatal.
namespace {

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

}  // namespace

std::string writeJson(const nlohmann::json& rows, const std::string& path) {
  std::ofstream out(path);
  out << "[\n";
  for (std::size_t i = 0; i < rows.size(); ++i) out << "  " << rows[i].dump() << (i + 1 < rows.size() ? ",\n" : "\n");
  out << "]\n";
  if (!out) throw std::runtime_error("cannot write " + path);
  return path;
}

void finish(const Options& o, const Paths& paths, const std::string& kind, const nlohmann::json& rows) {
  const std::string json = o.json.empty() ? fmt::format("/tmp/keel-bench-{}.{}.json", kind, ::getpid()) : o.json;
  writeJson(rows, json);
  if (!o.json.empty()) std::cout << "\njson: " << o.json << '\n';
  if (!o.no_plot) plot(paths, kind, json, o.plot.empty() ? "keel-bench-" + kind + ".svg" : o.plot);
  if (o.json.empty()) std::remove(json.c_str());
}

void header(const Options& o, const std::string& what, const char* trials) {
  std::cout << fmt::format("# keel bench {}: {} {} per cell{}, loads {}%, machine: {} CPUs{}\n", what, o.n, trials,
                           o.quick ? " (--quick)" : "", fmt::join(o.loads, "/"), std::thread::hardware_concurrency(),
                           o.low_latency ? ", /dev/cpu_dma_latency held at 0" : "")
            << std::flush;
}

void fillRow(DdsCell c, Row& row) {
  if (c.latencies_ns.empty() && c.error.empty())
    c.error = fmt::format("no trial ended within its bound ({} failed)", c.failed);
  row.skipped = c.latencies_ns.empty();
  row.s = summarise(std::move(c.latencies_ns));
  row.failed = c.failed;
  addNote(row.note, c.error);
  addNote(row.note, c.note);
}

}  // namespace keel::bench
