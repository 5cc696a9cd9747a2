// Property settings given on the command line (`keel run --set INSTANCE.PROPERTY=VALUE`): a
// seed, a gain, a mode for one run without editing the profiles. Parsed here, then typed and
// checked against a plan (the instance exists, its component declares the property, the value
// is of the property's declared type) and applied after the profiles' own overrides.
// Called by the CLI (to report problems before anything loads) and by Engine::create.
// Thread-safety: functions of their arguments.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "keel/result.hpp"
#include "plan/plan.hpp"

namespace keel::plan {

struct PropertySetting {
  std::string text;      // as given, for messages and the log
  std::string instance;  // a planned instance name: "actuator", "navigation.planner"
  std::string property;
  std::string value;  // typed when applied
};

/// Splits "INSTANCE.PROPERTY=VALUE" at the first '=' and, before it, at the last '.' (instance
/// names have dots in systems and composites; property names have none).
Result<PropertySetting> parsePropertySetting(std::string_view text);

/// Types every setting against the property its instance's component declares and sets it in
/// `plan`, in order (a later setting of one property wins). On failure nothing is set, and the
/// error has one line per bad setting.
Result<void> applyPropertySettings(Plan& plan, const std::vector<PropertySetting>& settings);

}  // namespace keel::plan
