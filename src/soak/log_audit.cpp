#include "soak/log_audit.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <algorithm>

#include "log/schema.hpp"

namespace keel::soak {
namespace {

namespace ev = log::schema::event;
namespace fd = log::schema::field;

/// What the log says of one fault id.
struct Fault {
  std::string kind;  // as injected; empty: not injected
  std::string component;
  bool armed = false;
  bool hardware = false;
  std::optional<std::int64_t> injected_ns;  // manifested (the `injected` record's time)
  bool undetected = false;                  // `injected` with detected: false (written at the end)
  std::optional<std::size_t> detected_line;
  bool diagnosed = false;
  bool acted = false;
  std::size_t line = 0;  // its first record
};

std::string str(const nlohmann::json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

}  // namespace

RoundAudit auditRound(std::string_view text, std::size_t first_line) {
  RoundAudit a;
  std::map<std::uint64_t, Fault> faults;
  std::map<std::string, bool> phases;  // engine phases seen
  std::optional<std::int64_t> stopping_ns;
  std::map<std::string, std::vector<std::int64_t>> left_active;  // component → when it stopped running
  std::vector<std::int64_t> latched_at;
  // Lines of emergency latches not yet followed by their action, per process (its `pid`; 0:
  // keel run's): a component process started while one is latched latches its own.
  std::map<std::int64_t, std::vector<std::size_t>> latches;
  std::size_t at = 0;
  std::size_t line_no = first_line;
  while (at < text.size()) {
    const std::size_t nl = text.find('\n', at);
    if (nl == std::string_view::npos) {
      a.violations.push_back(fmt::format("line {}: the log ends inside a line (torn: no newline)", line_no));
      break;
    }
    const std::string_view line = text.substr(at, nl - at);
    at = nl + 1;
    const std::size_t no = line_no++;
    ++a.lines;
    if (line.find('\0') != std::string_view::npos) {
      a.violations.push_back(fmt::format("line {}: NUL bytes (a hole where a line was not written)", no));
      continue;
    }
    nlohmann::json r = nlohmann::json::parse(line, nullptr, false);
    if (r.is_discarded() || !r.is_object() || !r.contains(fd::kEvent) || !r.contains(fd::kTime)) {
      a.violations.push_back(fmt::format("line {}: not a whole record (torn or lost part): {:.80}", no, line));
      continue;
    }
    const std::string event = str(r, fd::kEvent);
    const std::int64_t t = r[fd::kTime].is_number_integer() ? r[fd::kTime].get<std::int64_t>() : 0;
    if (event == ev::kEngine) {
      phases[str(r, fd::kPhase)] = true;
      if (str(r, fd::kPhase) == "stopping") stopping_ns = t;
      continue;
    }
    if (event == ev::kEmergency) {
      if (str(r, fd::kPhase) == "latched") {
        ++a.emergencies;
        latched_at.push_back(t);
        latches[r.value(fd::kPid, std::int64_t{0})].push_back(no);
      }
      continue;
    }
    if (event == ev::kAction && str(r, fd::kAction) == "emergency_stop") {
      auto& open = latches[r.value(fd::kPid, std::int64_t{0})];
      if (!open.empty()) {
        open.erase(open.begin());
        if (str(r, fd::kOutcome) == log::schema::kOk) ++a.emergencies_reached;
        else
          a.violations.push_back(fmt::format("line {}: emergency stop not reached: not finished in {}", no,
                                             r.value(fd::kNotFinished, nlohmann::json::array()).dump()));
      }
    }
    if (event == ev::kState && str(r, fd::kFrom) == "Active" && r.contains(fd::kComponent))
      left_active[str(r, fd::kComponent)].push_back(t);
    if (r.contains("collisions") && r["collisions"].is_number_integer()) {
      a.collisions = r["collisions"].get<int>();
      if (r.contains("neutral_by")) a.neutral_by = str(r, "neutral_by");
    }
    if (!r.contains(fd::kFaultId) || !r[fd::kFaultId].is_number_unsigned()) continue;
    Fault& f = faults[r[fd::kFaultId].get<std::uint64_t>()];
    if (f.line == 0) f.line = no;
    if (event == ev::kArmed) {
      f.armed = true;
      f.kind = str(r, fd::kKind);
      f.component = str(r, fd::kComponent);
    } else if (event == ev::kInjected) {
      f.injected_ns = t;
      if (r.value(fd::kHardware, false)) {
        f.hardware = true;
        f.kind = str(r, fd::kKind);
        f.component = str(r, fd::kComponent);
        if (r.contains(fd::kOutcome))
          a.violations.push_back(fmt::format("line {}: hardware fault '{}' not taken by '{}': {}", no,
                                             str(r, fd::kDetail), f.component, str(r, fd::kOutcome)));
      }
      if (r.contains(fd::kDetected) && !r[fd::kDetected].get<bool>()) f.undetected = true;
    } else if (event == ev::kDetected) {
      if (!f.detected_line) f.detected_line = no;
    } else if (event == ev::kDiagnosed) {
      f.diagnosed = true;
    } else if (event == ev::kAction) {
      f.acted = true;
      const std::string action = str(r, fd::kAction);
      if (action == "stop" || action == "emergency_stop") ++a.stops;
    }
  }
  for (const char* phase : {"load", "started", "stopping", "stopped"})
    if (!phases.contains(phase))
      a.violations.push_back(fmt::format("lines {}–{}: no engine '{}' record", first_line, line_no - 1, phase));
  if (a.collisions && *a.collisions > 0 && a.emergencies == 0 && a.stops == 0)
    a.violations.push_back(
        fmt::format("{} collision(s) while keel stopped nothing and latched no emergency", *a.collisions));
  for (const auto& [pid, open] : latches)
    for (std::size_t no : open)
      a.violations.push_back(fmt::format("line {}: emergency latched, and no emergency_stop action followed", no));
  for (const auto& [id, f] : faults) {
    const std::string what = fmt::format("line {}: fault {} ({} of '{}')", f.line, id,
                                         f.kind.empty() ? "detected" : f.kind, f.component);
    if (f.detected_line) {
      ++a.detected;
      if (!f.diagnosed) a.violations.push_back(what + ": detected, never diagnosed");
      else if (!f.acted) a.violations.push_back(what + ": diagnosed, no action taken");
    }
    if (f.kind.empty()) continue;  // not injected: a consequence, or a fault of the application's own
    KindCounts& k = a.by_kind[f.kind];
    ++k.armed;
    if (f.hardware) continue;  // its effects are faults of their own (a range, a model fault)
    if (!f.injected_ns) {
      ++k.not_manifested;
    } else if (f.detected_line && f.diagnosed && f.acted) {
      ++k.handled;
    } else if (f.undetected || !f.detected_line) {
      const std::int64_t t = *f.injected_ns;
      auto after = [t](const std::vector<std::int64_t>& times) {
        return std::any_of(times.begin(), times.end(), [t](std::int64_t u) { return u >= t; });
      };
      const auto left = left_active.find(f.component);
      if ((stopping_ns && *stopping_ns - t < kGraceNs) || after(latched_at) ||
          (left != left_active.end() && after(left->second)))
        ++k.overtaken;
      else a.violations.push_back(what + ": injected, never detected");
    }
  }
  return a;
}

}  // namespace keel::soak
