#include "fault/dependency_graph.hpp"

#include <fmt/format.h>

#include "fault/fault_manager_component.hpp"

namespace keel::fault {

using profile::Scope;

namespace {

/// "file:line: " of a profile element, empty when unknown.
/// `file:line: ` before a message, or nothing for what no profile line says.
std::string at(const profile::Where& w) { return w.file.empty() ? "" : w.str() + ": "; }

}  // namespace

Result<DependencyGraph> DependencyGraph::build(const plan::Plan& plan, const profile::ProfileSet& set) {
  DependencyGraph g;
  if (auto r = g.indexComponents(plan); !r) return r.error();
  if (auto r = g.indexDepends(plan); !r) return r.error();
  if (auto r = g.indexApplications(plan, set); !r) return r.error();
  return g;
}

Result<void> DependencyGraph::indexComponents(const plan::Plan& plan) {
  for (const auto& inst : plan.instances) {
    if (!index_.emplace(inst.name, names_.size()).second)
      return fail(fmt::format("dependency graph of '{}': component '{}' appears twice", plan.name, inst.name));
    names_.push_back(inst.name);
    policy_scope_.push_back(inst.policy ? inst.policy->dependency : Scope::Component);
  }
  executor_of_.assign(names_.size(), kNone);
  for (const auto& ex : plan.executors) {
    auto& members = executors_.emplace_back();
    for (const auto& m : ex.members) {
      auto it = index_.find(m);
      if (it == index_.end())
        return fail(
            fmt::format("dependency graph of '{}': executor '{}' runs unknown component '{}'", plan.name, ex.name, m));
      members.push_back(it->second);
      executor_of_[it->second] = executors_.size() - 1;
    }
  }
  composite_of_.assign(names_.size(), kNone);
  for (const auto& comp : plan.composites) {  // outer first: an inner one overwrites
    auto& members = composites_.emplace_back();
    for (const auto& m : comp.members) {
      auto it = index_.find(m);
      if (it == index_.end()) continue;  // the plan's own instances: always found
      members.push_back(it->second);
      composite_of_[it->second] = composites_.size() - 1;
    }
  }
  return {};
}

// A name is a component, or a composite: then every component inside it ("name.inner").
std::vector<DependencyGraph::Id> DependencyGraph::resolve(const std::string& name) const {
  if (auto it = index_.find(name); it != index_.end()) return {it->second};
  std::vector<Id> inner;
  const std::string prefix = name + ".";
  for (auto it = index_.lower_bound(prefix); it != index_.end() && it->first.starts_with(prefix); ++it)
    inner.push_back(it->second);
  return inner;
}

// coordination/needs: source needs target, so target's stop stops source.
Result<void> DependencyGraph::indexDepends(const plan::Plan& plan) {
  dependants_.assign(names_.size(), {});
  for (const auto& d : plan.depends) {
    const auto sources = resolve(d.source);
    const auto targets = resolve(d.target);
    if (sources.empty() || targets.empty())
      return fail(fmt::format("{}needs: no component '{}' in '{}'", at(d.where), sources.empty() ? d.source : d.target,
                              plan.name));
    for (Id t : targets)
      for (Id s : sources)
        if (s != t) dependants_[t].push_back(s);
  }
  return {};
}

Result<void> DependencyGraph::addGroup(Id app, const std::vector<std::vector<Id>>& entries, std::size_t min_healthy) {
  if (min_healthy > entries.size())
    return fail(fmt::format("application '{}' needs {} healthy of {} components", apps_[app].name, min_healthy,
                            entries.size()));
  groups_.push_back({app, min_healthy, entries.size()});
  for (const auto& entry : entries) {
    for (Id c : entry) uses_[c].push_back({groups_.size() - 1, entries_});
    ++entries_;
  }
  return {};
}

Result<void> DependencyGraph::indexApplications(const plan::Plan& plan, const profile::ProfileSet& set) {
  uses_.assign(names_.size(), {});
  if (!set.system) {  // a package (or a component, a composite): one implicit application
    App& app = apps_.emplace_back();
    app.name = plan.name;
    std::vector<std::vector<Id>> entries;
    for (Id c = 0; c < names_.size(); ++c) {
      if (names_[c] == kFaultManagerInstance) continue;  // the framework's, in no application
      app.members.push_back(c);
      entries.push_back({c});
    }
    // One group needing any one of them: a package runs while any component of it runs
    // (decision 0004); what one component's stop takes with it is its scope and dependants.
    return addGroup(0, entries, entries.empty() ? 0 : 1);
  }
  std::map<std::string, Id, std::less<>> app_index;
  for (const auto& a : set.system->applications) {
    app_index[a.name] = apps_.size();
    apps_.push_back({a.name, {}, {}});
  }
  for (const auto& inst : plan.instances) {
    if (inst.application.empty()) continue;  // the fault manager
    auto it = app_index.find(inst.application);
    if (it == app_index.end())
      return fail(fmt::format("component '{}' belongs to unknown application '{}'", inst.name, inst.application));
    apps_[it->second].members.push_back(index_.at(inst.name));
  }
  for (const auto& a : set.system->applications) {
    const Id id = app_index.at(a.name);
    for (const auto& dep : a.depends_on) {
      auto it = app_index.find(dep);
      if (it == app_index.end())
        return fail(fmt::format("application '{}' depends on unknown application '{}'", a.name, dep));
      apps_[it->second].dependants.push_back(id);
    }
    if (a.requires_.empty()) {  // every component of its package is needed
      std::vector<std::vector<Id>> entries;
      for (Id c : apps_[id].members) entries.push_back({c});
      if (auto r = addGroup(id, entries, entries.size()); !r) return r;
    }
    for (const auto& req : a.requires_) {
      std::vector<std::vector<Id>> entries;
      for (const auto& c : req.components) {
        entries.push_back(resolve(a.name + "." + c));
        if (entries.back().empty())
          return fail(
              fmt::format("{}application '{}' requires '{}', which is not in the plan", at(req.where), a.name, c));
      }
      if (auto r = addGroup(id, entries, static_cast<std::size_t>(req.min_healthy)); !r) return r;
    }
  }
  return {};
}

// A worklist over stopped components and stopped applications; each is handled once, so
// cycles terminate. Linear in the size of the graph.
Impact DependencyGraph::impactOf(const std::set<std::string>& failed) const {
  std::vector<Id> ids;
  for (const auto& name : failed)
    if (auto it = index_.find(name); it != index_.end()) ids.push_back(it->second);
  return impactOfIds(ids);
}

Impact DependencyGraph::impactOfIds(const std::vector<Id>& failed) const {
  std::vector<bool> stopped(names_.size(), false);
  std::vector<bool> app_stopped(apps_.size(), false);
  std::vector<bool> entry_down(entries_, false);
  std::vector<std::size_t> healthy(groups_.size());
  for (Id g = 0; g < groups_.size(); ++g) healthy[g] = groups_[g].size;
  std::vector<Id> components;  // stopped, their consequences not yet followed
  std::vector<Id> apps;
  auto stopComponent = [&](Id c) {
    if (stopped[c]) return;
    stopped[c] = true;
    components.push_back(c);
  };
  auto stopApp = [&](Id a) {
    if (app_stopped[a]) return;
    app_stopped[a] = true;
    apps.push_back(a);
  };
  for (Id c : failed) stopComponent(c);
  while (!components.empty() || !apps.empty()) {
    while (!components.empty()) {
      const Id c = components.back();
      components.pop_back();
      for (Id s : dependants_[c]) stopComponent(s);
      for (const Use& u : uses_[c]) {
        if (entry_down[u.entry]) continue;  // a composite entry already down
        entry_down[u.entry] = true;
        const Group& g = groups_[u.group];
        if (--healthy[u.group] < g.min_healthy) stopApp(g.app);
      }
    }
    while (!apps.empty()) {
      const App& a = apps_[apps.back()];
      apps.pop_back();
      for (Id m : a.members) stopComponent(m);
      for (Id d : a.dependants) stopApp(d);
    }
  }
  Impact out;
  for (Id c = 0; c < names_.size(); ++c)
    if (stopped[c]) out.stopped_components.push_back(names_[c]);
  for (Id a = 0; a < apps_.size(); ++a)
    (app_stopped[a] ? out.stopped_applications : out.running_applications).push_back(apps_[a].name);
  return out;
}

std::vector<DependencyGraph::Id> DependencyGraph::scopeIds(const std::string& component, Scope scope) const {
  auto it = index_.find(component);
  if (it == index_.end()) return {};
  const Id executor = executor_of_[it->second];
  if (scope == Scope::System) {
    std::vector<Id> all(names_.size());
    for (Id c = 0; c < all.size(); ++c) all[c] = c;
    return all;
  }
  if (scope == Scope::Composite) {
    const Id composite = composite_of_[it->second];
    return composite == kNone ? std::vector<Id>{it->second} : composites_[composite];
  }
  if (scope == Scope::Component || executor == kNone) return {it->second};
  return executors_[executor];
}

std::set<std::string> DependencyGraph::scopeOf(const std::string& component, Scope scope) const {
  std::set<std::string> names;
  for (Id c : scopeIds(component, scope)) names.insert(names_[c]);
  return names;
}

Impact DependencyGraph::blastRadius(const std::string& component, Scope scope) const {
  return impactOfIds(scopeIds(component, scope));
}

Scope DependencyGraph::policyScope(const std::string& component) const {
  auto it = index_.find(component);
  return it == index_.end() ? Scope::Component : policy_scope_[it->second];
}

}  // namespace keel::fault
