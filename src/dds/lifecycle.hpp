// The managed (lifecycle) nodes keel drives (docs/ros2-nodes.md#lifecycle-nodes), as keel run's
// DDS side reaches them: for each node, the writers of its `~/change_state` and `~/get_state`
// requests and the readers of its `~/transition_event` and `~/get_state` replies, all made when
// keel run starts watching, long before its first request.
//   A request is written as rmw_fastrtps reads it (the request alone, the request's id in the
//   sample's identity): the plain ChangeState_Request. Fast DDS answers every matched reply reader,
//   whoever asked, so a reply says nothing of which request it answers: keel takes a transition
//   as done when the node's own transition event says so, and a state when any get_state reply
//   says it (any client's: the node's state all the same).
//   The readers are best effort: a reliable CycloneDDS reader newly matched to a Fast DDS writer
//   holds back what it receives until the writer's first heartbeat (every 3 s while a sample is
//   unacknowledged), and a restarted node's first events would wait or be lost. On the host's
//   loopback a best-effort sample is lost only when a socket buffer overflows, and a transition
//   keel does not see confirmed it asks the node's state for.
// Only what a node's own process writes counts: a sample's writer must be of a participant the
// graph (ros2_graph.hpp) judges the node's.
// Thread-safety: open/close from one thread; request and askState from any thread after open;
// the listeners run on CycloneDDS's threads and call the watch (never under a lock of this).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dds/ros2_graph.hpp"
#include "keel/result.hpp"

namespace keel::dds {

/// Where what the lifecycle nodes say goes (keel run's side: its node supervisor).
class LifecycleWatch {
 public:
  virtual ~LifecycleWatch() = default;
  /// Node `instance` went from state `start` to `goal` (lifecycle_msgs/msg/State ids), as its
  /// `~/transition_event` says. CycloneDDS's threads.
  virtual void transitioned(const std::string& instance, std::uint8_t start, std::uint8_t goal) = 0;
  /// Node `instance` is in state `state`, as a `~/get_state` reply says. CycloneDDS's threads.
  virtual void stateIs(const std::string& instance, std::uint8_t state) = 0;
};

/// A lifecycle node to drive: keel's instance and its ROS 2 name ("/ns/name").
struct LifecycleNode {
  std::string instance;
  std::string name;
};

class LifecycleClients {
 public:
  /// `graph`: what judges whose participant a writer or reader is (it outlives this).
  LifecycleClients(LifecycleWatch& watch, Ros2Graph& graph);
  ~LifecycleClients();
  LifecycleClients(const LifecycleClients&) = delete;
  LifecycleClients& operator=(const LifecycleClients&) = delete;

  /// Makes each node's writers and readers in `participant`'s domain. Every problem is in the
  /// error; nothing is left open after a failure.
  Result<void> open(std::int32_t participant, const std::vector<LifecycleNode>& nodes);
  /// Every writer and reader open() made, each with whether it is a writer (for keel's listing
  /// in the ROS 2 graph).
  std::vector<std::pair<std::int32_t, bool>> entities() const;

  /// What became of a request.
  enum class Sent {
    Written,     // written: its reader of the node's current process is matched
    NotMatched,  // not written: no reader of the node's own process is matched yet
    Cyclone,     // not written: the node's reader is rmw_cyclonedds's, which reads another request
    NoSuchNode,  // not one of the nodes open() was given
  };
  /// Asks node `instance` for transition `transition` (lifecycle_msgs/msg/Transition id).
  Sent request(const std::string& instance, std::uint8_t transition);
  /// Asks node `instance` its state; the reply goes to the watch's stateIs.
  Sent askState(const std::string& instance);
  /// Deletes every writer and reader; no listener runs once it returns. Idempotent.
  void close();

  struct State;  // lifecycle.cpp

 private:
  std::unique_ptr<State> state_;
};

}  // namespace keel::dds
