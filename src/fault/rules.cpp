#include "fault/rules.hpp"

#include "fault/report.hpp"

#include <algorithm>

namespace keel::fault {

std::string_view toString(Step s) {
  switch (s) {
    case Step::Ignore: return "ignore";
    case Step::Reset: return "reset";
    case Step::Replace: return "replace";
    case Step::Stop: return "stop";
    case Step::Emergency: return "emergency";
    case Step::Done: return "done";
  }
  return "?";
}

profile::Severity Rules::severityOf(FaultKind kind) const {
  if (!has_policy) return stopsTheComponent(kind) ? profile::Severity::Stop : profile::Severity::Ignore;
  return severity[static_cast<std::size_t>(kind)];
}

Step Rules::firstStep(profile::Severity s) const {
  switch (s) {
    case profile::Severity::Ignore: return Step::Ignore;
    case profile::Severity::Reset: return Step::Reset;
    case profile::Severity::Stop: return alternative ? Step::Replace : Step::Stop;
    case profile::Severity::Emergency: return Step::Emergency;
  }
  return Step::Stop;
}

Rules compileRules(const profile::FaultPolicy* policy,
                   const std::map<std::string, profile::ComponentProfile>& components) {
  Rules r;
  if (policy == nullptr) return r;
  r.has_policy = true;
  r.severity.fill(policy->severity);
  for (std::size_t k = 0; k < kFaultKinds; ++k) {
    auto it = policy->severity_by_kind.find(std::string(toString(static_cast<FaultKind>(k))));
    if (it != policy->severity_by_kind.end()) r.severity[k] = it->second;
  }
  r.scope = policy->dependency;
  r.intensity = policy->restart.intensity;
  r.period_ns = static_cast<std::int64_t>(policy->restart.period_ms * 1e6);
  if (policy->alternative) {
    auto it = components.find(policy->alternative->reference);
    if (it != components.end()) r.alternative = &it->second;
    r.preload = policy->alternative->preload;
  }
  return r;
}

std::string_view toString(ActionKind a) {
  switch (a) {
    case ActionKind::Ignore: return "ignore";
    case ActionKind::Reset: return "reset";
    case ActionKind::Restore: return "restore";
    case ActionKind::Replace: return "replace";
    case ActionKind::Stop: return "stop";
    case ActionKind::EmergencyStop: return "emergency_stop";
    case ActionKind::Escalate: return "escalate";
  }
  return "?";
}

}  // namespace keel::fault
