// Recovery latency (recovered − detected) per handling mechanism, issue 4 "Performance".
// The real engine runs a package from bench/profiles/: one victim component on a 1 ms periodic
// task, with the fault policy of the mechanism measured. Each trial injects a segfault into the
// victim's next onExecute (runtime::arm), waits for the fault manager's Handling of that fault
// to carry a `recovered` time, and goes on after a few normal cycles.
//   reset              one engine; the victim is reset in place, trial after trial
//   replace_preloaded  a fresh engine per trial (a role is replaced once); the alternative was
//                      created at start
//   replace_cold       a fresh engine per trial; the alternative's library (used by nothing
//                      else) is dlopened at fault time — checked before every fault
//   reset_hang         one engine; a hung onExecute is found by the watchdog (20 ms heartbeat)
//                      and interrupted by a signal, then reset (detected → recovered)
// `recovered` is the end of the first good onExecute after the recovery.
//   build-bench/bin/keel_bench_recovery [--n 1000 | --quick] [--policy other|fifo|both]
//       [--mechanism all|reset|replace_preloaded|replace_cold|reset_hang] [--load 0|80] [--json FILE]
//       [--log FILE]   (the fault log, rewritten by each fresh engine; default a temporary file)
//       [--low-latency]  holds /dev/cpu_dma_latency at 0 while it runs, as a real-time
//                        deployment does: idle CPUs poll instead of halting (on a VM: no exit
//                        to the hypervisor), so a wake-up does not pay the halt's exit latency
// For the replacements the log also gives "in place": detected → the `replace` action (the
// alternative Active in the failed one's executor slot), before the next step that counts as
// `recovered`.
// Idle and under 80% load: bench/run_recovery.sh.
#include <dlfcn.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "latency_stats.hpp"
#include "profile/loader.hpp"
#include "runtime/engine.hpp"
#include "runtime/injection.hpp"

