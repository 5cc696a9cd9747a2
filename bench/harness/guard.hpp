// keel bench guard: the regression guard over keel's headline latencies, as CI runs it. A few
// hundred faults per cell, idle, SCHED_OTHER; each of keel's cells is compared with the machine's
// floor for the same work measured in the same run (keel p50 ÷ floor p50), so that a slower or
// busier machine moves both and the ratio stays. A check fails when its ratio is above its bound
// in every one of its attempts: one noisy burst does not fail it, a regression does.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "paths.hpp"
#include "report.hpp"

namespace keel::bench {

struct GuardCheck {
  std::string benchmark;   // recovery | isolation | detection: the benchmark whose cells it runs
  std::string cell;        // keel's cell
  std::string floor_cell;  // the floor's own cell; empty: the floor keel's cell measures inside it
  double bound = 0;        // keel p50 ÷ floor p50 above this fails
  std::string floor_name;  // what the floor is, for the report
};

/// The checks, their bounds, and why those bounds (docs/performance.md, "The regression guard").
const std::vector<GuardCheck>& guardChecks();

struct GuardVerdict {
  double keel_p50_us = 0, floor_p50_us = 0;
  double ratio = 0;  // keel ÷ floor at p50
  bool passed = false;
  std::string why;   // when it did not pass: what was wrong
  std::string note;  // keel's cell's note: its warnings, or why it stopped early
};

/// One attempt of `check`: keel's cell, which was asked for `n` faults, and the floor's summary
/// (its own cell's, or keel's cell's Row::floor). A cell that stopped early fails (its note
/// says why): the guard measures what it was asked to.
GuardVerdict judge(const GuardCheck& check, const Row& keel, const Summary& floor, int n);

struct GuardOptions {
  int n = 300;                    // faults per cell
  int attempts = 3;               // a check fails only when every attempt is above its bound
  std::vector<std::string> only;  // benchmarks: recovery, isolation, detection (default: all)
  std::string json;
};

/// Runs the checks, prints one line per attempt and a table; 0 when every check passed.
int guardBenchmark(const GuardOptions& o, const Paths& paths);

}  // namespace keel::bench
