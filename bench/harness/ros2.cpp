// keel bench ros2's cells (ros2.hpp).
#include "ros2.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

#include "bench_run.hpp"
#include "engine_setup.hpp"
#include "process.hpp"
#include "report.hpp"
#include "runtime/clock.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr auto kUpBound = 30s;       // a node's start → its first message
constexpr auto kTrialBound = 5s;     // a kill → its detection
constexpr auto kPublishing = 200ms;  // a node's first message → its kill
constexpr char kNamespace[] = "/keel_bench";
// How often the harness looks at a file (the node's output, keel's log) for what it waits for.
// Every time it reads there was taken by the process that wrote it, so looking often buys no
// precision, and at 80 % load the CPU a looking harness takes is the restarting node's.
constexpr auto kLook = 5ms;

std::string script(const Paths& paths) { return paths.peers + "/ros2_bench_node.py"; }

/// The node profile of ros2_bench_node.py as node `name`, publishing every `period_ms`.
std::string nodeProfile(const Paths& paths, const std::string& python, const std::string& name, int period_ms) {
  return fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?>
<ros2_node_profile>
  <name>BenchNode</name>
  <command>{} -u {}</command>
  <node>{}/{}</node>
  <parameters><parameter name="period_ms">{}</parameter></parameters>
  <start timeout="30000"/>
  <ports><data_port><name>beat</name><usage>output</usage><data_type>std_msgs/msg/Header</data_type>
    <topic>{}/beat</topic></data_port></ports>
</ros2_node_profile>
)",
                     python, script(paths), kNamespace, name, period_ms, kNamespace);
}

/// The lifecycle form of nodeProfile: ros2_bench_node.py --lifecycle, <lifecycle/>.
std::string managedProfile(const Paths& paths, const std::string& python, const std::string& name, int period_ms) {
  std::string text = nodeProfile(paths, python, name, period_ms);
  const std::string command = fmt::format("<command>{} -u {}</command>", python, script(paths));
  text.replace(text.find(command), command.size(),
               fmt::format("<command>{} -u {} --lifecycle</command><lifecycle/>", python, script(paths)));
  return text;
}

/// One lifecycle node `bench` (node_0.xml) with `standby` standbys, reset on a fault, as often
/// as the benchmark kills it.
std::string managedPackage(int standby) {
  return fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?>
<package_profile><name>bench_ros2</name><subcomponents><subcomponent><name>bench</name>
<reference>node_0.xml</reference>{}<fault_policy><severity>reset</severity>
<restart intensity="1000" period="1000"/></fault_policy></subcomponent></subcomponents></package_profile>
)",
                     standby > 0 ? fmt::format(R"(<process name="bench" standby="{}"/>)", standby) : "");
}

/// A package of `count` nodes (`node_K.xml`, subcomponents `node_K`; one: `bench`), each reset
/// (a restart) on a fault, as often as the benchmark kills it.
std::string nodesPackage(int count) {
  std::string subs;
  for (int k = 0; k < count; ++k)
    subs += fmt::format(
        "<subcomponent><name>{}</name><reference>node_{}.xml</reference><fault_policy><severity>reset</severity>"
        "<restart intensity=\"1000\" period=\"1000\"/></fault_policy></subcomponent>",
        count == 1 ? std::string("bench") : fmt::format("node_{}", k), k);
  return fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?>
<package_profile><name>bench_ros2</name><subcomponents>{}</subcomponents></package_profile>
)",
                     subs);
}

/// `first <ns> <pid>`: the node's first message, and its process.
std::optional<std::pair<std::int64_t, pid_t>> parseFirst(std::string_view line) {
  if (!line.starts_with("first ")) return std::nullopt;
  std::istringstream in{std::string(line.substr(6))};
  std::int64_t ns = 0;
  pid_t pid = 0;
  if (!(in >> ns >> pid)) return std::nullopt;
  return std::make_pair(ns, pid);
}

/// The lines a text file gains, read as it is written (whole lines only).
/// The lines written so far to the files of `dir` whose names start with `prefix` and end in
/// ".out" — a node's output, one file per process name keel gave it (a standby's is its own) —
/// each line once, as the files grow.
class FileLines {
 public:
  FileLines(std::string dir, std::string prefix) : dir_(std::move(dir)), prefix_(std::move(prefix)) {}
  std::vector<std::string> next() {
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir_, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind(prefix_, 0) != 0 || name.size() < 4 || name.compare(name.size() - 4, 4, ".out") != 0) continue;
      std::ifstream in(entry.path(), std::ios::binary);
      if (!in) continue;
      std::size_t& read = read_[name];
      in.seekg(static_cast<std::streamoff>(read));
      std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      std::size_t start = 0;
      for (std::size_t end = text.find('\n'); end != std::string::npos; end = text.find('\n', start)) {
        out.push_back(text.substr(start, end - start));
        start = end + 1;
      }
      read += start;
    }
    return out;
  }

 private:
  std::string dir_;
  std::string prefix_;
  std::map<std::string, std::size_t> read_;  // bytes taken, by file
};