namespace {

using namespace keel;
using namespace std::chrono_literals;

const std::string kProfiles = KEEL_BENCH_PROFILES;
const std::string kComponents = KEEL_BENCH_COMPONENTS;
const std::string kColdLibrary = kComponents + "/libkeel_bench_cold_spare.so";
std::string g_log;  // the fault log: a file, as `keel run` writes one

struct Cell {
  std::string mechanism, policy;
  bench::Summary s;
  std::size_t failed = 0;        // trials without a `recovered` within the bound
  std::size_t unexpected = 0;    // trials whose actions were not the mechanism's
  std::size_t already_mapped = 0;  // replace_cold: the library was mapped before the fault
  bench::Summary in_place;       // replacements: detected → the alternative Active in its place
};

/// From the log of one engine (one replacement): the `replace` action's time − detected.
std::optional<std::int64_t> inPlaceNs() {
  std::ifstream in(g_log);
  std::optional<std::int64_t> detected, replaced;
  for (std::string line; std::getline(in, line);) {
    auto r = nlohmann::json::parse(line, nullptr, false);
    if (r.is_discarded() || !r.contains("t_ns")) continue;
    if (r["event"] == "detected") detected = r["t_ns"].get<std::int64_t>();
    if (r["event"] == "action" && r["action"] == "replace" && r["outcome"] == "ok") replaced = r["t_ns"].get<std::int64_t>();
  }
  if (!detected || !replaced) return std::nullopt;
  return *replaced - *detected;
}

std::optional<profile::ProfileSet> loadPackage(const std::string& name, bool fifo) {
  auto set = profile::load(kProfiles + "/" + name + ".xml");
  if (!set) {
    for (const auto& d : set.error()) std::cerr << d.str() << '\n';
    return std::nullopt;
  }
  for (auto& [path, pkg] : set->packages)
    for (auto& task : pkg.tasks) {
      task.policy = fifo ? profile::SchedPolicy::Fifo : profile::SchedPolicy::Other;
      task.priority = fifo ? 50 : 0;
    }
  return std::move(*set);
}

std::unique_ptr<runtime::Engine> startEngine(profile::ProfileSet set) {
  runtime::EngineOptions opts;
  opts.log_path = g_log;  // rewritten by each fresh engine
  opts.search_path = {kComponents};
  opts.warn = [](const std::string& w) { std::cerr << "keel: warning: " << w << '\n'; };
  auto engine = runtime::Engine::create(std::move(set), std::move(opts));
  if (!engine) {
    std::cerr << "engine: " << engine.error().message << '\n';
    return nullptr;
  }
  if (auto r = (*engine)->start(); !r) {
    std::cerr << "start: " << r.error().message << '\n';
    return nullptr;
  }
  return std::move(*engine);
}

/// Injects `kind` into the victim and waits for the handling of that fault to recover.
/// Returns the Handling, or nullopt after `bound`.
std::optional<fault::Handling> trial(runtime::Engine& engine, runtime::InjectKind kind, std::chrono::milliseconds bound) {
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

bool coldLibraryMapped() {
  void* h = dlopen(kColdLibrary.c_str(), RTLD_LAZY | RTLD_NOLOAD);
  if (h == nullptr) return false;
  dlclose(h);  // NOLOAD took a reference
  return true;
}

Cell measure(const std::string& mechanism, bool fifo, int n) {
  Cell cell;
  cell.mechanism = mechanism;
  cell.policy = fifo ? "fifo" : "other";
  const bool per_engine = mechanism == "replace_preloaded" || mechanism == "replace_cold";
  const bool hang = mechanism == "reset_hang";
  const std::string package = hang ? "recovery_hang" : "recovery_" + mechanism;
  const std::string expected = per_engine ? "replace" : "reset";
  const auto kind = hang ? runtime::InjectKind::Hang : runtime::InjectKind::Segfault;
  const auto bound = hang ? 2000ms : 1000ms;
  auto set = loadPackage(package, fifo);
  if (!set) std::exit(1);
  std::vector<std::int64_t> lat, in_place;
  std::unique_ptr<runtime::Engine> engine;
  for (int i = 0; i < n; ++i) {
    if (!engine) {
      engine = startEngine(*set);
      if (!engine) std::exit(1);
      std::this_thread::sleep_for(10ms);  // about 10 normal cycles before the first fault
    }
    if (mechanism == "replace_cold" && coldLibraryMapped()) ++cell.already_mapped;
    auto h = trial(*engine, kind, bound);
    if (!h) {
      ++cell.failed;
      engine.reset();  // a fresh start for the next trial
      continue;
    }
    if (h->actions != expected || h->failed) {
      if (cell.unexpected++ == 0) std::cerr << mechanism << ": fault " << h->fault_id << " handled as '" << h->actions << "'\n";
    }
    lat.push_back(h->recovered_ns - h->detected_ns);
    if (per_engine) {
      engine.reset();  // shutdown (the log is complete); the next trial gets a fresh engine
      if (auto t = inPlaceNs()) in_place.push_back(*t);
    } else std::this_thread::sleep_for(3ms);  // a few normal cycles between trials
  }
  engine.reset();
  cell.s = bench::summarise(lat);
  cell.in_place = bench::summarise(in_place);
  return cell;
}

}  // namespace

int main(int argc, char** argv) {
  int n = 1000, load_label = -1;
  bool low_latency = false;
  std::string policy = "both", mechanism = "all", json_path;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--n" && i + 1 < argc) n = std::atoi(argv[++i]);
    else if (a == "--quick") n = 50;
    else if (a == "--policy" && i + 1 < argc) policy = argv[++i];
    else if (a == "--mechanism" && i + 1 < argc) mechanism = argv[++i];
    else if (a == "--load" && i + 1 < argc) load_label = std::atoi(argv[++i]);
    else if (a == "--json" && i + 1 < argc) json_path = argv[++i];
    else if (a == "--log" && i + 1 < argc) g_log = argv[++i];
    else if (a == "--low-latency") low_latency = true;
    else {
      std::cerr << "usage: keel_bench_recovery [--n N | --quick] [--policy other|fifo|both]\n"
                   "  [--mechanism all|reset|replace_preloaded|replace_cold|reset_hang] [--load 0|80] [--json FILE] [--log FILE]\n"
                   "  [--low-latency]\n";
      return 2;
    }
  }
  if (n < 1) n = 1;
  int pm_qos = -1;  // held open for the whole run: the kernel keeps the request while it is
  if (low_latency) {
    pm_qos = open("/dev/cpu_dma_latency", O_WRONLY);
    const std::int32_t zero = 0;
    if (pm_qos < 0 || write(pm_qos, &zero, sizeof zero) != sizeof zero) {
      std::cerr << "keel_bench_recovery: --low-latency: cannot write /dev/cpu_dma_latency (needs root)\n";
      return 1;
    }
  }
  const bool own_log = g_log.empty();
  if (own_log) g_log = fmt::format("/tmp/keel_bench_recovery.{}.log", getpid());
  const double load = bench::measureLoad(1.0);
  if (load_label < 0) load_label = load > 0.4 ? 80 : 0;
  fmt::print("machine load before the run: {:.0f}% (reported as load {}){}\n\n", load * 100, load_label,
             low_latency ? "; /dev/cpu_dma_latency held at 0" : "");
  fmt::print("| mechanism | policy | n | p50 µs | p99 µs | max µs | failed | in place p50 / p99 / max µs |\n"
             "|---|---|---|---|---|---|---|---|\n");
  std::ofstream json;
  if (!json_path.empty()) json.open(json_path);
  for (bool fifo : {false, true}) {
    if ((fifo && policy == "other") || (!fifo && policy == "fifo")) continue;
    for (const char* m : {"reset", "replace_preloaded", "replace_cold", "reset_hang"}) {
      if (mechanism != "all" && mechanism != m) continue;
      Cell c = measure(m, fifo, n);
      std::string failed = fmt::format("{}", c.failed);
      if (c.unexpected) failed += fmt::format(" ({} not '{}')", c.unexpected, c.mechanism == "reset" ? "reset" : "replace");
      if (c.already_mapped) failed += fmt::format(" ({} with the library already mapped)", c.already_mapped);
      const std::string in_place = c.in_place.n ? fmt::format("{:.1f} / {:.1f} / {:.1f}", c.in_place.p50_us,
                                                              c.in_place.p99_us, c.in_place.max_us)
                                                : "";
      fmt::print("| {} | {} | {} | {:.1f} | {:.1f} | {:.1f} | {} | {} |\n", c.mechanism, c.policy, c.s.n, c.s.p50_us,
                 c.s.p99_us, c.s.max_us, failed, in_place);
      std::fflush(stdout);
      if (json.is_open())
        json << fmt::format(
                    R"({{"load":{},"mechanism":"{}","policy":"{}","n":{},"p50_us":{:.2f},"p99_us":{:.2f},"max_us":{:.2f},"failed":{},"unexpected":{},"already_mapped":{},"in_place_p50_us":{:.2f},"in_place_p99_us":{:.2f},"in_place_max_us":{:.2f}}})",
                    load_label, c.mechanism, c.policy, c.s.n, c.s.p50_us, c.s.p99_us, c.s.max_us, c.failed,
                    c.unexpected, c.already_mapped, c.in_place.p50_us, c.in_place.p99_us, c.in_place.max_us)
             << '\n';
    }
  }
  if (own_log) std::remove(g_log.c_str());
  if (pm_qos >= 0) close(pm_qos);
  return 0;
}
