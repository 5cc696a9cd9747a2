// keel run PROFILE [--duration S] [--log FILE] [--log-tee FILE] [--inject SCENARIO] [--set I.P=V]...
//          [--console] [--cpu-dma-latency US]:
// runs a package or system profile until the duration ends, SIGINT/SIGTERM, or a component ends
// the run (RunControl::endRun), then stops and destroys everything (exit 0) and prints a
// one-screen summary of faults and their handling, and who ended the run. --set sets a
// component's property for this run (a bad one: exit 2 before anything loads). With --console,
// operator commands are read from stdin: `emergency` (emergency stop), `clear` (clears a
// latched emergency), `status`. --cpu-dma-latency holds the CPUs' wake-up latency at US µs while
// the engine runs (runtime/cpu_latency.hpp; not permitted: a warning, the run goes on).
// --log-tee copies each log line, as soon as the log has it, to a pipe, FIFO or file.
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <thread>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/summary.hpp"
#include "engine/engine.hpp"
#include "injection/scenario.hpp"
#include "log/schema.hpp"
#include "monitor/monitor.hpp"
#include "plan/property_settings.hpp"
#include "profile/loader.hpp"

namespace keel::cli {
namespace {

struct RunOptions {
  std::string profile;
  double duration_s = 0;  // 0: until a signal
  std::string log;
  std::string log_tee;
  std::string inject;
  std::vector<std::string> sets;  // INSTANCE.PROPERTY=VALUE
  bool console = false;
  std::optional<std::int32_t> cpu_dma_latency_us;
  std::string monitor;  // [ADDR:]PORT
  std::string record;   // FILE.mcap
  std::vector<std::string> monitor_origins;
  std::size_t monitor_queue_kib = 4096;
  bool strict = false;  // profile warnings are errors
};

/// Reads operator commands from stdin until EOF or `stop`; each is logged by the engine.
void console(engine::Engine& engine, const std::atomic<bool>& stop) {
  std::string line;
  while (!stop.load(std::memory_order_acquire)) {
    pollfd pfd{STDIN_FILENO, POLLIN, 0};
    if (poll(&pfd, 1, 100) <= 0) continue;
    char buf[256];
    const ssize_t n = read(STDIN_FILENO, buf, sizeof buf);
    if (n <= 0) return;  // EOF: no more commands
    line.append(buf, static_cast<std::size_t>(n));
    for (std::size_t nl; (nl = line.find('\n')) != std::string::npos; line.erase(0, nl + 1)) {
      std::string cmd = line.substr(0, nl);
      while (!cmd.empty() && std::isspace(static_cast<unsigned char>(cmd.back()))) cmd.pop_back();
      if (cmd == "emergency") {
        auto ran = engine.emergencyStop("console");
        fmt::print("keel: emergency stop latched ({} components stopped in neutral)\n", ran.size());
      } else if (cmd == "clear") {
        fmt::print("keel: {}\n", engine.clearEmergency("console") ? "emergency cleared" : "no emergency latched");
      } else if (cmd == "status") {
        fmt::print("keel: emergency {}; {} faults detected\n",
                   engine.faultManager().emergencyLatched() ? "latched" : "not latched",
                   engine.faultManager().detectionCount());
      } else if (!cmd.empty()) {
        fmt::print(stderr, "keel: unknown console command '{}' (emergency, clear, status)\n", cmd);
      }
      std::fflush(stdout);
    }
  }
}

/// Blocks SIGINT/SIGTERM in this thread (and so in every thread created after), so that only
/// waitForEnd receives them.
sigset_t blockStopSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  return set;
}

/// The run's log when there is no --log: a memory file, kept until the summary is read.
struct AnonymousLog {
  int fd = -1;
  AnonymousLog() = default;
  AnonymousLog(const AnonymousLog&) = delete;
  AnonymousLog& operator=(const AnonymousLog&) = delete;
  ~AnonymousLog() {
    if (fd >= 0) ::close(fd);
  }
};

/// Why the wait ended: a signal's number, kEnded (a component ended the run) or 0 (duration).
constexpr int kEnded = -1;

/// A pending SIGINT/SIGTERM, or 0.
int pendingSignal(const sigset_t& set) {
  timespec zero{0, 0};
  const int sig = sigtimedwait(&set, nullptr, &zero);
  return sig > 0 ? sig : 0;
}

/// Waits for the end of the duration (none: 0), a stop signal or a component's endRun. A
/// component's end wakes it at once; signals are looked at every 20 ms.
int waitForEnd(const sigset_t& set, double duration_s, const engine::Engine& engine) {
  using Clock = std::chrono::steady_clock;
  const auto end = duration_s > 0
                       ? Clock::now() +
                             std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(duration_s))
                       : Clock::time_point::max();
  for (;;) {
    if (int sig = pendingSignal(set)) return sig;
    const auto now = Clock::now();
    if (now >= end) return 0;
    if (engine.waitForEnd(std::min(end, now + std::chrono::milliseconds(20)))) return kEnded;
  }
}

