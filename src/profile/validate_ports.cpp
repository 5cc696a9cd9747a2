// Port checks of an assembly: port connections (existence, kind, direction, types, fan-in and
// fan-out), a composite's exported ports, and that an alternative offers the same ports as
// the component it replaces.
#include <algorithm>

#include <fmt/format.h>

#include "profile/field_reader.hpp"
#include "profile/validate.hpp"

namespace keel::profile::detail {
namespace {

void error(Diagnostics& diags, const Where& where, std::string message) {
  diags.push_back(Diagnostic{where, std::move(message)});
}

/// The port `ep` names, or nullopt (reported, unless its profile failed to load).
std::optional<PortSig> resolve(const ProfileSet& set, const std::vector<Subcomponent>& subs, const Endpoint& ep,
                               const Where& where, std::string_view what, Diagnostics& diags) {
  const Subcomponent* sub = findSubcomponent(subs, ep.component);
  if (sub == nullptr && ep.component == kFaultManager) {  // keel's system component (paper §3.2)
    if (ep.port == kFaultManagerPort)
      return PortSig{std::string(kFaultManagerPort), PortKind::Event, false, "input", "keel::FaultEvent", {}};
    error(diags, where,
          fmt::format("{}: component '{}' has no port '{}' (ports: {})", what, ep.component, ep.port,
                      kFaultManagerPort));
    return std::nullopt;
  }
  if (sub == nullptr) {
    error(diags, where,
          fmt::format("{}: no subcomponent '{}' (subcomponents: {})", what, ep.component, subcomponentNames(subs)));
    return std::nullopt;
  }
  const auto ports = portsOf(set, sub->reference);
  if (!ports) return std::nullopt;
  std::vector<std::string> names;
  for (const PortSig& p : *ports) {
    if (p.name == ep.port) return p;
    names.push_back(p.name);
  }
  error(diags, where,
        fmt::format("{}: component '{}' has no port '{}' (ports: {})", what, ep.component, ep.port, nameList(names)));
  return std::nullopt;
}

std::string dotted(const Endpoint& e) { return e.component + "." + e.port; }

std::string aPort(PortKind kind) { return fmt::format("{} {} port", kind == PortKind::Event ? "an" : "a", name(kind)); }

/// Kind, direction and type of one connection whose two ends exist.
void checkEnds(Connection& c, const PortSig& src, const PortSig& dst, Diagnostics& diags) {
  if (!c.port_type_given) {
    if (src.kind != dst.kind) {
      return error(diags, c.where,
                   fmt::format("port_connection: '{}' is {} but '{}' is {}", dotted(c.source), aPort(src.kind),
                               dotted(c.target), aPort(dst.kind)));
    }
    c.port_type = src.kind;
  }
  bool ok = true;
  for (const auto& [ep, p] : {std::pair{&c.source, &src}, std::pair{&c.target, &dst}}) {
    if (p->kind == c.port_type) continue;
    ok = false;
    error(diags, c.where,
          fmt::format("port_connection: port '{}' is {}, but port_type is {}", dotted(*ep), aPort(p->kind),
                      name(c.port_type)));
  }
  if (!ok) return;
  const bool service = c.port_type == PortKind::Service;
  if (!src.source_side) {
    ok = false;
    error(diags, c.where,
          fmt::format("port_connection: source '{}' is {}; a source must be {}", dotted(c.source), describe(src),
                      service ? "a required service port" : "an output port"));
  }
  if (dst.source_side) {
    ok = false;
    error(diags, c.where,
          fmt::format("port_connection: target '{}' is {}; a target must be {}", dotted(c.target), describe(dst),
                      service ? "a provided service port" : "an input port"));
  }
  if (ok && !c.source.field.empty()) {  // its path is resolved against the message's fields when keel runs
    if (c.port_type != PortKind::Data)
      error(diags, c.where,
            fmt::format("port_connection: field '{}' of source '{}': only a data connection carries a field",
                        c.source.field, dotted(c.source)));
    else if (!sameCppType(dst.type, "double"))
      error(diags, c.where,
            fmt::format("port_connection: field '{}' of source '{}' is a number, but target '{}' is '{}' (a field "
                        "goes to a 'double' input)",
                        c.source.field, dotted(c.source), dotted(c.target), dst.type));
    return;
  }
  if (ok && !sameCppType(src.type, dst.type)) {
    error(diags, c.where,
          fmt::format("port_connection: {} differ: '{}' is '{}', '{}' is '{}'",
                      service ? "service types" : "data types", dotted(c.source), src.type, dotted(c.target),
                      dst.type));
  }
}

bool sameEnd(const Endpoint& a, const Endpoint& b) { return a.component == b.component && a.port == b.port; }

/// A connection listed twice, or a required service port bound to two providers.
void checkMultiplicity(const std::vector<Connection>& cs, std::size_t i, Diagnostics& diags) {
  const Connection& c = cs[i];
  for (std::size_t j = 0; j < i; ++j) {
    const Connection& d = cs[j];
    if (sameEnd(c.source, d.source) && sameEnd(c.target, d.target)) {
      return error(diags, c.where,
                   fmt::format("duplicate port_connection '{}' -> '{}' (first at "
                               "line {})",
                               dotted(c.source), dotted(c.target), d.where.line));
    }
    if (c.port_type == PortKind::Service && d.port_type == PortKind::Service && sameEnd(c.source, d.source)) {
      return error(diags, c.where,
                   fmt::format("port_connection: required service port '{}' is already connected "
                               "to '{}' (line {})",
                               dotted(c.source), dotted(d.target), d.where.line));
    }
  }
}

}  // namespace

void checkConnections(const ProfileSet& set, const std::vector<Subcomponent>& subs,
                      std::vector<Connection>& connections, Diagnostics& diags) {
  for (std::size_t i = 0; i < connections.size(); ++i) {
    Connection& c = connections[i];
    const auto src = resolve(set, subs, c.source, c.where, "port_connection", diags);
    const auto dst = resolve(set, subs, c.target, c.where, "port_connection", diags);
    if (src && dst) {
      const std::size_t before = diags.size();
      checkEnds(c, *src, *dst, diags);
      if (diags.size() == before && c.port_type == PortKind::Service) checkServiceMethods(set, c, *src, *dst, diags);
    }
    checkMultiplicity(connections, i, diags);
  }
}

void checkDds(const ProfileSet& set, const std::vector<Subcomponent>& subs, const DdsSpec& dds, Diagnostics& diags) {
  for (const DdsBinding& b : dds.bindings) {
    const char* element = b.publish ? "<publish>" : "<subscribe>";
    const auto port = resolve(set, subs, b.endpoint, b.where, element, diags);
    if (!port) continue;
    if (port->kind != PortKind::Data) {
      error(diags, b.where,
            fmt::format("{}: '{}' is {}; DDS topics carry data ports' values", element, dotted(b.endpoint),
                        aPort(port->kind)));
    } else if (port->source_side != b.publish) {
      error(diags, b.where,
            fmt::format("{}: '{}' is {}; {} needs {} port", element, dotted(b.endpoint), describe(*port), element,
                        b.publish ? "an output" : "an input"));
    } else if (port->type != b.type) {
      error(diags, b.where,
            fmt::format("{}: topic '{}' has type '{}', but port '{}' has data_type '{}' (a keel::msg type's data_type "
                        "is its ROS 2 name)",
                        element, b.topic, b.type, dotted(b.endpoint), port->type));
    }
  }
}

void checkExports(const ProfileSet& set, const CompositeProfile& composite, Diagnostics& diags) {
  for (const ExportedPort& e : composite.exported_ports) {
    (void)resolve(set, composite.subcomponents, e.inner, e.where, fmt::format("export_port '{}'", e.name), diags);
  }
}

namespace {

/// A node's alternative takes the role's place in the ROS 2 graph, where keel watches the role
/// by its name, its output topics and its diagnostics status: they must be the role's.
void checkNodeAlternative(const NodeProfile& mine, const NodeProfile& theirs, const Alternative& alt,
                          const std::string& who, Diagnostics& diags) {
  if (theirs.fullName() != mine.fullName())
    error(diags, alt.where,
          fmt::format("{} is node '{}', not '{}': it takes the node's place in the ROS 2 graph, under its name", who,
                      theirs.fullName(), mine.fullName()));
  if (theirs.diagnostics_name != mine.diagnostics_name) {
    auto named = [](const std::string& n) { return n.empty() ? std::string("none") : fmt::format("\"{}\"", n); };
    error(diags, alt.where,
          fmt::format("{}: its <diagnostics name> is {}, the node's {}: keel reads one status for the role", who,
                      named(theirs.diagnostics_name), named(mine.diagnostics_name)));
  }
  for (const NodeTopic& t : mine.topics) {
    const auto q = std::find_if(theirs.topics.begin(), theirs.topics.end(),
                                [&](const NodeTopic& x) { return x.port == t.port; });
    if (q != theirs.topics.end() && q->topic != t.topic)
      error(diags, alt.where,
            fmt::format("{}: port '{}' is on topic '{}', the node's on '{}': it takes the node's place on its topics",
                        who, t.port, q->topic, t.topic));
  }
}

}  // namespace

void checkAlternatives(const ProfileSet& set, const std::vector<Subcomponent>& subs, Diagnostics& diags) {
  for (const Subcomponent& s : subs) {
    if (!s.fault_policy || !s.fault_policy->alternative) continue;
    const Alternative& alt = *s.fault_policy->alternative;
    const auto mine = portsOf(set, s.reference);
    const auto theirs = portsOf(set, alt.reference);
    if (!mine || !theirs || !set.components.count(alt.reference)) continue;
    const std::string who = fmt::format("subcomponent '{}': alternative '{}'", s.name, profileName(set, alt.reference));
    const std::string original = profileName(set, s.reference);
    // A node stands in for a node, a component for a component: keel starts the one as it did the other.
    const bool node = set.nodes.count(s.reference) > 0;
    if (node != (set.nodes.count(alt.reference) > 0)) {
      error(diags, alt.where,
            node ? fmt::format("{} is a component, but '{}' is a ROS 2 node: a node's alternative is another "
                               "<ros2_node_profile>",
                               who, original)
                 : fmt::format("{} is a ROS 2 node, but '{}' is a component: only a node's alternative may be a "
                               "<ros2_node_profile>",
                               who, original));
      continue;
    }
    if (node) checkNodeAlternative(set.nodes.at(s.reference), set.nodes.at(alt.reference), alt, who, diags);
    for (const PortSig& p : *mine) {
      const auto q = std::find_if(theirs->begin(), theirs->end(), [&](const PortSig& x) { return x.name == p.name; });
      if (q == theirs->end()) {
        error(diags, alt.where,
              fmt::format("{} has no port '{}' ({} of component '{}')", who, p.name, describe(p), original));
      } else if (q->kind != p.kind || q->usage != p.usage || q->type != p.type) {
        error(diags, alt.where,
              fmt::format("{}: port '{}' is {}, but in component '{}' it is {}", who, p.name, describe(*q), original,
                          describe(p)));
      }
    }
    for (const PortSig& q : *theirs) {
      const bool known = std::any_of(mine->begin(), mine->end(), [&](const PortSig& p) { return p.name == q.name; });
      if (!known) {
        error(diags, alt.where,
              fmt::format("{} has port '{}' that component '{}' does not have", who, q.name, original));
      }
    }
  }
}

}  // namespace keel::profile::detail
