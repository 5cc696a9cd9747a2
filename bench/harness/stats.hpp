// Latency samples and their summary (p50, p99, max), for keel's benchmark harness.
#pragma once

#include <cstdint>
#include <vector>

namespace keel::bench {

struct Summary {
  std::size_t n = 0;
  double p50_us = 0, p99_us = 0, max_us = 0;
};

/// Summarises samples given in nanoseconds (nearest-rank percentiles).
Summary summarise(std::vector<std::int64_t> samples_ns);

}  // namespace keel::bench
