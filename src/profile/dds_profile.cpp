// <dds domain="0"> of a package or system profile: <publish> and <subscribe> bindings of
// data ports to DDS topics with ROS 2's names (docs/dds.md). Checked here: the file's own
// syntax (topic and type names as ROS 2 writes them, QoS names, times). That the component and
// port exist and the types agree needs the component profiles: validate_assembly.cpp.
#include <fmt/format.h>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"
#include "profile/ros2_names.hpp"

namespace keel::profile::detail {
namespace {

/// A time in ms: positive, finite.
std::optional<double> readMs(Ctx& ctx, pugi::xml_node n, const char* attr, const std::string& owner) {
  const auto text = attribute(n, attr);
  if (!text) return std::nullopt;
  return readPositive(ctx, n, *text, fmt::format("{} of {} (ms)", attr, owner));
}

void readBinding(Ctx& ctx, pugi::xml_node n, bool publish, DdsSpec& out) {
  DdsBinding b;
  b.publish = publish;
  b.where = ctx.where(n);
  readChildren(ctx, n, {},
               {"component", "port", "topic", "type", "qos", "depth", "deadline", "liveliness", "ownership"});
  const auto component = requiredAttribute(ctx, n, "component");
  const auto port = requiredAttribute(ctx, n, "port");
  const auto topic = requiredAttribute(ctx, n, "topic");
  const auto type = requiredAttribute(ctx, n, "type");
  if (!component || !port || !topic || !type) return;
  b.endpoint = {std::string(trim(*component)), std::string(trim(*port))};
  const std::string owner = fmt::format("<{}> of {}.{}", publish ? "publish" : "subscribe", b.endpoint.component,
                                        b.endpoint.port);
  bool ok = true;
  const std::string t(trim(*topic));
  if (const std::string why = topicProblem(t); !why.empty()) {
    ctx.error(n, fmt::format("topic '{}' of {} is not a ROS 2 topic name: {}", t, owner, why));
    ok = false;
  }
  b.topic = t.front() == '/' ? t : "/" + t;
  b.type = std::string(trim(*type));
  if (const std::string why = typeProblem(b.type); !why.empty()) {
    ctx.error(n, fmt::format("type '{}' of {} is not a ROS 2 message type: {}", b.type, owner, why));
    ok = false;
  }
  if (const auto q = attribute(n, "qos")) {
    const auto v = readWord(ctx, n, trim(*q), "qos of " + owner, ddsQosNames());
    if (!v) ok = false;
    b.qos = v.value_or(DdsQos::Default);
  }
  if (const auto d = attribute(n, "depth")) {
    b.depth = readCount(ctx, n, *d, "depth of " + owner);
    if (!b.depth || *b.depth == 0) {
      if (b.depth) ctx.error(n, fmt::format("depth of {} must be at least 1", owner));
      ok = false;
    }
  }
  if (const auto o = attribute(n, "ownership")) {
    static const std::vector<std::pair<std::string_view, bool>> kOwnership = {{"shared", false}, {"exclusive", true}};
    const auto v = readWord(ctx, n, trim(*o), "ownership of " + owner, kOwnership);
    if (!v) ok = false;
    if (v && *v && publish) {
      ctx.error(n, fmt::format("ownership of {}: a writer's ownership is its component's <redundancy>", owner));
      ok = false;
    }
    b.exclusive = v.value_or(false);
  }
  b.deadline_ms = readMs(ctx, n, "deadline", owner);
  b.liveliness_ms = readMs(ctx, n, "liveliness", owner);
  if ((attribute(n, "deadline") && !b.deadline_ms) || (attribute(n, "liveliness") && !b.liveliness_ms)) ok = false;
  if (ok) out.bindings.push_back(std::move(b));
}

}  // namespace

DdsSpec parseDds(Ctx& ctx, pugi::xml_node node) {
  DdsSpec out;
  out.where = ctx.where(node);
  readChildren(ctx, node,
               {{"publish", [&](pugi::xml_node n) { readBinding(ctx, n, true, out); }, true},
                {"subscribe", [&](pugi::xml_node n) { readBinding(ctx, n, false, out); }, true}},
               {"domain", "diagnostics"});
  if (const auto d = attribute(node, "diagnostics"))
    out.diagnostics = readBool(ctx, node, *d, "diagnostics of <dds>").value_or(true);
  if (const auto d = attribute(node, "domain")) {
    // DDS's domain ids: 0..232 (the port formula's limit); ROS 2 recommends 0..101 on Linux.
    out.domain = readIntIn(ctx, node, trim(*d), "domain of <dds>", 0, 232);
  }
  // One topic, one role per port: a second binding of the same port and direction is a slip.
  for (std::size_t i = 0; i < out.bindings.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      const DdsBinding& a = out.bindings[j];
      const DdsBinding& b = out.bindings[i];
      if (a.publish == b.publish && a.endpoint.component == b.endpoint.component &&
          a.endpoint.port == b.endpoint.port && a.topic == b.topic)
        ctx.error(b.where, fmt::format("{}.{} is bound to topic '{}' twice (the first at line {})",
                                       b.endpoint.component, b.endpoint.port, b.topic, a.where.line));
    }
  return out;
}

}  // namespace keel::profile::detail
