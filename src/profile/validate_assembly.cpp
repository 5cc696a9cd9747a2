// Checks of an assembly (package or composite): unique subcomponent names, property overrides
// typed against the referenced component, tasks and coordination dependencies.
#include <algorithm>
#include <sstream>

#include <fmt/format.h>

#include "profile/field_reader.hpp"
#include "profile/validate.hpp"

namespace keel::profile::detail {
namespace {

void error(Diagnostics& diags, const Where& where, std::string message) {
  diags.push_back(Diagnostic{where, std::move(message)});
}

/// Types the override `o` of subcomponent `sub` against the declaration in `component`.
void typeOverride(const ComponentProfile& component, const Subcomponent& sub, Property& o, Diagnostics& diags) {
  const Property* decl = nullptr;
  std::vector<std::string> names;
  for (const Property& p : component.properties) {
    names.push_back(p.name);
    if (p.name == o.name) decl = &p;
  }
  if (decl == nullptr) {
    return error(diags, o.where,
                 fmt::format("subcomponent '{}': component '{}' has no property '{}' (properties: {})", sub.name,
                             component.name, o.name, nameList(names)));
  }
  if (decl->type.empty()) return;  // its declaration is broken and already reported
  if (!o.type.empty() && o.type != decl->type) {
    return error(diags, o.where,
                 fmt::format("property '{}' of subcomponent '{}' has type '{}' but component '{}' "
                             "declares it '{}'",
                             o.name, sub.name, o.type, component.name, decl->type));
  }
  const auto* text = std::get_if<std::string>(&o.value);
  if (text == nullptr) return;  // already typed
  auto value = parsePropertyValue(decl->type, *text);
  if (!value) {
    return error(diags, o.where,
                 fmt::format("property '{}' of subcomponent '{}' must be {}, got '{}'", o.name, sub.name,
                             describeType(decl->type), *text));
  }
  o.type = decl->type;
  o.value = std::move(*value);
}

void checkOverrides(const ProfileSet& set, Subcomponent& sub, Diagnostics& diags) {
  if (sub.property_overrides.empty()) return;
  if (const auto c = set.components.find(sub.reference); c != set.components.end()) {
    for (auto& [name, o] : sub.property_overrides) typeOverride(c->second, sub, o, diags);
    return;
  }
  if (const auto c = set.composites.find(sub.reference); c != set.composites.end()) {
    for (const auto& [name, o] : sub.property_overrides) {
      error(diags, o.where,
            fmt::format("subcomponent '{}': composite '{}' has no property '{}' (properties: none)", sub.name,
                        c->second.name, name));
    }
  }
}

/// The data ports of subcomponent `sub`'s component or node; null for a composite (or an
/// unresolved reference, reported elsewhere).
const std::vector<DataPort>* dataPortsOf(const ProfileSet& set, const Subcomponent& sub) {
  if (const auto c = set.components.find(sub.reference); c != set.components.end()) return &c->second.data_ports;
  if (const auto n = set.nodes.find(sub.reference); n != set.nodes.end()) return &n->second.component.data_ports;
  return nullptr;
}

/// A property declared refers="ports" names numeric output ports of the subcomponents beside
/// `sub`, each `[name=]subcomponent.port`: each must be there.
void checkPortReferences(const ProfileSet& set, const std::vector<Subcomponent>& subs, const Subcomponent& sub,
                         Diagnostics& diags) {
  const auto c = set.components.find(sub.reference);
  if (c == set.components.end()) return;
  for (const Property& decl : c->second.properties) {
    if (decl.refers.empty()) continue;
    const auto o = sub.property_overrides.find(decl.name);
    const Property& given = o != sub.property_overrides.end() ? o->second : decl;
    const auto* text = std::get_if<std::string>(&given.value);
    if (text == nullptr) continue;  // mistyped: reported
    std::istringstream words(*text);
    for (std::string word; words >> word;) {
      const std::string ref = word.substr(word.find('=') == std::string::npos ? 0 : word.find('=') + 1);
      const auto dot = ref.find('.');
      auto say = [&](const std::string& why) {
        error(diags, given.where,
              fmt::format("property '{}' of subcomponent '{}': '{}' {}", decl.name, sub.name, word, why));
      };
      if (dot == std::string::npos || dot == 0 || dot + 1 == ref.size()) {
        say("is not [name=]subcomponent.port");
        continue;
      }
      const std::string owner = ref.substr(0, dot), port = ref.substr(dot + 1);
      const auto other = std::find_if(subs.begin(), subs.end(), [&](const Subcomponent& s) { return s.name == owner; });
      if (other == subs.end()) {
        std::vector<std::string> names;
        names.reserve(subs.size());
        for (const auto& s : subs) names.push_back(s.name);
        say(fmt::format("names no subcomponent '{}' (subcomponents: {})", owner, nameList(names)));
        continue;
      }
      const std::vector<DataPort>* ports = dataPortsOf(set, *other);
      if (ports == nullptr) continue;
      std::vector<std::string> outputs;
      const DataPort* found = nullptr;
      for (const DataPort& d : *ports) {
        if (d.usage == PortDirection::Output) outputs.push_back(d.name);
        if (d.name == port) found = &d;
      }
      if (found == nullptr || found->usage != PortDirection::Output) {
        say(fmt::format("names no output port '{}' of subcomponent '{}' (its output ports: {})", port, owner,
                        outputs.empty() ? std::string("none") : nameList(outputs)));
        continue;
      }
      const auto type = normalisePropertyType(found->data_type);
      if (!type || (*type != "int" && *type != "double"))
        say(fmt::format("is not numeric: port '{}' of subcomponent '{}' carries '{}'", port, owner, found->data_type));
    }
  }
}

/// <attach/> watches a node someone else started: only a node can be attached to.
void checkAttach(const ProfileSet& set, const Subcomponent& sub, Diagnostics& diags) {
  if (!sub.attach || set.nodes.count(sub.reference) > 0) return;
  const char* kind = set.composites.count(sub.reference) > 0 ? "composite" : "component";
  if (set.components.count(sub.reference) == 0 && set.composites.count(sub.reference) == 0) return;  // reported
  error(diags, *sub.attach,
        fmt::format("<attach/> of subcomponent '{}': {} '{}' is not a ROS 2 node (keel attaches to a node someone "
                    "else started; its reference must be a <ros2_node_profile>)",
                    sub.name, kind, profileName(set, sub.reference)));
}

/// Two subcomponents that are one ROS 2 node: keel would start, or watch, one name twice.
void checkSameNode(const ProfileSet& set, const std::vector<Subcomponent>& subs, std::size_t i, Diagnostics& diags) {
  const auto node = set.nodes.find(subs[i].reference);
  if (node == set.nodes.end() || node->second.node_name.empty()) return;  // not a node, or its <node> is reported
  for (std::size_t j = 0; j < i; ++j) {
    const auto other = set.nodes.find(subs[j].reference);
    if (other == set.nodes.end() || other->second.fullName() != node->second.fullName()) continue;
    return error(diags, subs[i].where,
                 fmt::format("subcomponents '{}' (line {}) and '{}' are both ROS 2 node '{}' (one node, one "
                             "subcomponent)",
                             subs[j].name, subs[j].where.line, subs[i].name, node->second.fullName()));
  }
}

const ComponentProfile* componentOf(const ProfileSet& set, const PackageProfile& pkg, const std::string& member) {
  const Subcomponent* sub = findSubcomponent(pkg.subcomponents, member);
  if (sub == nullptr) return nullptr;
  const auto c = set.components.find(sub->reference);
  return c == set.components.end() ? nullptr : &c->second;
}

}  // namespace

void checkSubcomponents(ProfileSet& set, std::vector<Subcomponent>& subs, Diagnostics& diags) {
  for (std::size_t i = 0; i < subs.size(); ++i) {
    if (subs[i].name == kFaultManager)
      error(diags, subs[i].where,
            fmt::format("subcomponent name '{}' is reserved for keel's fault "
                        "manager",
                        subs[i].name));
    for (std::size_t j = 0; j < i; ++j) {
      if (subs[j].name == subs[i].name) {
        error(diags, subs[i].where,
              fmt::format("duplicate subcomponent '{}' (first at line {})", subs[i].name, subs[j].where.line));
        break;
      }
    }
    checkOverrides(set, subs[i], diags);
    checkPortReferences(set, subs, subs[i], diags);
    checkAttach(set, subs[i], diags);
    checkSameNode(set, subs, i, diags);
  }
}

void checkTasks(const ProfileSet& set, const PackageProfile& pkg, Diagnostics& diags) {
  std::map<std::string, const Task*> task_of;  // member -> its task
  for (std::size_t i = 0; i < pkg.tasks.size(); ++i) {
    const Task& t = pkg.tasks[i];
    for (std::size_t j = 0; j < i; ++j) {
      if (pkg.tasks[j].name == t.name) {
        error(diags, t.where, fmt::format("duplicate task '{}' (first at line {})", t.name, pkg.tasks[j].where.line));
      }
    }
    for (const std::string& m : t.members) {
      if (findSubcomponent(pkg.subcomponents, m) == nullptr) {
        error(diags, t.where,
              fmt::format("task '{}': no subcomponent '{}' (subcomponents: {})", t.name, m,
                          subcomponentNames(pkg.subcomponents)));
        continue;
      }
      const auto [it, inserted] = task_of.emplace(m, &t);
      if (!inserted) {
        error(diags, t.where,
              it->second == &t ? fmt::format("task '{}' lists member '{}' twice", t.name, m)
                               : fmt::format("task '{}': subcomponent '{}' is already in task '{}' (line {})", t.name,
                                             m, it->second->name, it->second->where.line));
        continue;
      }
      const ComponentProfile* c = componentOf(set, pkg, m);
      if (c != nullptr && set.nodes.count(c->file) > 0) {
        error(diags, t.where,
              fmt::format("task '{}': subcomponent '{}' is a ROS 2 node (node profile '{}') and cannot be a task "
                          "member: it runs in a process of its own",
                          t.name, m, c->name));
      } else if (c != nullptr && c->execution.type == ExecutionType::Passive) {
        error(diags, t.where,
              fmt::format("task '{}': subcomponent '{}' is passive (component '{}') and cannot be "
                          "a task member",
                          t.name, m, c->name));
      }
    }
  }
}

namespace {

/// One list of a <coordination>: both ends are subcomponents, no self-edge, no duplicate, no
/// cycle (an execution order in a cycle never runs; a stop dependency in one is meaningless).
void checkEdges(const std::vector<Subcomponent>& subs, const std::vector<Depends>& list, std::string_view element,
                Diagnostics& diags) {
  Graph graph;
  for (const Subcomponent& s : subs) graph.emplace_back(s.name, std::vector<Edge>{});
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Depends& d = list[i];
    bool ok = true;
    for (const std::string* end : {&d.source, &d.target}) {
      if (findSubcomponent(subs, *end) != nullptr) continue;
      ok = false;
      error(diags, d.where,
            fmt::format("{}: no subcomponent '{}' (subcomponents: {})", element, *end, subcomponentNames(subs)));
    }
    if (ok && d.source == d.target) {
      ok = false;
      error(diags, d.where, fmt::format("{}: subcomponent '{}' cannot depend on itself", element, d.source));
    }
    for (std::size_t j = 0; ok && j < i; ++j) {
      const Depends& e = list[j];
      if (e.source == d.source && e.target == d.target) {
        ok = false;
        error(diags, d.where,
              fmt::format("duplicate {} '{}' -> '{}' (first at line {})", element, d.source, d.target, e.where.line));
      }
    }
    if (!ok) continue;
    for (auto& [node, edges] : graph) {
      if (node == d.source) edges.push_back(Edge{d.target, d.where});
    }
  }
  reportCycles(graph, diags);
}

/// The execution type of subcomponent `name`'s component; nullopt for a composite.
std::optional<ExecutionType> executionOf(const ProfileSet& set, const std::vector<Subcomponent>& subs,
                                         const std::string& name) {
  const Subcomponent* s = findSubcomponent(subs, name);
  if (s == nullptr) return std::nullopt;
  const auto c = set.components.find(s->reference);
  if (c == set.components.end()) return std::nullopt;
  return c->second.execution.type;
}

}  // namespace

