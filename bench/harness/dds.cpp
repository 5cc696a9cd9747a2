#include "dds.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <fmt/format.h>

#include <charconv>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string_view>
#include <thread>
#include <utility>

#include "bench_run.hpp"
#include "engine_setup.hpp"
#include "process.hpp"
#include "report.hpp"
#include "runtime/clock.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using keel_bench::BenchPage;

constexpr auto kStartBound = 20s;  // keel runs up and their topics matched
constexpr int kWarmUp = 100;       // round trips dropped first (discovery, first page faults)
constexpr int kPeriodUs = 1000;    // every writer's period: 1 kHz
constexpr auto kTrialBound = 5s;   // a kill → its detection or takeover
constexpr char kHeader[] = "std_msgs/msg/Header";

// Fast DDS (rclpy's rmw) on UDPv4 127.0.0.1 alone, 127.0.0.1 its initial peer; no type
// propagation, as tests/dds/fastdds-lo.xml says why (CycloneDDS 0.10.2 crashes on some of Fast DDS
// 3's type lookup replies: docs/dds.md#what-keel-does-not-do).
constexpr std::string_view kFastDdsConfig = R"(<?xml version="1.0" encoding="UTF-8"?>
<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <transport_descriptors>
    <transport_descriptor><transport_id>udp_lo</transport_id><type>UDPv4</type>
      <interfaceWhiteList><address>127.0.0.1</address></interfaceWhiteList></transport_descriptor>
  </transport_descriptors>
  <participant profile_name="lo_only" is_default_profile="true">
    <rtps>
      <useBuiltinTransports>false</useBuiltinTransports>
      <userTransports><transport_id>udp_lo</transport_id></userTransports>
      <propertiesPolicy><properties>
        <property><name>fastdds.type_propagation</name><value>disabled</value></property>
      </properties></propertiesPolicy>
      <builtin><initialPeersList><locator><udpv4><address>127.0.0.1</address></udpv4></locator></initialPeersList></builtin>
    </rtps>
  </participant>
</profiles>
)";

/// `command pong IN OUT` and `command ping OUT IN N PERIOD_US` (keel-bench-dds-raw, rclpy's
/// script) on the topics `<prefix>ping_<tag>` and `<prefix>pong_<tag>`: the ping's `rtt <ns>`
/// lines until `done`; the reason otherwise.
DdsCell pingPong(const std::vector<std::string>& command, const std::string& prefix, const std::string& tag, int n) {
  const std::string ping_topic = prefix + "ping_" + tag, pong_topic = prefix + "pong_" + tag;
  std::vector<std::string> pong_argv = command, ping_argv = command;
  pong_argv.insert(pong_argv.end(), {"pong", ping_topic, pong_topic});
  ping_argv.insert(ping_argv.end(), {"ping", ping_topic, pong_topic, std::to_string(n), std::to_string(kPeriodUs)});
  DdsCell cell;
  Fd quiet(::open("/dev/null", O_WRONLY | O_CLOEXEC));
  auto pong = Process::spawn(pong_argv, {.out = quiet.get(), .err = quiet.get()}, false, true);
  if (!pong) {
    cell.error = "pong: " + pong.error().message;
    return cell;
  }
  Pipe out;
  if (!out.open()) {
    cell.error = "pipe";
    return cell;
  }
  auto ping = Process::spawn(ping_argv, {.out = out.write.get(), .err = out.write.get()}, false, true);
  out.write.reset();
  if (!ping) {
    cell.error = "ping: " + ping.error().message;
    return cell;
  }
  LineReader lines(out.read.get());
  const auto deadline = Clock::now() + kStartBound + std::chrono::milliseconds(2 * (n + kWarmUp)) + 30s;
  bool done = false;
  std::string last;
  while (auto line = lines.next(deadline)) {
    if (*line == "done") {
      done = true;
      break;
    }
    std::int64_t v = 0;
    if (line->starts_with("rtt ") &&
        std::from_chars(line->data() + 4, line->data() + line->size(), v).ec == std::errc())
      cell.latencies_ns.push_back(v);
    else if (!line->empty()) last = *line;
  }
  ping->waitUntil(Clock::now() + 5s);
  if (!done) cell.error = "ping did not finish" + (last.empty() ? "" : ": " + last);
  if (cell.latencies_ns.size() < static_cast<std::size_t>(n))
    cell.failed = static_cast<std::size_t>(n) - cell.latencies_ns.size();
  return cell;
}

