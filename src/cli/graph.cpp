// keel graph PROFILE.xml: the structure of a package or system profile as Graphviz DOT:
// instances grouped by executor (tasks) or application, data/event/service connections and
// dependencies. Nothing is loaded or run. (The blast radius, --fail, comes with the fault
// manager.)
#include <fmt/format.h>

#include <iostream>
#include <map>

#include "cli/commands.hpp"
#include "profile/loader.hpp"
#include "runtime/plan.hpp"

namespace keel::cli {
namespace {

std::string quote(const std::string& s) { return "\"" + s + "\""; }

int graph(const std::string& file) {
  auto set = profile::load(file);
  if (!set) {
    for (const auto& d : set.error()) std::cerr << d.str() << '\n';
    return 2;
  }
  auto plan = runtime::makePlan(*set);
  if (!plan) {
    std::cerr << plan.error().message << '\n';
    return 2;
  }
  std::string out = fmt::format("digraph {} {{\n  rankdir=LR;\n  node [shape=box, style=rounded];\n",
                                quote(plan->name));
  std::map<std::string, std::vector<std::string>> by_app;
  for (const auto& i : plan->instances) by_app[i.application].push_back(i.name);
  int cluster = 0;
  for (const auto& [app, names] : by_app) {
    if (!app.empty()) out += fmt::format("  subgraph cluster_{} {{\n    label={};\n", cluster++, quote(app));
    for (const auto& ex : plan->executors) {
      std::vector<std::string> here;
      for (const auto& m : ex.members)
        if (std::find(names.begin(), names.end(), m) != names.end()) here.push_back(m);
      if (here.empty()) continue;
      std::string label = ex.periodic ? fmt::format("{} ({} ms)", ex.name, ex.period_ms) : ex.name + " (aperiodic)";
      out += fmt::format("    subgraph cluster_{} {{\n      label={}; style=dashed;\n", cluster++, quote(label));
      for (const auto& m : here) out += fmt::format("      {};\n", quote(m));
      out += "    }\n";
    }
    for (const auto& n : names) {
      bool in_executor = false;
      for (const auto& ex : plan->executors)
        in_executor |= std::find(ex.members.begin(), ex.members.end(), n) != ex.members.end();
      if (!in_executor) out += fmt::format("    {} [style=\"rounded,dotted\"];\n", quote(n));
    }
    if (!app.empty()) out += "  }\n";
  }
  for (const auto& c : plan->connections) {
    const char* style = c.type == profile::PortType::Data ? "solid" : c.type == profile::PortType::Event ? "dashed" : "bold";
    out += fmt::format("  {} -> {} [label={}, style={}];\n", quote(c.source.component), quote(c.target.component),
                       quote(c.source.port + " → " + c.target.port), style);
  }
  for (const auto& d : plan->depends)
    out += fmt::format("  {} -> {} [label=\"depends\", style=dotted, color=gray40];\n", quote(d.source), quote(d.target));
  if (set->system) {  // applications as nodes of their own, with their dependencies
    for (const auto& app : set->system->applications) {
      out += fmt::format("  {} [shape=folder, label={}];\n", quote("app:" + app.name), quote(app.name));
      for (const auto& dep : app.depends_on)
        out += fmt::format("  {} -> {} [label=\"depends_on\", style=dotted];\n", quote("app:" + app.name),
                           quote("app:" + dep));
    }
  }
  out += "}\n";
  std::cout << out;
  return 0;
}

}  // namespace

void addGraphCommand(CLI::App& app, std::function<int()>& run) {
  auto file = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("graph", "Print the component graph of a profile (Graphviz DOT)");
  cmd->add_option("profile", *file, "package_profile or system_profile XML")->required();
  cmd->callback([file, &run] { run = [file] { return graph(*file); }; });
}

}  // namespace keel::cli
