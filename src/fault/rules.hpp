// The integrator's fault rules of one component (its <fault_policy>, docs/profiles.md) compiled
// into a plain table before anything runs. No XML at fault time.
// Thread-safety: immutable once built.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "keel/component.hpp"
#include "keel/fault_event.hpp"
#include "profile/model.hpp"

namespace keel::fault {

inline constexpr std::size_t kFaultKinds = static_cast<std::size_t>(FaultKind::Lifecycle) + 1;

/// The steps of handling, in escalation order (docs/fault-handling.md): reset → replace → stop →
/// emergency.
enum class Step : std::uint8_t { Ignore, Reset, Replace, Stop, Emergency, Done };
std::string_view toString(Step s);
using profile::toString;  // Severity, Scope

/// Kinds after which a component cannot simply go on (its callback did not finish).
constexpr bool stopsTheComponent(FaultKind k) {
  return k == FaultKind::Signal || k == FaultKind::Exception || k == FaultKind::ErrorCode ||
         k == FaultKind::Heartbeat || k == FaultKind::Process;
}

struct Rules {
  bool has_policy = false;  // false: no <fault_policy> — detection and containment only
  std::array<profile::Severity, kFaultKinds> severity{};
  profile::Scope scope = profile::Scope::Component;
  int intensity = 3;
  std::int64_t period_ns = 10'000'000'000;
  const profile::ComponentProfile* alternative = nullptr;
  bool preload = false;

  /// The severity of `kind`. Without a policy: `stop` (contained: the component alone) for the
  /// kinds after which it cannot go on, `ignore` (logged) for the others.
  profile::Severity severityOf(FaultKind kind) const;
  /// The first step for `severity`: reset → Reset, stop → Replace (Stop when there is no
  /// alternative), emergency → Emergency, ignore → Ignore.
  Step firstStep(profile::Severity severity) const;
};

/// Compiles `policy` (null: none). `components` resolves the alternative's profile.
Rules compileRules(const profile::FaultPolicy* policy,
                   const std::map<std::string, profile::ComponentProfile>& components);

}  // namespace keel::fault