void checkCoordination(ProfileSet& set, const std::vector<Subcomponent>& subs, const Coordination& coordination,
                       Diagnostics& diags) {
  checkEdges(subs, coordination.depends, "depends", diags);
  checkEdges(subs, coordination.needs, "needs", diags);
  for (const Depends& d : coordination.depends) {  // OPRoS's execution order with a passive end
    if (executionOf(set, subs, d.target) == ExecutionType::Passive)
      set.warnings.push_back(
          {d.where, fmt::format("depends: '{}' is passive and never executes, so '{}', which executes after it, "
                                "never executes either (OPRoS's execution order; <needs> is keel's stop dependency)",
                                d.target, d.source)});
    else if (executionOf(set, subs, d.source) == ExecutionType::Passive)
      set.warnings.push_back(
          {d.where, fmt::format("depends has no effect: '{}' is passive, and OPRoS's execution order orders "
                                "executions (<needs> is keel's stop dependency)",
                                d.source)});
  }
}

void checkIneffectivePolicies(ProfileSet& set, const std::vector<Subcomponent>& subs, const DdsSpec* dds) {
  for (const Subcomponent& sub : subs) {
    if (!sub.fault_policy) continue;
    const FaultPolicy& p = *sub.fault_policy;
    const bool subscribes = dds && std::any_of(dds->bindings.begin(), dds->bindings.end(), [&](const DdsBinding& b) {
                              return !b.publish && b.endpoint.component == sub.name;
                            });
    const bool node = set.nodes.count(sub.reference) > 0;
    if (const auto it = p.severity_kind_where.find("remote"); it != p.severity_kind_where.end() && !subscribes && !node)
      set.warnings.push_back({it->second, fmt::format("<severity kind=\"remote\"> of subcomponent '{}' has no effect: "
                                                      "remote faults come from its DDS subscriptions, and this "
                                                      "profile's <dds> has no <subscribe> of it",
                                                      sub.name)});
    // A node is a passive component to keel's engine, but its heartbeat and deadline are the
    // node supervisor's to give a meaning; and its remote faults do not come from a <dds>.
    const auto c = set.components.find(sub.reference);
    if (c == set.components.end() || c->second.execution.type != ExecutionType::Passive || set.nodes.count(c->first))
      continue;
    if (p.heartbeat_timeout_ms)
      set.warnings.push_back({p.heartbeat_where, fmt::format("<heartbeat> of subcomponent '{}' has no effect: '{}' is "
                                                             "passive, and its calls run on their callers' threads, "
                                                             "whose own heartbeat sees a call that hangs",
                                                             sub.name, c->second.name)});
    if (p.deadline_ms)
      set.warnings.push_back({p.deadline_where, fmt::format("<deadline> of subcomponent '{}' has no effect: '{}' is "
                                                            "passive, and a deadline bounds onExecute, which only an "
                                                            "executor calls",
                                                            sub.name, c->second.name)});
  }
}

}  // namespace keel::profile::detail
