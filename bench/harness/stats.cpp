#include "latency_stats.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

namespace keel::bench {

Summary summarise(std::vector<std::int64_t> s) {
  Summary out;
  out.n = s.size();
  if (s.empty()) return out;
  std::sort(s.begin(), s.end());
  auto at = [&s](double q) {
    std::size_t i = static_cast<std::size_t>(q * static_cast<double>(s.size() - 1) + 0.5);
    return s[std::min(i, s.size() - 1)] / 1e3;
  };
  out.p50_us = at(0.50);
  out.p99_us = at(0.99);
  out.max_us = s.back() / 1e3;
  return out;
}

namespace {
std::pair<long long, long long> cpuTimes() {  // (busy, total) jiffies
  std::ifstream in("/proc/stat");
  std::string cpu;
  long long v, busy = 0, total = 0;
  in >> cpu;
  for (int i = 0; i < 10 && in >> v; ++i) {
    total += v;
    if (i != 3 && i != 4) busy += v;  // idle, iowait
  }
  return {busy, total};
}
}  // namespace

double measureLoad(double seconds) {
  auto a = cpuTimes();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  auto b = cpuTimes();
  return b.second == a.second ? 0 : double(b.first - a.first) / double(b.second - a.second);
}

}  // namespace keel::bench
