// The validation driver and the helpers the checks share; see validate.hpp.
#include "profile/validate.hpp"

#include <algorithm>
#include <functional>

#include <fmt/format.h>

#include "profile/field_reader.hpp"

namespace keel::profile::detail {

void validate(ProfileSet& set, Diagnostics& diags) {
  for (auto& [path, composite] : set.composites) {
    checkSubcomponents(set, composite.subcomponents, diags);
    checkConnections(set, composite.subcomponents, composite.connections, diags);
    checkExports(set, composite, diags);
    checkAlternatives(set, composite.subcomponents, diags);
    checkCoordination(set, composite.subcomponents, composite.coordination, diags);
    checkIneffectivePolicies(set, composite.subcomponents, nullptr);
  }
  for (auto& [path, pkg] : set.packages) {
    checkSubcomponents(set, pkg.subcomponents, diags);
    checkConnections(set, pkg.subcomponents, pkg.connections, diags);
    checkAlternatives(set, pkg.subcomponents, diags);
    checkTasks(set, pkg, diags);
    checkCoordination(set, pkg.subcomponents, pkg.coordination, diags);
    if (pkg.dds) checkDds(set, pkg.subcomponents, *pkg.dds, diags);
    checkIneffectivePolicies(set, pkg.subcomponents, pkg.dds ? &*pkg.dds : nullptr);
  }
  if (set.system) checkSystem(set, *set.system, diags);
  checkTypeReferences(set);
}

namespace {

PortSig sigOf(const DataPort& p) {
  return {p.name, PortKind::Data, p.usage == PortDirection::Output, std::string(name(p.usage)), p.data_type, {}};
}
PortSig sigOf(const EventPort& p) {
  return {p.name, PortKind::Event, p.usage == PortDirection::Output, std::string(name(p.usage)), p.data_type, {}};
}
PortSig sigOf(const ServicePort& p) {
  return {p.name, PortKind::Service, p.usage == ServiceUsage::Required, std::string(name(p.usage)),
          p.type, p.reference};
}

}  // namespace

std::optional<std::vector<PortSig>> portsOf(const ProfileSet& set, const std::string& path, int depth) {
  if (const auto c = set.components.find(path); c != set.components.end()) {
    std::vector<PortSig> out;
    for (const auto& p : c->second.data_ports) out.push_back(sigOf(p));
    for (const auto& p : c->second.event_ports) out.push_back(sigOf(p));
    for (const auto& p : c->second.service_ports) out.push_back(sigOf(p));
    return out;
  }
  const auto comp = set.composites.find(path);
  if (comp == set.composites.end() || depth > 64) return std::nullopt;
  std::vector<PortSig> out;
  for (const ExportedPort& e : comp->second.exported_ports) {
    const Subcomponent* sub = findSubcomponent(comp->second.subcomponents, e.inner.component);
    if (sub == nullptr) continue;
    const auto inner = portsOf(set, sub->reference, depth + 1);
    if (!inner) continue;
    for (const PortSig& p : *inner) {
      if (p.name != e.inner.port) continue;
      PortSig outer = p;
      outer.name = e.name;
      out.push_back(std::move(outer));
    }
  }
  return out;
}

std::string describe(const PortSig& p) {
  if (p.kind == PortKind::Service) {
    return fmt::format("a {} service port of type '{}'", p.usage, p.type);
  }
  return fmt::format("an {} {} port of data_type '{}'", p.usage, name(p.kind), p.type);
}

const Subcomponent* findSubcomponent(const std::vector<Subcomponent>& subs, const std::string& name) {
  for (const Subcomponent& s : subs) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::string nameList(const std::vector<std::string>& names) {
  if (names.empty()) return "none";
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::string subcomponentNames(const std::vector<Subcomponent>& subs) {
  std::vector<std::string> names;
  names.reserve(subs.size());
  for (const Subcomponent& s : subs) names.push_back(s.name);
  return nameList(names);
}

std::string profileName(const ProfileSet& set, const std::string& path) {
  if (const auto c = set.components.find(path); c != set.components.end()) return c->second.name;
  if (const auto c = set.composites.find(path); c != set.composites.end()) return c->second.name;
  if (const auto p = set.packages.find(path); p != set.packages.end()) return p->second.name;
  return path;
}

void reportCycles(const Graph& graph, Diagnostics& diags) {
  enum class Mark { White, Grey, Black };
  std::map<std::string, Mark> mark;
  std::map<std::string, const std::vector<Edge>*> edges;
  for (const auto& [node, out] : graph) {
    mark.emplace(node, Mark::White);
    edges.emplace(node, &out);
  }
  std::vector<std::string> path;
  std::function<void(const std::string&)> visit = [&](const std::string& node) {
    mark[node] = Mark::Grey;
    path.push_back(node);
    for (const Edge& e : *edges[node]) {
      const auto m = mark.find(e.to);
      if (m == mark.end() || m->second == Mark::Black) continue;
      if (m->second == Mark::White) {
        visit(e.to);
        continue;
      }
      const auto from = std::find(path.begin(), path.end(), e.to);
      std::string cycle;
      for (auto it = from; it != path.end(); ++it) cycle += *it + " -> ";
      diags.push_back(Diagnostic{e.where, "circular dependency: " + cycle + e.to});
    }
    path.pop_back();
    mark[node] = Mark::Black;
  };
  for (const auto& [node, out] : graph) {
    if (mark[node] == Mark::White) visit(node);
  }
}

}  // namespace keel::profile::detail
