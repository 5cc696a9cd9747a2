// <component_profile>: identity, execution environment and semantics, properties (SPEC §3).
// Ports are read by ports.cpp. OPRoS elements keel does not use are accepted and ignored.
#include <fmt/format.h>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"

namespace keel::profile::detail {

void reportMissing(Ctx& ctx, pugi::xml_node parent, std::string_view child, const std::string& owner) {
  if (owner.empty()) {
    ctx.error(parent, fmt::format("missing <{}> in {}", child, tag(parent)));
  } else {
    ctx.error(parent, fmt::format("missing <{}> in {}", child, owner));
  }
}

namespace {

std::string readLibraryName(Ctx& ctx, pugi::xml_node node) {
  std::string library;
  readChildren(ctx, node,
               {{"library_name", [&](pugi::xml_node n) { library = leafText(ctx, n); }},
                {"library_type", {}},
                {"impl_language", {}},
                {"compiler", {}},
                {"app_domain", {}},
                {"app_robot", {}},
                {"mutex_group", {}},
                {"os", {}},
                {"cpu", {}}});
  return library;
}

Property readProperty(Ctx& ctx, pugi::xml_node node, const std::string& owner) {
  Property p;
  p.where = ctx.where(node);
  const std::string text = leafText(ctx, node, {"name", "type", "description"});
  p.name = requiredAttribute(ctx, node, "name").value_or("");
  const auto written = requiredAttribute(ctx, node, "type");
  if (!written) return p;
  const auto type = normalisePropertyType(*written);
  if (!type) {
    ctx.error(node, fmt::format("property '{}' of {} has unknown type '{}' (types: {})", p.name, owner, *written,
                                kPropertyTypes));
    return p;
  }
  p.type = *type;
  auto value = parsePropertyValue(p.type, text);
  const bool negative_unsigned = value && isUnsignedType(*written) && std::get<std::int64_t>(*value) < 0;
  if (!value || negative_unsigned) {
    ctx.error(node, fmt::format("property '{}' of {} must be {}, got '{}'", p.name, owner,
                                negative_unsigned ? "a non-negative " + *written : describeType(p.type), text));
    p.type.clear();  // not usable: overrides of it are not checked
    return p;
  }
  p.value = std::move(*value);
  return p;
}

}  // namespace

Execution parseExecution(Ctx& ctx, pugi::xml_node node, const std::string& owner) {
  Execution e;
  e.where = ctx.where(node);
  bool priority_given = false, priority_ok = true;
  pugi::xml_node priority_node = node;
  auto text = [&](pugi::xml_node n) { return leafText(ctx, n); };
  readChildren(ctx, node,
               {{"type",
                 [&](pugi::xml_node n) {
                   if (auto v = readWord(ctx, n, text(n), "<type> of " + owner, executionTypes())) e.type = *v;
                 }},
                {"period",
                 [&](pugi::xml_node n) {
                   if (auto v = readPositive(ctx, n, text(n), "<period> of " + owner)) e.period_ms = *v;
                 }},
                {"priority",
                 [&](pugi::xml_node n) {
                   priority_node = n;
                   const auto v = readIntIn(ctx, n, text(n), "<priority> of " + owner, 0, 99);
                   e.priority = v.value_or(0);
                   priority_given = true;
                   priority_ok = v.has_value();
                 }},
                {"policy",
                 [&](pugi::xml_node n) {
                   if (auto v = readWord(ctx, n, text(n), "<policy> of " + owner, schedPolicies())) e.policy = *v;
                 }},
                {"instance_creation", {}},
                {"creation_type", {}},
                {"lifecycle_type", {}},
                {"timeout", {}}});
  if (priority_ok) {
    checkRealtimePriority(ctx, priority_node, e.policy, e.priority, priority_given, "<priority> of " + owner, owner);
  }
  return e;
}

std::vector<Property> parseProperties(Ctx& ctx, pugi::xml_node node, const std::string& owner) {
  std::vector<Property> props;
  readChildren(ctx, node,
               {{"property",
                 [&](pugi::xml_node n) {
                   Property p = readProperty(ctx, n, owner);
                   for (const Property& q : props) {
                     if (q.name == p.name && !p.name.empty()) {
                       ctx.error(n, fmt::format("duplicate property '{}' in {} (first at line {})", p.name, owner,
                                                q.where.line));
                       return;
                     }
                   }
                   // Kept even when its value was bad (type ""), so that overrides of it do not
                   // cascade into "no such property"; load() fails on the error anyway.
                   if (!p.name.empty()) props.push_back(std::move(p));
                 },
                 true}});
  return props;
}

void parseComponentProfile(Ctx& ctx, pugi::xml_node root, ComponentProfile& out) {
  out.where = ctx.where(root);
  out.name = std::string(trim(root.child("name").child_value()));
  const std::string owner = out.name.empty() ? "component profile" : "component '" + out.name + "'";
  readChildren(ctx, root,
               {{"name", [&](pugi::xml_node n) { out.name = leafText(ctx, n); }},
                {"description", [&](pugi::xml_node n) { out.description = leafText(ctx, n); }},
                {"execution_environment", [&](pugi::xml_node n) { out.library_name = readLibraryName(ctx, n); }},
                {"execution_semantics", [&](pugi::xml_node n) { out.execution = parseExecution(ctx, n, owner); }},
                {"properties", [&](pugi::xml_node n) { out.properties = parseProperties(ctx, n, owner); }},
                {"ports", [&](pugi::xml_node n) { parsePorts(ctx, n, out); }},
                {"id", {}},
                {"version", {}},
                {"copyright", {}},
                {"layout", {}},
                {"collapsed", {}},
                {"data_type_list", {}},
                {"defined_data_types", {}},
                {"defined_service_types", {}}});
  if (out.name.empty()) reportMissing(ctx, root, "name");
}

}  // namespace keel::profile::detail
