// OPRoS's type profiles, which a component profile's ports reference: <service_port_type_profile>
// (a service type's methods) and <data_type> (user structs); and <system_config>, an OPRoS
// engine's own configuration, which keel reads only to say what it is. See docs/opros.md.
#include <fmt/format.h>

#include <algorithm>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"

namespace keel::profile::detail {
namespace {

enum class CallType { Blocking, Nonblocking };

const std::vector<std::pair<std::string_view, CallType>>& callTypes() {
  static const std::vector<std::pair<std::string_view, CallType>> t = {{"blocking", CallType::Blocking},
                                                                       {"nonblocking", CallType::Nonblocking}};
  return t;
}

void readMethod(Ctx& ctx, pugi::xml_node node, ServiceTypeProfile& out) {
  ServiceMethod m;
  m.where = ctx.where(node);
  m.name = attribute(node, "name").value_or("");
  const std::string owner = fmt::format("method '{}' of service type '{}'", m.name, out.name);
  std::vector<std::pair<int, std::pair<std::string, std::string>>> params;  // (index, (name, type))
  auto readParam = [&](pugi::xml_node n) {
    std::string name, type;
    readChildren(ctx, n,
                 {{"name", [&](pugi::xml_node c) { name = leafText(ctx, c); }},
                  {"type", [&](pugi::xml_node c) { type = leafText(ctx, c); }},
                  unusedChild("default", "keel passes every argument a call gives")},
                 {"index"});
    const auto index_text = requiredAttribute(ctx, n, "index");
    if (!index_text) return;
    const auto index = readIntIn(ctx, n, *index_text, "index of a <param> of " + owner, 1, 64);
    if (!index) return;
    if (type.empty()) return reportMissing(ctx, n, "type", "a <param> of " + owner);
    for (const auto& [i, p] : params)
      if (i == *index) return ctx.error(n, fmt::format("two <param>s of {} have index {}", owner, *index));
    params.push_back({*index, {std::move(name), std::move(type)}});
  };
  readChildren(ctx, node, {{"param", readParam, true}}, {"name", "return_type", "call_type"});
  if (m.name.empty())
    return ctx.error(node, fmt::format("missing attribute 'name' of <method> in service type '{}'", out.name));
  m.return_type = attribute(node, "return_type").value_or("void");
  if (auto call = attribute(node, "call_type"))
    m.blocking = readWord(ctx, node, *call, "call_type of " + owner, callTypes()).value_or(CallType::Blocking) ==
                 CallType::Blocking;
  std::sort(params.begin(), params.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (params[i].first != static_cast<int>(i) + 1)
      ctx.error(node, fmt::format("the <param>s of {} skip index {}", owner, i + 1));
    m.params.push_back(std::move(params[i].second));
  }
  for (const ServiceMethod& other : out.methods)
    if (other.name == m.name)
      return ctx.error(node, fmt::format("duplicate method '{}' in service type '{}' (first at line {})", m.name,
                                         out.name, other.where.line));
  out.methods.push_back(std::move(m));
}

void readStruct(Ctx& ctx, pugi::xml_node node, DataTypeProfile& out) {
  DataTypeProfile::Struct s;
  s.where = ctx.where(node);
  s.name = attribute(node, "name").value_or("");
  readChildren(ctx, node,
               {{"item",
                 [&](pugi::xml_node n) {
                   const std::string field = leafText(ctx, n, {"type"});
                   const auto type = requiredAttribute(ctx, n, "type");
                   if (field.empty()) return ctx.error(n, fmt::format("an <item> of struct '{}' has no name", s.name));
                   if (type) s.fields.emplace_back(field, *type);
                 },
                 true}},
               {"name"});
  if (s.name.empty()) return ctx.error(node, "missing attribute 'name' of <struct>");
  out.structs.push_back(std::move(s));
}

}  // namespace

void parseServiceTypeProfile(Ctx& ctx, pugi::xml_node root, ServiceTypeProfile& out) {
  out.where = ctx.where(root);
  pugi::xml_node type;
  readChildren(ctx, root, {{"service_port_type", [&](pugi::xml_node n) { type = n; }}});
  if (!type) return reportMissing(ctx, root, "service_port_type");
  out.name = std::string(trim(type.child("type_name").child_value()));
  readChildren(ctx, type,
               {{"type_name", [&](pugi::xml_node n) { out.name = leafText(ctx, n); }},
                {"method", [&](pugi::xml_node n) { readMethod(ctx, n, out); }, true},
                {"description", {}}});
  if (out.name.empty()) reportMissing(ctx, type, "type_name");
}

void parseDataTypeProfile(Ctx& ctx, pugi::xml_node root, DataTypeProfile& out) {
  out.where = ctx.where(root);
  readChildren(ctx, root, {{"struct", [&](pugi::xml_node n) { readStruct(ctx, n, out); }, true}, {"description", {}}});
  if (out.structs.empty() && !root.child("struct")) reportMissing(ctx, root, "struct");
}

void parseEngineConfig(Ctx& ctx, pugi::xml_node root) {
  ctx.warn(root,
           "an OPRoS engine's configuration (<system_config>), not an application: keel has no use for it. Its "
           "nodes are OPRoS's remote deployment; keel places components in processes with <process> "
           "(docs/opros.md#what-loads)");
}

}  // namespace keel::profile::detail
