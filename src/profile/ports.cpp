// <ports> of a component profile: data, event and service ports, and the signal-model rule
// <validity> of paper §5.1.2 (docs/profiles.md).
#include <fmt/format.h>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"
#include "profile/ros2_names.hpp"

namespace keel::profile::detail {
namespace {

/// min/max: one bound for every element, or element-wise; min <= max where both apply. `what`
/// names the rule: "<validity> of data port 'p'".
void checkBounds(Ctx& ctx, pugi::xml_node at, const Validity& v, const std::string& what) {
  if (v.min.empty() || v.max.empty()) return;
  if (v.min.size() != v.max.size() && v.min.size() != 1 && v.max.size() != 1) {
    ctx.error(at, fmt::format("{}: <min> has {} values but <max> has {}", what, v.min.size(), v.max.size()));
    return;
  }
  const std::size_t n = std::max(v.min.size(), v.max.size());
  for (std::size_t i = 0; i < n; ++i) {
    const double lo = v.min[v.min.size() == 1 ? 0 : i];
    const double hi = v.max[v.max.size() == 1 ? 0 : i];
    if (lo <= hi) continue;
    const std::string index = n == 1 ? "" : fmt::format("[{}]", i);
    ctx.error(at, fmt::format("{}: min{} {} is greater than max{} {}", what, index, lo, index, hi));
  }
}

/// A data or event port's <usage>: false when it is none of input and output, a port OPRoS's
/// engine drops without a word (published profiles have `output1`); keel drops it and says so.
bool readUsage(Ctx& ctx, pugi::xml_node n, const std::string& text, const std::string& owner, PortDirection& usage) {
  if (auto v = parseWord(text, usages())) {
    usage = *v;
    return true;
  }
  ctx.warn(n, fmt::format("{} dropped: <usage> '{}' is neither input nor output (OPRoS's engine drops such ports "
                          "too)",
                          owner, text));
  return false;
}

/// What the three port readers share: the port's place and name (read ahead, so that messages
/// about earlier children can name the port), the phrase messages name it by, the children
/// every port reads alike (its name; a data or event port's usage and data type), and the check
/// of what every port must have.
template <class Port>
struct PortReading {
  PortReading(Ctx& c, pugi::xml_node n, Port& port, std::string_view kind)
      : ctx(c), node(n), p(port), owner(fmt::format("{} port '{}'", kind, trim(n.child("name").child_value()))) {
    p.where = ctx.where(node);
    p.name = std::string(trim(node.child("name").child_value()));
  }
  std::string text(pugi::xml_node n) const { return leafText(ctx, n); }
  Child name() {
    return {"name", [this](pugi::xml_node n) { p.name = text(n); }};
  }
  /// A data or event port's <usage> (its direction).
  Child direction() {
    return {"usage", [this](pugi::xml_node n) {
              usage = true;
              dropped = !readUsage(ctx, n, text(n), owner, p.usage);
            }};
  }
  Child dataType() {
    return {"data_type", [this](pugi::xml_node n) { p.data_type = text(n); }};
  }
  /// Reports what the port lacks; whether it is kept (it has a name, and was not dropped).
  bool complete() {
    if (p.name.empty()) {
      reportMissing(ctx, node, "name");
      return false;
    }
    if (!usage) reportMissing(ctx, node, "usage", owner);
    return !dropped;
  }

