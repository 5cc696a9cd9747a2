// <subcomponents> and <port_connections>, shared by package and composite profiles
// (docs/profiles.md).
// Property overrides are kept as text here; validate_assembly.cpp types them against the
// referenced component once it is loaded.
#include <fmt/format.h>

#include <cctype>
#include <filesystem>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"

namespace keel::profile::detail {
namespace {

const std::vector<std::pair<std::string_view, RootKind>>& subcomponentTypes() {
  static const std::vector<std::pair<std::string_view, RootKind>> t = {{"atomic", RootKind::Component},
                                                                       {"composite", RootKind::Composite},
                                                                       {"original", RootKind::Component}};
  return t;
}

std::map<std::string, Property> readOverrides(Ctx& ctx, pugi::xml_node node, const std::string& owner) {
  std::map<std::string, Property> out;
  readChildren(ctx, node,
               {{"property",
                 [&](pugi::xml_node n) {
                   Property p;
                   p.where = ctx.where(n);
                   const std::string text = leafText(ctx, n, {"name", "type", "description"});
                   const auto prop = requiredAttribute(ctx, n, "name");
                   if (!prop) return;
                   p.name = *prop;
                   if (auto written = attribute(n, "type")) {
                     auto type = normalisePropertyType(*written);
                     if (!type) {
                       ctx.error(n, fmt::format("property '{}' of {} has unknown type '{}' (types: {})", p.name, owner,
                                                *written, kPropertyTypes));
                       return;
                     }
                     p.type = *type;
                   }
                   p.value = text;  // typed by validation
                   const auto [it, inserted] = out.emplace(p.name, p);
                   if (!inserted) {
                     ctx.error(n, fmt::format("duplicate property '{}' in {} (first at line {})", p.name, owner,
                                              it->second.where.line));
                   }
                 },
                 true}});
  return out;
}

// A process name becomes part of diagnostics, of the host's command line and of its memfds'
// names: letters, digits, '_', '-' and '.', as instance names.
bool processNameOk(std::string_view name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') return false;
  return true;
}

std::optional<ProcessSpec> readProcess(Ctx& ctx, pugi::xml_node node, const std::string& owner) {
  readChildren(ctx, node, {}, {"name", "standby"});
  ProcessSpec p;
  p.where = ctx.where(node);
  const auto name = requiredAttribute(ctx, node, "name");
  if (!name) return std::nullopt;
  if (!processNameOk(*name)) {
    ctx.error(node, fmt::format("<process> of {}: name '{}' is not a process name (1 to 64 letters, digits, "
                                "'_', '-' or '.')",
                                owner, *name));
    return std::nullopt;
  }
  p.name = *name;
  if (auto standby = attribute(node, "standby")) {
    const auto n = readIntIn(ctx, node, *standby, "standby of <process> of " + owner, 0, kMaxStandby);
    if (!n) return std::nullopt;
    p.standby = *n;
  }
  return p;
}

std::optional<Redundancy> readRedundancy(Ctx& ctx, pugi::xml_node node, const std::string& owner) {
  readChildren(ctx, node, {}, {"group", "strength"});
  Redundancy r;
  r.where = ctx.where(node);
  const auto group = requiredAttribute(ctx, node, "group");
  const auto strength = requiredAttribute(ctx, node, "strength");
  if (!group || !strength) return std::nullopt;
  r.group = std::string(trim(*group));
  if (r.group.empty()) {
    ctx.error(node, fmt::format("<redundancy> of {}: empty group", owner));
    return std::nullopt;
  }
  const auto n = readIntIn(ctx, node, trim(*strength), "strength of <redundancy> of " + owner, 0, 1'000'000);
  if (!n) return std::nullopt;
  r.strength = *n;
  return r;
}

/// Where OPRoS's engine and IDE put a subcomponent's profile, relative to the assembly's
/// folder D, for an assembly D/app.xml: D/app/REF (the engine's default deployment),
/// D/INSTANCE/REF (its other deployment), D/app/STEM/REF (a packed package), D/../STEM/profile/REF
/// and D/../STEM/REF (an IDE workspace, atomic and composite). Only for a bare file name.
std::vector<std::string> oprosPlaces(const Ctx& ctx, const std::string& written, const std::string& instance) {
  const std::filesystem::path ref(written);
  if (ref.has_parent_path() || ref.empty()) return {};
  const std::string app = std::filesystem::path(ctx.file().display()).stem().string();
  const std::string stem = ref.stem().string();
  std::vector<std::string> places = {app + "/" + written, app + "/" + stem + "/" + written,
                                     "../" + stem + "/profile/" + written, "../" + stem + "/" + written};
  if (!instance.empty() && instance != app) places.insert(places.begin() + 1, instance + "/" + written);
  return places;
}

void readSubcomponent(Ctx& ctx, pugi::xml_node node, std::vector<Subcomponent>& out) {
  Subcomponent s;
  s.where = ctx.where(node);
  s.name = std::string(trim(node.child("name").child_value()));
  const std::string owner = fmt::format("subcomponent '{}'", s.name);
  pugi::xml_node reference;
  std::optional<RootKind> declared;
  readChildren(ctx, node,
               {{"name", [&](pugi::xml_node n) { s.name = leafText(ctx, n); }},
                {"reference", [&](pugi::xml_node n) { reference = n; }},
                {"type",
                 [&](pugi::xml_node n) {
                   declared = readWord(ctx, n, leafText(ctx, n), "<type> of " + owner, subcomponentTypes());
                 }},
                {"properties", [&](pugi::xml_node n) { s.property_overrides = readOverrides(ctx, n, owner); }},
                {"fault_policy", [&](pugi::xml_node n) { s.fault_policy = parseFaultPolicy(ctx, n, s.name); }},
                {"process", [&](pugi::xml_node n) { s.process = readProcess(ctx, n, owner); }},
                {"redundancy", [&](pugi::xml_node n) { s.redundancy = readRedundancy(ctx, n, owner); }},
                {"attach",
                 [&](pugi::xml_node n) {
                   readChildren(ctx, n, {});
                   s.attach = ctx.where(n);
                 }},
                {"node_id",
                 [&](pugi::xml_node n) {
                   if (const std::string node_id = leafText(ctx, n); !node_id.empty())
                     ctx.unused(n, "<node_id>",
                                "OPRoS deploys such a subcomponent on another node's engine; keel runs it on this "
                                "machine, in a process of its own with <process> (docs/isolation.md)");
                 }},
                {"id", {}},
                {"version", {}},
                {"layout", {}},
                {"port_layouts", {}}},
               {"read_only", "layout"});
  if (s.attach && s.process)  // whoever started the node chose its process
    ctx.error(s.process->where, fmt::format("<process> of {}: a ROS 2 node is a process of its own, and with "
                                            "<attach/> someone else starts it",
                                            owner));
  if (s.name.empty()) return reportMissing(ctx, node, "name");
  if (!reference) return reportMissing(ctx, node, "reference", owner);
  const std::string written = leafText(ctx, reference);
  s.reference = ctx.reference(reference, written, owner, {RootKind::Component, RootKind::Composite, RootKind::Node},
                              declared, oprosPlaces(ctx, written, s.name));
  out.push_back(std::move(s));
}

std::optional<Endpoint> readEndpoint(Ctx& ctx, pugi::xml_node node, bool source) {
  readChildren(ctx, node, {}, {"component_name", "port_name", "field"});
  const auto component = requiredAttribute(ctx, node, "component_name");
  const auto port = requiredAttribute(ctx, node, "port_name");
  if (!component || !port) return std::nullopt;
  Endpoint e{*component, *port};
  if (auto field = attribute(node, "field")) {
    if (!source) {
      ctx.error(ctx.where(node), "field of <target>: a connection carries a field of its source's messages");
      return std::nullopt;
    }
    if (field->empty()) {
      ctx.error(ctx.where(node), "empty field of <source>: a dotted path to a number of the port's messages");
      return std::nullopt;
    }
    e.field = *field;
  }
  return e;
}

void readConnection(Ctx& ctx, pugi::xml_node node, std::vector<Connection>& out) {
  Connection c;
  c.where = ctx.where(node);
  std::optional<Endpoint> source, target;
  readChildren(ctx, node,
               {{"source", [&](pugi::xml_node n) { source = readEndpoint(ctx, n, true); }},
                {"target", [&](pugi::xml_node n) { target = readEndpoint(ctx, n, false); }},
                {"bend_point", {}, true},
                {"bend_points", {}, true}},
               {"port_type", {"io_type", "OPRoS connects components of one engine directly"}});
  bool ok = true;
  if (auto type = attribute(node, "port_type")) {
    const auto t = readWord(ctx, node, *type, "port_type of <port_connection>", portTypes());
    ok = t.has_value();
    c.port_type = t.value_or(PortKind::Data);
  } else {
    c.port_type_given = false;
  }
  if (!node.child("source")) reportMissing(ctx, node, "source");
  if (!node.child("target")) reportMissing(ctx, node, "target");
  if (!ok || !source || !target) return;
  c.source = std::move(*source);
  c.target = std::move(*target);
  out.push_back(std::move(c));
}

}  // namespace

std::vector<Subcomponent> parseSubcomponents(Ctx& ctx, pugi::xml_node node) {
  std::vector<Subcomponent> out;
  readChildren(ctx, node, {{"subcomponent", [&](pugi::xml_node n) { readSubcomponent(ctx, n, out); }, true}});
  return out;
}

std::vector<Connection> parseConnections(Ctx& ctx, pugi::xml_node node) {
  std::vector<Connection> out;
  readChildren(ctx, node, {{"port_connection", [&](pugi::xml_node n) { readConnection(ctx, n, out); }, true}});
  return out;
}

}  // namespace keel::profile::detail
