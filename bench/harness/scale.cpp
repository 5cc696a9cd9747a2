// `keel bench scale`: how keel's costs grow with 1, 10, 100, 1000 components. For each
// size N, `trials` times, on the real engine, with the fault log written to a file as
// `keel run --log` writes it:
//  - start-up: a generated package of N BenchVictim instances (a trivial onExecute), each with a
//    fault policy (severity stop), on periodic tasks of kScaleTaskSize members at kScalePeriodMs
//    — a task groups the components that run at one rate in one order (the paper's robot: a few
//    sonars and their voter), and 100 Hz is a usual control rate, so 1000 components make 100
//    threads. Timed: profile::load (XML parsed and validated) + Engine::create (plan, log
//    opened, library resolved and instances created, rules, dependency graph) + start
//    (initialize, connect, the fault manager's thread, executors started with their members'
//    onStart, detectors). Median of the trials; every trial checks that N components are Active.
//  - memory: resident set (/proc/self/statm) after start minus before load (freed heap given
//    back first with malloc_trim), median of the trials; per component: that / N. It holds the
//    profiles, the plan, the instances and their rules, the dependency graph, the executors'
//    threads (their stacks as far as touched) and the engine's fixed cost — mostly the fault
//    manager's preallocated ring of 512 fault reports, about 0.85 MiB — which is nearly all of
//    it at N = 1. One unmeasured N = 1 start-up runs first, so one-time costs of the process
//    (keel's code paged in, the component library's first dlopen, malloc arenas) are in no row;
//    a stack or heap block a previous trial freed and glibc kept may be reused uncounted.
//  - diagnosis against the dependency graph: a generated system of the same N components, as
//    ceil(N / kScaleTaskSize) applications in a chain (each depends_on the one before, each one
//    task), so that a fault of a0.c0 (severity stop) makes the fault manager stop a0 and, by
//    the graph, every application and component: the whole graph (N + applications nodes) is
//    walked. The `diagnosed` record carries the detection's time (it is written with it), so
//    detected → diagnosed is read as detected → the fault manager's `action: stop` record, the
//    moment the diagnosis is known and carried out: hand-off to the manager's thread, the
//    detection's records, the graph query, and the stop posted to every stopped component.
//    One fault per engine (everything is stopped after it), one engine per trial.
//    graph_walk is the graph query alone — DependencyGraph::impactOf(scopeOf(a0.c0)), what the
//    fault manager asks at that fault — timed kWalksPerTrial times per trial on the engine's
//    own graph while it runs, so its percentiles have samples even with one trial.
#include "scale.hpp"

#include <fmt/format.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>
#include <thread>

#include "engine_setup.hpp"
#include "process.hpp"
#include "runtime/injection.hpp"
#include "stats.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;

constexpr int kWalksPerTrial = 200;
constexpr const char* kVictim = "a0.c0";
constexpr auto kStopBound = 2s;
// None is expected, and each is in the fault log anyway.
const auto kNoWarnings = [](const std::string&) {};

std::int64_t nowNs() { return runtime::steadyNs(); }

void writeFile(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string componentProfile(const Paths& paths) { return paths.profiles + "/BenchVictim.xml"; }

/// `count` subcomponents c0.. with their fault policy, on tasks of kScaleTaskSize members.
std::string packageXml(const std::string& name, int count, const std::string& reference) {
  std::string subs, tasks;
  for (int i = 0; i < count; ++i)
    subs += fmt::format(
        "    <subcomponent><name>c{}</name><reference>{}</reference>\n"
        "      <fault_policy><severity>stop</severity></fault_policy></subcomponent>\n",
        i, reference);
  for (int first = 0; first < count; first += kScaleTaskSize) {
    tasks += fmt::format(R"(    <task name="t{}" period="{}">)", first / kScaleTaskSize, kScalePeriodMs);
    for (int i = first; i < std::min(count, first + kScaleTaskSize); ++i)
      tasks += fmt::format("<member component=\"c{}\"/>", i);
    tasks += "</task>\n";
  }
  return fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<package_profile>\n  <name>{}</name>\n"
      "  <subcomponents>\n{}  </subcomponents>\n  <tasks>\n{}  </tasks>\n</package_profile>\n",
      name, subs, tasks);
}

