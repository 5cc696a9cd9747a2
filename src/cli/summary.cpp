#include "cli/summary.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "log/schema.hpp"

namespace keel::cli {
namespace {

namespace ev = log::schema::event;
namespace fd = log::schema::field;

std::string str(const nlohmann::json& r, const char* key) {
  const auto it = r.find(key);
  return it != r.end() && it->is_string() ? it->get<std::string>() : std::string();
}

std::uint64_t count(const nlohmann::json& r, const char* key) {
  const auto it = r.find(key);
  return it != r.end() && it->is_number_unsigned() ? it->get<std::uint64_t>() : 0;
}

std::optional<std::int64_t> time(const nlohmann::json& r) {
  const auto it = r.find(fd::kTime);
  if (it == r.end() || !it->is_number_integer()) return std::nullopt;
  return it->get<std::int64_t>();
}

/// Builds the summary record by record; lookups by name and fault id.
class Reader {
 public:
  void add(const nlohmann::json& r) {
    const std::string event = str(r, fd::kEvent);
    if (event == ev::kEngine) engine(r);
    else if (event == ev::kState) state(r);
    else if (event == ev::kCounts) counts(r);
    else if (event == ev::kDetected) detected(r);
    else if (event == ev::kDiagnosed) handling(r).severity = str(r, fd::kSeverity);
    else if (event == ev::kAction) action(r);
    else if (event == ev::kRecovered) recovered(r);
    else if (event == ev::kInjected && r.contains(fd::kDetected) && !r[fd::kDetected].get<bool>()) ++s_.undetected;
    else if (event == ev::kEmergency) s_.emergency_latched = str(r, fd::kPhase) == "latched";
    else if (event == ev::kWarning) ++s_.warnings;
    else if (event == ev::kNode) node(r);
    else if (event == ev::kHost && str(r, fd::kPhase) == "died")
      s_.dead_processes.push_back(fmt::format("{} (pid {})", str(r, fd::kProcess), count(r, fd::kPid)));
    else if (event == ev::kEndRequested && s_.ended_by.empty()) {
      s_.ended_by = str(r, fd::kComponent);
      s_.end_summary = str(r, fd::kSummary);
    }
  }
  void unreadable() { ++s_.unreadable_lines; }

  void node(const nlohmann::json& r) {
    const std::string name = str(r, fd::kComponent);
    auto [it, added] = node_at_.emplace(name, s_.nodes.size());
    if (added) s_.nodes.push_back({name, str(r, fd::kNodeName), {}, 0, 0, {}, false, {}});
    RunSummary::NodeLine& n = s_.nodes[it->second];
    const std::string phase = str(r, fd::kPhase);
    if (phase == "started" || phase == "restarted" || phase == "replaced") {
      ++n.starts;
      if (const std::string out = str(r, fd::kOutput); !out.empty()) n.output = out;
    } else if (phase == "exited" || phase == "stopped") {
      n.last_end = str(r, fd::kDetail);
      n.failed = phase == "exited";
      if (n.failed) {
        ++n.exits;
        n.last_lines.clear();
        if (const auto lines = r.find(fd::kLastLines); lines != r.end() && lines->is_array())
          for (const auto& l : *lines)
            if (l.is_string()) n.last_lines.push_back(l.get<std::string>());
      }
    }
  }

  RunSummary finish() && {
    std::sort(s_.handlings.begin(), s_.handlings.end(),
              [](const auto& a, const auto& b) { return a.fault_id < b.fault_id; });
    return std::move(s_);
  }

 private:
  RunSummary s_;
  std::map<std::string, std::size_t> component_at_;
  std::map<std::string, std::size_t> node_at_;
  std::map<std::pair<std::string, std::string>, std::size_t> executor_at_;  // (process, name)
  std::map<std::pair<std::string, std::string>, std::size_t> fault_at_;     // (component, kind)
  std::map<std::uint64_t, std::size_t> handling_at_;

  RunSummary::ComponentLine& component(const std::string& name) {
    auto [it, added] = component_at_.try_emplace(name, s_.components.size());
    if (added) {
      s_.components.emplace_back();
      s_.components.back().name = name;
    }
    return s_.components[it->second];
  }
  RunSummary::Handling& handling(const nlohmann::json& r) {
    const std::uint64_t id = count(r, fd::kFaultId);
    auto [it, added] = handling_at_.try_emplace(id, s_.handlings.size());
    if (added) {
      s_.handlings.emplace_back();
      s_.handlings.back().fault_id = id;
    }
    return s_.handlings[it->second];
  }

