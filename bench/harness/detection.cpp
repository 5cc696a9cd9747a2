// Detection latency (detected − injected) per detector, SPEC §5–6 / issue "fault detection".
// A victim component runs on a 1 ms periodic executor beside a bystander; each trial arms one
// injection, waits for its detection, puts the victim back to Active and goes on. Hangs are
// reported as the overshoot past the heartbeat timeout.
//   build/bin/keel_bench_detection [--n 1000] [--policy other|fifo|both] [--json FILE]
// Run it idle, and under load with bench/run_detection.sh (stress-ng at 80%).
#include <fmt/format.h>

#include <atomic>
#include <cstring>
#include <fstream>
#include <iostream>
#include <thread>

#include "fault/fault_manager.hpp"
#include "fault/watchdog.hpp"
#include "latency_stats.hpp"
#include "runtime/component_core.hpp"
#include "runtime/executor.hpp"
#include "runtime/guard.hpp"
#include "runtime/injection.hpp"
#include "runtime/invoke.hpp"

namespace {

using namespace keel;
using namespace std::chrono_literals;

class Victim : public Component {
 public:
  OutputDataPort<double> out{this, "out"};
  ReturnCode onExecute() override {
    out.push(5.0);
    return ReturnCode::Ok;
  }
};

class Hooks : public runtime::RuntimeHooks {
 public:
  explicit Hooks(fault::FaultManager& fm) : fm_(fm) {}
  void stateChanged(Component&, State, State) override {}
  void faultDetected(Component& c, const FaultEvent& f) override { fm_.onFault(c, f); }
  void runPending(Component& c) override { fm_.runPending(c); }
  void recovered(Component& c, std::int64_t t) override { fm_.recovered(c, t); }

 private:
  fault::FaultManager& fm_;
};

struct Row {
  std::string kind, policy;
  bench::Summary s;
  double timeout_ms = 0;
};

constexpr std::int64_t kHeartbeatNs = 20'000'000;

Row measure(runtime::InjectKind kind, bool fifo, int n) {
  fault::FaultLog log;
  Victim victim, bystander;
  fault::FaultManager fm(log, [&](std::string_view) -> Component* { return nullptr; });
  Hooks hooks(fm);
  for (auto [c, name] : {std::pair<Component*, const char*>{&victim, "victim"}, {&bystander, "bystander"}}) {
    auto& core = runtime::coreOf(*c);
    core.instance_name = name;
    core.hooks = &hooks;
    (void)runtime::transition(*c, Transition::Initialize);
  }
  static detail::ValidityRule rule{{0.0}, {10.0}};
  victim.out.setValidity(&rule);
  runtime::coreOf(victim).heartbeat_ns = kHeartbeatNs;
  runtime::Executor ex({"victim", runtime::ExecutorKind::Periodic, 1ms, fifo ? 50 : 0,
                        fifo ? runtime::Policy::Fifo : runtime::Policy::Other},
                       [](const std::string& w) { std::cerr << w << '\n'; });
  ex.add(victim);
  ex.add(bystander);
  const std::atomic<Component*> watched{&victim};
  fault::Watchdog dog({{&watched, kHeartbeatNs, 1'000'000}}, fm, [](const std::string& w) { std::cerr << w << '\n'; }, fifo);
  ex.start();
  dog.start();
  auto& core = runtime::coreOf(victim);
  for (int i = 0; i < n; ++i) {
    const std::size_t before = fm.detectionCount();
    runtime::arm(victim, kind, fm.nextId(), {"out", -1.0, 0});
    auto deadline = std::chrono::steady_clock::now() + 5s;
    while (fm.detectionCount() == before && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(200us);  // light polling: the bench must not disturb the victim
    if (kind == runtime::InjectKind::Hang) {
      core.release_hang.store(true);
      while (core.callback_since_ns.load() != 0) std::this_thread::sleep_for(50us);
      core.release_hang.store(false);
    }
    runtime::setState(victim, State::Active);
    std::this_thread::sleep_for(2ms);  // a few normal cycles between trials
  }
  dog.stop();
  ex.requestStop();
  (void)ex.join(5s);
  std::vector<std::int64_t> lat;
  for (const auto& d : fm.detections()) {
    if (d.injected_ns == 0) continue;
    std::int64_t l = d.detected_ns - d.injected_ns;
    if (kind == runtime::InjectKind::Hang) l -= kHeartbeatNs;
    lat.push_back(l);
  }
  return {std::string(runtime::toString(kind)), fifo ? "fifo" : "other", bench::summarise(lat),
          kind == runtime::InjectKind::Hang ? kHeartbeatNs / 1e6 : 0};
}

}  // namespace

int main(int argc, char** argv) {
  int n = 1000;
  std::string policy = "both", json_path;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--n" && i + 1 < argc) n = std::atoi(argv[++i]);
    else if (a == "--policy" && i + 1 < argc) policy = argv[++i];
    else if (a == "--json" && i + 1 < argc) json_path = argv[++i];
    else {
      std::cerr << "usage: keel_bench_detection [--n N] [--policy other|fifo|both] [--json FILE]\n";
      return 2;
    }
  }
  runtime::installSignalHandlers();
  const double load = bench::measureLoad(1.0);
  fmt::print("machine load before the run: {:.0f}%\n\n", load * 100);
  fmt::print("| detector (injected) | policy | n | p50 µs | p99 µs | max µs |\n|---|---|---|---|---|---|\n");
  std::vector<Row> rows;
  for (bool fifo : {false, true}) {
    if ((fifo && policy == "other") || (!fifo && policy == "fifo")) continue;
    for (auto kind : {runtime::InjectKind::Segfault, runtime::InjectKind::DivideByZero, runtime::InjectKind::Abort,
                      runtime::InjectKind::Throw, runtime::InjectKind::ErrorCode, runtime::InjectKind::OutOfRange,
                      runtime::InjectKind::Hang}) {
      Row r = measure(kind, fifo, kind == runtime::InjectKind::Hang ? std::max(1, n / 2) : n);
      std::string label = r.kind + (r.timeout_ms ? fmt::format(" (past {} ms timeout)", r.timeout_ms) : "");
      fmt::print("| {} | {} | {} | {:.1f} | {:.1f} | {:.1f} |\n", label, r.policy, r.s.n, r.s.p50_us, r.s.p99_us,
                 r.s.max_us);
      std::fflush(stdout);
      rows.push_back(r);
    }
  }
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    for (const auto& r : rows)
      out << fmt::format(R"({{"load":{:.2f},"kind":"{}","policy":"{}","n":{},"p50_us":{:.2f},"p99_us":{:.2f},"max_us":{:.2f}}})",
                         load, r.kind, r.policy, r.s.n, r.s.p50_us, r.s.p99_us, r.s.max_us)
          << '\n';
  }
  return 0;
}
