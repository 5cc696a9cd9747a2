#include "recovery.hpp"

#include <dlfcn.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "engine_setup.hpp"
#include "monitor/monitor.hpp"
#include "monitor_client.hpp"
#include "process.hpp"
#include "report.hpp"
#include "runtime/injection.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;

/// What one measurement needs to know, fixed for the cell.
struct Setup {
  const Paths& paths;
  std::string log_path;
  std::string error;     // why the cell could not run
  std::string warnings;  // the engine's warnings (a policy it could not set, ...)
};

/// From the log of one engine (one replacement): the `replace` action's time − detected.
std::optional<std::int64_t> inPlaceNs(const std::string& log_path) {
  std::ifstream in(log_path);
  std::optional<std::int64_t> detected, replaced;
  for (std::string line; std::getline(in, line);) {
    auto r = nlohmann::json::parse(line, nullptr, false);
    if (r.is_discarded() || !r.contains("t_ns")) continue;
    if (r["event"] == "detected") detected = r["t_ns"].get<std::int64_t>();
    if (r["event"] == "action" && r["action"] == "replace" && r["outcome"] == "ok")
      replaced = r["t_ns"].get<std::int64_t>();
  }
  if (!detected || !replaced) return std::nullopt;
  return *replaced - *detected;
}

/// The mechanism's package with every task under the cell's policy.
std::optional<profile::ProfileSet> loadPackage(Setup& setup, const std::string& name, bool fifo) {
  auto set = loadProfiles(setup.paths.profiles + "/" + name + ".xml", setup.error);
  if (!set) return std::nullopt;
  for (auto& [path, pkg] : set->packages)
    for (auto& task : pkg.tasks) {
      task.policy = fifo ? SchedPolicy::Fifo : SchedPolicy::Other;
      task.priority = fifo ? kFifoPriority : 0;
    }
  return set;
}

/// An engine under test, and what watches it in the `_monitored` cells: keel run --monitor's
/// monitor with a client connected and subscribed to everything. Stopped in that order.
struct Run {
  std::unique_ptr<engine::Engine> engine;
  std::unique_ptr<monitor::Monitor> monitor;
  std::unique_ptr<MonitorClient> client;

  Run() = default;
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;
  Run(Run&& other) noexcept = default;
  Run& operator=(Run&& other) noexcept {
    reset();  // the monitor before the engine it watches
    engine = std::move(other.engine);
    monitor = std::move(other.monitor);
    client = std::move(other.client);
    return *this;
  }
  explicit operator bool() const { return engine != nullptr; }
  void reset(std::vector<std::int64_t>* to_client = nullptr) {
    if (client && to_client) {
      // What reached the client before it closes (the last record may still be on its way).
      const auto latencies = client->detectionLatencies();
      to_client->insert(to_client->end(), latencies.begin(), latencies.end());
    }
    client.reset();
    if (monitor) (void)monitor->stop();
    monitor.reset();
    engine.reset();
  }
  ~Run() { reset(); }
};

/// A fresh engine (the log rewritten), watched when `monitored`, started.
Run startEngine(Setup& setup, profile::ProfileSet set, bool monitored) {
  Run run;
  run.engine = createEngine(
      std::move(set), setup.paths, setup.log_path, [&setup](const std::string& w) { addNote(setup.warnings, w); },
      setup.error);
  if (!run.engine) return run;
  if (monitored) {
    auto m = monitor::Monitor::start(*run.engine, {"127.0.0.1:0", {}, setup.log_path, "bench", ""});
    if (!m) {
      setup.error = "monitor: " + m.error().message;
      run.reset();
      return run;
    }
    run.monitor = std::move(*m);
    const std::string url = run.monitor->url();  // http://127.0.0.1:PORT/?token=...
    const auto port = static_cast<std::uint16_t>(std::stoi(url.substr(url.rfind(':') + 1)));
    run.client = std::make_unique<MonitorClient>(port);
    if (!run.client->error().empty()) {
      setup.error = run.client->error();
      run.reset();
      return run;
    }
  }
  if (!bench::startEngine(*run.engine, setup.error)) {
    run.reset();
  } else if (run.client && !run.client->waitForData()) {
    setup.error = "monitor client: no data within 2 s";
    run.reset();
  }
  return run;
}