  void engine(const nlohmann::json& r) {
    const std::string phase = str(r, fd::kPhase);
    if (phase == "load") {
      s_.name = str(r, fd::kName);
      if (const auto it = r.find(fd::kComponents); it != r.end() && it->is_array())
        for (const auto& n : *it)  // the plan's order
          if (n.is_string()) component(n.get<std::string>());
    } else if (phase == "started") s_.started_ns = time(r);
    else if (phase == "stopping") {
      s_.stopping_ns = time(r);
      s_.stop_reason = str(r, fd::kReason);
    }
  }
  void state(const nlohmann::json& r) {
    if (s_.stopping_ns) return;  // the table shows each component as the run found it at its stop
    if (r.contains(fd::kApplication)) {
      if (str(r, fd::kTo) == "stopped") s_.stopped_applications.push_back(str(r, fd::kApplication));
      return;
    }
    if (r.contains(fd::kComposite)) return;  // derived from its members, which the table shows
    if (auto s = r.find(fd::kServing); s != r.end() && *s == false) return;  // not standing for its name
    component(str(r, fd::kComponent)).state = str(r, fd::kTo);
  }
  void counts(const nlohmann::json& r) {
    const std::string process = str(r, fd::kProcess);
    if (r.contains(fd::kComponent)) {  // summed: a process's primary and the standby that took over
      auto& c = component(str(r, fd::kComponent));
      c.counted = true;
      c.class_name = str(r, fd::kClass);
      c.executor = str(r, fd::kExecutor);
      c.process = process;
      c.executions += count(r, fd::kExecutions);
      c.deadline_misses += count(r, fd::kDeadlineMisses);
      return;
    }
    const std::string name = str(r, fd::kExecutor);
    auto [it, added] = executor_at_.try_emplace({process, name}, s_.executors.size());
    if (added) {
      s_.executors.emplace_back();
      s_.executors.back().name = name;
      s_.executors.back().process = process;
    }
    auto& e = s_.executors[it->second];
    if (const auto p = r.find(fd::kPeriodMs); p != r.end() && p->is_number()) e.period_ms = p->get<double>();
    e.cycles += count(r, fd::kCycles);
    e.late_cycles += count(r, fd::kLateCycles);
  }
  void detected(const nlohmann::json& r) {
    const std::string who = str(r, fd::kComponent);
    const std::string kind = str(r, fd::kKind);
    ++component(who).faults;
    auto [it, added] = fault_at_.try_emplace({who, kind}, s_.faults.size());
    if (added) s_.faults.push_back({who, kind, str(r, fd::kDetail), 0});
    ++s_.faults[it->second].count;
    auto& h = handling(r);
    h.component = who;
    h.kind = kind;
  }
  void action(const nlohmann::json& r) {
    if (count(r, fd::kFaultId) == 0) return;  // an operator's emergency stop: no fault's handling
    auto& h = handling(r);
    if (!h.actions.empty()) h.actions += ", ";
    h.actions += str(r, fd::kAction);
    if (str(r, fd::kOutcome) == log::schema::kFailed) h.failed = true;
    if (const std::string by = str(r, fd::kReplacement); !by.empty())
      component(str(r, fd::kComponent)).replacement = by;
  }
  void recovered(const nlohmann::json& r) {
    auto& h = handling(r);
    if (const auto it = r.find(fd::kLatencyUs); it != r.end() && it->is_number())
      h.recovered_after_us = it->get<double>();
  }
};

std::string where(const std::string& executor, const std::string& process) {
  return process.empty() ? executor : fmt::format("{} (process {})", executor, process);
}

void printHandling(std::ostream& out, const RunSummary& s) {
  if (s.handlings.empty()) return;
  constexpr std::size_t kShown = 12;  // one screen: the first ones, then totals
  fmt::print(out, "\nhandling:{:>72}\n", "recovered after");
  for (std::size_t i = 0; i < s.handlings.size() && i < kShown; ++i) {
    const auto& h = s.handlings[i];
    std::string outcome = h.recovered_after_us ? fmt::format("{:.1f} us", *h.recovered_after_us)
                          : h.failed           ? "failed"
                                               : "-";
    fmt::print(out, "  #{:<4} {:<20} {:<10} {:<9} {:<30} {:>10}\n", h.fault_id, h.component, h.kind, h.severity,
               h.actions, outcome);
  }
  if (s.handlings.size() > kShown) fmt::print(out, "  ... {} more in the log\n", s.handlings.size() - kShown);
  std::vector<double> latencies;
  for (const auto& h : s.handlings)
    if (h.recovered_after_us) latencies.push_back(*h.recovered_after_us);
  if (!latencies.empty()) {
    std::sort(latencies.begin(), latencies.end());
    fmt::print(out, "  recovered {} of {} faults: median {:.1f} us, max {:.1f} us\n", latencies.size(),
               s.handlings.size(), latencies[latencies.size() / 2], latencies.back());
  }
}

}  // namespace

RunSummary summarize(std::istream& log) {
  Reader reader;
  for (std::string line; std::getline(log, line);) {
    if (line.empty()) continue;
    auto r = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (r.is_object()) reader.add(r);
    else reader.unreadable();
  }
  return std::move(reader).finish();
}

void printSummary(std::ostream& out, const RunSummary& s) {
  const double ran_s = s.started_ns && s.stopping_ns ? (*s.stopping_ns - *s.started_ns) / 1e9 : 0;
  fmt::print(out, "keel: '{}' ran {:.2f} s{}\n\n", s.name, ran_s,
             s.stop_reason.empty() ? "" : fmt::format(" (stopped: {})", s.stop_reason));
  fmt::print(out, "{:<28} {:<9} {:>10} {:>15} {:>7}  {}\n", "component", "at stop", "executions", "deadline misses",
             "faults", "executor");
  for (const auto& c : s.components) {
    const std::string name = c.replacement.empty() ? c.name : fmt::format("{} (now {})", c.name, c.replacement);
    if (!c.counted) {  // its process died, or it never ran
      fmt::print(out, "{:<28} {:<9} {:>10} {:>15} {:>7}  {}\n", name, c.state, "-", "-", c.faults, "-");
      continue;
    }
    fmt::print(out, "{:<28} {:<9} {:>10} {:>15} {:>7}  {}\n", name, c.state, c.executions, c.deadline_misses, c.faults,
               where(c.executor, c.process));
  }
  if (!s.executors.empty()) {
    fmt::print(out, "\n{:<40} {:>10} {:>10} {:>12}\n", "executor", "period_ms", "cycles", "late cycles");
    for (const auto& e : s.executors)
      fmt::print(out, "{:<40} {:>10} {:>10} {:>12}\n", where(e.name, e.process),
                 e.period_ms > 0 ? fmt::format("{:.3f}", e.period_ms) : "aperiodic", e.cycles, e.late_cycles);
  }
  if (!s.dead_processes.empty())
    fmt::print(out, "(not counted: what ran in {}, which died)\n", fmt::join(s.dead_processes, ", "));
  if (!s.nodes.empty()) {
    fmt::print(out, "\n{:<20} {:<24} {:>7} {:>6}  {}\n", "node", "in the ROS 2 graph", "starts", "exits", "output");
    for (const auto& n : s.nodes) {
      fmt::print(out, "{:<20} {:<24} {:>7} {:>6}  {}\n", n.name, n.node, n.starts, n.exits, n.output);
      if (!n.failed) continue;
      fmt::print(out, "  it ended by itself: {}; its last lines:\n", n.last_end);
      for (const auto& l : n.last_lines) fmt::print(out, "  | {}\n", l);
    }
  }
  if (s.faults.empty()) {
    fmt::print(out, "\nno faults\n");
  } else {
    fmt::print(out, "\nfaults:\n");
    for (const auto& f : s.faults)
      fmt::print(out, "  {:<24} {:<10} x{:<5} {}\n", f.component, f.kind, f.count, f.first_detail);
    printHandling(out, s);
  }
  if (s.undetected > 0) fmt::print(out, "  injected and never detected: {}\n", s.undetected);
  if (!s.stopped_applications.empty())
    fmt::print(out, "  stopped applications: {}\n", fmt::join(s.stopped_applications, ", "));
  if (s.emergency_latched) fmt::print(out, "  EMERGENCY STOP LATCHED (not cleared)\n");
  if (s.warnings > 0) fmt::print(out, "{} warning{} (in the log)\n", s.warnings, s.warnings == 1 ? "" : "s");
  if (s.unreadable_lines > 0) fmt::print(out, "{} line(s) of the log are not JSON records\n", s.unreadable_lines);
  if (!s.ended_by.empty()) fmt::print(out, "ended by {}: {}\n", s.ended_by, s.end_summary);
}

}  // namespace keel::cli
