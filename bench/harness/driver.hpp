// What every benchmark of keel-bench shares (main.cpp runs them): the options of a run, the
// cells over load levels and policies, and the output (markdown tables, --json, the plot).
// Each benchmark's driver is a file of its own: recovery_driver.cpp, detection_driver.cpp,
// isolation_driver.cpp, dds_driver.cpp, ros2_driver.cpp.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "dds.hpp"
#include "load.hpp"
#include "paths.hpp"
#include "report.hpp"
#include "runtime/cpu_latency.hpp"

namespace keel::bench {

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
std::optional<std::string> fifoRefused();
std::vector<bool> policiesOf(const Options& o);
LoadSource loadSourceOf(const std::string& s);
/// --low-latency: the runtime's own request (what `keel run --cpu-dma-latency 0` holds), for the
/// whole run; refused, the run stops rather than measure something else than asked.
runtime::CpuLatencyRequest lowLatency(bool on);

/// One benchmark's cells: for each load level (the load started once per level), each policy
/// and each item, `run` fills a Row's measurement; the load and policy columns are filled here.
using CellRunner = std::function<void(const std::string& item, bool fifo, Row& row)>;
std::vector<Row> runCells(const Options& o, const Paths& paths, const std::vector<std::string>& items,
                          const CellRunner& run);

/// Writes the rows as a JSON array, one cell per line; returns the file written.
std::string writeJson(const nlohmann::json& rows, const std::string& path);
/// The rows to --json (or a temporary file) and the plot from it, unless --no-plot.
void finish(const Options& o, const Paths& paths, const std::string& kind, const nlohmann::json& rows);
/// The run's first line: what, how many per cell, the loads, the machine.
void header(const Options& o, const std::string& what, const char* trials = "faults");
/// A DDS or ROS 2 cell's result in its row: a cell with no sample is skipped, with the reason
/// (not shown as a cell whose percentiles are 0).
void fillRow(DdsCell c, Row& row);

// One cell of a benchmark, as its driver runs it (`keel bench guard` runs some of them too).
/// A recovery mechanism, a peer or a floor; `log` is the fault log keel's cells write.
void recoveryCell(const Paths& paths, int n, const std::string& log, const std::string& what, bool fifo, Row& row);
/// An injected kind (with its floor measured in the same cell, where it has one) or a floor.
void detectionCell(int n, const std::string& what, bool fifo, Row& row);
/// A port, the takeover (with its floor measured in the same cell), a cold respawn or a floor.
void isolationCell(const Paths& paths, int n, const std::string& what, bool fifo, Row& row);

// The benchmarks: each prints its tables and returns keel-bench's exit status.
int recoveryBenchmark(Options o, const Paths& paths);
int detectionBenchmark(Options o, const Paths& paths);
int isolationBenchmark(Options o, const Paths& paths);
int ddsBenchmark(Options o, const Paths& paths);
int ros2Benchmark(Options o, const Paths& paths);

/// A name --only of `keel bench detection` takes besides the injected kinds: a floor's.
bool isDetectionFloor(std::string_view name);
/// The cells of `keel bench dds`.
inline constexpr std::array<std::string_view, 5> kDdsCells{"roundtrip_keel", "roundtrip_raw", "roundtrip_rclpy",
                                                           "remote", "failover"};
/// The cells of `keel bench ros2`.
inline constexpr std::array<std::string_view, 9> kRos2Cells{"death",    "floor_death",   "restart",
                                                            "respawn",  "deadline_only", "idle_cpu",
                                                            "takeover", "cold",          "standby_cost"};

}  // namespace keel::bench
