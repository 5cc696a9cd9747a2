#include "cli/summary.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace keel::cli {

void printSummary(std::ostream& out, const engine::Engine& engine, double ran_s) {
  fmt::print(out, "keel: '{}' ran {:.2f} s\n\n", engine.plan().name, ran_s);
  fmt::print(out, "{:<28} {:<9} {:>10} {:>7} {:>9} {:>9}\n", "component", "state", "executions", "faults", "overruns",
             "executor");
  for (const auto& inst : engine.instances()) {
    const Component& c = *inst.active();
    const auto& core = runtime::coreOf(c);
    const auto& first = runtime::coreOf(*inst.component);  // counts of the one it replaced too
    std::string name = inst.plan->name;
    if (&c != inst.component.get()) name += " (now " + core.class_name + ")";
    const std::uint64_t executions = core.executions.load() +
                                     (&c != inst.component.get() ? first.executions.load() : 0);
    const std::uint64_t faults = core.faults.load() + (&c != inst.component.get() ? first.faults.load() : 0);
    if (!inst.plan->process.empty()) {  // runs in a component process: its counts are that process's
      fmt::print(out, "{:<28} {:<9} {:>10} {:>7} {:>9} {:>9}\n", name, toString(c.state()), "-", faults, "-",
                 "process:" + inst.plan->process);
      continue;
    }
    fmt::print(out, "{:<28} {:<9} {:>10} {:>7} {:>9} {:>9}\n", name, toString(c.state()), executions, faults,
               core.deadline_overruns.load(), core.executor.load() ? core.executor.load()->config().name : "passive");
  }
  fmt::print(out, "\n{:<28} {:>10} {:>10} {:>9}\n", "executor", "period_ms", "cycles", "overruns");
  for (const auto& ex : engine.executors()) {
    const auto& c = ex->config();
    auto s = ex->stats();
    std::string period = c.kind == runtime::ExecutorKind::Periodic ? fmt::format("{:.3f}", c.period.count() / 1e6)
                                                                   : "aperiodic";
    fmt::print(out, "{:<28} {:>10} {:>10} {:>9}\n", c.name, period, s.cycles, s.overruns);
  }
  auto faults = engine.faultCounts();
  if (faults.empty()) {
    fmt::print(out, "\nno faults\n");
    return;
  }
  fmt::print(out, "\nfaults:\n");
  for (const auto& f : faults) fmt::print(out, "  {:<24} {:<10} x{:<5} {}\n", f.component, f.kind, f.count, f.detail);
  printHandling(out, engine.faultManager());
}

void printHandling(std::ostream& out, const fault::FaultManager& manager) {
  const auto handlings = manager.handlings();
  if (handlings.empty()) return;
  constexpr std::size_t kShown = 12;  // one screen: the first ones, then totals
  fmt::print(out, "\nhandling:{:>72}\n", "recovered after");
  for (std::size_t i = 0; i < handlings.size() && i < kShown; ++i) {
    const auto& h = handlings[i];
    std::string outcome = h.recovered_ns ? fmt::format("{:.1f} us", (h.recovered_ns - h.detected_ns) / 1e3)
                          : h.failed     ? "failed"
                                         : "-";
    fmt::print(out, "  #{:<4} {:<20} {:<10} {:<9} {:<30} {:>10}\n", h.fault_id, h.component, toString(h.kind),
               h.severity, h.actions, outcome);
  }
  if (handlings.size() > kShown) fmt::print(out, "  ... {} more in the log\n", handlings.size() - kShown);
  std::vector<double> latencies;
  for (const auto& h : handlings)
    if (h.recovered_ns) latencies.push_back((h.recovered_ns - h.detected_ns) / 1e3);
  if (!latencies.empty()) {
    std::sort(latencies.begin(), latencies.end());
    fmt::print(out, "  recovered {} of {} faults: median {:.1f} us, max {:.1f} us\n", latencies.size(),
               handlings.size(), latencies[latencies.size() / 2], latencies.back());
  }
  if (auto apps = manager.stoppedApplications(); !apps.empty())
    fmt::print(out, "  stopped applications: {}\n", fmt::join(apps, ", "));
  if (manager.emergencyLatched()) fmt::print(out, "  EMERGENCY STOP LATCHED (not cleared)\n");
}

}  // namespace keel::cli
