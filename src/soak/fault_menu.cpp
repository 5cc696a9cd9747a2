#include "soak/fault_menu.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <string_view>

#include "plan/fault_manager_profile.hpp"

namespace keel::soak {
namespace {

/// Whether a data port of this (normalised) type carries one number: what out_of_range corrupts.
bool scalarNumeric(std::string_view type) {
  static constexpr std::string_view kTypes[] = {"double",        "float",        "int",          "long",
                                                "short",         "unsigned",     "int8_t",       "int16_t",
                                                "int32_t",       "int64_t",      "uint8_t",      "uint16_t",
                                                "uint32_t",      "uint64_t",     "std::int32_t", "std::int64_t",
                                                "std::uint32_t", "std::uint64_t"};
  return std::find(std::begin(kTypes), std::end(kTypes), type) != std::end(kTypes);
}

const profile::DataPort* dataPort(const plan::PlannedInstance& pi, std::string_view name) {
  for (const auto& p : pi.profile->data_ports)
    if (p.name == name) return &p;
  return nullptr;
}

/// The output port's values are checked: a <validity> on it, or on an input port it feeds.
bool checked(const plan::Plan& plan, const plan::PlannedInstance& pi, const profile::DataPort& out) {
  if (out.validity) return true;
  for (const auto& c : plan.connections) {
    if (c.type != PortKind::Data || c.source.component != pi.name || c.source.port != out.name) continue;
    const plan::PlannedInstance* target = plan.find(c.target.component);
    const profile::DataPort* in = target ? dataPort(*target, c.target.port) : nullptr;
    if (in && in->validity) return true;
  }
  return false;
}

std::string attribute(std::string_view name, std::string_view value) {
  std::string escaped;
  for (char ch : value) {
    switch (ch) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '"': escaped += "&quot;"; break;
      default: escaped += ch;
    }
  }
  return fmt::format(" {}=\"{}\"", name, escaped);
}

}  // namespace

std::vector<Offer> faultMenu(const plan::Plan& plan, const HardwareOffers& hardware) {
  std::set<std::string, std::less<>> executed;
  for (const auto& ex : plan.executors) executed.insert(ex.members.begin(), ex.members.end());
  std::vector<Offer> menu;
  for (const auto& pi : plan.instances) {
    if (pi.name == plan::kFaultManagerInstance) continue;
    if (executed.contains(pi.name)) {
      for (const char* kind : {"segfault", "divide_by_zero", "abort", "throw", "error_code"})
        menu.push_back({pi.name, kind, "", "", 0, false});
      if (pi.policy && pi.policy->heartbeat_timeout_ms) {
        menu.push_back({pi.name, "hang", "", "", 0, false});
        menu.push_back({pi.name, "stall_heartbeat", "", "", 3 * *pi.policy->heartbeat_timeout_ms, false});
      }
    }
    for (const auto& p : pi.profile->data_ports)
      if (p.usage == PortDirection::Output && scalarNumeric(p.data_type) && checked(plan, pi, p))
        menu.push_back({pi.name, "out_of_range", "", p.name, 0, false});
    if (!pi.process.empty()) menu.push_back({pi.name, "kill", "", "", 0, false});
    if (auto it = hardware.find(pi.name); it != hardware.end()) {
      for (const auto& command : it->second) {
        const std::size_t space = command.find(' ');
        const std::string kind = command.substr(0, space);
        const std::string args = space == std::string::npos ? "" : command.substr(space + 1);
        menu.push_back({pi.name, kind, args, "", 0, true});
      }
    }
  }
  return menu;
}

std::string randomScenario(const std::vector<Offer>& menu, std::mt19937_64& rng, double first_ms, double every_ms,
                           double length_ms) {
  std::map<std::string, std::vector<const Offer*>> by_kind;
  for (const auto& o : menu) by_kind[o.kind].push_back(&o);
  std::vector<const std::vector<const Offer*>*> kinds;
  kinds.reserve(by_kind.size());
  for (const auto& [kind, offers] : by_kind) kinds.push_back(&offers);
  std::string xml = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- made by keel soak -->\n<fault_scenario>\n";
  if (!kinds.empty()) {
    std::uniform_real_distribution<double> gap(every_ms / 2, every_ms * 3 / 2);
    double at = first_ms;
    while (at < length_ms) {
      const auto& offers = *kinds[std::uniform_int_distribution<std::size_t>(0, kinds.size() - 1)(rng)];
      const Offer& o = *offers[std::uniform_int_distribution<std::size_t>(0, offers.size() - 1)(rng)];
      xml += fmt::format("  <fault{}{}{}", attribute("at", fmt::format("{:.0f}", at)),
                         attribute("component", o.component), attribute("kind", o.kind));
      if (!o.args.empty()) xml += attribute("args", o.args);
      if (!o.port.empty()) xml += attribute("port", o.port);
      if (o.duration_ms > 0) xml += attribute("duration", fmt::format("{:.0f}", o.duration_ms));
      xml += "/>\n";
      at += gap(rng);
    }
  }
  return xml + "</fault_scenario>\n";
}

}  // namespace keel::soak