/// The `reason` of the log's `stopping` record.
std::string stopReason(int why, const engine::Engine& engine) {
  if (why == kEnded) return "ended by " + engine.runEnd()->component;
  if (why == 0) return "duration";
  const char* name = sigdescr_np(why);
  return name ? name : "signal " + std::to_string(why);
}

/// Prints each line of `errors` as keel run's.
void printErrors(const std::string& errors) {
  std::istringstream lines(errors);
  for (std::string line; std::getline(lines, line);) std::cerr << "keel run: " << line << '\n';
}

/// The --set options, parsed and applied to `plan`; nothing after printing every problem, a
/// line each.
std::optional<std::vector<plan::PropertySetting>> applySettings(const RunOptions& o, plan::Plan& plan) {
  std::vector<plan::PropertySetting> settings;
  std::string errors;
  for (const auto& text : o.sets) {
    auto s = plan::parsePropertySetting(text);
    if (s) settings.push_back(std::move(*s));
    else errors += s.error().message + '\n';
  }
  if (errors.empty()) {
    if (auto r = plan::applyPropertySettings(plan, settings); !r) errors = r.error().message + '\n';
  }
  if (errors.empty()) return settings;
  printErrors(errors);
  return std::nullopt;
}

int runProfile(const RunOptions& o) {
  sigset_t stop_signals = blockStopSignals();
  if (!o.monitor.empty()) {
    if (auto listen = monitor::parseListen(o.monitor); !listen) {
      std::cerr << "keel run: " << listen.error().message << '\n';
      return 2;
    }
  }
  auto set = profile::load(o.profile);
  if (!set) {
    for (const auto& d : set.error()) std::cerr << d.str() << '\n';
    return 2;
  }
  if (o.strict && !set->warnings.empty()) {
    for (const auto& w : set->warnings) std::cerr << w.str() << " (--strict)\n";
    return 2;
  }
  for (const auto& w : set->warnings) std::cerr << w.warningStr() << '\n';
  const profile::Diagnostics warnings = set->warnings;
  auto planned = plan::planProfiles(std::move(*set));  // the run's one plan
  if (!planned) {
    std::cerr << planned.error().message << '\n';
    return 1;
  }
  // The run always has a log: the summary is read from it after shutdown. Without --log it is an
  // anonymous file, which component processes join by its /proc path.
  engine::EngineOptions eo;
  AnonymousLog anonymous_log;
  eo.log_path = o.log;
  eo.log_tee = o.log_tee;
  if (o.log.empty()) {
    anonymous_log.fd = ::memfd_create("keel-run-log", MFD_CLOEXEC);
    if (anonymous_log.fd < 0) {
      std::cerr << "keel run: cannot create the run's log: " << std::generic_category().message(errno) << '\n';
      return 1;
    }
    eo.log_path = fmt::format("/proc/{}/fd/{}", ::getpid(), anonymous_log.fd);
  }
  eo.cpu_dma_latency_us = o.cpu_dma_latency_us;
  auto settings = applySettings(o, planned->plan);
  if (!settings) return 2;
  eo.property_settings = std::move(*settings);
  if (!o.inject.empty()) {
    auto scenario = injection::loadScenario(o.inject);
    if (!scenario) {
      for (const auto& d : scenario.error()) std::cerr << d.str() << '\n';
      return 2;
    }
    eo.scenario = std::move(*scenario);
  }
  // Component processes plan the same run from the same arguments (docs/isolation.md).
  eo.host_launch.args.push_back(std::filesystem::absolute(o.profile).string());
  for (const auto& text : o.sets) eo.host_launch.args.insert(eo.host_launch.args.end(), {"--set", text});
  if (!o.inject.empty())
    eo.host_launch.args.insert(eo.host_launch.args.end(), {"--inject", std::filesystem::absolute(o.inject).string()});
  eo.host_launch.args.insert(eo.host_launch.args.end(), {"--log", std::filesystem::absolute(eo.log_path).string()});
  auto engine = engine::Engine::create(std::move(*planned), eo);
  if (!engine) {
    std::cerr << engine.error().message << '\n';
    return 1;
  }
  for (const auto& w : warnings) (*engine)->log().write(log::schema::warning(w.str()));
  std::unique_ptr<monitor::Monitor> live;
  if (!o.monitor.empty() || !o.record.empty()) {
    monitor::MonitorOptions mo{o.monitor, o.monitor_origins, eo.log_path,
                               o.profile, o.record,          o.monitor_queue_kib * 1024};
    auto started = monitor::Monitor::start(**engine, std::move(mo));
    if (!started) {
      std::cerr << "keel run: " << started.error().message << '\n';
      return 1;
    }
    live = std::move(*started);
    if (!o.monitor.empty()) {
      fmt::print("monitor: {}\n", live->url());
      std::fflush(stdout);
    }
  }
  if (auto r = (*engine)->start(); !r) {
    std::cerr << r.error().message << '\n';
    (*engine)->shutdown();
    return 1;
  }
  std::atomic<bool> stop_console{false};
  std::thread console_thread;
  if (o.console) console_thread = std::thread([&] { console(**engine, stop_console); });
  const int why = waitForEnd(stop_signals, o.duration_s, **engine);
  stop_console.store(true, std::memory_order_release);
  if (console_thread.joinable()) console_thread.join();
  nlohmann::json stopping = log::schema::engine("stopping");
  stopping[log::schema::field::kReason] = stopReason(why, **engine);
  (*engine)->log().write(std::move(stopping));
  (*engine)->shutdown();  // a component may still end the run from its onStop
  if (live) {             // after the last record: clients see the run end, the recording has it all
    if (auto r = live->stop(); !r) std::cerr << "keel run: " << r.error().message << '\n';
  }
  std::ifstream log(eo.log_path);
  printSummary(std::cout, summarize(log));
  return 0;
}

}  // namespace

