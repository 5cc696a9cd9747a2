// <ports> and <emergency> of a <ros2_node_profile> (docs/profiles.md#ros-2-node-profile): the
// topics keel watches (a node's outputs) or writes (its inputs), each a data port of the
// node's component with its ROS 2 type, topic, QoS and the <validity> of its fields; and what
// keel does with the node during an emergency stop. Topic and type names are checked by
// ros2_names.hpp; that a field exists in its message is checked where the types are known.
#include <fmt/format.h>

#include <algorithm>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"
#include "profile/ros2_names.hpp"

namespace keel::profile::detail {
namespace {

/// Why `topic` is not a name a node's topic can be watched by: absolute, and ROS 2's rules.
std::string nodeTopicProblem(std::string_view topic) {
  if (!topic.empty() && topic.front() != '/')
    return "topic name must be absolute, it must lead with a '/' (a node resolves a relative name in its own "
           "namespace)";
  return topicProblem(topic);
}

struct NodePortReader {
  Ctx& ctx;
  pugi::xml_node node;
  std::string owner;  // "data port 'cmd'"
  DataPort p;
  NodeTopic t;
  bool usage = false;  // a <usage> was given
  bool input = false;  // and it says input
  pugi::xml_node deadline, liveliness;

  std::string text(pugi::xml_node n) const { return leafText(ctx, n); }

  void dataType(pugi::xml_node n) {
    p.data_type = text(n);
    if (const std::string why = typeProblem(p.data_type); !why.empty() && !p.data_type.empty())
      ctx.error(n, fmt::format("<data_type> '{}' of {} is not a ROS 2 message type: {}", p.data_type, owner, why));
  }

  void topic(pugi::xml_node n) {
    t.topic = text(n);
    if (const std::string why = nodeTopicProblem(t.topic); !why.empty() && !t.topic.empty())
      ctx.error(n, fmt::format("<topic> '{}' of {} is not a ROS 2 topic name: {}", t.topic, owner, why));
  }

  void read() {
    readChildren(ctx, node,
                 {{"name", [&](pugi::xml_node n) { p.name = text(n); }},
                  {"usage",
                   [&](pugi::xml_node n) {
                     usage = true;
                     const auto v = readWord(ctx, n, text(n), "<usage> of " + owner, usages());
                     input = v == PortDirection::Input;
                     p.usage = v.value_or(p.usage);
                   }},
                  {"data_type", [&](pugi::xml_node n) { dataType(n); }},
                  {"topic", [&](pugi::xml_node n) { topic(n); }},
                  {"qos",
                   [&](pugi::xml_node n) {
                     if (auto v = readWord(ctx, n, text(n), "<qos> of " + owner, ddsQosNames())) t.qos = *v;
                   }},
                  {"depth", [&](pugi::xml_node n) { t.depth = readCount(ctx, n, text(n), "<depth> of " + owner); }},
                  {"deadline",
                   [&](pugi::xml_node n) {
                     deadline = n;
                     t.deadline_ms = readPositive(ctx, n, text(n), "<deadline> of " + owner);
                   }},
                  {"liveliness",
                   [&](pugi::xml_node n) {
                     liveliness = n;
                     t.liveliness_ms = readPositive(ctx, n, text(n), "<liveliness> of " + owner);
                   }},
                  {"validity", [&](pugi::xml_node n) { readValidity(ctx, n, owner, p, true); }, true},
                  {"description", {}}});
  }

