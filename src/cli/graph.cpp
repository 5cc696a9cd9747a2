// keel graph PROFILE.xml [--fail COMPONENT]... [--scope component|executor|composite|system]: the structure
// of a package or system profile as Graphviz DOT — applications as clusters (with what each
// needs and the applications it depends on), executors (tasks) inside them, data/event/service
// connections and coordination dependencies; a ROS 2 node an ellipse with its ROS 2 name. With --fail, the blast radius
// of a fault stop of that component (fault::DependencyGraph): drawn on the graph, and summarised on stderr and in a
// comment at the top of the DOT. Nothing is loaded or run.
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <map>
#include <optional>
#include <set>

#include "cli/commands.hpp"
#include "fault/dependency_graph.hpp"
#include "plan/plan.hpp"
#include "profile/loader.hpp"

namespace keel::cli {
namespace {

struct Options {
  std::string file;
  std::vector<std::string> fail;
  std::string scope;  // empty: each failed component's own fault policy
};

/// The blast radius drawn on the graph; empty without --fail.
struct Marks {
  std::set<std::string> failed;
  std::set<std::string> stopped;  // components, the failed ones included
  std::set<std::string> stopped_applications;
};

constexpr const char* kFailedStyle = "fillcolor=\"#e06666\", color=red3, penwidth=2";
constexpr const char* kStoppedStyle = "fillcolor=\"#f6b26b\"";

/// `s` inside a DOT string.
std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

std::string quote(const std::string& s) { return "\"" + escape(s) + "\""; }

std::string list(const std::vector<std::string>& names) { return fmt::format("[{}]", fmt::join(names, ", ")); }

std::optional<profile::Scope> parseScope(const std::string& s) {
  for (auto scope :
       {profile::Scope::Component, profile::Scope::Executor, profile::Scope::Composite, profile::Scope::System})
    if (s == profile::toString(scope)) return scope;
  return std::nullopt;
}

/// A component node; `loose`: on no executor (passive); `more`: its other attributes (", a=b").
std::string node(const std::string& name, bool loose, const Marks& marks, const std::string& indent,
                 const std::string& more = "") {
  std::string style = loose ? "rounded,dotted" : "rounded";
  std::string extra;
  if (marks.failed.count(name)) {
    style += ",filled";
    extra = std::string(", ") + kFailedStyle;
  } else if (marks.stopped.count(name)) {
    style += ",filled";
    extra = std::string(", ") + kStoppedStyle;
  }
  if (style == "rounded" && more.empty()) return fmt::format("{}{};\n", indent, quote(name));
  return fmt::format("{}{} [style={}{}{}];\n", indent, quote(name), quote(style), extra, more);
}

/// A ROS 2 node's look: an ellipse, its ROS 2 name under its own (nothing for a component).
std::string rosNodeLook(const plan::Plan& plan, const std::string& name) {
  const plan::PlannedInstance* pi = plan.find(name);
  if (pi == nullptr || pi->node == nullptr) return {};
  return fmt::format(", shape=ellipse, label=\"{}\\n{} (ROS 2 node{})\"", escape(name), escape(pi->node->fullName()),
                     pi->attached ? ", attached" : "");
}

/// The executors (dashed clusters) running `names`, then the passive ones among them.
std::string components(const plan::Plan& plan, const std::vector<std::string>& names, int& cluster, const Marks& marks,
                       const std::string& indent) {
  std::string out;
  std::set<std::string> placed;
  for (const auto& ex : plan.executors) {
    std::vector<std::string> here;
    for (const auto& m : ex.members)
      if (std::find(names.begin(), names.end(), m) != names.end()) here.push_back(m);
    if (here.empty()) continue;
    const std::string label = ex.periodic ? fmt::format("{} ({} ms)", ex.name, ex.period_ms) : ex.name + " (aperiodic)";
    out += fmt::format("{}subgraph cluster_{} {{\n{}  label={}; style=dashed;\n", indent, cluster++, indent,
                       quote(label));
    for (const auto& m : here) out += node(m, false, marks, indent + "  ");
    out += indent + "}\n";
    placed.insert(here.begin(), here.end());
  }
  for (const auto& n : names)
    if (!placed.count(n)) out += node(n, true, marks, indent, rosNodeLook(plan, n));
  return out;
}

/// The label of an application's node: its name, then what it needs to run, one line
/// ("1 of {b1, b2, b3}") per requirement group. Already escaped, with DOT line breaks.
std::string appLabel(const profile::Application& app) {
  std::string out = "\"" + escape(app.name);
  if (app.requires_.empty()) out += "\\nneeds every component";
  for (const auto& r : app.requires_) {
    const bool all = r.min_healthy == static_cast<int>(r.components.size());
    out += fmt::format("\\n{} of {{{}}}", all ? std::string("all") : std::to_string(r.min_healthy),
                       escape(fmt::format("{}", fmt::join(r.components, ", "))));
  }
  return out + "\"";
}

/// Each application a cluster holding a node that stands for it (shape folder), so that the
/// depends_on edges join real nodes; compound edges are clipped at the clusters' borders.
std::string applications(const plan::Plan& plan, const profile::SystemProfile& system, int& cluster,
                         const Marks& marks) {
  std::string out;
  std::map<std::string, int> cluster_of;
  for (const auto& app : system.applications) {
    std::vector<std::string> names;
    for (const auto& i : plan.instances)
      if (i.application == app.name) names.push_back(i.name);
    const bool stopped = marks.stopped_applications.count(app.name) != 0;
    cluster_of[app.name] = cluster;
    out += fmt::format("  subgraph cluster_{} {{\n    label={};{}\n", cluster++,
                       quote(stopped ? app.name + " (stopped)" : app.name),
                       stopped ? " style=filled; fillcolor=gray90;" : "");
    out += fmt::format("    {} [shape=folder, label={}{}];\n", quote("app:" + app.name), appLabel(app),
                       stopped ? std::string(", style=filled, ") + kStoppedStyle : "");
    out += components(plan, names, cluster, marks, "    ");
    out += "  }\n";
  }
  for (const auto& app : system.applications)
    for (const auto& dep : app.depends_on)
      out += fmt::format("  {} -> {} [label=\"depends_on\", style=dotted, ltail=cluster_{}, lhead=cluster_{}];\n",
                         quote("app:" + app.name), quote("app:" + dep), cluster_of[app.name], cluster_of[dep]);
  return out;
}

std::string dot(const plan::Plan& plan, const profile::ProfileSet& set, const Marks& marks,
                const std::string& summary) {
  std::string out = fmt::format("digraph {} {{\n", quote(plan.name));
  if (!summary.empty()) out += "  // keel graph --fail\n  // " + summary + "\n";
  out += "  rankdir=LR; compound=true;\n  node [shape=box, style=rounded];\n";
  int cluster = 0;
  std::vector<std::string> outside;  // in no application: a package's, or the fault manager
  for (const auto& i : plan.instances)
    if (!set.system || i.application.empty()) outside.push_back(i.name);
  if (set.system) out += applications(plan, *set.system, cluster, marks);
  out += components(plan, outside, cluster, marks, "  ");
  for (const auto& c : plan.connections) {
    const char* style = c.type == PortKind::Data ? "solid" : c.type == PortKind::Event ? "dashed" : "bold";
    out += fmt::format("  {} -> {} [label={}, style={}];\n", quote(c.source.component), quote(c.target.component),
                       quote(c.source.port + (c.source.field.empty() ? "" : "." + c.source.field) + " → " +
                             c.target.port),
                       style);
  }
  for (const auto& d : plan.depends)
    out += fmt::format("  {} -> {} [label=\"depends\", style=dotted, color=gray40];\n", quote(d.source),
                       quote(d.target));
  return out + "}\n";
}

/// Fills `marks` with the blast radius of a fault stop of each of `o.fail`; returns the summary
/// line, or nothing after printing why the blast radius cannot be drawn.
std::optional<std::string> blastRadius(const Options& o, const plan::Plan& plan, const profile::ProfileSet& set,
                                       Marks& marks) {
  auto graph = fault::DependencyGraph::build(plan, set);
  if (!graph) {
    std::cerr << "keel graph: " << graph.error().message << '\n';
    return std::nullopt;
  }
  std::set<std::string> scope;
  std::vector<std::string> where;
  for (const auto& c : o.fail) {
    if (!graph->contains(c)) {
      std::cerr << fmt::format("keel graph: no component '{}' in '{}' (components: {})\n", c, plan.name,
                               fmt::join(graph->components(), ", "));
      return std::nullopt;
    }
    const auto s = o.scope.empty() ? graph->policyScope(c) : *parseScope(o.scope);
    auto members = graph->scopeOf(c, s);
    scope.insert(members.begin(), members.end());
    where.push_back(fmt::format("{} (scope {})", c, profile::toString(s)));
    marks.failed.insert(c);
  }
  const fault::Impact impact = graph->impactOf(scope);
  marks.stopped.insert(impact.stopped_components.begin(), impact.stopped_components.end());
  marks.stopped_applications.insert(impact.stopped_applications.begin(), impact.stopped_applications.end());
  return fmt::format("{} {}: stops components {}; stops applications {}; keeps running {}",
                     where.size() == 1 ? "fault at" : "faults at", fmt::join(where, ", "),
                     list(impact.stopped_components), list(impact.stopped_applications),
                     list(impact.running_applications));
}

int graph(const Options& o) {
  auto set = profile::load(o.file);
  if (!set) {
    for (const auto& d : set.error()) std::cerr << d.str() << '\n';
    return 2;
  }
  auto plan = plan::makePlan(*set);
  if (!plan) {
    std::cerr << plan.error().message << '\n';
    return 2;
  }
  Marks marks;
  std::string summary;
  if (!o.fail.empty()) {
    auto s = blastRadius(o, *plan, *set, marks);
    if (!s) return 2;
    summary = *s;
    std::cerr << summary << '\n';
  }
  std::cout << dot(*plan, *set, marks, summary);
  return 0;
}

}  // namespace

void addGraphCommand(CLI::App& app, std::function<int()>& run) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("graph", "Print the component graph of a profile (Graphviz DOT)");
  cmd->add_option("profile", o->file, "package_profile or system_profile XML")->required();
  auto* fail = cmd->add_option("--fail", o->fail,
                               "Show what a fault stop of this component stops (the blast radius); repeatable")
                   ->allow_extra_args(false);
  cmd->add_option("--scope", o->scope, "Containment scope of the fault (default: the component's fault policy)")
      ->check(CLI::IsMember({"component", "executor", "composite", "system"}))
      ->needs(fail);
  cmd->callback([o, &run] { run = [o] { return graph(*o); }; });
}

}  // namespace keel::cli