void addRunCommand(CLI::App& app, std::function<int()>& run) {
  auto opts = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Run a package or system profile");
  cmd->add_option("profile", opts->profile, "package_profile or system_profile XML")->required();
  cmd->add_option("--duration", opts->duration_s, "seconds to run (default: until SIGINT/SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--log", opts->log, "write the fault log (JSON lines) to this file");
  cmd->add_option("--log-tee", opts->log_tee,
                  "also write each log line, right after the log has it, to this pipe, FIFO (never waiting for its "
                  "reader: a line it has no room for is dropped and counted) or file (appended to)");
  cmd->add_option("--inject", opts->inject, "inject the faults of this fault_scenario XML");
  cmd->add_flag("--strict", opts->strict,
                "refuse to run a profile with warnings (what it says and keel does not act on, as keel validate "
                "--strict)");
  cmd->add_option("--set", opts->sets,
                  "INSTANCE.PROPERTY=VALUE: set a component's property for this run, after the profile's "
                  "overrides (repeatable; e.g. --set actuator.seed=7 --set navigation.planner.speed=0.4)")
      ->allow_extra_args(false);
  cmd->add_flag("--console", opts->console,
                "read operator commands from stdin: emergency, clear (a latched emergency), status");
  cmd->add_option("--monitor", opts->monitor,
                  "[ADDR:]PORT: serve the live monitor there (127.0.0.1 unless ADDR; 0: any free port): the web "
                  "page at http://ADDR:PORT/ and the Foxglove WebSocket protocol; prints its address with the "
                  "control token (docs/monitor.md)");
  cmd->add_option("--monitor-queue", opts->monitor_queue_kib,
                  "KIB: what the monitor holds for each client (default 4096); a client that reads slower than "
                  "the run writes loses what is beyond it, counted and told, and never slows the run")
      ->check(CLI::Range(16, 1 << 20));
  cmd->add_option("--record", opts->record,
                  "FILE.mcap: record the monitor's channels (/keel/state, /keel/faults) in MCAP, readable by "
                  "Foxglove and keel report; written at least once a second (a kill -9 loses at most the last)");
  cmd->add_option("--monitor-origin", opts->monitor_origins,
                  "ORIGIN: also let browser pages from ORIGIN connect to the monitor, e.g. "
                  "https://app.foxglove.dev (repeatable; the token still guards the controls)")
      ->allow_extra_args(false);
  cmd->add_option("--cpu-dma-latency", opts->cpu_dma_latency_us,
                  "US: while running, idle CPUs may only enter sleep states that wake within US µs "
                  "(0: they poll and never halt; /dev/cpu_dma_latency, root). On a machine whose idle CPUs "
                  "halt, faults are caught in about half the median time (docs/performance.md)")
      ->check(CLI::Range(0, 2'000'000'000));
  cmd->callback([opts, &run] { run = [opts] { return runProfile(*opts); }; });
}

}  // namespace keel::cli
