// Field rules against the type registry (field_validity.hpp).
#include "dds/field_validity.hpp"

#include <fmt/format.h>

#include "dds/type_registry.hpp"

namespace keel::dds {
namespace {

/// How many numbers the field `steps` reaches always has, or 0 when that depends on the value
/// (a sequence on the way).
std::size_t fixedCount(const std::vector<const detail::MessageField*>& steps) {
  std::size_t n = 1;
  for (const detail::MessageField* f : steps) {
    if (!f->array) continue;
    const std::string_view t = f->type;
    const std::size_t open = t.rfind('[');
    const std::string_view size = t.substr(open + 1, t.size() - open - 2);
    if (size.empty() || size.front() == '<') return 0;
    n *= std::stoul(std::string(size));
  }
  return n;
}

}  // namespace

Result<std::vector<runtime::FieldRule>> resolveFieldRules(const detail::DdsType* type, std::string_view type_name,
                                                          const profile::DataPort& port, std::string_view who) {
  std::vector<runtime::FieldRule> rules;
  std::string errors;
  for (const profile::Validity& v : port.field_validity) {
    const std::string rule = fmt::format("{}: {}<validity field=\"{}\"> of data port '{}'", v.where.str(), who, v.field,
                                         port.name);
    if (type == nullptr) {
      errors += fmt::format(
          "{}: its type '{}' is not a ROS 2 message keel has (a keel::msg type: docs/messages.md), "
          "so it has no fields to check\n",
          rule, type_name);
      continue;
    }
    auto steps = runtime::resolveFieldPath(type->fields, type->ros_name, v.field);
    if (!steps) {
      errors += fmt::format("{}: {}\n", rule, steps.error().message);
      continue;
    }
    detail::ValidityRule bounds{v.min, v.max};
    const std::size_t always = fixedCount(*steps);
    if (const std::size_t want = bounds.elementWise(); want != 0 && always != 0 && want != always) {
      errors += fmt::format(
          "{}: {} bounds, one per element, but '{}' always has {} element{} (one bound applies to "
          "every element)\n",
          rule, want, v.field, always, always == 1 ? "" : "s");
      continue;
    }
    rules.push_back({v.field, std::move(*steps), std::move(bounds)});
  }
  if (!errors.empty()) return fail(errors);
  return rules;
}

Result<std::vector<runtime::FieldRule>> resolveFieldRules(const profile::DataPort& port, std::string_view who,
                                                          bool unknown_ok) {
  const detail::DdsType* type = findType(port.data_type);
  if (type == nullptr && unknown_ok) return std::vector<runtime::FieldRule>{};
  return resolveFieldRules(type, port.data_type, port, who);
}

}  // namespace keel::dds
