// <composite_component_profile>: subcomponents, their connections and the ports the composite
// exports (OPRoS). An export is written either keel's way,
//   <export_port name="range" component="voter" port="out"/>
// or OPRoS's way, with child elements
//   <export_port><export_port_name>range</export_port_name><component_name>voter</component_name>
//     <port_name>out</port_name><port_type>data</port_type><port_dir>output</port_dir></export_port>
// (port_type and port_dir are derived from the inner port and ignored).
#include <fmt/format.h>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"

namespace keel::profile::detail {
namespace {

void readExportPort(Ctx& ctx, pugi::xml_node node, std::vector<ExportedPort>& out) {
  ExportedPort e;
  e.where = ctx.where(node);
  auto text = [&](std::string& into) { return [&ctx, &into](pugi::xml_node n) { into = leafText(ctx, n); }; };
  readChildren(ctx, node,
               {{"export_port_name", text(e.name)},
                {"component_name", text(e.inner.component)},
                {"port_name", text(e.inner.port)},
                {"port_type", {}},  // derived from the inner port
                {"port_dir", {}},
                {"export_portview", {}},
                {"bend_points", {}, true}},
               {"name", "component", "port"});
  const bool attributes = node.attribute("name") || node.attribute("component") || node.attribute("port");
  const bool children = node.child("export_port_name") || node.child("component_name") || node.child("port_name");
  if (attributes && children) {
    ctx.error(node,
              "<export_port> mixes attributes (name, component, port) and child elements "
              "(export_port_name, component_name, port_name)");
    return;
  }
  if (!children) {
    const auto port_name = requiredAttribute(ctx, node, "name");
    const auto component = requiredAttribute(ctx, node, "component");
    const auto port = requiredAttribute(ctx, node, "port");
    if (!port_name || !component || !port) return;
    e = ExportedPort{*port_name, Endpoint{*component, *port}, e.where};
  } else {
    bool ok = true;
    for (const char* child : {"export_port_name", "component_name", "port_name"}) {
      if (!node.child(child)) {
        reportMissing(ctx, node, child);
        ok = false;
      }
    }
    if (!ok) return;
  }
  for (const ExportedPort& other : out) {
    if (other.name == e.name) {
      ctx.error(node, fmt::format("duplicate export_port '{}' (first at line {})", e.name, other.where.line));
      return;
    }
  }
  out.push_back(std::move(e));
}

}  // namespace

void parseCompositeProfile(Ctx& ctx, pugi::xml_node root, CompositeProfile& out) {
  out.where = ctx.where(root);
  readChildren(ctx, root,
               assemblyChildren(
                   ctx, out.name, out.description, out.connections,
                   {{"subcomponents", [&](pugi::xml_node n) { out.subcomponents = parseSubcomponents(ctx, n); }},
                    {"export_ports",
                     [&](pugi::xml_node n) {
                       readChildren(ctx, n,
                                    {{"export_port",
                                      [&](pugi::xml_node p) { readExportPort(ctx, p, out.exported_ports); }, true}});
                     }},
                    {"coordination", [&](pugi::xml_node n) { out.coordination = parseCoordination(ctx, n); }},
                    {"layout", {}},
                    {"port_layouts", {}},
                    {"app_domain", {}, false, kNoAppDomain},
                    {"execution_environment", {}, false, kNoAssemblyEnvironment}}),
               {"layout"});
  if (out.name.empty()) reportMissing(ctx, root, "name");
}

}  // namespace keel::profile::detail