/// Network namespaces and a veth pair between them, removed when this goes.
class TwoHosts {
 public:
  TwoHosts() {
    const int tag = ::getpid() % 100000;
    names_[0] = fmt::format("keel_b1_{}", tag);
    names_[1] = fmt::format("keel_b2_{}", tag);
    const std::string v1 = fmt::format("kb1_{}", tag), v2 = fmt::format("kb2_{}", tag);
    const int net = 16 + tag % 200;
    const std::vector<std::vector<std::string>> steps{{"netns", "add", names_[0]},
                                                      {"netns", "add", names_[1]},
                                                      {"link", "add", v1, "type", "veth", "peer", "name", v2},
                                                      {"link", "set", v1, "netns", names_[0]},
                                                      {"link", "set", v2, "netns", names_[1]},
                                                      {"-n", names_[0], "addr", "add", fmt::format("10.{}.7.1/24", net),
                                                       "dev", v1},
                                                      {"-n", names_[1], "addr", "add", fmt::format("10.{}.7.2/24", net),
                                                       "dev", v2},
                                                      {"-n", names_[0], "link", "set", "lo", "up"},
                                                      {"-n", names_[1], "link", "set", "lo", "up"},
                                                      {"-n", names_[0], "link", "set", v1, "up"},
                                                      {"-n", names_[1], "link", "set", v2, "up"}};
    const std::string ip = findInPath("ip");
    for (const auto& step : steps) {
      std::vector<std::string> argv{ip};
      argv.insert(argv.end(), step.begin(), step.end());
      const Captured ran = runCaptured(argv, false, Clock::now() + 10s);
      if (!ran.error.empty() || ran.status != 0) {
        error_ = fmt::format("ip {}: {}", fmt::join(step, " "),
                             ran.error.empty() ? (ran.lines.empty() ? "failed" : ran.lines.back()) : ran.error);
        return;
      }
      if (step[0] == "netns") ++made_;
    }
  }
  ~TwoHosts() {
    for (int i = 0; i < made_; ++i)
      runCaptured({findInPath("ip"), "netns", "del", names_[i]}, false, Clock::now() + 10s);
  }
  TwoHosts(const TwoHosts&) = delete;
  TwoHosts& operator=(const TwoHosts&) = delete;
  const std::string& error() const { return error_; }
  std::vector<std::string> on(int host) const { return {findInPath("ip"), "netns", "exec", names_[host]}; }

 private:
  std::string names_[2];
  int made_ = 0;
  std::string error_;
};

/// ROS_DOMAIN_ID when it names a domain, else one from the pid.
int domainOf(const char* env) {
  int v = -1;
  if (env != nullptr && *env != '\0' && std::from_chars(env, env + std::string_view(env).size(), v).ec == std::errc() &&
      v >= 0 && v <= 232)
    return v;
  return 1 + ::getpid() % 100;
}

std::string port(const char* name, const char* usage) {
  return fmt::format(
      "<data_port><name>{}</name><usage>{}</usage><data_type>{}</data_type><queue_size>1000</queue_size></data_port>",
      name, usage, kHeader);
}

}  // namespace

std::vector<std::pair<std::string, std::string>> componentFiles(const std::string& page) {
  auto xml = [&](const char* name, const std::string& semantics, const std::string& ports) {
    return benchComponentXml("keel_bench_dds", name, semantics, ports, page,
                             R"(<property name="who" type="int">1</property>)");
  };
  return {{"BenchDdsStamp.xml", xml("BenchDdsStamp", "<type>periodic</type><period>1</period>", port("out", "output"))},
          {"BenchDdsEcho.xml",
           xml("BenchDdsEcho", "<type>aperiodic</type>", port("in", "input") + port("out", "output"))},
          {"BenchDdsSink.xml", xml("BenchDdsSink", "<type>aperiodic</type>", port("in", "input"))}};
}

