// <system_profile>: the applications of a robot and their dependencies (paper §5.2, Fig. 7).
//   <application name="nav" reference="nav.xml">
//     <depends_on>obstacle</depends_on>
//     <requires min_healthy="2"><component>sonar1</component>...</requires>
//   </application>
//   <port_connections> as in a package, endpoints named "application.subcomponent"
// Cross-application checks (names, cycles, required components) are in validate_system.cpp.
#include <fmt/format.h>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"

namespace keel::profile::detail {
namespace {

void readRequires(Ctx& ctx, pugi::xml_node node, Application& app, const std::string& owner) {
  Requirement r;
  r.where = ctx.where(node);
  readChildren(ctx, node,
               {{"component",
                 [&](pugi::xml_node n) {
                   std::string c = leafText(ctx, n);
                   if (c.empty()) return ctx.error(n, fmt::format("empty <component> in {}", owner));
                   for (const std::string& seen : r.components) {
                     if (seen == c) {
                       return ctx.error(n, fmt::format("{} lists component '{}' twice in <requires>", owner, c));
                     }
                   }
                   r.components.push_back(std::move(c));
                 },
                 true}},
               {"min_healthy"});
  if (r.components.empty() && !node.child("component")) {
    return ctx.error(node, fmt::format("<requires> of {} lists no <component>", owner));
  }
  if (auto text = attribute(node, "min_healthy")) {
    const auto v = parseInt(*text);
    const int n = static_cast<int>(r.components.size());
    if (!v || *v < 1 || *v > n) {
      return ctx.error(node, fmt::format("min_healthy of {} must be from 1 to {} (the number of "
                                         "listed components), got '{}'",
                                         owner, n, *text));
    }
    r.min_healthy = static_cast<int>(*v);
  }
  app.requires_.push_back(std::move(r));
}

void readApplication(Ctx& ctx, pugi::xml_node node, std::vector<Application>& out) {
  Application app;
  app.where = ctx.where(node);
  const auto app_name = attribute(node, "name");
  const std::string owner = fmt::format("application '{}'", app_name.value_or(""));
  readChildren(ctx, node,
               {{"depends_on",
                 [&](pugi::xml_node n) {
                   std::string dep = leafText(ctx, n);
                   if (dep.empty()) return ctx.error(n, fmt::format("empty <depends_on> in {}", owner));
                   app.depends_on.push_back(std::move(dep));
                 },
                 true},
                {"requires", [&](pugi::xml_node n) { readRequires(ctx, n, app, owner); }, true}},
               {"name", "reference"});
  if (!requiredAttribute(ctx, node, "name")) return;
  app.name = *app_name;
  const auto reference = requiredAttribute(ctx, node, "reference");
  if (!reference) return;
  app.reference = ctx.reference(node, trim(*reference), owner, {RootKind::Package});
  if (!app.reference.empty()) out.push_back(std::move(app));
}

}  // namespace

void parseSystemProfile(Ctx& ctx, pugi::xml_node root, SystemProfile& out) {
  out.where = ctx.where(root);
  readChildren(ctx, root,
               assemblyChildren(ctx, out.name, out.description, out.connections,
                                {{"applications",
                                  [&](pugi::xml_node n) {
                                    readChildren(ctx, n,
                                                 {{"application",
                                                   [&](pugi::xml_node a) { readApplication(ctx, a, out.applications); },
                                                   true}});
                                  }},
                                 {"dds", [&](pugi::xml_node n) { out.dds = parseDds(ctx, n); }}}));
  if (out.name.empty()) reportMissing(ctx, root, "name");
}

}  // namespace keel::profile::detail