int applicationsFor(int components) { return (components + kScaleTaskSize - 1) / kScaleTaskSize; }

long rssKib() {
  std::ifstream statm("/proc/self/statm");
  long size = 0, resident = 0;
  statm >> size >> resident;
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

std::size_t activeComponents(const engine::Engine& engine) {
  return static_cast<std::size_t>(std::count_if(engine.instances().begin(), engine.instances().end(),
                                                [](const auto& i) { return i.serving()->state() == State::Active; }));
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : (v[m - 1] + v[m]) / 2;
}

/// What the trials of one size collect.
struct SizeRun {
  int n = 0;
  std::string log;
  std::vector<double> load_ms, create_ms, start_ms, startup_ms, rss_kib;
  std::vector<std::int64_t> diagnosis_ns, walks_ns;
  int graph_nodes = 0;
  int failed = 0;
  std::string error;
};

/// One start-up of the package of run.n components: times, memory, then shut down.
void startupTrial(const Paths& paths, const std::string& package, SizeRun& run) {
  malloc_trim(0);
  const long rss0 = rssKib();
  const std::int64_t t0 = nowNs();
  auto set = loadProfiles(package, run.error);
  if (!set) return;
  const std::int64_t t1 = nowNs();
  auto engine = createEngine(std::move(*set), paths, run.log, kNoWarnings, run.error);
  if (!engine) return;
  const std::int64_t t2 = nowNs();
  if (!startEngine(*engine, run.error)) return;
  const std::int64_t t3 = nowNs();
  const long rss1 = rssKib();
  if (const std::size_t active = activeComponents(*engine); active != static_cast<std::size_t>(run.n)) {
    run.error = fmt::format("{} components Active of {}", active, run.n);
    return;
  }
  run.load_ms.push_back(static_cast<double>(t1 - t0) / 1e6);
  run.create_ms.push_back(static_cast<double>(t2 - t1) / 1e6);
  run.start_ms.push_back(static_cast<double>(t3 - t2) / 1e6);
  run.startup_ms.push_back(static_cast<double>(t3 - t0) / 1e6);
  run.rss_kib.push_back(static_cast<double>(rss1 - rss0));
}

/// The graph query the fault manager makes at a stop of `victim`, timed kWalksPerTrial times.
void timeGraphWalk(const fault::DependencyGraph& graph, std::vector<std::int64_t>& out) {
  const auto scope = graph.policyScope(kVictim);
  for (int i = 0; i < kWalksPerTrial; ++i) {
    const std::int64_t t0 = nowNs();
    const fault::Impact impact = graph.impactOf(graph.scopeOf(kVictim, scope));
    const std::int64_t t1 = nowNs();
    if (impact.stopped_components.empty()) return;  // not the graph expected: no sample
    out.push_back(t1 - t0);
  }
}

/// Waits until the handling of fault `id` has carried out its stop.
bool waitForStop(const fault::FaultManager& fm, std::uint64_t id) {
  const auto until = std::chrono::steady_clock::now() + kStopBound;
  while (std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(200us);
    if (auto h = fm.handling(id); h && h->actions.find("stop") != std::string::npos) return true;
  }
  return false;
}

/// The `action: stop` of fault `id` in the log, if it succeeded: its delay after `detected`,
/// and what it stopped.
struct StopRecord {
  std::int64_t latency_ns = 0;
  std::size_t components = 0, applications = 0;
};

std::optional<StopRecord> readStop(const std::string& log, std::uint64_t id) {
  std::ifstream in(log);
  std::optional<std::int64_t> detected;
  for (std::string line; std::getline(in, line);) {
    auto r = nlohmann::json::parse(line, nullptr, false);
    if (r.is_discarded() || r.value("fault_id", std::uint64_t{0}) != id) continue;
    if (r["event"] == "detected") detected = r["t_ns"].get<std::int64_t>();
    if (r["event"] == "action" && r["action"] == "stop" && r["outcome"] == "ok" && detected)
      return StopRecord{r["t_ns"].get<std::int64_t>() - *detected, r["components"].size(), r["applications"].size()};
  }
  return std::nullopt;
}

/// One fault of a0.c0 in the system of run.n components; the stop must take the whole graph.
void diagnosisTrial(const Paths& paths, const std::string& system, SizeRun& run) {
  auto set = loadProfiles(system, run.error);
  if (!set) return;
  const std::size_t apps = set->system ? set->system->applications.size() : 0;
  auto engine = createEngine(std::move(*set), paths, run.log, kNoWarnings, run.error);
  if (!engine || !startEngine(*engine, run.error)) return;
  const fault::DependencyGraph* graph = engine->graph();
  if (graph == nullptr || engine->find(kVictim) == nullptr) {
    run.error = fmt::format("no dependency graph or no component '{}'", kVictim);
    return;
  }
  run.graph_nodes = static_cast<int>(graph->components().size() + apps);
  timeGraphWalk(*graph, run.walks_ns);
  auto& fm = engine->faultManager();
  const std::uint64_t id = fm.nextId();
  if (!runtime::arm(*engine->find(kVictim), runtime::InjectKind::ErrorCode, id)) {
    run.error = "cannot inject into " + std::string(kVictim);
    return;
  }
  const bool stopped = waitForStop(fm, id);
  engine.reset();  // shutdown: the log is complete
  const auto rec = readStop(run.log, id);
  if (!stopped || !rec || rec->components != static_cast<std::size_t>(run.n) || rec->applications != apps) {
    ++run.failed;
    return;
  }
  run.diagnosis_ns.push_back(rec->latency_ns);
}

ScaleRow summariseRun(const SizeRun& run, int trials) {
  ScaleRow row;
  row.components = run.n;
  row.applications = applicationsFor(run.n);
  row.graph_nodes = run.graph_nodes;
  row.trials = trials;
  row.error = run.error;
  row.load_ms = median(run.load_ms);
  row.create_ms = median(run.create_ms);
  row.start_ms = median(run.start_ms);
  row.startup_ms = median(run.startup_ms);
  row.memory_kib = median(run.rss_kib);
  row.memory_kib_per_component = row.memory_kib / std::max(run.n, 1);
  const Summary d = summarise(run.diagnosis_ns);
  const Summary w = summarise(run.walks_ns);
  row.diagnosis_p50_us = d.p50_us;
  row.diagnosis_p99_us = d.p99_us;
  row.faults = static_cast<int>(d.n);
  row.failed = run.failed;
  row.graph_walk_p50_us = w.p50_us;
  row.graph_walk_p99_us = w.p99_us;
  return row;
}

ScaleRow measureSize(const Paths& paths, const std::string& dir, int n, int trials) {
  SizeRun run;
  run.n = n;
  run.log = dir + "/scale.jsonl";  // rewritten by each engine
  const std::string package = writeScalePackage(dir, paths, n);
  const std::string system = writeScaleSystem(dir, paths, n);
  for (int t = 0; t < trials && run.error.empty(); ++t) startupTrial(paths, package, run);
  for (int t = 0; t < trials && run.error.empty(); ++t) diagnosisTrial(paths, system, run);
  return summariseRun(run, trials);
}

}  // namespace