/// A node's CPU time so far (its /proc stat's utime + stime), in clock ticks; 0 once it is gone.
long long cpuTicks(pid_t pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto close = text.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream rest(text.substr(close + 2));
  std::string field;
  long long utime = 0, stime = 0;
  for (int i = 3; i <= 15 && rest >> field; ++i) {  // fields 14 and 15 (1-based): utime, stime
    if (i == 14) std::from_chars(field.data(), field.data() + field.size(), utime);
    if (i == 15) std::from_chars(field.data(), field.data() + field.size(), stime);
  }
  return utime + stime;
}

std::int64_t selfCpuNs() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  auto ns = [](const timeval& t) { return std::int64_t{t.tv_sec} * 1'000'000'000 + std::int64_t{t.tv_usec} * 1000; };
  return ns(u.ru_utime) + ns(u.ru_stime);
}

/// The engine over the profiles of `files` (name → text) written in `dir`, `root` the package.
std::unique_ptr<engine::Engine> engineOver(const TempDir& dir,
                                           const std::vector<std::pair<std::string, std::string>>& files,
                                           const std::string& root, const Paths& paths, const std::string& log,
                                           std::string& note, std::string& error) {
  for (const auto& [name, text] : files) std::ofstream(dir.path() + "/" + name) << text;
  auto set = loadProfiles(dir.path() + "/" + root, error);
  if (!set) return nullptr;
  auto engine = createEngine(
      std::move(*set), paths, log, [&note](const std::string& w) { addNote(note, w); }, error);
  if (!engine || !startEngine(*engine, error)) return nullptr;
  return engine;
}

/// The node's next first message whose process is not `gone`, from `lines`, within kUpBound.
std::optional<std::pair<std::int64_t, pid_t>> nextLife(FileLines& lines, pid_t gone) {
  std::optional<std::pair<std::int64_t, pid_t>> first;
  pollUntil(
      [&] {
        for (const auto& l : lines.next())
          if (auto f = parseFirst(l); f && f->second != gone) first = f;
        return first.has_value();
      },
      kUpBound, kLook);
  return first;
}

/// The node started by the harness (`extra`: more of its --ros-args), its output on a pipe.
struct OwnNode {
  std::optional<Process> process;
  Pipe out;
  std::optional<LineReader> lines;

  std::string start(const Paths& paths, const std::string& python, const std::vector<std::string>& extra) {
    if (!out.open()) return "pipe";
    std::vector<std::string> argv{python,        "-u",
                                  script(paths), "--ros-args",
                                  "-r",          "__node:=own_node",
                                  "-r",          std::string("__ns:=") + kNamespace};
    argv.insert(argv.end(), extra.begin(), extra.end());
    auto p = Process::spawn(argv, {.out = out.write.get(), .err = out.write.get()}, false, true);
    out.write.reset();
    if (!p) return "the node: " + p.error().message;
    process.emplace(std::move(*p));
    lines.emplace(out.read.get());
    return {};
  }
  /// Its first message's time; nullopt when none came within kUpBound.
  std::optional<std::int64_t> first() {
    const auto deadline = Clock::now() + kUpBound;
    while (auto line = lines->next(deadline))
      if (auto f = parseFirst(*line)) return f->first;
    return std::nullopt;
  }
};

/// keel's engine reading the node's topic (a <subscribe> of BenchDdsSink; `deadline_ms` > 0: with
/// that deadline), the fault log `log` in `dir`.
std::unique_ptr<engine::Engine> readerEngine(const TempDir& dir, const SharedPage& page, int deadline_ms,
                                             const Paths& paths, const std::string& log, std::string& note,
                                             std::string& error) {
  auto files = componentFiles(page.path());
  files.emplace_back("app.xml",
                     packageXml("bench_reader", subcomponent("sink", "BenchDdsSink"),
                                binding("subscribe", "sink", "in", std::string(kNamespace) + "/beat",
                                        deadline_ms > 0 ? fmt::format(R"( deadline="{}")", deadline_ms) : "")));
  return engineOver(dir, files, "app.xml", paths, log, note, error);
}

}  // namespace

