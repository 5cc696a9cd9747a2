// Latency samples and their summary (p50, p99, max), for keel's benchmark harnesses.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace keel::bench {

struct Summary {
  std::size_t n = 0;
  double p50_us = 0, p99_us = 0, max_us = 0;
};

/// Summarises samples given in nanoseconds.
Summary summarise(std::vector<std::int64_t> samples_ns);

/// Fraction of CPU time the machine spent busy over `seconds` (from /proc/stat), 0..1.
double measureLoad(double seconds);

}  // namespace keel::bench
