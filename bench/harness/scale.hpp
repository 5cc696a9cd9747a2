// How keel's costs grow with the number of components (`keel bench scale`): start-up time,
// memory per component, and the fault manager's diagnosis time against the size of the
// dependency graph it walks.
// Each size N runs generated profiles (written into a temporary directory): a package of N
// BenchVictim instances for start-up and memory, and a system of the same N components as a
// chain of applications for the diagnosis; what each column includes is said in scale.cpp.
// Thread-safety: measureScale runs engines one after the other on the calling thread.
#pragma once

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

#include "paths.hpp"

namespace keel::bench {

/// Components per periodic task (and per application of the system), and the tasks' period.
inline constexpr int kScaleTaskSize = 10;
inline constexpr int kScalePeriodMs = 10;

struct ScaleRow {
  int components = 0;
  int applications = 0;                                 // of the system profile the diagnosis runs (a chain)
  int graph_nodes = 0;                                  // nodes of the dependency graph the diagnosis walks
  double startup_ms = 0;                                // load + create + initialize + start, median of the trials
  double load_ms = 0, create_ms = 0, start_ms = 0;      // its parts, each the median of the trials
  double memory_kib = 0;                                // resident set grown by one start-up, median of the trials
  double memory_kib_per_component = 0;                  // memory_kib / components
  double diagnosis_p50_us = 0, diagnosis_p99_us = 0;    // detected → diagnosed
  double graph_walk_p50_us = 0, graph_walk_p99_us = 0;  // the dependency graph's answer alone
  int faults = 0;                                       // faults behind the diagnosis percentiles
  int failed = 0;                                       // faults whose stop did not come, or not of the whole graph
  int trials = 0;
  std::string error;  // non-empty: the size could not run (profile, engine)
};

std::vector<ScaleRow> measureScale(const Paths& paths, const std::vector<int>& sizes, int trials);
void printScale(const std::vector<ScaleRow>& rows, std::ostream& out);  // a markdown table
nlohmann::json toJson(const ScaleRow& row);

/// Writes into `dir` a package profile of `components` BenchVictim instances, c0, c1, ..., on
/// periodic tasks of kScaleTaskSize; returns its path.
std::string writeScalePackage(const std::string& dir, const Paths& paths, int components);
/// Writes into `dir` a system profile of `components` BenchVictim instances in applications
/// a0, a1, ... of kScaleTaskSize components each (one task per application), each depending
/// on the one before; a fault of a0.c0 stops them all. Returns its path.
std::string writeScaleSystem(const std::string& dir, const Paths& paths, int components);

}  // namespace keel::bench
