// <package_profile> (alias <application_profile>): subcomponents, connections, tasks (the
// paper's executors) and coordination dependencies (docs/profiles.md). Name checks across these
// lists are in validate_assembly.cpp.
#include <fmt/format.h>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"

namespace keel::profile::detail {
namespace {

void readMember(Ctx& ctx, pugi::xml_node n, Task& task) {
  const std::string text = leafText(ctx, n, {"component"});
  const auto attr = attribute(n, "component");
  if (attr && !text.empty()) {
    ctx.error(n, fmt::format("<member> of task '{}' names a component both as attribute and as "
                             "text",
                             task.name));
    return;
  }
  std::string member = attr ? std::string(trim(*attr)) : text;
  if (member.empty()) {
    ctx.error(n, fmt::format("<member> of task '{}' names no component", task.name));
    return;
  }
  task.members.push_back(std::move(member));
}

void readTask(Ctx& ctx, pugi::xml_node node, std::vector<Task>& out) {
  Task t;
  t.where = ctx.where(node);
  t.name = attribute(node, "name").value_or("");  // read first: member messages name the task
  readChildren(ctx, node, {{"member", [&](pugi::xml_node n) { readMember(ctx, n, t); }, true}},
               {"name", "period", "priority", "policy"});
  if (!requiredAttribute(ctx, node, "name")) return;
  const std::string owner = fmt::format("task '{}'", t.name);
  if (auto period = requiredAttribute(ctx, node, "period")) {
    if (auto v = readPositive(ctx, node, *period, "period of " + owner)) t.period_ms = *v;
  }
  const auto priority = attribute(node, "priority");
  const auto p = priority ? readIntIn(ctx, node, *priority, "priority of " + owner, 0, 99) : std::optional<int>(0);
  t.priority = p.value_or(0);
  if (auto policy = attribute(node, "policy")) {
    t.policy = readWord(ctx, node, *policy, "policy of " + owner, schedPolicies()).value_or(t.policy);
  }
  if (p) {
    checkRealtimePriority(ctx, node, t.policy, t.priority, priority.has_value(), "priority of " + owner, owner);
  }
  if (t.members.empty() && !node.child("member")) {
    ctx.error(node, fmt::format("{} has no <member>", owner));
  }
  out.push_back(std::move(t));
}

std::vector<Task> parseTasks(Ctx& ctx, pugi::xml_node node) {
  std::vector<Task> out;
  readChildren(ctx, node, {{"task", [&](pugi::xml_node n) { readTask(ctx, n, out); }, true}});
  return out;
}

}  // namespace

Coordination parseCoordination(Ctx& ctx, pugi::xml_node node) {
  Coordination out;
  auto edge = [&ctx](std::vector<Depends>& into) {
    return [&ctx, &into](pugi::xml_node n) {
      readChildren(ctx, n, {}, {"source", "target"});
      const auto source = requiredAttribute(ctx, n, "source");
      const auto target = requiredAttribute(ctx, n, "target");
      if (source && target) into.push_back(Depends{*source, *target, ctx.where(n)});
    };
  };
  readChildren(ctx, node, {{"depends", edge(out.depends), true}, {"needs", edge(out.needs), true}});
  return out;
}

std::vector<Child> assemblyChildren(Ctx& ctx, std::string& name, std::string& description,
                                    std::vector<Connection>& connections, std::initializer_list<Child> own) {
  std::vector<Child> all(own);
  all.insert(all.end(),
             {{"name", [&ctx, &name](pugi::xml_node n) { name = leafText(ctx, n); }},
              {"description", [&ctx, &description](pugi::xml_node n) { description = leafText(ctx, n); }},
              {"port_connections", [&ctx, &connections](pugi::xml_node n) { connections = parseConnections(ctx, n); }},
              {"id", {}},
              {"version", {}},
              {"copyright", {}}});
  return all;
}

void parsePackageProfile(Ctx& ctx, pugi::xml_node root, PackageProfile& out) {
  out.where = ctx.where(root);
  readChildren(
      ctx, root,
      assemblyChildren(ctx, out.name, out.description, out.connections,
                       {{"subcomponents", [&](pugi::xml_node n) { out.subcomponents = parseSubcomponents(ctx, n); }},
                        {"tasks", [&](pugi::xml_node n) { out.tasks = parseTasks(ctx, n); }},
                        {"coordination", [&](pugi::xml_node n) { out.coordination = parseCoordination(ctx, n); }},
                        {"dds", [&](pugi::xml_node n) { out.dds = parseDds(ctx, n); }},
                        {"topics", {}, false, "OPRoS reserved it for topic-based events, which it never delivered"},
                        {"app_domain", {}, false, kNoAppDomain},
                        {"execution_environment", {}, false, kNoAssemblyEnvironment}}));
  if (out.name.empty()) reportMissing(ctx, root, "name");
}

}  // namespace keel::profile::detail
