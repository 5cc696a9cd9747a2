// /parameter_events as keel run reads it (docs/ros2-nodes.md): every ROS 2 node publishes there,
// on each change of its parameters (a declaration, `ros2 param set`, a parameter client), an
// rcl_interfaces/msg/ParameterEvent naming the node and its new, changed and deleted parameters.
// keel reads the events of the nodes it runs, so that a node it restarts comes back with the
// values it last had; each is told to the ParameterWatch (keel run's side: its node supervisor).
// The topic is volatile: what a node announced before keel's reader matched its writer is lost.
// Thread-safety: open/close from one thread; the listener runs on CycloneDDS's threads, one
// sample at a time (a lock), and calls the watch under it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dds/ros2_graph.hpp"
#include "keel/result.hpp"
#include "profile/parameter_value.hpp"
#include "runtime/warning.hpp"

namespace keel::msg::rcl_interfaces {
struct ParameterEvent;
}  // namespace keel::msg::rcl_interfaces

namespace keel::dds {

/// Where the parameter changes of the nodes keel runs go.
class ParameterWatch {
 public:
  virtual ~ParameterWatch() = default;
  /// Node `instance` (keel's instance of a watched node) announced `update`. Called on
  /// CycloneDDS's threads, one event at a time.
  virtual void parametersChanged(const std::string& instance, const profile::ParameterUpdate& update) = 0;
};

/// What `event` says of its node's parameters: each new or changed parameter's typed value; a
/// deleted one, or one set to no value (PARAMETER_NOT_SET), by name. A byte array, which a params
/// file cannot hold, or a value of a type this keel does not know, is in neither: its name goes to
/// `skipped`.
profile::ParameterUpdate updateOf(const msg::rcl_interfaces::ParameterEvent& event, std::vector<std::string>& skipped);

class ParameterEvents {
 public:
  ParameterEvents(ParameterWatch& watch, runtime::Warn warn);
  ~ParameterEvents();
  ParameterEvents(const ParameterEvents&) = delete;
  ParameterEvents& operator=(const ParameterEvents&) = delete;

  /// Reads /parameter_events in `participant`'s domain for `nodes` (their instances and fully
  /// qualified names; their outputs are not used), which rclcpp and rclpy publish reliable,
  /// volatile, keep last 1000: best effort (each event as it comes: parameter_events.cpp says
  /// why), volatile, every sample kept. Returns the reader.
  Result<std::int32_t> open(std::int32_t participant, std::vector<WatchedNode> nodes);
  /// Deletes the reader; no listener runs once it returns. Idempotent.
  void close();

  struct State;  // parameter_events.cpp

 private:
  std::unique_ptr<State> state_;
};

}  // namespace keel::dds
