// <ros2_node_profile>: a ROS 2 node keel starts and watches (docs/profiles.md#ros-2-node-profile).
// Read here: its identity, <command> (split and its program found: command_line.hpp), <node>
// (ROS 2's name rules: ros2_names.hpp), <environment>, <parameters>, the start and stop times,
// <diagnostics>; its <ports> and <emergency> are read by node_ports.cpp. The node is also made
// the passive component keel's engine sees (NodeProfile::component).
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "profile/command_line.hpp"
#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"
#include "profile/ros2_names.hpp"

namespace keel::profile::detail {
namespace {

struct NodeReader {
  Ctx& ctx;
  NodeProfile& out;
  std::string owner;  // "node profile 'Wander'"
  pugi::xml_node command;
  pugi::xml_node node;

  void variable(pugi::xml_node n) {
    readChildren(ctx, n, {}, {"name", "value"});
    const auto name = requiredAttribute(ctx, n, "name");
    const auto value = requiredAttribute(ctx, n, "value");
    if (!name || !value) return;
    if (const std::string why = environmentNameProblem(*name); !why.empty())
      return ctx.error(n, fmt::format("name '{}' of <variable> of {} is not an environment variable's name: {}", *name,
                                      owner, why));
    if (*name == "ROS_DOMAIN_ID")
      return ctx.error(n, fmt::format("<variable> ROS_DOMAIN_ID of {}: keel sets it, to the DDS domain keel itself "
                                      "is on, so that keel sees the node",
                                      owner));
    for (const EnvironmentVariable& v : out.environment)
      if (v.name == *name)
        return ctx.error(n,
                         fmt::format("duplicate <variable> '{}' in {} (first at line {})", *name, owner, v.where.line));
    out.environment.push_back({*name, *value, ctx.where(n)});
  }

  void parameter(pugi::xml_node n) {
    const std::string value = leafText(ctx, n, {"name"});
    const auto name = requiredAttribute(ctx, n, "name");
    if (!name) return;
    if (const std::string why = parameterNameProblem(*name); !why.empty())
      return ctx.error(n,
                       fmt::format("parameter name '{}' of {} is not a ROS 2 parameter name: {}", *name, owner, why));
    for (const NodeParameter& p : out.parameters)
      if (p.name == *name)
        return ctx.error(n,
                         fmt::format("duplicate parameter '{}' in {} (first at line {})", *name, owner, p.where.line));
    out.parameters.push_back({*name, value, ctx.where(n)});
  }

  /// <start timeout=".."/>, <stop grace=".."/>: a required time in ms.
  void duration(pugi::xml_node n, const char* attr, double& into) {
    readChildren(ctx, n, {}, {attr});
    const auto text = requiredAttribute(ctx, n, attr);
    if (!text) return;
    if (auto v = readPositive(ctx, n, trim(*text), fmt::format("{} of {} of {}", attr, tag(n), owner))) into = *v;
  }

  void diagnostics(pugi::xml_node n) {
    readChildren(ctx, n, {}, {"name"});
    const auto name = requiredAttribute(ctx, n, "name");
    if (!name) return;
    out.diagnostics_name = std::string(trim(*name));
    if (out.diagnostics_name.empty()) ctx.error(n, fmt::format("<diagnostics> of {}: empty name", owner));
  }

  /// <lifecycle transition_timeout=".."/>: a managed node, its transitions' time (ms, optional).
  void lifecycle(pugi::xml_node n) {
    readChildren(ctx, n, {}, {"transition_timeout"});
    NodeLifecycle l;
    l.where = ctx.where(n);
    if (const auto text = attribute(n, "transition_timeout"))
      if (auto v = readPositive(ctx, n, trim(*text), fmt::format("transition_timeout of <lifecycle> of {}", owner)))
        l.transition_timeout_ms = *v;
    out.lifecycle = l;
  }

  /// <node>: "/ns/name", split; what is wrong with it named in rmw's words.
  void nodeName() {
    out.node_where = ctx.where(node);
    const std::string text = leafText(ctx, node);
    auto bad = [&](std::string_view why) {
      ctx.error(node, fmt::format("<node> '{}' of {} is not a fully qualified node name: {}", text, owner, why));
    };
    if (text.empty()) return ctx.error(node, fmt::format("empty <node> in {}", owner));
    if (text.front() != '/')
      return bad(fmt::format("it must lead with a '/' and the node's namespace ('/{}' in the root namespace)", text));
    if (text.find("//") != std::string::npos) return bad("namespace must not contain repeated '/'");
    const std::size_t last = text.rfind('/');
    const std::string ns = last == 0 ? "/" : text.substr(0, last);
    const std::string name = text.substr(last + 1);
    if (const std::string why = namespaceProblem(ns); !why.empty()) return bad(why);
    if (const std::string why = nodeNameProblem(name); !why.empty()) return bad(why);
    out.node_namespace = ns;
    out.node_name = name;
  }

