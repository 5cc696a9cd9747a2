#include "monitor/run_model.hpp"

#include "log/schema.hpp"

namespace keel::monitor {
namespace {

namespace event = log::schema::event;
namespace field = log::schema::field;
using nlohmann::json;

std::string text(const json& record, const char* key) {
  auto it = record.find(key);
  return it != record.end() && it->is_string() ? it->get<std::string>() : std::string();
}

}  // namespace

RunModel::RunModel(Topology topology) : topology_(std::move(topology)) {
  for (const auto& c : topology_.components) {
    order_.push_back(c.name);
    auto& s = components_[c.name];
    s.application = c.application;
    s.process = c.process;
  }
}

RunModel::ComponentState& RunModel::component(const std::string& name) {
  auto it = components_.find(name);
  if (it != components_.end()) return it->second;
  order_.push_back(name);  // not in the plan (a log read without one): shown as it appears
  return components_[name];
}

bool RunModel::apply(const json& record) {
  if (!record.is_object()) return false;
  if (auto t = record.find(field::kTime); t != record.end() && t->is_number_integer())
    last_t_ns_ = std::max(last_t_ns_, t->get<std::int64_t>());
  const std::string ev = text(record, field::kEvent);
  const std::string name = ev == event::kState && record.contains(field::kComposite)
                               ? text(record, field::kComposite)  // a composite: a row of its own
                               : text(record, field::kComponent);
  if (ev == event::kState && !name.empty()) {
    if (auto s = record.find(field::kServing); s != record.end() && *s == false) return false;  // not standing for it
    auto& c = component(name);
    c.state = text(record, field::kTo);
    if (auto pid = record.find(field::kPid); pid != record.end() && pid->is_number_integer()) c.pid = pid->get<long>();
    return true;
  }
  if (ev == event::kDetected && !name.empty()) {
    ++component(name).faults;
    return true;
  }
  if (ev == event::kEmergency) {
    const bool latched = text(record, field::kPhase) == "latched";
    const bool changed = latched != emergency_;
    emergency_ = latched;
    return changed;
  }
  if (ev == event::kHost) {
    // A component process started, took over or died: its members' pid follows.
    const std::string process = text(record, field::kProcess);
    auto pid = record.find(field::kPid);
    if (process.empty() || pid == record.end() || !pid->is_number_integer()) return false;
    const std::string phase = text(record, field::kPhase);
    if (phase != "starting" && phase != "took_over" && phase != "respawned") return false;
    bool changed = false;
    for (auto& [n, c] : components_) {
      if (c.process != process || c.pid == pid->get<long>()) continue;
      c.pid = pid->get<long>();
      changed = true;
    }
    return changed;
  }
  return false;
}

json RunModel::snapshot(std::int64_t t_ns) const {
  json components = json::array();
  for (const auto& name : order_) {
    const auto& c = components_.find(name)->second;
    json one = {{"name", name}, {"application", c.application}, {"state", c.state}, {"faults", c.faults}};
    if (!c.process.empty()) one["process"] = c.process;
    if (c.pid != 0) one["pid"] = c.pid;
    components.push_back(std::move(one));
  }
  json connections = json::array();
  for (const auto& w : topology_.connections)
    connections.push_back(
        {{"from", w.from}, {"from_port", w.from_port}, {"to", w.to}, {"to_port", w.to_port}, {"type", w.type}});
  return {{"t_ns", t_ns},
          {"run", topology_.run},
          {"emergency", emergency_},
          {"components", std::move(components)},
          {"connections", std::move(connections)}};
}

const std::string& RunModel::snapshotSchema() {
  static const std::string schema =
      json{{"type", "object"},
           {"title", "keel.State"},
           {"description", "Every component's lifecycle state and fault count, the emergency latch and the wiring"},
           {"properties",
            {{"t_ns", {{"type", "integer"}, {"description", "ns since the run started (steady clock)"}}},
             {"run", {{"type", "string"}}},
             {"emergency", {{"type", "boolean"}}},
             {"components",
              {{"type", "array"},
               {"items",
                {{"type", "object"},
                 {"properties",
                  {{"name", {{"type", "string"}}},
                   {"application", {{"type", "string"}}},
                   {"state", {{"type", "string"}}},
                   {"faults", {{"type", "integer"}}},
                   {"process", {{"type", "string"}}},
                   {"pid", {{"type", "integer"}}}}}}}}},
             {"connections",
              {{"type", "array"},
               {"items",
                {{"type", "object"},
                 {"properties",
                  {{"from", {{"type", "string"}}},
                   {"from_port", {{"type", "string"}}},
                   {"to", {{"type", "string"}}},
                   {"to_port", {{"type", "string"}}},
                   {"type", {{"type", "string"}}}}}}}}}}}}
          .dump();
  return schema;
}

}  // namespace keel::monitor
