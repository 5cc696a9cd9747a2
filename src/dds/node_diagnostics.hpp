// What the ROS 2 nodes keel watches say of themselves on /diagnostics (docs/ros2-nodes.md): a
// node whose profile names its own status (`<diagnostics name="sonar: driver"/>`) is at fault
// when that status is at ERROR. Statuses are read from the node's own writers only (its
// participant, as the graph judges it: ros2_graph.hpp), since any node may publish any name; each
// sample's level goes to the GraphWatch, which raises one fault per episode at ERROR.
// Thread-safety: open/close from one thread; the listener runs on CycloneDDS's threads.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "dds/ros2_graph.hpp"
#include "keel/result.hpp"

namespace keel::dds {

class NodeDiagnostics {
 public:
  NodeDiagnostics(Ros2Graph& graph, GraphWatch& watch);
  ~NodeDiagnostics();
  NodeDiagnostics(const NodeDiagnostics&) = delete;
  NodeDiagnostics& operator=(const NodeDiagnostics&) = delete;

  /// Reads /diagnostics in `participant`'s domain for the `nodes` that name a status of their
  /// own: best effort (it matches diagnostic_updater's reliable writers too), volatile.
  Result<void> open(std::int32_t participant, std::vector<WatchedNode> nodes);
  /// Deletes the reader; no listener runs once it returns. Idempotent.
  void close();

  struct State;  // node_diagnostics.cpp

 private:
  std::unique_ptr<State> state_;
};

}  // namespace keel::dds
