#include "cli/summary.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

namespace keel::cli {

void printSummary(std::ostream& out, const runtime::Engine& engine, double ran_s) {
  fmt::print(out, "keel: '{}' ran {:.2f} s\n\n", engine.plan().name, ran_s);
  fmt::print(out, "{:<28} {:<9} {:>10} {:>7} {:>9} {:>9}\n", "component", "state", "executions",
             "faults", "overruns", "executor");
  for (const auto& inst : engine.instances()) {
    const auto& core = runtime::coreOf(*inst.component);
    fmt::print(out, "{:<28} {:<9} {:>10} {:>7} {:>9} {:>9}\n", inst.plan->name,
               toString(inst.component->state()), core.executions.load(), core.faults.load(),
               core.deadline_overruns.load(), inst.executor ? inst.executor->config().name : "passive");
  }
  fmt::print(out, "\n{:<28} {:>10} {:>10} {:>9}\n", "executor", "period_ms", "cycles", "overruns");
  for (const auto& ex : engine.executors()) {
    const auto& c = ex->config();
    auto s = ex->stats();
    std::string period = c.kind == runtime::ExecutorKind::Periodic
                             ? fmt::format("{:.3f}", c.period.count() / 1e6)
                             : "aperiodic";
    fmt::print(out, "{:<28} {:>10} {:>10} {:>9}\n", c.name, period, s.cycles, s.overruns);
  }
  auto faults = engine.faultCounts();
  if (faults.empty()) {
    fmt::print(out, "\nno faults\n");
    return;
  }
  fmt::print(out, "\nfaults:\n");
  for (const auto& f : faults)
    fmt::print(out, "  {:<24} {:<10} x{:<5} {}\n", f.component, f.kind, f.count, f.detail);
}

}  // namespace keel::cli