std::string packageXml(const std::string& name, const std::string& subcomponents, const std::string& bindings) {
  return fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?>
<package_profile>
  <name>{}</name>
  <subcomponents>{}</subcomponents>
  <dds diagnostics="false">{}</dds>
</package_profile>
)",
                     name, subcomponents, bindings);
}

std::string subcomponent(const char* name, const char* type, const std::string& more) {
  return fmt::format("<subcomponent><name>{}</name><reference>{}.xml</reference>{}</subcomponent>", name, type, more);
}

std::string binding(const char* kind, const char* component, const char* port_name, const std::string& topic,
                    const std::string& more) {
  return fmt::format(R"(<{} component="{}" port="{}" topic="{}" type="{}"{}/>)", kind, component, port_name, topic,
                     kHeader, more);
}

std::string rclpyPython() {
  // A path is made absolute: the nodes' profiles, which name it, are in folders of their own.
  if (const char* p = std::getenv("KEEL_RCLPY_PYTHON"); p && *p)
    return std::string_view(p).find('/') == std::string_view::npos ? p : std::filesystem::absolute(p).string();
  const std::string python = findInPath("python3");
  if (python.empty()) return {};
  const Captured ran = runCaptured({python, "-c", "import rclpy"}, false, Clock::now() + 20s);
  return ran.error.empty() && ran.status == 0 ? python : std::string();
}

// The harness's own environment, not only its children's: the remote cell's engine runs in this
// process, and its CycloneDDS reads the same variables. Set on the main thread before the
// benchmark starts any thread (ddsBenchmark makes this first), so that no getenv runs beside a
// setenv.
DdsEnvironment::DdsEnvironment() : dir_("keel-bench-dds-env-"), domain_(domainOf(std::getenv("ROS_DOMAIN_ID"))) {
  const std::string& dir = dir_.path();
  std::ofstream(dir + "/cyclonedds.xml") << kCycloneLoopbackConfig;
  std::ofstream(dir + "/fastdds.xml") << kFastDdsConfig;
  ::setenv("CYCLONEDDS_URI", ("file://" + dir + "/cyclonedds.xml").c_str(), 1);  // NOLINT(concurrency-mt-unsafe): above
  ::setenv("FASTDDS_DEFAULT_PROFILES_FILE", (dir + "/fastdds.xml").c_str(), 1);  // NOLINT(concurrency-mt-unsafe): above
  ::setenv("ROS_DOMAIN_ID", std::to_string(domain_).c_str(), 1);                 // NOLINT(concurrency-mt-unsafe): above
}

DdsCell measureKeelRoundTrip(const Paths& paths, int n) {
  DdsCell cell;
  BenchRun pong(paths, "keel-bench-dds-"), ping(paths, "keel-bench-dds-");
  auto files = componentFiles(ping.pagePath());
  files.emplace_back("pong.xml", packageXml("bench_pong", subcomponent("echo", "BenchDdsEcho"),
                                            binding("subscribe", "echo", "in", "/keel_bench/ping_keel") +
                                                binding("publish", "echo", "out", "/keel_bench/pong_keel")));
  files.emplace_back("ping.xml",
                     packageXml("bench_ping",
                                subcomponent("stamp", "BenchDdsStamp") + subcomponent("sink", "BenchDdsSink"),
                                binding("publish", "stamp", "out", "/keel_bench/ping_keel") +
                                    binding("subscribe", "sink", "in", "/keel_bench/pong_keel")));
  if (cell.error = pong.start(files, "pong.xml"); !cell.error.empty()) return cell;
  if (cell.error = ping.start(files, "ping.xml"); !cell.error.empty()) return cell;
  BenchPage& page = ping.page();
  if (!pollUntil([&] { return page.received.load() >= kWarmUp; }, kStartBound)) {
    cell.error = ping.failure(pong.failure("no round trip within 20 s"));
    return cell;
  }
  const std::uint64_t from = page.received.load();
  const auto want = std::min<std::uint64_t>(from + static_cast<std::uint64_t>(n), BenchPage::kMaxSamples);
  if (!pollUntil([&] { return page.received.load() >= want; }, std::chrono::milliseconds(3 * n) + 10s))
    cell.error = ping.failure(fmt::format("{} of {} round trips", page.received.load() - from, want - from));
  ping.stop();
  pong.stop();
  const std::uint64_t got = std::min<std::uint64_t>(page.received.load(), want);
  for (std::uint64_t k = from; k < got; ++k) cell.latencies_ns.push_back(page.latency_ns[k].load());
  return cell;
}

