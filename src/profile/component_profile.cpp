// <component_profile>: identity, execution environment and semantics, properties
// (docs/profiles.md).
// Ports are read by ports.cpp. OPRoS elements keel does not use are accepted and ignored.
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

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

// What the OPRoS IDE writes about a build, and OPRoS's engine read and never used: no warning.
std::string readLibraryName(Ctx& ctx, pugi::xml_node node) {
  std::string library;
  readChildren(ctx, node,
               {{"library_name", [&](pugi::xml_node n) { library = leafText(ctx, n); }},
                {"library_type", {}},
                {"impl_language", {}},
                {"compiler", {}},
                {"os", {}},
                {"cpu", {}},
                {"app_domain", {}},
                {"app_robot", {}},
                {"mutex_group", {}, false, "keel serialises a component's callbacks itself"}});
  return library;
}

constexpr std::string_view kExports =
    "the variables OPRoS's monitor read (EXPORT_VARIABLE); keel's monitor shows ports, states and faults "
    "(docs/monitor.md)";

/// The type profiles a component lists (OPRoS's IDE writes them): each is read, and its types
/// known to the checks of the ports (validate_ports.cpp). A missing one is a warning.
void readTypeFiles(Ctx& ctx, pugi::xml_node node, const char* child, RootKind kind, const std::string& owner) {
  readChildren(ctx, node,
               {{child,
                 [&](pugi::xml_node n) {
                   (void)ctx.optionalReference(n, leafText(ctx, n), fmt::format("{} of {}", tag(n), owner), kind);
                 },
                 true}});
}

Property readProperty(Ctx& ctx, pugi::xml_node node, const std::string& owner) {
  Property p;
  p.where = ctx.where(node);
  const std::string text = leafText(ctx, node, {"name", "type", "description", "refers"});
  p.name = requiredAttribute(ctx, node, "name").value_or("");
  if (const auto refers = attribute(node, "refers")) {
    if (*refers == "ports") p.refers = *refers;
    else
      ctx.error(node,
                fmt::format("property '{}' of {}: refers=\"{}\" is not known (known: ports)", p.name, owner, *refers));
  }
  // OPRoS's engine passes every property to the component as a string, whatever its type says
  // (docs/opros.md): without a type, or with one keel does not know, it is a string here too.
  const auto written = attribute(node, "type");
  const auto type = written ? normalisePropertyType(*written) : std::optional<std::string>("string");
  if (!type) {
    ctx.warn(node, fmt::format("property '{}' of {} has unknown type '{}' (types: {}): kept as a string, as OPRoS "
                               "does",
                               p.name, owner, *written, kPropertyTypes));
    p.type = "string";
    p.value = text;
    return p;
  }
  p.type = *type;
  auto value = parsePropertyValue(p.type, text);
  const bool negative_unsigned = value && written && isUnsignedType(*written) && std::get<std::int64_t>(*value) < 0;
  if (!value || negative_unsigned) {
    // Published OPRoS profiles do this (type="int" holding COM3), and OPRoS's engine ignores the
    // type: the text is kept as a string, and a component that reads it typed is told then.
    ctx.warn(node,
             fmt::format("property '{}' of {} must be {}, got '{}': kept as a string, as OPRoS does (it "
                         "ignores a property's type); a component that reads it typed fails to start",
                         p.name, owner, negative_unsigned ? "a non-negative " + *written : describeType(p.type), text));
    p.type = "string";
    p.value = text;
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
                   const std::string t = text(n);
                   if (auto v = readWord(ctx, n, t, "<type> of " + owner, executionTypes())) e.type = *v;
                   if (auto s = parseWord(t, executionSharing())) e.sharing = *s;
                   if (equalsNoCase(trim(t), "non-periodic"))
                     ctx.warn(n, fmt::format("<type> non-periodic of {} read as aperiodic, as OPRoS does", owner));
                 }},
                {"period",
                 [&](pugi::xml_node n) {
                   const std::string t = text(n);
                   if (t.empty()) return;  // <period/>: not set (OPRoS writes it so on passive components)
                   if (auto v = readPositive(ctx, n, t, "<period> of " + owner)) e.period_ms = *v;
                 }},
                {"priority",
                 [&](pugi::xml_node n) {
                   priority_node = n;
                   const std::string t = text(n);
                   if (t.empty()) return;
                   const std::optional<std::int64_t> v = parseInt(t);
                   priority_given = true;
                   priority_ok = v.has_value();
                   if (!v)
                     return ctx.error(n, fmt::format("<priority> of {} must be an integer from 0 to 99, got '{}'",
                                                     owner, t));
                   e.priority = static_cast<int>(std::clamp<std::int64_t>(*v, 0, 99));
                   if (e.priority != *v)  // OPRoS clamps to the OS's range; real files have 127
                     ctx.warn(n,
                              fmt::format("<priority> {} of {} clamped to {}, as OPRoS does (priorities are 0 to 99)",
                                          *v, owner, e.priority));
                 }},
                {"policy",
                 [&](pugi::xml_node n) {
                   if (auto v = readWord(ctx, n, text(n), "<policy> of " + owner, schedPolicies())) e.policy = *v;
                 }},
                // Read and never used by OPRoS's engine either: no warning.
                {"instance_creation", {}},
                {"creation_type", {}},
                {"lifecycle_type", {}},
                {"timeout", {}, false, "keel's time limits are the fault policy's <deadline> and <heartbeat>"}});
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
  readChildren(
      ctx, root,
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
       {"data_type_list", [&](pugi::xml_node n) { readTypeFiles(ctx, n, "reference", RootKind::DataType, owner); }},
       {"defined_data_types",
        [&](pugi::xml_node n) { readTypeFiles(ctx, n, "defined_data_type", RootKind::DataType, owner); }},
       {"defined_service_types",
        [&](pugi::xml_node n) { readTypeFiles(ctx, n, "defined_service_type", RootKind::ServiceType, owner); }},
       {"exports", {}, false, kExports},
       {"monitoring", {}, false, kExports},
       {"fsm", {}, false, "keel does not run OPRoS's state machine profiles"},
       {"app_domain", {}, false, kNoAppDomain}});
  if (out.name.empty()) reportMissing(ctx, root, "name");
}

}  // namespace keel::profile::detail
