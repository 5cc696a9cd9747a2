// Checks of a system profile (paper §5.2, Fig. 7): unique application names, depends_on
// naming applications, no circular dependency (printed), <requires> naming components of
// the application's package, and the connections between applications (checked as a
// package's, over the subcomponents of every application named "application.subcomponent").
// A package that failed to load is not checked again here.
#include <algorithm>

#include <fmt/format.h>

#include "profile/validate.hpp"

namespace keel::profile::detail {
namespace {

void error(Diagnostics& diags, const Where& where, std::string message) {
  diags.push_back(Diagnostic{where, std::move(message)});
}

const Application* findApplication(const SystemProfile& system, const std::string& name) {
  for (const Application& a : system.applications) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

std::string applicationNames(const SystemProfile& system) {
  std::vector<std::string> names;
  for (const Application& a : system.applications) names.push_back(a.name);
  return nameList(names);
}

/// Checks the depends_on of `app`; returns the edges to keep for the cycle search.
std::vector<Edge> checkDependsOn(const SystemProfile& system, const Application& app, Diagnostics& diags) {
  std::vector<Edge> edges;
  for (std::size_t i = 0; i < app.depends_on.size(); ++i) {
    const std::string& dep = app.depends_on[i];
    if (dep == app.name) {
      error(diags, app.where, fmt::format("application '{}' cannot depend on itself", app.name));
    } else if (findApplication(system, dep) == nullptr) {
      error(diags, app.where,
            fmt::format("application '{}': depends_on '{}' is not an application (applications: "
                        "{})",
                        app.name, dep, applicationNames(system)));
    } else if (std::find(app.depends_on.begin(), app.depends_on.begin() + static_cast<long>(i), dep) !=
               app.depends_on.begin() + static_cast<long>(i)) {
      error(diags, app.where, fmt::format("application '{}' lists depends_on '{}' twice", app.name, dep));
    } else {
      edges.push_back(Edge{dep, app.where});
    }
  }
  return edges;
}

void checkRequires(const ProfileSet& set, const Application& app, Diagnostics& diags) {
  const auto pkg = set.packages.find(app.reference);
  if (pkg == set.packages.end()) return;
  for (const Requirement& r : app.requires_) {
    for (const std::string& c : r.components) {
      if (findSubcomponent(pkg->second.subcomponents, c) != nullptr) continue;
      error(diags, r.where,
            fmt::format("application '{}' requires component '{}', which package '{}' does not "
                        "have (subcomponents: {})",
                        app.name, c, pkg->second.name, subcomponentNames(pkg->second.subcomponents)));
    }
  }
}

/// Every application's subcomponents, named "application.subcomponent"; `unloaded` gets the
/// applications whose package failed to load.
std::vector<Subcomponent> qualifiedSubcomponents(const ProfileSet& set, const SystemProfile& system,
                                                 std::vector<std::string>& unloaded) {
  std::vector<Subcomponent> out;
  for (const Application& app : system.applications) {
    const auto pkg = set.packages.find(app.reference);
    if (pkg == set.packages.end()) {
      unloaded.push_back(app.name + ".");
      continue;
    }
    for (Subcomponent sub : pkg->second.subcomponents) {
      sub.name = app.name + "." + sub.name;
      out.push_back(std::move(sub));
    }
  }
  return out;
}

bool inUnloaded(const Endpoint& e, const std::vector<std::string>& unloaded) {
  return std::any_of(unloaded.begin(), unloaded.end(),
                     [&](const std::string& prefix) { return e.component.rfind(prefix, 0) == 0; });
}

/// The system's <port_connections>, exactly as a package's; a connection to an application
/// whose package failed to load is not checked (that failure is reported already).
void checkSystemConnections(const ProfileSet& set, SystemProfile& system, Diagnostics& diags) {
  std::vector<std::string> unloaded;
  const std::vector<Subcomponent> subs = qualifiedSubcomponents(set, system, unloaded);
  std::vector<Connection*> checked;
  std::vector<Connection> copies;
  for (Connection& c : system.connections) {
    if (inUnloaded(c.source, unloaded) || inUnloaded(c.target, unloaded)) continue;
    checked.push_back(&c);
    copies.push_back(c);
  }
  checkConnections(set, subs, copies, diags);
  for (std::size_t i = 0; i < copies.size(); ++i) checked[i]->port_type = copies[i].port_type;
}

}  // namespace

void checkSystem(const ProfileSet& set, SystemProfile& system, Diagnostics& diags) {
  Graph graph;
  const auto& apps = system.applications;
  for (std::size_t i = 0; i < apps.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (apps[j].name == apps[i].name) {
        error(diags, apps[i].where,
              fmt::format("duplicate application '{}' (first at line {})", apps[i].name, apps[j].where.line));
        break;
      }
    }
    graph.emplace_back(apps[i].name, checkDependsOn(system, apps[i], diags));
    checkRequires(set, apps[i], diags);
  }
  reportCycles(graph, diags);
  checkSystemConnections(set, system, diags);
  if (system.dds) {
    std::vector<std::string> unloaded;
    const std::vector<Subcomponent> subs = qualifiedSubcomponents(set, system, unloaded);
    DdsSpec loaded = *system.dds;
    std::erase_if(loaded.bindings, [&](const DdsBinding& b) { return inUnloaded(b.endpoint, unloaded); });
    checkDds(set, subs, loaded, diags);
  }
}

}  // namespace keel::profile::detail