  /// Reports what the port lacks and what an input cannot have; whether it is kept (it has a name).
  bool complete() {
    if (p.name.empty()) {
      reportMissing(ctx, node, "name");
      return false;
    }
    if (!usage) reportMissing(ctx, node, "usage", owner);
    if (p.data_type.empty()) reportMissing(ctx, node, "data_type", owner);
    if (t.topic.empty()) reportMissing(ctx, node, "topic", owner);
    // keel writes an input's topic: a deadline or a lease there would time keel, not the node.
    for (pugi::xml_node n : {deadline, liveliness})
      if (n && input)
        ctx.error(n, fmt::format("{} of {}: keel writes an input port's topic, so this would watch keel, not the node "
                                 "(deadline and liveliness watch a node's output ports)",
                                 tag(n), owner));
    t.port = p.name;
    return true;
  }
};

/// Port names are unique (connections name a port by name), and so are topics: a topic is one port.
void checkUnique(Ctx& ctx, const NodeProfile& node, const std::string& owner) {
  const auto& ports = node.component.data_ports;
  for (std::size_t i = 0; i < ports.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (ports[j].name == ports[i].name) {
        ctx.error(ports[i].where, fmt::format("duplicate port '{}' in {} (first at line {})", ports[i].name, owner,
                                              ports[j].where.line));
        break;
      }
      if (node.topics[j].topic == node.topics[i].topic && !node.topics[i].topic.empty()) {
        ctx.error(ports[i].where, fmt::format("data ports '{}' (line {}) and '{}' are both on topic '{}': a topic is "
                                              "one port of a node",
                                              ports[j].name, ports[j].where.line, ports[i].name, node.topics[i].topic));
        break;
      }
    }
  }
}

void readSafeCommand(Ctx& ctx, pugi::xml_node n, NodeProfile& node, const std::string& owner, NodeEmergency& e) {
  readChildren(ctx, n, {}, {"topic", "type", "rate"});
  const auto topic = requiredAttribute(ctx, n, "topic");
  const auto type = requiredAttribute(ctx, n, "type");
  if (!topic || !type) return;
  SafeCommand s;
  s.where = ctx.where(n);
  s.topic = std::string(trim(*topic));
  s.type = std::string(trim(*type));
  const std::string what = "<publish> of <emergency> of " + owner;
  bool ok = true;
  if (const std::string why = nodeTopicProblem(s.topic); !why.empty()) {
    ctx.error(n, fmt::format("topic '{}' of {} is not a ROS 2 topic name: {}", s.topic, what, why));
    ok = false;
  }
  if (const std::string why = typeProblem(s.type); !why.empty()) {
    ctx.error(n, fmt::format("type '{}' of {} is not a ROS 2 message type: {}", s.type, what, why));
    ok = false;
  }
  if (const auto rate = attribute(n, "rate")) {
    const auto hz = readPositive(ctx, n, trim(*rate), fmt::format("rate of {} (Hz)", what));
    ok = ok && hz.has_value();
    s.rate_hz = hz.value_or(s.rate_hz);
  }
  for (std::size_t i = 0; ok && i < node.topics.size(); ++i) {
    const DataPort& port = node.component.data_ports[i];
    if (node.topics[i].topic != s.topic || port.data_type == s.type || port.data_type.empty()) continue;
    ctx.error(n, fmt::format("type '{}' of {}: data port '{}' on topic '{}' has data_type '{}'", s.type, what,
                             port.name, s.topic, port.data_type));
    ok = false;
  }
  for (const SafeCommand& other : e.publish)
    if (ok && other.topic == s.topic) {
      ctx.error(n, fmt::format("duplicate <publish topic=\"{}\"> in <emergency> of {} (first at line {})", s.topic,
                               owner, other.where.line));
      ok = false;
    }
  if (ok) e.publish.push_back(std::move(s));
}

}  // namespace

void parseNodePorts(Ctx& ctx, pugi::xml_node node, NodeProfile& out, const std::string& owner) {
  auto notData = [&](pugi::xml_node n) {
    ctx.error(n, fmt::format("{} in {}: only data ports are supported for nodes (a node's port is one of its topics)",
                             tag(n), owner));
  };
  readChildren(ctx, node,
               {{"data_port",
                 [&](pugi::xml_node n) {
                   NodePortReader r{ctx,   n,  fmt::format("data port '{}'", trim(n.child("name").child_value())),
                                    {},    {}, false,
                                    false, {}, {}};
                   r.p.where = r.t.where = ctx.where(n);
                   r.read();
                   if (!r.complete()) return;
                   out.component.data_ports.push_back(std::move(r.p));
                   out.topics.push_back(std::move(r.t));
                 },
                 true},
                {"event_port", notData, true},
                {"service_port", notData, true}});
  checkUnique(ctx, out, owner);
}

void parseNodeEmergency(Ctx& ctx, pugi::xml_node node, NodeProfile& out, const std::string& owner) {
  NodeEmergency e;
  e.where = ctx.where(node);
  readChildren(ctx, node,
               {{"stop",
                 [&](pugi::xml_node n) {
                   readChildren(ctx, n, {});
                   e.stop = true;
                 }},
                {"publish", [&](pugi::xml_node n) { readSafeCommand(ctx, n, out, owner, e); }, true}});
  if (!e.stop && e.publish.empty() && !node.find_child([](pugi::xml_node c) { return c.type() == pugi::node_element; }))
    ctx.warn(node, fmt::format("<emergency> of {} has neither <stop/> nor <publish>: it does nothing", owner));
  out.emergency = std::move(e);
}

}  // namespace keel::profile::detail