Ros2Kills measureSupervised(const Paths& paths, const std::string& python, int n) {
  Ros2Kills out;
  std::string& error = out.death.error;
  TempDir dir("keel-bench-ros2-");
  const std::string log = dir.path() + "/fault.jsonl";
  auto engine = engineOver(dir,
                           {{"node_0.xml", nodeProfile(paths, python, "supervised", 10)}, {"app.xml", nodesPackage(1)}},
                           "app.xml", paths, log, out.death.note, error);
  if (!engine) return out;
  const std::int64_t epoch = engine->log().epoch();
  LogTail tail(log);
  FileLines lines(dir.path(), "fault.bench.");  // the node's output, as keel keeps it
  pid_t gone = 0;
  std::int64_t killed = 0;
  for (int i = 0; i <= n; ++i) {  // kill 0 warms up, uncounted
    const auto life = nextLife(lines, gone);
    if (!life) {
      error = fmt::format("kill {}: the node sent nothing within {} s of its (re)start", i, kUpBound.count());
      break;
    }
    if (i > 1) out.back.latencies_ns.push_back(life->first - killed);
    std::this_thread::sleep_for(kPublishing);
    (void)tail.newRecords();
    killed = runtime::steadyNs();
    ::kill(life->second, SIGKILL);
    gone = life->second;
    std::optional<std::int64_t> detected;
    const bool seen = pollUntil(
        [&] {
          for (const auto& r : tail.newRecords())
            if (r.value("event", "") == "detected" && r.value("kind", "") == "process")
              detected = r.value("t_ns", std::int64_t{0}) + epoch - killed;
          return detected.has_value();
        },
        kTrialBound, kLook);
    if (!seen) ++out.death.failed;
    else if (i > 0) out.death.latencies_ns.push_back(*detected);
  }
  if (error.empty() && n > 0) {
    if (const auto life = nextLife(lines, gone)) out.back.latencies_ns.push_back(life->first - killed);
    else ++out.back.failed;
  }
  engine->shutdown();
  out.back.note = "kill → the restarted node's first message (its own clock: CLOCK_MONOTONIC)";
  return out;
}

Ros2Kills measureRespawnLoop(const Paths& paths, const std::string& python, int n) {
  Ros2Kills out;
  std::string& error = out.death.error;
  // The rest of the system as in the keel cell: keel's engine reading the node's topic, so that
  // the node starts among the same DDS participants, only not supervised.
  SharedPage page;
  if (error = page.create(); !error.empty()) return out;
  TempDir dir("keel-bench-ros2-respawn-");
  auto engine = readerEngine(dir, page, 0, paths, dir.path() + "/fault.jsonl", out.back.note, error);
  if (!engine) return out;
  auto node = std::make_unique<OwnNode>();
  if (error = node->start(paths, python, {}); !error.empty()) return out;
  std::optional<std::int64_t> first = node->first();
  for (int i = 0; i <= n && error.empty(); ++i) {  // kill 0 warms up, uncounted
    if (!first) {
      error = fmt::format("kill {}: the node sent nothing within {} s of its start", i, kUpBound.count());
      break;
    }
    std::this_thread::sleep_for(kPublishing);
    const std::int64_t killed = runtime::steadyNs();
    node->process->signal(SIGKILL);
    if (!node->process->waitUntil(Clock::now() + kTrialBound)) {
      ++out.death.failed;
      break;
    }
    const std::int64_t ended = runtime::steadyNs();
    if (i > 0) out.death.latencies_ns.push_back(ended - killed);
    node = std::make_unique<OwnNode>();
    if (error = node->start(paths, python, {}); !error.empty()) break;
    first = node->first();
    if (first && i > 0) out.back.latencies_ns.push_back(*first - killed);
  }
  node.reset();
  engine->shutdown();
  out.death.note = "kill → the node's pidfd readable (the harness its parent)";
  addNote(out.back.note, "the harness waits for the exit and starts the node again, keel's engine reading its topic");
  return out;
}

