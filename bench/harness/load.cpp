#include "load.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <tuple>
#include <vector>

namespace keel::bench {
namespace {

using namespace std::chrono_literals;

std::pair<long long, long long> cpuTimes() {  // (busy, total) jiffies over all CPUs
  std::ifstream in("/proc/stat");
  std::string cpu;
  long long v = 0, busy = 0, total = 0;
  in >> cpu;
  // user nice system idle iowait irq softirq steal; guest and guest_nice are already counted
  // in user and nice
  for (int i = 0; i < 8 && in >> v; ++i) {
    total += v;
    if (i != 3 && i != 4) busy += v;  // idle, iowait
  }
  return {busy, total};
}

std::atomic<bool> g_stop{false};
void onTerm(int) { g_stop.store(true); }

}  // namespace

BackgroundLoad::BackgroundLoad(int percent, LoadSource source, const std::string& self_exe) {
  if (percent <= 0) return;
  percent = std::min(percent, 100);
  const std::string stress_ng = findInPath("stress-ng");
  if (source == LoadSource::StressNg && stress_ng.empty())
    throw std::runtime_error("stress-ng is not installed (scripts/deps.sh installs it)");
  const bool stress = source != LoadSource::Internal && !stress_ng.empty();
  // Through `_guard`: should keel-bench die without stopping it, the load gets SIGTERM (and
  // stress-ng's --timeout bounds it even so).
  std::vector<std::string> argv{self_exe, "_guard", std::to_string(::getpid())};
  const std::vector<std::string> load =
      stress ? std::vector<std::string>{stress_ng,   "--cpu", "0", "--cpu-load", std::to_string(percent),
                                        "--timeout", "7200s"}
             : std::vector<std::string>{self_exe, "_load", std::to_string(percent)};
  argv.insert(argv.end(), load.begin(), load.end());
  const Fd null(::open("/dev/null", O_WRONLY | O_CLOEXEC));
  auto spawned = Process::spawn(argv, {.in = -1, .out = null.get(), .err = null.get()}, false, true);
  if (!spawned) throw std::runtime_error("cannot start the load: " + spawned.error().message);
  process_.emplace(std::move(*spawned));
  source_ = stress ? "stress-ng" : "internal";
  std::this_thread::sleep_for(1s);  // workers started and at their duty cycle
}

BackgroundLoad::~BackgroundLoad() {
  if (!process_) return;
  process_->signal(SIGTERM);  // stress-ng stops and reaps its workers; the group is killed after 3 s
  (void)process_->waitUntil(std::chrono::steady_clock::now() + 3s);
}

int runGuarded(int argc, char** argv) {
  if (argc < 4) return 2;
  if (::prctl(PR_SET_PDEATHSIG, SIGTERM) != 0) return 126;
  // The parent may have died before the prctl: then no signal would ever come.
  pid_t parent = 0;
  const std::string_view arg(argv[2]);
  if (std::from_chars(arg.data(), arg.data() + arg.size(), parent).ec != std::errc()) return 2;
  if (::getppid() != parent) return 1;
  ::execv(argv[3], argv + 3);
  return 127;
}

int runInternalLoad(int percent) {
  ::signal(SIGTERM, onTerm);
  const auto period = 10ms;
  const auto busy = period * percent / 100;
  const unsigned cpus = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> workers;
  for (unsigned i = 0; i < cpus; ++i)
    workers.emplace_back([&] {
      auto next = std::chrono::steady_clock::now();
      while (!g_stop.load(std::memory_order_relaxed)) {
        const auto busy_until = next + busy;
        while (std::chrono::steady_clock::now() < busy_until) {}
        next += period;
        std::this_thread::sleep_until(next);
      }
    });
  for (auto& w : workers) w.join();
  return 0;
}

CpuMeter::CpuMeter() { std::tie(busy0_, total0_) = cpuTimes(); }

double CpuMeter::busy() const {
  const auto [b, t] = cpuTimes();
  return t == total0_ ? 0.0 : static_cast<double>(b - busy0_) / static_cast<double>(t - total0_);
}

}  // namespace keel::bench
