#include "detection.hpp"

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include <fmt/format.h>

#include "fault/fault_manager.hpp"
#include "fault/watchdog.hpp"
#include "report.hpp"
#include "runtime/component_core.hpp"
#include "runtime/executor.hpp"
#include "runtime/guard.hpp"
#include "runtime/invoke.hpp"
#include "runtime/port_access.hpp"

namespace keel::bench {
namespace {

using namespace std::chrono_literals;

class Victim : public Component {
 public:
  OutputDataPort<double> out{this, "out"};
  ReturnCode onExecute() override {
    out.push(5.0);
    return ReturnCode::Ok;
  }
};

}  // namespace

std::string detectorOf(runtime::InjectKind kind) {
  switch (kind) {
    case runtime::InjectKind::Segfault:
    case runtime::InjectKind::DivideByZero:
    case runtime::InjectKind::Abort: return "signal";
    case runtime::InjectKind::Throw: return "exception";
    case runtime::InjectKind::ErrorCode: return "error_code";
    case runtime::InjectKind::OutOfRange: return "range";
    case runtime::InjectKind::Hang:
    case runtime::InjectKind::StallHeartbeat: return "watchdog";
    case runtime::InjectKind::Kill: return "process";
    case runtime::InjectKind::None: break;
  }
  return "none";
}

DetectionCell measureDetection(runtime::InjectKind kind, bool fifo, int n) {
  runtime::installSignalHandlers();
  DetectionCell cell;
  auto warn = [&cell](const std::string& w) { addNote(cell.warnings, w); };
  log::FaultLog log;
  Victim victim, bystander;
  fault::FaultManager fm(log, [&](std::string_view) -> Component* { return nullptr; });
  for (auto [c, name] : {std::pair<Component*, const char*>{&victim, "victim"}, {&bystander, "bystander"}}) {
    auto& core = runtime::coreOf(*c);
    core.instance_name = name;
    core.fault_sink = &fm;  // the runtime's fault sink, as the engine wires it
    (void)runtime::transition(*c, Transition::Initialize);
  }
  static detail::ValidityRule rule{{0.0}, {10.0}};
  detail::PortAccess::setValidity(victim.out, &rule);
  runtime::coreOf(victim).watch.heartbeat_ns = kDetectionHeartbeatNs;
  runtime::Executor ex({"victim", runtime::ExecutorKind::Periodic, 1ms, fifo ? 50 : 0,
                        fifo ? SchedPolicy::Fifo : SchedPolicy::Other},
                       warn);
  ex.add(victim);
  ex.add(bystander);
  const std::atomic<Component*> watched{&victim};
  fault::Watchdog dog({{&watched, kDetectionHeartbeatNs, 1'000'000}}, fm, warn, fifo);
  ex.start();
  dog.start();
  auto& core = runtime::coreOf(victim);
  auto injected = [&fm] {
    std::size_t k = 0;
    for (const auto& d : fm.detections()) k += d.injected_ns != 0;
    return k;
  };
  for (int i = 0; i < n; ++i) {
    if (victim.state() != State::Active) runtime::setState(victim, State::Active);  // see below
    const std::size_t before = injected();
    std::size_t seen = fm.detectionCount();
    runtime::arm(victim, kind, fm.nextId(), {"out", -1.0, 0});
    bool detected = false;
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (!detected && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(200us);  // light polling: the bench must not disturb the victim
      const std::size_t now = fm.detectionCount();
      if (now == seen) continue;
      seen = now;
      detected = injected() != before;
      // Else a cycle later than the heartbeat (a loaded machine, a sanitizer's slowdown) was a
      // real heartbeat fault, not injected: it stopped the victim (Error is set before the
      // count), which must run again for the armed injection to strike.
      if (!detected) runtime::setState(victim, State::Active);
    }
    if (!detected) ++cell.failed;
    // The detection is counted before the manager stops the victim (Error): wait for that, or
    // the Active set below would be undone and the next injection never run. A range fault
    // does not stop a component without rules.
    if (kind != runtime::InjectKind::OutOfRange) {
      const auto settled = std::chrono::steady_clock::now() + 1s;
      while (victim.state() == State::Active && std::chrono::steady_clock::now() < settled)
        std::this_thread::sleep_for(50us);
    }
    if (kind == runtime::InjectKind::Hang) {
      core.injection.release_hang.store(true);
      while (core.watch.callback_since_ns.load() != 0) std::this_thread::sleep_for(50us);
      core.injection.release_hang.store(false);
    }
    runtime::setState(victim, State::Active);
    std::this_thread::sleep_for(2ms);  // a few normal cycles between trials
  }
  dog.stop();
  ex.requestStop();
  (void)ex.join(5s);
  std::size_t late = 0;
  for (const auto& d : fm.detections()) {
    late += d.injected_ns == 0;
    if (d.injected_ns == 0) continue;
    std::int64_t l = d.detected_ns - d.injected_ns;
    if (kind == runtime::InjectKind::Hang) l -= kDetectionHeartbeatNs;
    cell.latencies_ns.push_back(l);
  }
  if (late != 0)
    warn(fmt::format("{} heartbeat fault(s) of a cycle later than {} ms, not injected", late,
                     kDetectionHeartbeatNs / 1'000'000));
  return cell;
}

}  // namespace keel::bench
