// What `keel bench` prints and writes: one Row per cell (a load level × a mechanism or detector ×
// a scheduling policy), rendered as markdown tables — the cells in full, and for recovery a
// table shaped like the paper's Table 3 with the paper's column beside ours and keel/peer
// ratios — and as JSON (one object per cell).
#pragma once

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

#include "stats.hpp"

namespace keel::bench {

struct Row {
  int load = 0;              // the level asked for: % busy on every CPU
  double load_achieved = 0;  // % of the machine's CPU time busy during the cell (everyone)
  std::string load_source;   // stress-ng | internal | none
  std::string what;          // recovery: the mechanism; detection: the injected kind
  std::string detector;      // detection: the detector that finds it
  std::string policy;        // other | fifo
  Summary s;
  std::size_t failed = 0;  // faults not recovered / not detected within the bound
  bool skipped = false;    // the cell did not run (note says why)
  std::string note;        // why skipped, the engine's warnings, unexpected handlings
  Summary floor;           // detection: the machine's floor for the same fault, measured
                           // interleaved with this cell (n == 0: the kind has none)
};

/// Appends `note` to `notes` ("; " between), unless it is there already.
void addNote(std::string& notes, const std::string& note);

/// One cell as JSON. Recovery: {"load","load_achieved","load_source","mechanism","policy","n",
/// "p50_us","p99_us","max_us","failed"[,"skipped"][,"note"]}; detection has "kind" and
/// "detector" in place of "mechanism", and where the cell measured its floor
/// "floor_p50_us", "floor_p99_us" and "vs_floor": {"p50":…, "p99":…} (keel ÷ floor; 1: keel adds
/// nothing to what the machine costs).
nlohmann::json toJson(const Row& row, bool detection);

/// keel's cells (not the peers', not the floors') gain their ratio to each peer of the same
/// load and policy:
/// "vs_peer_erlang": {"p50":…, "p99":…} (keel ÷ peer: below 1, keel is faster).
void addPeerRatios(nlohmann::json& rows);

/// Detection: keel ÷ the floor each cell measured, as a table, a row per load and policy
/// (nothing when no cell measured one).
void printFloorRatios(const std::vector<Row>& rows, std::ostream& out);

/// Every cell, one line each.
void printCells(const std::vector<Row>& rows, bool detection, std::ostream& out);

/// Isolation: the ports (keel across processes with its floor, in one process, DDS) and the
/// takeover (with its floor, beside the cold respawn), a row per load and policy.
void printIsolation(const std::vector<Row>& rows, std::ostream& out);

/// DDS: the round trips (keel's, the CycloneDDS C program's, keel ÷ it, rclpy's), then remote
/// detection and failover beside their goals (deadline + 10 ms, lease + 10 ms), a row per load.
void printDds(const std::vector<Row>& rows, int deadline_ms, int lease_ms, std::ostream& out);

/// Recovery only: per policy, load levels down and mechanisms across ("p50 / p99 µs"), the
/// paper's Linux-Pentium4 column beside, then keel ÷ peer per load.
void printTable3(const std::vector<Row>& rows, std::ostream& out);

}  // namespace keel::bench
