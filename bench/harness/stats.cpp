#include "stats.hpp"

#include <algorithm>
#include <cmath>

namespace keel::bench {

Summary summarise(std::vector<std::int64_t> s) {
  Summary out;
  out.n = s.size();
  if (s.empty()) return out;
  std::sort(s.begin(), s.end());
  auto at = [&s](double q) {
    auto i = static_cast<std::size_t>(std::lround(q * static_cast<double>(s.size() - 1)));
    return static_cast<double>(s[std::min(i, s.size() - 1)]) / 1e3;
  };
  out.p50_us = at(0.50);
  out.p99_us = at(0.99);
  out.max_us = static_cast<double>(s.back()) / 1e3;
  return out;
}

}  // namespace keel::bench