std::string writeScalePackage(const std::string& dir, const Paths& paths, int components) {
  const std::string name = fmt::format("scale_package_{}", components);
  std::string path = dir + "/" + name + ".xml";
  writeFile(path, packageXml(name, components, componentProfile(paths)));
  return path;
}

std::string writeScaleSystem(const std::string& dir, const Paths& paths, int components) {
  const int apps = applicationsFor(components);
  const int last = components - (apps - 1) * kScaleTaskSize;  // components of the last application
  const std::string full = fmt::format("scale_app_{}", kScaleTaskSize), rest = fmt::format("scale_app_{}", last);
  writeFile(dir + "/" + full + ".xml", packageXml(full, kScaleTaskSize, componentProfile(paths)));
  writeFile(dir + "/" + rest + ".xml", packageXml(rest, last, componentProfile(paths)));
  std::string list;
  for (int a = 0; a < apps; ++a) {
    const std::string depends = a == 0 ? "" : fmt::format("<depends_on>a{}</depends_on>", a - 1);
    list += fmt::format("    <application name=\"a{}\" reference=\"{}.xml\">{}</application>\n", a,
                        a + 1 == apps ? rest : full, depends);
  }
  std::string path = fmt::format("{}/scale_system_{}.xml", dir, components);
  writeFile(path, fmt::format("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<system_profile>\n  <name>scale_{}</name>\n"
                              "  <applications>\n{}  </applications>\n</system_profile>\n",
                              components, list));
  return path;
}