/// Injects `kind` into the victim and waits for the handling of that fault to recover.
/// Returns the Handling, or nullopt after `bound`.
std::optional<fault::Handling> trial(engine::Engine& engine, runtime::InjectKind kind,
                                     std::chrono::milliseconds bound) {
  Component* victim = engine.find("victim");
  auto& fm = engine.faultManager();
  const std::uint64_t id = fm.nextId();
  const std::size_t before = fm.recoveredCount();
  runtime::arm(*victim, kind, id);
  const auto until = std::chrono::steady_clock::now() + bound;
  while (std::chrono::steady_clock::now() < until) {
    // light polling (an atomic load): the bench must not disturb the victim
    std::this_thread::sleep_for(200us);
    if (fm.recoveredCount() == before) continue;
    if (auto h = fm.handling(id); h && h->recovered_ns != 0) return h;
  }
  return std::nullopt;
}

bool libraryMapped(const std::string& path) {
  void* h = dlopen(path.c_str(), RTLD_LAZY | RTLD_NOLOAD);
  if (h == nullptr) return false;
  dlclose(h);  // NOLOAD took a reference
  return true;
}

}  // namespace

RecoveryCell measureRecovery(const Paths& paths, const std::string& mechanism, bool fifo, int n,
                             const std::string& log_path) {
  RecoveryCell cell;
  Setup setup{paths, log_path, {}, {}};
  // `<mechanism>_monitored`: the same, watched by a live monitor and a client of it.
  const bool monitored = mechanism.ends_with("_monitored");
  const std::string measured = monitored ? mechanism.substr(0, mechanism.size() - 10) : mechanism;
  // `<mechanism>_opros`: the same with a victim written against the OPRoS API.
  const std::string base = measured.ends_with("_opros") ? measured.substr(0, measured.size() - 6) : measured;
  const bool per_engine = base == "replace_preloaded" || base == "replace_cold";
  const bool hang = measured == "reset_hang";
  const std::string package = hang ? "recovery_hang" : "recovery_" + measured;
  const std::string expected = per_engine ? "replace" : "reset";
  const std::string cold_library = paths.components + "/libkeel_bench_cold_spare.so";
  const auto kind = hang ? runtime::InjectKind::Hang : runtime::InjectKind::Segfault;
  const auto bound = hang ? 2000ms : 1000ms;
  auto set = loadPackage(setup, package, fifo);
  if (!set) {
    cell.error = setup.error;
    return cell;
  }
  Run engine;
  for (int i = 0; i < n; ++i) {
    if (!engine) {
      engine = startEngine(setup, *set, monitored);
      if (!engine) {
        cell.error = setup.error;
        return cell;
      }
      std::this_thread::sleep_for(10ms);  // about 10 normal cycles before the first fault
    }
    if (base == "replace_cold" && libraryMapped(cold_library)) ++cell.already_mapped;
    auto h = trial(*engine.engine, kind, bound);
    if (!h) {
      ++cell.failed;
      engine.reset(&cell.to_client_ns);  // a fresh start for the next trial
      continue;
    }
    if (h->actions != expected || h->failed) ++cell.unexpected;
    cell.latencies_ns.push_back(h->recovered_ns - h->detected_ns);
    if (per_engine) {
      engine.reset(&cell.to_client_ns);  // shutdown (the log is complete); the next trial gets a fresh engine
      if (auto t = inPlaceNs(log_path)) cell.in_place_ns.push_back(*t);
    } else {
      std::this_thread::sleep_for(3ms);  // a few normal cycles between trials
    }
  }
  if (engine.client) std::this_thread::sleep_for(100ms);  // the last detection on its way to the client
  engine.reset(&cell.to_client_ns);
  cell.warnings = setup.warnings;
  return cell;
}

}  // namespace keel::bench
