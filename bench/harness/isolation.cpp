#include "isolation.hpp"

#include <signal.h>
#include <unistd.h>

#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <thread>
#include <utility>

#include "bench_run.hpp"
#include "runtime/clock.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using keel_bench::BenchPage;

constexpr auto kStartBound = 20s;  // keel run up, its processes started and running
constexpr auto kTrialBound = 3s;   // a kill → the new process's first step

/// One component profile of the isolation benchmark's library.
std::string componentXml(const std::string& name, const std::string& semantics, const std::string& ports,
                         const std::string& page) {
  return benchComponentXml("keel_bench_isolation", name, semantics, ports, page);
}

std::vector<std::pair<std::string, std::string>> beatFiles(const std::string& page, bool standby, bool fifo) {
  return {{"BenchBeat.xml",
           componentXml("BenchBeat", "<type>periodic</type><period>1</period>" + schedXml(fifo), "", page)},
          {"takeover.xml", fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?>
<package_profile>
  <name>bench_takeover</name>
  <subcomponents>
    <subcomponent><name>beat</name><reference>BenchBeat.xml</reference>
      <fault_policy><severity>reset</severity><checkpoint period="1"/><restart intensity="100000" period="1000"/></fault_policy>
      <process name="beat" standby="{}"/>
    </subcomponent>
  </subcomponents>
</package_profile>
)",
                                       standby ? 1 : 0)}};
}

int threadsOf(pid_t pid) {
  std::error_code ec;
  int n = 0;
  for (auto it = std::filesystem::directory_iterator(fmt::format("/proc/{}/task", pid), ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    ++n;
  return n;
}

/// keel run up: its first active process ran a step, and with a standby, that one is waiting.
std::string awaitStart(BenchRun& run, bool standby) {
  const bool up = pollUntil(
      [&] {
        return run.page().active_pid.load(std::memory_order_acquire) != 0 &&
               (!standby || run.hostPhases("standby") > 0);
      },
      kStartBound);
  return up ? "" : run.failure("keel run did not start its process within 20 s");
}

}  // namespace

IsolationCell measureTakeover(const Paths& paths, bool standby, bool fifo, int n,
                              const std::function<void(int, int)>& between) {
  IsolationCell cell;
  BenchRun run(paths);
  if (cell.error = run.start(beatFiles(run.pagePath(), standby, fifo), "takeover.xml"); !cell.error.empty())
    return cell;
  if (cell.error = awaitStart(run, standby); !cell.error.empty()) return cell;
  BenchPage& page = run.page();
  cell.host_threads = threadsOf(page.active_pid.load());
  const int chunk = std::max(1, n / 10);
  std::size_t took_over = 0, respawned = 0;
  for (int i = 0; i <= n; ++i) {  // kill 0 warms up, uncounted
    // The standby the last takeover started is waiting (or, without one, the process runs).
    if (standby &&
        !pollUntil([&] { return run.hostPhases("standby") >= static_cast<std::size_t>(i) + 1; }, kTrialBound)) {
      cell.error = run.failure(fmt::format("no new standby after kill {}", i));
      break;
    }
    std::this_thread::sleep_for(5ms);  // a few steps of the active, and the standby asleep on its lock
    const pid_t active = page.active_pid.load(std::memory_order_acquire);
    const std::int64_t killed = runtime::steadyNs();
    ::kill(active, SIGKILL);
    if (!pollUntil([&] { return page.active_pid.load(std::memory_order_acquire) != active; }, kTrialBound)) {
      cell.error = run.failure(fmt::format("kill {}: no process ran the component within 3 s", i));
      break;
    }
    const std::int64_t first = page.first_ns.load(std::memory_order_relaxed);
    // What keel did: the record is written before the new process's first step.
    pollUntil([&] { return run.hostPhases("took_over") + run.hostPhases("respawned") > took_over + respawned; }, 1s);
    const bool was_takeover = run.hostPhases("took_over") > took_over;
    took_over = run.hostPhases("took_over");
    respawned = run.hostPhases("respawned");
    if (i == 0) continue;
    if (was_takeover != standby) {
      ++cell.unexpected;
      continue;
    }
    cell.latencies_ns.push_back(first - killed);
    if (between && i % chunk == 0) between(chunk, cell.host_threads);
  }
  run.stop();
  run.hostPhases("");  // the last records
  const auto& handled = run.recoveredNs();
  if (handled.size() > 1) cell.detected_to_step_ns.assign(handled.begin() + 1, handled.end());  // not the warm-up's
  if (cell.unexpected)
    cell.warnings = fmt::format("{} kills {} instead", cell.unexpected, standby ? "respawned" : "taken over");
  return cell;
}

IsolationCell measurePort(const Paths& paths, bool crossing, bool fifo, int n) {
  IsolationCell cell;
  BenchRun run(paths);
  const std::string port =
      R"(<data_port><name>{}</name><usage>{}</usage><data_type>keel_bench::Stamp</data_type></data_port>)";
  const std::vector<std::pair<std::string, std::string>> files{
      {"BenchStampSource.xml",
       componentXml("BenchStampSource", "<type>periodic</type><period>1</period>" + schedXml(fifo),
                    fmt::format(fmt::runtime(port), "out", "output"), run.pagePath())},
      {"BenchStampSink.xml", componentXml("BenchStampSink", "<type>aperiodic</type>" + schedXml(fifo),
                                          fmt::format(fmt::runtime(port), "in", "input"), run.pagePath())},
      {"port.xml", fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?>
<package_profile>
  <name>bench_port</name>
  <subcomponents>
    <subcomponent><name>source</name><reference>BenchStampSource.xml</reference>{}</subcomponent>
    <subcomponent><name>sink</name><reference>BenchStampSink.xml</reference></subcomponent>
  </subcomponents>
  <port_connections>
    <port_connection port_type="data"><source component_name="source" port_name="out"/><target component_name="sink" port_name="in"/></port_connection>
  </port_connections>
</package_profile>
)",
                               crossing ? R"(<process name="source"/>)" : "")}};
  if (cell.error = run.start(files, "port.xml"); !cell.error.empty()) return cell;
  BenchPage& page = run.page();
  constexpr std::uint64_t kWarmUp = 100;
  if (!pollUntil([&] { return page.received.load() >= kWarmUp; }, kStartBound)) {
    cell.error = run.failure("no sample arrived within 20 s");
    return cell;
  }
  const std::uint64_t from = page.received.load();
  const auto want = std::min<std::uint64_t>(from + static_cast<std::uint64_t>(n), BenchPage::kMaxSamples);
  if (!pollUntil([&] { return page.received.load() >= want; }, std::chrono::milliseconds(3 * n) + 10s))
    cell.error = run.failure(fmt::format("{} of {} samples arrived", page.received.load() - from, want - from));
  run.stop();
  const std::uint64_t got = std::min<std::uint64_t>(page.received.load(), BenchPage::kMaxSamples);
  for (std::uint64_t k = from; k < std::min(got, want); ++k) cell.latencies_ns.push_back(page.latency_ns[k].load());
  return cell;
}

