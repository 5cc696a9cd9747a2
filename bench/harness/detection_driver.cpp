// keel bench detection: its cells and its tables (driver.hpp).
#include <fmt/format.h>

#include <iostream>
#include <string>
#include <string_view>

#include "detection.hpp"
#include "floor.hpp"
#include "runtime/injection.hpp"

#include "driver.hpp"

namespace keel::bench {

namespace {

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

}  // namespace

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

bool isDetectionFloor(std::string_view name) { return floorNamed(name) != nullptr; }

int detectionBenchmark(Options o, const Paths& paths) {
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
  finish(o, paths, "detection", j);
  return 0;
}

}  // namespace keel::bench