DdsCell measureDeadlineOnly(const Paths& paths, const std::string& python, int n) {
  DdsCell cell;
  SharedPage page;
  if (cell.error = page.create(); !cell.error.empty()) return cell;
  TempDir dir("keel-bench-ros2-deadline-");
  const std::string log = dir.path() + "/fault.jsonl";
  auto engine = readerEngine(dir, page, kNodeDeadlineMs, paths, log, cell.note, cell.error);
  if (!engine) return cell;
  const std::int64_t epoch = engine->log().epoch();
  LogTail tail(log);
  std::size_t detected = 0, recovered = 0;
  std::optional<std::int64_t> latency;
  std::int64_t killed = 0;
  auto scan = [&] {
    for (const auto& r : tail.newRecords()) {
      const std::string event = r.value("event", "");
      if (event == "detected" && r.value("kind", "") == "remote") {
        ++detected;
        latency = r.value("t_ns", std::int64_t{0}) + epoch - killed;
      }
      if (event == "recovered") ++recovered;
    }
  };
  for (int i = 0; i <= n; ++i) {  // kill 0 warms up, uncounted
    OwnNode node;                 // offering the deadline keel's reader asks for
    if (cell.error = node.start(paths, python, {"-p", fmt::format("deadline_ms:={}", kNodeDeadlineMs)});
        !cell.error.empty())
      break;
    if (!node.first()) {
      cell.error = fmt::format("kill {}: the node sent nothing within {} s of its start", i, kUpBound.count());
      break;
    }
    // The last outage over (its `recovered`: the new node's first sample), the node heard a while.
    if (!pollUntil(
            [&] {
              scan();
              return recovered >= detected;
            },
            kTrialBound, kLook)) {
      cell.error = fmt::format("kill {}: the node's return was not a recovery", i);
      break;
    }
    std::this_thread::sleep_for(kPublishing);
    const std::size_t before = detected;
    latency.reset();
    killed = runtime::steadyNs();
    node.process->signal(SIGKILL);
    if (!pollUntil(
            [&] {
              scan();
              return detected > before;
            },
            kTrialBound + std::chrono::milliseconds(kNodeDeadlineMs), kLook)) {
      ++cell.failed;
      continue;
    }
    if (i > 0 && latency) cell.latencies_ns.push_back(*latency);
  }
  engine->shutdown();
  cell.note = fmt::format("a <subscribe deadline=\"{}\"> on the node's topic, the node not supervised",
                          kNodeDeadlineMs);
  return cell;
}

Ros2Kills measureManaged(const Paths& paths, const std::string& python, int n, int standby) {
  Ros2Kills out;
  std::string& error = out.back.error;
  TempDir dir("keel-bench-ros2-managed-");
  const std::string log = dir.path() + "/fault.jsonl";
  auto engine = engineOver(dir,
                           {{"node_0.xml", managedProfile(paths, python, "managed", 10)},
                            {"app.xml", managedPackage(standby)}},
                           "app.xml", paths, log, out.back.note, error);
  if (!engine) return out;
  LogTail tail(log);
  FileLines lines(dir.path(), "fault.bench.");  // the node's processes', a file per name
  std::set<pid_t> ready;                        // standbys configured, by pid
  auto standbyReady = [&](pid_t serving) {
    for (const auto& r : tail.newRecords())
      if (r.value("event", "") == "node" && r.value("phase", "") == "standby_ready") ready.insert(r.value("pid", 0));
    return std::any_of(ready.begin(), ready.end(), [&](pid_t p) { return p != serving && ::kill(p, 0) == 0; });
  };
  pid_t gone = 0;
  std::int64_t killed = 0;
  for (int i = 0; i <= n; ++i) {  // kill 0 warms up, uncounted
    const auto life = nextLife(lines, gone);
    if (!life) {
      error = fmt::format("kill {}: the node sent nothing within {} s", i, kUpBound.count());
      break;
    }
    if (i > 1) out.back.latencies_ns.push_back(life->first - killed);
    if (standby > 0 && !pollUntil([&] { return standbyReady(life->second); }, kUpBound, kLook)) {
      error = fmt::format("kill {}: no standby ready within {} s", i, kUpBound.count());
      break;
    }
    std::this_thread::sleep_for(kPublishing);
    killed = runtime::steadyNs();
    ::kill(life->second, SIGKILL);
    gone = life->second;
  }
  if (error.empty() && n > 0) {
    if (const auto life = nextLife(lines, gone)) out.back.latencies_ns.push_back(life->first - killed);
    else ++out.back.failed;
  }
  engine->shutdown();
  out.back.note = standby > 0 ? "kill -9 of the active → the standby's first message"
                              : "kill -9 → the restarted node's first message (start, configure, activate)";
  return out;
}

