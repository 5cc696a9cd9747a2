// <fault_policy> of a subcomponent: the rule tags of paper §5 as docs/profiles.md gives them.
// Defaults (model.hpp, docs/profiles.md): severity reset, dependency component, restart
// intensity 3 in 10000 ms; heartbeat, deadline, checkpoint and alternative absent.
#include <fmt/format.h>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"

namespace keel::profile::detail {
namespace {

struct PolicyReader {
  Ctx& ctx;
  FaultPolicy& out;
  std::string who;    // "subcomponent 'sonar'"
  std::string owner;  // "fault_policy of subcomponent 'sonar'"
  int default_line = 0;
  std::map<std::string, int> kind_lines;

  void severity(pugi::xml_node n) {
    const std::string text = leafText(ctx, n, {"kind"});
    const auto kind_text = attribute(n, "kind");
    const auto value = readWord(ctx, n, text, "<severity> of " + owner, severities());
    if (!kind_text) {
      if (default_line != 0) return duplicate(n, "<severity>", default_line);
      default_line = ctx.where(n).line;
      if (value) out.severity = *value;
      return;
    }
    const auto kind = readWord(ctx, n, *kind_text, "kind of <severity> of " + owner, faultKinds());
    if (!kind) return;
    const std::string key(*kind);
    const auto [it, inserted] = kind_lines.emplace(key, ctx.where(n).line);
    if (!inserted) return duplicate(n, fmt::format("<severity kind=\"{}\">", key), it->second);
    if (value) out.severity_by_kind[key] = *value;
    out.severity_kind_where[key] = ctx.where(n);
  }

  void duplicate(pugi::xml_node n, const std::string& what, int first) {
    ctx.error(n, fmt::format("duplicate {} in {} (first at line {})", what, owner, first));
  }

  /// A required, positive number of ms in attribute `attr` of an empty element.
  std::optional<double> positiveAttribute(pugi::xml_node n, const char* attr) {
    readChildren(ctx, n, {}, {attr});
    const auto text = requiredAttribute(ctx, n, attr);
    if (!text) return std::nullopt;
    return readPositive(ctx, n, *text, fmt::format("{} of {} of {}", attr, tag(n), owner));
  }

  void alternative(pugi::xml_node n) {
    readChildren(ctx, n, {}, {"reference", "preload"});
    Alternative alt;
    alt.where = ctx.where(n);
    if (auto preload = attribute(n, "preload")) {
      alt.preload = readBool(ctx, n, *preload, "preload of <alternative> of " + owner).value_or(false);
    }
    const auto ref = requiredAttribute(ctx, n, "reference");
    if (!ref) return;
    // A component's alternative is a component, a node's a node: validate_ports.cpp pairs them.
    alt.reference = ctx.reference(n, trim(*ref), "<alternative> of " + who, {RootKind::Component, RootKind::Node});
    if (!alt.reference.empty()) out.alternative = std::move(alt);
  }

  void restart(pugi::xml_node n) {
    readChildren(ctx, n, {}, {"intensity", "period"});
    if (auto text = attribute(n, "intensity")) {
      if (auto v = readIntIn(ctx, n, *text, "intensity of <restart> of " + owner, 0, 1000000)) {
        out.restart.intensity = *v;
      }
    }
    if (auto text = attribute(n, "period")) {
      if (auto v = readPositive(ctx, n, *text, "period of <restart> of " + owner)) {
        out.restart.period_ms = *v;
      }
    }
  }
};

}  // namespace

FaultPolicy parseFaultPolicy(Ctx& ctx, pugi::xml_node node, const std::string& owner) {
  FaultPolicy policy;
  policy.where = ctx.where(node);
  const std::string who = fmt::format("subcomponent '{}'", owner);
  PolicyReader r{ctx, policy, who, "fault_policy of " + who, 0, {}};
  readChildren(ctx, node,
               {{"severity", [&](pugi::xml_node n) { r.severity(n); }, true},
                {"dependency",
                 [&](pugi::xml_node n) {
                   if (auto v = readWord(ctx, n, leafText(ctx, n), "<dependency> of " + r.owner, scopes())) {
                     policy.dependency = *v;
                   }
                 }},
                {"heartbeat",
                 [&](pugi::xml_node n) {
                   policy.heartbeat_timeout_ms = r.positiveAttribute(n, "timeout");
                   policy.heartbeat_where = ctx.where(n);
                 }},
                {"deadline",
                 [&](pugi::xml_node n) {
                   policy.deadline_ms = readPositive(ctx, n, leafText(ctx, n), "<deadline> of " + r.owner);
                   policy.deadline_where = ctx.where(n);
                 }},
                {"checkpoint",
                 [&](pugi::xml_node n) {
                   policy.checkpoint_period_ms = r.positiveAttribute(n, "period");
                   policy.checkpoint_where = ctx.where(n);
                 }},
                {"alternative", [&](pugi::xml_node n) { r.alternative(n); }},
                {"restart", [&](pugi::xml_node n) { r.restart(n); }}});
  return policy;
}

}  // namespace keel::profile::detail
