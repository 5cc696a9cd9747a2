// The ROS 2 graph as keel run sees it, for the nodes it watches (docs/ros2-nodes.md): which DDS
// participants list a node's name on `ros_discovery_info` (the rmws' graph topic) or publish one
// of its declared output topics (DCPSPublication), what process each participant announces (its
// pid: CycloneDDS's `__Pid`, Fast DDS's `fastdds.physical_data.process`), and which of the
// node's output topics each one publishes. Whenever that changes for a node, the node's sightings go to the
// GraphWatch: the node supervisor decides from them whether the node is up, and whether it left.
// A participant that leaves (a clean exit, or its lease expired) takes its listing with it.
// Thread-safety: open/close from one thread; the listeners run on CycloneDDS's threads, one
// at a time (a lock), and call the watch under it.
#pragma once

#include <sys/types.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "keel/result.hpp"
#include "runtime/warning.hpp"

namespace keel::dds {

/// One participant that lists a watched node by name, or publishes one of its output topics.
struct NodeSighting {
  std::string participant;  // its GUID prefix, hex
  pid_t pid = 0;            // its process, as it announces it; 0: not announced
  std::string host;         // its host, as it announces it; "": not announced
  bool listed = false;      // it lists the node's name on ros_discovery_info
  /// The node's declared output topics its participant does not publish (yet), ROS 2 names.
  std::vector<std::string> missing;
  bool operator==(const NodeSighting&) const = default;
};

/// Where the graph's news of watched nodes goes (keel run's side: its node supervisor).
class GraphWatch {
 public:
  virtual ~GraphWatch() = default;
  /// What the graph shows of node `instance` changed: every participant listing it or
  /// publishing one of its topics now (none: it is not in the graph). Called on CycloneDDS's threads, under the graph's
  /// lock: it must not call back into the graph.
  virtual void nodeSeen(const std::string& instance, const std::vector<NodeSighting>& sightings) = 0;
  /// Whether a participant of process `pid` (0: not announced) that lists node `instance` or
  /// not (`listed`) is the node's: its writers' samples are the node's values. Any thread.
  virtual bool ownsParticipant(const std::string& instance, pid_t pid, bool listed) = 0;
  /// Node `instance` published its own status (its profile's <diagnostics name>) on
  /// /diagnostics: at ERROR (`error`) or not; `what` is the status's name and message.
  virtual void nodeReported(const std::string& instance, bool error, const std::string& what) = 0;
};

/// A node to watch: keel's instance, its ROS 2 name, its declared output topics.
struct WatchedNode {
  std::string instance;
  std::string name;                  // "/ns/name"
  std::vector<std::string> outputs;  // ROS 2 topic names: "/cmd_vel"
  std::string diagnostics;           // the name of its own /diagnostics status; "": none
  /// Its other names ("/ns/name_standby_1": a lifecycle node's standbys, one of which may serve
  /// it): a participant listing one of them lists the node.
  std::vector<std::string> aliases{};

  /// Whether `listed` (the names a participant lists) holds the node's name or an alias.
  template <class Names>
  bool listedIn(const Names& listed) const {
    return listed.contains(name) ||
           std::any_of(aliases.begin(), aliases.end(), [&](const std::string& a) { return listed.contains(a); });
  }
};

class Ros2Graph {
 public:
  Ros2Graph(GraphWatch& watch, runtime::Warn warn);
  ~Ros2Graph();
  Ros2Graph(const Ros2Graph&) = delete;
  Ros2Graph& operator=(const Ros2Graph&) = delete;

  /// Reads the graph in `participant`'s domain for `nodes`. Each node's first sightings (none,
  /// if it is not there) are reported once the readers have what DDS holds.
  Result<void> open(std::int32_t participant, std::vector<WatchedNode> nodes);
  /// Whether the participant whose GUID is `participant` (16 bytes) is node `instance`'s, as the
  /// watch judges from its pid and listing. Any thread.
  bool ownedBy(const std::string& instance, const std::uint8_t* participant);
  /// The process the participant whose GUID is `participant` (16 bytes) announces; 0: not
  /// announced, or not discovered. Any thread.
  pid_t pidOf(const std::uint8_t* participant);
  /// Deletes the readers; no listener runs once it returns. Idempotent.
  void close();

  struct State;  // ros2_graph.cpp

 private:
  std::unique_ptr<State> state_;
};

}  // namespace keel::dds