namespace {

/// A process's resident memory (/proc/<pid>/status VmRSS), MiB; 0 once it is gone.
double rssMib(pid_t pid) {
  std::ifstream in(fmt::format("/proc/{}/status", pid));
  for (std::string line; std::getline(in, line);)
    if (line.starts_with("VmRSS:")) {
      std::istringstream fields(line.substr(6));
      double kib = 0;
      fields >> kib;
      return kib / 1024;
    }
  return 0;
}

}  // namespace

StandbyCost measureStandbyCost(const Paths& paths, const std::string& python) {
  StandbyCost out;
  TempDir dir("keel-bench-ros2-standby-");
  const std::string log = dir.path() + "/fault.jsonl";
  std::string note;
  auto engine = engineOver(dir,
                           {{"node_0.xml", managedProfile(paths, python, "managed", 10)},
                            {"app.xml", managedPackage(1)}},
                           "app.xml", paths, log, note, out.error);
  if (!engine) return out;
  LogTail tail(log);
  pid_t active = 0, standby = 0;
  if (!pollUntil(
          [&] {
            for (const auto& r : tail.newRecords()) {
              if (r.value("event", "") != "node") continue;
              if (r.value("phase", "") == "activated") active = r.value("pid", 0);
              if (r.value("phase", "") == "standby_ready") standby = r.value("pid", 0);
            }
            return active != 0 && standby != 0;
          },
          60s, kLook)) {
    out.error = "the node active and its standby ready: not within 60 s";
    engine->shutdown();
    return out;
  }
  std::this_thread::sleep_for(2s);  // discovery's first burst over
  const std::int64_t wall0 = runtime::steadyNs();
  const long long active0 = cpuTicks(active), standby0 = cpuTicks(standby);
  std::this_thread::sleep_for(kIdleWindow);
  const auto wall = static_cast<double>(runtime::steadyNs() - wall0);
  const double tick_ns = 1e9 / static_cast<double>(::sysconf(_SC_CLK_TCK));
  out.active_cpu_percent = static_cast<double>(cpuTicks(active) - active0) * tick_ns / wall * 100;
  out.standby_cpu_percent = static_cast<double>(cpuTicks(standby) - standby0) * tick_ns / wall * 100;
  out.active_rss_mib = rssMib(active);
  out.standby_rss_mib = rssMib(standby);
  engine->shutdown();
  return out;
}

IdleCpu measureIdleCpu(const Paths& paths, const std::string& python) {
  IdleCpu out;
  TempDir dir("keel-bench-ros2-idle-");
  std::vector<std::pair<std::string, std::string>> files;
  files.reserve(kIdleNodes + 1);
  for (int k = 0; k < kIdleNodes; ++k)
    files.emplace_back(fmt::format("node_{}.xml", k), nodeProfile(paths, python, fmt::format("idle_{}", k), 1000));
  files.emplace_back("app.xml", nodesPackage(kIdleNodes));
  const std::string log = dir.path() + "/fault.jsonl";
  std::string note;
  auto engine = engineOver(dir, files, "app.xml", paths, log, note, out.error);
  if (!engine) return out;
  LogTail tail(log);
  std::set<pid_t> up;
  if (!pollUntil(
          [&] {
            for (const auto& r : tail.newRecords())
              if (r.value("event", "") == "node" && r.value("phase", "") == "up") up.insert(r.value("pid", 0));
            return up.size() >= static_cast<std::size_t>(kIdleNodes);
          },
          60s, kLook)) {
    out.error = fmt::format("{} of {} nodes up within 60 s", up.size(), kIdleNodes);
    engine->shutdown();
    return out;
  }
  std::this_thread::sleep_for(2s);  // discovery's first burst over
  auto nodesTicks = [&] {
    long long sum = 0;
    for (pid_t p : up) sum += cpuTicks(p);
    return sum;
  };
  const std::int64_t self0 = selfCpuNs(), wall0 = runtime::steadyNs();
  const long long nodes0 = nodesTicks();
  std::this_thread::sleep_for(kIdleWindow);
  const std::int64_t wall = runtime::steadyNs() - wall0;
  const double tick_ns = 1e9 / static_cast<double>(::sysconf(_SC_CLK_TCK));
  out.keel_percent = static_cast<double>(selfCpuNs() - self0) / static_cast<double>(wall) * 100;
  out.nodes_percent = static_cast<double>(nodesTicks() - nodes0) * tick_ns / static_cast<double>(wall) * 100;
  for (const auto& r : tail.newRecords())
    if (r.value("event", "") == "detected") addNote(out.error, "a fault while idle: " + r.value("detail", ""));
  engine->shutdown();
  return out;
}

}  // namespace keel::bench
