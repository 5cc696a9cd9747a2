#include "plan/property_settings.hpp"

#include <fmt/format.h>

#include "profile/values.hpp"

namespace keel::plan {
namespace {

std::string list(const std::vector<std::string>& names) {
  if (names.empty()) return "none";
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// The typed value of `s` for `plan`, or why there is none.
Result<PropertyValue> typeSetting(const Plan& plan, const PropertySetting& s) {
  const PlannedInstance* inst = plan.find(s.instance);
  if (inst == nullptr) {
    std::vector<std::string> names;
    for (const auto& i : plan.instances) names.push_back(i.name);
    return fail(fmt::format("--set '{}': no instance '{}' (instances: {})", s.text, s.instance, list(names)));
  }
  const profile::Property* decl = nullptr;
  std::vector<std::string> names;
  for (const auto& p : inst->profile->properties) {
    names.push_back(p.name);
    if (p.name == s.property) decl = &p;
  }
  if (decl == nullptr) {
    return fail(fmt::format("--set '{}': component '{}' of instance '{}' has no property '{}' (properties: {})", s.text,
                            inst->profile->name, s.instance, s.property, list(names)));
  }
  auto value = profile::detail::parsePropertyValue(decl->type, s.value);
  if (!value) {
    return fail(
        fmt::format("--set '{}': property '{}' of instance '{}' is of type {}: the value must be {}, "
                    "got '{}'",
                    s.text, s.property, s.instance, decl->type, profile::detail::describeType(decl->type), s.value));
  }
  return std::move(*value);
}

}  // namespace

Result<PropertySetting> parsePropertySetting(std::string_view text) {
  const auto bad = [&] {
    return fail(fmt::format("--set '{}': expected INSTANCE.PROPERTY=VALUE (e.g. actuator.seed=7)", text));
  };
  const auto eq = text.find('=');
  if (eq == std::string_view::npos) return bad();
  const std::string_view key = text.substr(0, eq);
  const auto dot = key.rfind('.');
  if (dot == std::string_view::npos || dot == 0 || dot + 1 == key.size()) return bad();
  return PropertySetting{std::string(text), std::string(key.substr(0, dot)), std::string(key.substr(dot + 1)),
                         std::string(text.substr(eq + 1))};
}

Result<void> applyPropertySettings(Plan& plan, const std::vector<PropertySetting>& settings) {
  std::vector<PropertyValue> values;
  std::string errors;
  for (const auto& s : settings) {
    auto v = typeSetting(plan, s);
    if (!v) errors += (errors.empty() ? "" : "\n") + v.error().message;
    else values.push_back(std::move(*v));
  }
  if (!errors.empty()) return fail(errors);
  for (std::size_t i = 0; i < settings.size(); ++i) {
    for (auto& inst : plan.instances)
      if (inst.name == settings[i].instance) {
        inst.properties[settings[i].property] = values[i];
        inst.property_where.erase(settings[i].property);  // from the command line: no file
      }
  }
  return {};
}

}  // namespace keel::plan