std::vector<ScaleRow> measureScale(const Paths& paths, const std::vector<int>& sizes, int trials) {
  std::vector<ScaleRow> rows;
  const TempDir dir("keel_bench_scale.");
  if (dir.path().empty()) {
    ScaleRow row;
    row.error = "cannot make a temporary directory";
    return {row};
  }
  trials = std::max(trials, 1);
  rows.reserve(sizes.size());
  {  // warm-up, not measured: the process's one-time costs belong to no row
    SizeRun warm;
    warm.n = 1;
    warm.log = dir.path() + "/scale.jsonl";
    startupTrial(paths, writeScalePackage(dir.path(), paths, 1), warm);
  }
  for (int n : sizes) rows.push_back(measureSize(paths, dir.path(), std::max(n, 1), trials));
  return rows;
}

void printScale(const std::vector<ScaleRow>& rows, std::ostream& out) {
  out << "| components | applications | graph nodes | start-up ms | load / create / start ms | memory KiB "
         "| KiB per component | diagnosis p50 / p99 µs (faults) | graph walk p50 / p99 µs | trials |\n"
         "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    std::string faults = fmt::format("{}", r.faults);
    if (r.failed) faults += fmt::format(", {} failed", r.failed);
    out << fmt::format(
        "| {} | {} | {} | {:.1f} | {:.1f} / {:.1f} / {:.1f} | {:.0f} | {:.1f} | {:.1f} / {:.1f} ({}) | "
        "{:.1f} / {:.1f} | {} |",
        r.components, r.applications, r.graph_nodes, r.startup_ms, r.load_ms, r.create_ms, r.start_ms, r.memory_kib,
        r.memory_kib_per_component, r.diagnosis_p50_us, r.diagnosis_p99_us, faults, r.graph_walk_p50_us,
        r.graph_walk_p99_us, r.trials);
    if (!r.error.empty()) out << " error: " << r.error;
    out << '\n';
  }
}

nlohmann::json toJson(const ScaleRow& r) {
  nlohmann::json j = {{"components", r.components},
                      {"applications", r.applications},
                      {"graph_nodes", r.graph_nodes},
                      {"startup_ms", r.startup_ms},
                      {"load_ms", r.load_ms},
                      {"create_ms", r.create_ms},
                      {"start_ms", r.start_ms},
                      {"memory_kib", r.memory_kib},
                      {"memory_kib_per_component", r.memory_kib_per_component},
                      {"diagnosis_p50_us", r.diagnosis_p50_us},
                      {"diagnosis_p99_us", r.diagnosis_p99_us},
                      {"graph_walk_p50_us", r.graph_walk_p50_us},
                      {"graph_walk_p99_us", r.graph_walk_p99_us},
                      {"faults", r.faults},
                      {"failed", r.failed},
                      {"trials", r.trials}};
  if (!r.error.empty()) j["error"] = r.error;
  return j;
}

}  // namespace keel::bench