  /// <command>: its words, and its program made an absolute path on the node's PATH.
  void commandLine() {
    out.command_where = ctx.where(command);
    const std::string text = leafText(ctx, command);
    if (text.empty()) return ctx.error(command, fmt::format("empty <command> in {}", owner));
    auto words = splitCommand(text);
    if (!words) return ctx.error(command, fmt::format("<command> of {}: {}", owner, words.error().message));
    if (words->empty()) return ctx.error(command, fmt::format("empty <command> in {}", owner));
    out.command = std::move(*words);
    std::optional<std::string> path;
    std::string path_from = "keel's PATH";
    const auto set = std::find_if(out.environment.begin(), out.environment.end(),
                                  [](const EnvironmentVariable& v) { return v.name == "PATH"; });
    if (set != out.environment.end()) {
      path = set->value;
      path_from = fmt::format("the PATH of its <environment> (line {})", set->where.line);
    } else if (const char* keel_path = std::getenv("PATH")) {
      path = keel_path;
    }
    const std::string folder = std::filesystem::path(out.file).parent_path().string();
    auto program = findExecutable(out.command.front(), path, path_from, folder);
    if (!program) return ctx.error(command, fmt::format("<command> of {}: {}", owner, program.error().message));
    out.executable = std::move(*program);
  }

  /// The node as a passive component with the node's data ports (read into it by parseNodePorts).
  void component() {
    ComponentProfile& c = out.component;
    c.file = out.file;
    c.name = out.name;
    c.description = out.description;
    c.where = out.where;
    c.execution.type = ExecutionType::Passive;
    c.execution.where = out.where;
  }
};

}  // namespace

void parseNodeProfile(Ctx& ctx, pugi::xml_node root, NodeProfile& out) {
  out.where = ctx.where(root);
  out.name = std::string(trim(root.child("name").child_value()));
  NodeReader r{ctx, out, out.name.empty() ? tag(root) : fmt::format("node profile '{}'", out.name), {}, {}};
  pugi::xml_node ports, emergency;
  readChildren(ctx, root,
               {{"name", [&](pugi::xml_node n) { out.name = leafText(ctx, n); }},
                {"description", [&](pugi::xml_node n) { out.description = leafText(ctx, n); }},
                {"command", [&](pugi::xml_node n) { r.command = n; }},
                {"node", [&](pugi::xml_node n) { r.node = n; }},
                {"environment",
                 [&](pugi::xml_node n) {
                   readChildren(ctx, n, {{"variable", [&](pugi::xml_node v) { r.variable(v); }, true}});
                 }},
                {"parameters",
                 [&](pugi::xml_node n) {
                   readChildren(ctx, n, {{"parameter", [&](pugi::xml_node p) { r.parameter(p); }, true}});
                 }},
                {"start", [&](pugi::xml_node n) { r.duration(n, "timeout", out.start_timeout_ms); }},
                {"stop", [&](pugi::xml_node n) { r.duration(n, "grace", out.stop_grace_ms); }},
                {"diagnostics", [&](pugi::xml_node n) { r.diagnostics(n); }},
                {"lifecycle", [&](pugi::xml_node n) { r.lifecycle(n); }},
                {"ports", [&](pugi::xml_node n) { ports = n; }},
                {"emergency", [&](pugi::xml_node n) { emergency = n; }}});
  if (out.name.empty()) reportMissing(ctx, root, "name");
  // The command after the environment, whose PATH it is looked up on, wherever each is written.
  if (r.command) r.commandLine();
  else reportMissing(ctx, root, "command", r.owner);
  if (r.node) r.nodeName();
  else reportMissing(ctx, root, "node", r.owner);
  r.component();
  // The ports before the emergency, whose topics' types they check, wherever each is written.
  if (ports) parseNodePorts(ctx, ports, out, r.owner);
  if (emergency) parseNodeEmergency(ctx, emergency, out, r.owner);
}

}  // namespace keel::profile::detail