DdsCell measureRawRoundTrip(const Paths& paths, int n) {
  DdsCell cell = pingPong({paths.bin + "/keel-bench-dds-raw"}, "rt/keel_bench/", "raw", n);
  cell.note = "CycloneDDS's C API, a WaitSet thread on each side";
  return cell;
}

DdsCell measureRclpyRoundTrip(const Paths& paths, int n) {
  DdsCell cell;
  const std::string python = rclpyPython();
  if (python.empty()) {
    cell.error = "no python with rclpy (set KEEL_RCLPY_PYTHON; scripts/peers.sh makes tests/peers/venv)";
    return cell;
  }
  cell = pingPong({python, paths.peers + "/rclpy_pingpong.py"}, "/keel_bench/", "rclpy", n);
  cell.note = "rclpy (Fast DDS), a SingleThreadedExecutor";
  return cell;
}

DdsCell measureRemoteDetection(const Paths& paths, int n) {
  DdsCell cell;
  SharedPage page;
  TempDir dir("keel-bench-dds-remote-");
  if (cell.error = page.create(); !cell.error.empty()) return cell;
  for (const auto& [name, text] : componentFiles(page.path())) std::ofstream(dir.path() + "/" + name) << text;
  std::ofstream(dir.path() + "/remote.xml") << packageXml("bench_remote", subcomponent("sink", "BenchDdsSink"),
                                                          binding("subscribe", "sink", "in", "/keel_bench/beat",
                                                                  fmt::format(R"( deadline="{}")", kRemoteDeadlineMs)));
  auto set = loadProfiles(dir.path() + "/remote.xml", cell.error);
  if (!set) return cell;
  const std::string log = dir.path() + "/fault.jsonl";
  auto engine = createEngine(
      std::move(*set), paths, log, [&](const std::string& w) { addNote(cell.note, w); }, cell.error);
  if (!engine || !startEngine(*engine, cell.error)) return cell;
  const std::int64_t epoch = engine->log().epoch();
  LogTail tail(log);
  const std::string raw = paths.bin + "/keel-bench-dds-raw";
  std::size_t detected = 0, recovered = 0;
  auto scan = [&](std::int64_t killed, std::optional<std::int64_t>& latency) {
    for (const auto& r : tail.newRecords()) {
      const std::string event = r.value("event", "");
      if (event == "detected" && r.value("kind", "") == "remote") {
        ++detected;
        latency = r.value("t_ns", std::int64_t{0}) + epoch - killed;
      }
      if (event == "recovered") ++recovered;
    }
  };
  for (int i = 0; i <= n; ++i) {  // trial 0 warms up, uncounted
    Pipe out;
    if (!out.open()) {
      cell.error = "pipe";
      break;
    }
    auto writer = Process::spawn({raw, "writer", "rt/keel_bench/beat", std::to_string(kPeriodUs),
                                  std::to_string(kRemoteDeadlineMs)},
                                 {.out = out.write.get(), .err = out.write.get()}, false, true);
    out.write.reset();
    if (!writer) {
      cell.error = "keel-bench-dds-raw: " + writer.error().message;
      break;
    }
    LineReader lines(out.read.get());
    const auto said = lines.next(Clock::now() + kStartBound);
    if (!said || *said != "matched") {
      cell.error = fmt::format("trial {}: the writer did not match keel's reader: {}", i, said.value_or("nothing"));
      break;
    }
    std::optional<std::int64_t> latency;
    // The last outage over (its `recovered`), and the writer heard for a while.
    if (!pollUntil(
            [&] {
              scan(0, latency);
              return recovered >= detected;
            },
            kTrialBound)) {
      cell.error = fmt::format("trial {}: the writer's return was not a recovery", i);
      break;
    }
    std::this_thread::sleep_for(100ms);
    const std::size_t before = detected;
    const std::int64_t killed = runtime::steadyNs();
    writer->signal(SIGKILL);
    if (!pollUntil(
            [&] {
              scan(killed, latency);
              return detected > before;
            },
            kTrialBound)) {
      ++cell.failed;
      continue;
    }
    if (i > 0) cell.latencies_ns.push_back(*latency);
  }
  engine->shutdown();
  cell.note = fmt::format("deadline {} ms, the writer killed 100 ms into its samples (every {} ms)", kRemoteDeadlineMs,
                          kPeriodUs / 1000);
  return cell;
}