namespace {

struct ProcessUsage {
  long ticks = 0, switches = 0;
};

/// utime + stime and context switches of every thread of `pid`.
ProcessUsage usageOf(pid_t pid) {
  ProcessUsage u;
  std::error_code ec;
  for (const auto& t : std::filesystem::directory_iterator(fmt::format("/proc/{}/task", pid), ec)) {
    std::ifstream stat(t.path() / "stat");
    std::string s((std::istreambuf_iterator<char>(stat)), {});
    const auto close = s.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream fields(s.substr(close + 2));
    std::vector<std::string> f{std::istream_iterator<std::string>(fields), {}};
    if (f.size() > 12) u.ticks += std::stol(f[11]) + std::stol(f[12]);  // fields 14, 15 of stat
    std::ifstream status(t.path() / "status");
    for (std::string line; std::getline(status, line);)
      if (line.starts_with("voluntary_ctxt_switches:") || line.starts_with("nonvoluntary_ctxt_switches:"))
        u.switches += std::stol(line.substr(line.find(':') + 1));
  }
  return u;
}

/// A line's value in /proc/PID/smaps_rollup ("Rss:", "Pss:"), kB.
long rollup(pid_t pid, const std::string& key) {
  std::ifstream in(fmt::format("/proc/{}/smaps_rollup", pid));
  for (std::string line; std::getline(in, line);)
    if (line.starts_with(key)) return std::stol(line.substr(key.size()));
  return -1;
}

}  // namespace

StandbyCost measureStandbyCost(const Paths& paths, double seconds) {
  StandbyCost c;
  c.tick_hz = static_cast<int>(::sysconf(_SC_CLK_TCK));
  BenchRun run(paths);
  if (c.error = run.start(beatFiles(run.pagePath(), true, false), "takeover.xml"); !c.error.empty()) return c;
  if (c.error = awaitStart(run, true); !c.error.empty()) return c;
  std::this_thread::sleep_for(500ms);  // both settled
  BenchPage& page = run.page();
  const pid_t active = page.active_pid.load();
  pid_t standby = 0;
  for (std::uint32_t k = 0; k < page.initialised.load(); ++k)
    if (const pid_t p = page.pids[k].load(); p != active && ::kill(p, 0) == 0) standby = p;
  if (standby == 0) {
    c.error = "no standby process found";
    return c;
  }
  const ProcessUsage a0 = usageOf(active), s0 = usageOf(standby);
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const ProcessUsage a1 = usageOf(active), s1 = usageOf(standby);
  c.seconds = seconds;
  c.active_cpu_ticks = a1.ticks - a0.ticks;
  c.standby_cpu_ticks = s1.ticks - s0.ticks;
  c.active_switches = a1.switches - a0.switches;
  c.standby_switches = s1.switches - s0.switches;
  c.active_rss_kb = rollup(active, "Rss:");
  c.standby_rss_kb = rollup(standby, "Rss:");
  c.active_pss_kb = rollup(active, "Pss:");
  c.standby_pss_kb = rollup(standby, "Pss:");
  c.active_anon_kb = rollup(active, "Anonymous:");
  c.standby_anon_kb = rollup(standby, "Anonymous:");
  run.stop();
  return c;
}

}  // namespace keel::bench
