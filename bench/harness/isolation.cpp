#include "isolation.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <sstream>
#include <thread>
#include <utility>

#include "isolation_page.hpp"
#include "process.hpp"
#include "runtime/clock.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using keel_bench::IsolationPage;

constexpr auto kStartBound = 20s;  // keel run up, its processes started and running
constexpr auto kTrialBound = 3s;   // a kill → the new process's first step

std::string schedXml(bool fifo) {
  return fifo ? fmt::format("<priority>{}</priority><policy>fifo</policy>", kFifoPriority) : "";
}

/// One component profile of the benchmark's library.
std::string componentXml(const std::string& name, const std::string& semantics, const std::string& ports,
                         const std::string& page) {
  return fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?>
<component_profile>
  <name>{}</name>
  <execution_environment><library_name>keel_bench_isolation</library_name></execution_environment>
  <execution_semantics>{}</execution_semantics>
  <properties><property name="page" type="string">{}</property></properties>
  <ports>{}</ports>
</component_profile>
)",
                     name, semantics, page, ports);
}

/// A `keel run` of profiles written for it, its page and its fault log, as a user runs it.
class BenchRun {
 public:
  explicit BenchRun(const Paths& paths)
      : paths_(paths), dir_("keel-bench-isolation-"),
        page_path_(fmt::format("/dev/shm/keel-bench-isolation.{}.{}", ::getpid(), counter_++)) {}
  ~BenchRun() {
    proc_.reset();  // killed and reaped if still there: its hosts follow (no orphans)
    if (page_) ::munmap(page_, sizeof(IsolationPage));
    ::unlink(page_path_.c_str());
  }
  BenchRun(const BenchRun&) = delete;
  BenchRun& operator=(const BenchRun&) = delete;

  const std::string& pagePath() const { return page_path_; }
  IsolationPage& page() { return *page_; }

  /// Writes `files` (name → text) beside each other, maps a fresh page and starts keel run on
  /// `package`; empty, or why not.
  std::string start(const std::vector<std::pair<std::string, std::string>>& files, const std::string& package) {
    if (dir_.path().empty()) return "mkdtemp failed";
    const int fd = ::open(page_path_.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0 || ::ftruncate(fd, sizeof(IsolationPage)) != 0) return "cannot create " + page_path_;
    void* p = ::mmap(nullptr, sizeof(IsolationPage), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    ::close(fd);
    if (p == MAP_FAILED) return "cannot map " + page_path_;
    page_ = new (p) IsolationPage;
    for (const auto& [name, text] : files) std::ofstream(dir_.path() + "/" + name) << text;
    log_path_ = dir_.path() + "/fault.jsonl";
    out_path_ = dir_.path() + "/keel-run.out";
    const int out = ::open(out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    ::setenv("KEEL_COMPONENT_PATH", paths_.components.c_str(), 1);
    auto spawned = Process::spawn({paths_.bin + "/keel", "run", dir_.path() + "/" + package, "--duration", "86400",
                                   "--log", log_path_},
                                  {.out = out, .err = out}, false, true);
    ::close(out);
    if (!spawned) return "keel run: " + spawned.error().message;
    proc_.emplace(std::move(*spawned));
    return {};
  }

  /// Why keel run is not running as it should: its last lines.
  std::string failure(const std::string& what) const {
    std::ifstream in(out_path_);
    std::string line, last;
    while (std::getline(in, line))
      if (!line.empty()) last = line;
    return what + (last.empty() ? "" : ": keel run said: " + last);
  }

  /// The fault log's records written since the last call (whole lines only).
  std::vector<nlohmann::json> newRecords() {
    std::vector<nlohmann::json> out;
    std::ifstream in(log_path_);
    if (!in) return out;
    in.seekg(static_cast<std::streamoff>(log_read_));
    std::string line;
    while (std::getline(in, line) && !in.eof()) {
      log_read_ += line.size() + 1;
      auto r = nlohmann::json::parse(line, nullptr, false);
      if (!r.is_discarded()) out.push_back(std::move(r));
    }
    return out;
  }

  /// Host records of `phase` seen so far (every call reads the new part of the log).
  std::size_t hostPhases(const std::string& phase) {
    for (auto& r : newRecords()) {
      const std::string event = r.value("event", "");
      if (event == "host") ++phases_[r.value("phase", "")];
      if (event == "recovered") recovered_ns_.push_back(static_cast<std::int64_t>(r.value("latency_us", 0.0) * 1000));
    }
    return phases_[phase];
  }
  /// Each `recovered` record's recovered − detected so far: for a process fault, from the first to
  /// see the death (the standby waking, or keel run) to the first good step.
  const std::vector<std::int64_t>& recoveredNs() const { return recovered_ns_; }

  /// SIGTERM, as an operator stops it: keel run stops its processes and ends.
  void stop() {
    if (!proc_) return;
    proc_->signal(SIGTERM);
    proc_->waitUntil(Clock::now() + 10s);
    proc_.reset();
  }

 private:
  static inline int counter_ = 0;
  const Paths& paths_;
  TempDir dir_;
  std::string page_path_, log_path_, out_path_;
  IsolationPage* page_ = nullptr;
  std::optional<Process> proc_;
  std::size_t log_read_ = 0;
  std::map<std::string, std::size_t> phases_;
  std::vector<std::int64_t> recovered_ns_;
};

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
  IsolationPage& page = run.page();
  cell.host_threads = threadsOf(page.active_pid.load());
  const int chunk = std::max(1, n / 10);
  std::size_t took_over = 0, respawned = 0;
  for (int i = 0; i <= n; ++i) {  // kill 0 warms up, uncounted
    // The standby the last takeover started is waiting (or, without one, the process runs).
    if (standby &&
        !pollUntil([&] { return run.hostPhases("standby") >= static_cast<std::size_t>(i + 1); }, kTrialBound)) {
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
  IsolationPage& page = run.page();
  constexpr std::uint64_t kWarmUp = 100;
  if (!pollUntil([&] { return page.received.load() >= kWarmUp; }, kStartBound)) {
    cell.error = run.failure("no sample arrived within 20 s");
    return cell;
  }
  const std::uint64_t from = page.received.load();
  const auto want = std::min<std::uint64_t>(from + static_cast<std::uint64_t>(n), IsolationPage::kMaxSamples);
  if (!pollUntil([&] { return page.received.load() >= want; }, std::chrono::milliseconds(3 * n) + 10s))
    cell.error = run.failure(fmt::format("{} of {} samples arrived", page.received.load() - from, want - from));
  run.stop();
  const std::uint64_t got = std::min<std::uint64_t>(page.received.load(), IsolationPage::kMaxSamples);
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
  IsolationPage& page = run.page();
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