  Ctx& ctx;
  pugi::xml_node node;
  Port& p;
  std::string owner;
  bool usage = false;    // a <usage> was given
  bool dropped = false;  // its <usage> was neither input nor output
};

void readDataPort(Ctx& ctx, pugi::xml_node node, ComponentProfile& out) {
  DataPort p;
  PortReading r(ctx, node, p, "data");
  const std::string& owner = r.owner;
  pugi::xml_node policy, size;  // the first spelling of each, for "both" messages
  auto queue_policy = [&](pugi::xml_node n) {
    if (policy) {
      ctx.error(n, fmt::format("{} and {} in {}: one queue policy (line {})", tag(policy), tag(n), owner,
                               ctx.where(policy).line));
      return;
    }
    policy = n;
    if (auto v = readWord(ctx, n, r.text(n), fmt::format("{} of {}", tag(n), owner), queuePolicies())) {
      p.queue_policy = *v;
    }
  };
  auto queue_size = [&](pugi::xml_node n, const std::string& value) {
    if (size) {
      ctx.error(n, fmt::format("{} and {} in {}: one queue size (line {})", tag(size), tag(n), owner,
                               ctx.where(size).line));
      return;
    }
    size = n;
    if (auto v = readCount(ctx, n, value, fmt::format("{} of {}", tag(n), owner))) p.queue_size = *v;
  };
  readChildren(ctx, node,
               {r.name(),
                r.direction(),
                r.dataType(),
                {"queueing_policy", queue_policy},
                {"queuing_policy", queue_policy},
                {"policy", queue_policy},  // OPRoS's older spelling (ETRI's helloworld)
                {"queue_size", [&](pugi::xml_node n) { queue_size(n, r.text(n)); }},
                {"policy_param",  // <policy_param name="size">10</policy_param>
                 [&](pugi::xml_node n) {
                   const std::string value = leafText(ctx, n, {"name"});
                   const std::string param = attribute(n, "name").value_or("");
                   if (param == "size") return queue_size(n, value);
                   ctx.error(n, fmt::format(R"(<policy_param name="{}"> of {}: the one parameter is name="size")",
                                            param, owner));
                 },
                 true},
                {"validity", [&](pugi::xml_node n) { readValidity(ctx, n, owner, p, false); }, true},
                {"reference",
                 [&](pugi::xml_node n) {
                   p.reference = ctx.optionalReference(n, r.text(n), owner, RootKind::DataType);
                 }},
                {"description", {}},
                {"layout", {}}});
  const bool kept = r.complete();
  if (!p.name.empty() && p.data_type.empty()) reportMissing(ctx, node, "data_type", owner);
  if (kept) out.data_ports.push_back(std::move(p));
}

void readEventPort(Ctx& ctx, pugi::xml_node node, ComponentProfile& out) {
  EventPort p;
  PortReading r(ctx, node, p, "event");
  readChildren(ctx, node,
               {r.name(),
                r.direction(),
                r.dataType(),
                {"queue_size",
                 [&](pugi::xml_node n) {
                   if (auto v = readCount(ctx, n, r.text(n), "<queue_size> of " + r.owner)) p.queue_size = *v;
                 }},
                {"queueing_policy", {}, false, "an event port queues every event (FIFO, <queue_size> of them)"},
                {"reference", {}, false, "an event port's type is checked by its <data_type>"},
                {"description", {}},
                {"layout", {}}});
  if (r.complete()) out.event_ports.push_back(std::move(p));
}

void readServicePort(Ctx& ctx, pugi::xml_node node, ComponentProfile& out) {
  ServicePort p;
  PortReading r(ctx, node, p, "service");
  readChildren(ctx, node,
               {r.name(),
                {"type", [&](pugi::xml_node n) { p.type = r.text(n); }},
                {"usage",
                 [&](pugi::xml_node n) {
                   r.usage = true;
                   if (auto v = readWord(ctx, n, r.text(n), "<usage> of " + r.owner, serviceUsages())) p.usage = *v;
                 }},
                {"timeout",
                 [&](pugi::xml_node n) {
                   if (auto v = readPositive(ctx, n, r.text(n), "<timeout> of " + r.owner)) p.timeout_ms = *v;
                 }},
                {"reference",
                 [&](pugi::xml_node n) {
                   p.reference = ctx.optionalReference(n, r.text(n), r.owner, RootKind::ServiceType);
                 }},
                {"description", {}},
                {"layout", {}}});
  if (!r.complete()) return;
  if (p.type.empty()) reportMissing(ctx, node, "type", r.owner);
  out.service_ports.push_back(std::move(p));
}

/// Port names are unique across the three kinds: a connection names a port by name alone.
void checkUniqueNames(Ctx& ctx, const ComponentProfile& c) {
  std::vector<std::pair<std::string, Where>> seen;
  auto add = [&](const std::string& port, const Where& w) {
    for (const auto& [name, first] : seen) {
      if (name == port) {
        ctx.error(w, fmt::format("duplicate port '{}' in component '{}' (first at line {})", port, c.name, first.line));
        return;
      }
    }
    seen.emplace_back(port, w);
  };
  for (const auto& p : c.data_ports) add(p.name, p.where);
  for (const auto& p : c.event_ports) add(p.name, p.where);
  for (const auto& p : c.service_ports) add(p.name, p.where);
}

}  // namespace

Validity parseValidity(Ctx& ctx, pugi::xml_node node, const std::string& owner, bool field) {
  Validity v;
  v.where = ctx.where(node);
  // A field's bound names it: "<min> of <validity field="linear.x"> of data port 'cmd'".
  std::string rule = "<validity>";
  if (field) {
    if (const auto path = requiredAttribute(ctx, node, "field")) {
      v.field = std::string(trim(*path));
      rule = fmt::format("<validity field=\"{}\">", v.field);
      if (const std::string why = fieldPathProblem(v.field); !why.empty())
        ctx.error(node, fmt::format("field '{}' of <validity> of {} is not a field path (field names separated by "
                                    "'.', e.g. linear.x): {}",
                                    v.field, owner, why));
    }
  }
  const std::string bound_owner = field ? fmt::format("{} of {}", rule, owner) : owner;
  auto bound = [&](std::vector<double>& into) {
    return [&ctx, &into, &bound_owner](pugi::xml_node n) {
      const std::string text = leafText(ctx, n);
      auto list = parseDoubleList(text, true);
      if (!list || list->empty()) {
        ctx.error(n, fmt::format("<{}> of {} must be a number or a list of numbers, got '{}'", n.name(), bound_owner,
                                 text));
        return;
      }
      into = std::move(*list);
    };
  };
  if (field) readChildren(ctx, node, {{"min", bound(v.min)}, {"max", bound(v.max)}}, {"field"});
  else readChildren(ctx, node, {{"min", bound(v.min)}, {"max", bound(v.max)}});
  checkBounds(ctx, node, v, fmt::format("{} of {}", rule, owner));
  return v;
}

void readValidity(Ctx& ctx, pugi::xml_node node, const std::string& owner, DataPort& p, bool field_only) {
  if (!field_only && !node.attribute("field")) {
    if (p.validity)
      return ctx.error(node, fmt::format("duplicate <validity> in <data_port> (first at line {}); a field's "
                                         "<validity> names it: <validity field=\"linear.x\">",
                                         p.validity->where.line));
    p.validity = parseValidity(ctx, node, owner);
    return;
  }
  Validity v = parseValidity(ctx, node, owner, true);
  if (v.field.empty()) return;  // reported
  for (const Validity& w : p.field_validity)
    if (w.field == v.field)
      return ctx.error(node, fmt::format("duplicate <validity field=\"{}\"> in {} (first at line {})", v.field, owner,
                                         w.where.line));
  p.field_validity.push_back(std::move(v));
}

void parsePorts(Ctx& ctx, pugi::xml_node node, ComponentProfile& out) {
  readChildren(ctx, node,
               {{"data_port", [&](pugi::xml_node n) { readDataPort(ctx, n, out); }, true},
                {"event_port", [&](pugi::xml_node n) { readEventPort(ctx, n, out); }, true},
                {"service_port", [&](pugi::xml_node n) { readServicePort(ctx, n, out); }, true}});
  checkUniqueNames(ctx, out);
}

}  // namespace keel::profile::detail
