// The DDS peer of `keel bench isolation` (peers.hpp): `ddsperf pong` and `ddsperf ping` in two
// processes, CycloneDDS pinned to 127.0.0.1 by a configuration of their own (by default it
// would join multicast on the first network interface), ping's per-second lines read as it
// prints them:
//   [pid] 2.000  host:pid size 64 mean 65.8us min 37.6us 50% 62.4us 90% 71.8us 99% 439.0us max 573.9us cnt 979
#include <fcntl.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "dds.hpp"
#include "peers.hpp"
#include "process.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

/// The value (µs) after `key` in a ddsperf line ("50% 62.4us"), or nullopt.
std::optional<double> micros(std::string_view line, std::string_view key) {
  const auto at = line.find(key);
  if (at == std::string_view::npos) return std::nullopt;
  const char* begin = line.data() + at + key.size();
  double v = 0;
  const auto [end, ec] = std::from_chars(begin, line.data() + line.size(), v);
  if (ec != std::errc() || std::string_view(end, 2) != "us") return std::nullopt;
  return v;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

DdsResult runDdsPeer(int n, bool fifo) {
  DdsResult r;
  const std::string ddsperf = findInPath("ddsperf");
  if (ddsperf.empty()) {
    r.skipped = "ddsperf not found (scripts/deps.sh bench installs cyclonedds-tools)";
    return r;
  }
  const TempDir dir("keel-bench-dds-");
  const std::string config = dir.path() + "/cyclonedds.xml";
  std::ofstream(config) << kCycloneLoopbackConfig;
  const std::vector<EnvChange> env{{"CYCLONEDDS_URI", "file://" + config}};
  const int seconds = std::max(5, n / 1000) + 1;        // the first second is discovery: dropped
  Fd quiet(::open("/dev/null", O_WRONLY | O_CLOEXEC));  // pong prints its own statistics
  auto pong = Process::spawn({ddsperf, "-D", std::to_string(seconds + 3), "pong", "waitset"},
                             {.out = quiet.get(), .err = quiet.get()}, fifo, true, env);
  Pipe out;
  std::optional<Process> ping;
  if (pong && out.open()) {
    std::this_thread::sleep_for(500ms);
    auto spawned = Process::spawn({ddsperf, "-D", std::to_string(seconds), "ping", "1kHz", "size", "64", "waitset"},
                                  {.out = out.write.get(), .err = out.write.get()}, fifo, true, env);
    if (spawned) ping.emplace(std::move(*spawned));
    else r.skipped = "ddsperf ping: " + spawned.error().message;
  } else {
    r.skipped = pong ? "pipe" : "ddsperf pong: " + pong.error().message;
  }
  if (!ping) return r;
  out.write.reset();
  std::vector<double> p50, p99;
  LineReader lines(out.read.get());
  const auto deadline = Clock::now() + std::chrono::seconds(seconds + 10);
  bool first = true;
  while (auto line = lines.next(deadline)) {
    if (line->find(" size 64 ") == std::string::npos) continue;
    const auto a = micros(*line, " 50% "), b = micros(*line, " 99% "), m = micros(*line, " max ");
    const auto cnt = line->find(" cnt ");
    if (!a || !b || !m || cnt == std::string::npos) continue;
    if (first) {  // discovery and the first samples' page faults
      first = false;
      continue;
    }
    p50.push_back(*a / 2);
    p99.push_back(*b / 2);
    r.max_us = std::max(r.max_us, *m / 2);
    r.samples += std::strtoul(line->c_str() + cnt + 5, nullptr, 10);
  }
  ping->waitUntil(Clock::now() + 5s);
  pong->waitUntil(Clock::now() + 5s);
  if (p50.empty()) {
    r.skipped = "ddsperf ping printed no round trips (no pong found?)";
    return r;
  }
  r.p50_us = median(p50);
  r.p99_us = median(p99);
  r.detail = "CycloneDDS ddsperf, 64 B at 1 kHz, round trip ÷ 2";
  return r;
}

}  // namespace keel::bench