DdsCell measureFailover(const Paths& paths, int n) {
  DdsCell cell;
  if (::geteuid() != 0 || findInPath("ip").empty()) {
    cell.error = "needs root and ip(8): the two hosts are network namespaces";
    return cell;
  }
  TwoHosts hosts;
  if (!hosts.error().empty()) {
    cell.error = hosts.error();
    return cell;
  }
  // CycloneDDS's default: each host's interface, multicast discovery, as on a robot's network.
  const std::vector<EnvChange> veth{{"CYCLONEDDS_URI", std::nullopt}};
  auto role = [](int who, int strength) {
    return packageXml(fmt::format("bench_nav_{}", who),
                      subcomponent("nav", "BenchDdsStamp",
                                   fmt::format(R"(<properties><property name="who">{}</property></properties>)"
                                               R"(<redundancy group="nav" strength="{}"/>)",
                                               who, strength)),
                      binding("publish", "nav", "out", "/keel_bench/nav",
                              fmt::format(R"( liveliness="{}")", kFailoverLeaseMs)));
  };
  BenchRun reader(paths, "keel-bench-dds-"), standby(paths, "keel-bench-dds-");
  auto files = componentFiles(reader.pagePath());
  files.emplace_back("reader.xml",
                     packageXml("bench_reader", subcomponent("sink", "BenchDdsSink"),
                                binding("subscribe", "sink", "in", "/keel_bench/nav",
                                        fmt::format(R"( ownership="exclusive" liveliness="{}")", kFailoverLeaseMs))));
  files.emplace_back("primary.xml", role(1, 10));
  files.emplace_back("standby.xml", role(2, 5));
  if (cell.error = reader.start(files, "reader.xml", hosts.on(0), veth); !cell.error.empty()) return cell;
  if (cell.error = standby.start(files, "standby.xml", hosts.on(1), veth); !cell.error.empty()) return cell;
  BenchPage& page = reader.page();
  if (!pollUntil([&] { return page.active_pid.load(std::memory_order_acquire) == 2; }, kStartBound)) {
    cell.error = reader.failure(standby.failure("the reader heard no standby within 20 s"));
    return cell;
  }
  for (int i = 0; i <= n; ++i) {  // trial 0 warms up, uncounted
    BenchRun primary(paths, "keel-bench-dds-");
    if (cell.error = primary.start(files, "primary.xml", hosts.on(0), veth); !cell.error.empty()) break;
    if (!pollUntil([&] { return page.active_pid.load(std::memory_order_acquire) == 1; }, kStartBound)) {
      cell.error = primary.failure(fmt::format("trial {}: the reader did not hear the primary within 20 s", i));
      break;
    }
    std::this_thread::sleep_for(300ms);  // the primary heard for a while, the standby writing all along
    const std::int64_t killed = runtime::steadyNs();
    primary.signal(SIGKILL);
    if (!pollUntil([&] { return page.active_pid.load(std::memory_order_acquire) == 2; }, kTrialBound)) {
      ++cell.failed;
      continue;
    }
    if (i > 0) cell.latencies_ns.push_back(page.first_ns.load(std::memory_order_relaxed) - killed);
  }
  reader.stop();
  standby.stop();
  cell.note = fmt::format("lease {} ms, writes every {} ms; the primary on the reader's host, the standby on the other",
                          kFailoverLeaseMs, kPeriodUs / 1000);
  return cell;
}

}  // namespace keel::bench
