// The run as the monitor shows it (docs/monitor.md): every component's lifecycle state and
// fault count, the emergency latch, and the wiring, kept up to date from the run's fault-log
// records. It makes the `/keel/state` snapshot a client sees on every change.
// Thread-safety: one owner thread (the monitor's hub).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace keel::monitor {

/// What the plan says of the run, before any record: its components and their connections.
struct Topology {
  struct Component {
    std::string name;         // qualified instance name, as the log names it
    std::string application;  // system profiles: its application; else empty
    std::string process;      // its <process>, or empty for keel run's own
  };
  struct Connection {
    std::string from, from_port, to, to_port;
    std::string type;  // data, event, service
  };
  std::string run;  // the root profile's name
  std::vector<Component> components;
  std::vector<Connection> connections;
};

class RunModel {
 public:
  explicit RunModel(Topology topology);

  /// Takes one fault-log record; true when the snapshot changed (a state, a fault count, the
  /// emergency latch, a process id).
  bool apply(const nlohmann::json& record);
  /// The `/keel/state` message at `t_ns` (ns since the run started): {t_ns, run, emergency, components[{name,
  /// application, state, faults, pid?}], connections[{from, from_port, to, to_port, type}]}.
  nlohmann::json snapshot(std::int64_t t_ns) const;
  /// The newest record time seen (ns since the run started).
  std::int64_t lastTime() const { return last_t_ns_; }

  /// The JSON schema of snapshot(), for the channel's advertisement.
  static const std::string& snapshotSchema();

 private:
  struct ComponentState {
    std::string application;
    std::string process;
    std::string state = "Created";
    std::uint64_t faults = 0;
    long pid = 0;  // its process's, for one in a component process
  };
  Topology topology_;
  std::vector<std::string> order_;  // components in plan order
  std::map<std::string, ComponentState, std::less<>> components_;
  std::map<std::string, long, std::less<>> process_pids_;
  bool emergency_ = false;
  std::int64_t last_t_ns_ = 0;

  ComponentState& component(const std::string& name);
};

}  // namespace keel::monitor
