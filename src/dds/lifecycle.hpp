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
// A managed node may run as several processes under names of their own (its standbys:
// "/ns/name_standby_1"); each name is reached apart. Only what the process keel runs under a name
// writes or reads counts: an endpoint's participant must announce that process's pid (as the
// graph, ros2_graph.hpp, knows it) — a killed process's stays in the graph until its lease ends.
// Thread-safety: open/close from one thread; request and askState from any thread after open;
// the listeners run on CycloneDDS's threads and call the watch (never under a lock of this).
#pragma once

#include <sys/types.h>

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
  /// The process named `name` of node `instance` went from state `start` to `goal`
  /// (lifecycle_msgs/msg/State ids), as its `~/transition_event` says. CycloneDDS's threads.
  virtual void transitioned(const std::string& instance, const std::string& name, std::uint8_t start,
                            std::uint8_t goal) = 0;
  /// The process named `name` of node `instance` is in state `state`, as a `~/get_state` reply
  /// says. CycloneDDS's threads.
  virtual void stateIs(const std::string& instance, const std::string& name, std::uint8_t state) = 0;
  /// Whether process `pid` is the one keel runs as `name` of node `instance` now. Any thread.
  virtual bool runs(const std::string& instance, const std::string& name, pid_t pid) = 0;
};

/// A lifecycle node to drive: keel's instance and every ROS 2 name it may run under ("/ns/name",
/// then its standbys' "/ns/name_standby_K").
struct LifecycleNode {
  std::string instance;
  std::vector<std::string> names;
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
  /// in the ROS 2 graph; renew() replaces writers).
  std::vector<std::pair<std::int32_t, bool>> entities() const;

  /// What became of a request.
  enum class Sent {
    Written,     // written: its reader of the node's current process is matched
    NotMatched,  // not written: no reader of the node's own process is matched yet
    Cyclone,     // not written: the node's reader is rmw_cyclonedds's, which reads another request
    NoSuchNode,  // not one of the nodes open() was given
  };
  /// Asks the process named `name` of node `instance` for transition `transition`
  /// (lifecycle_msgs/msg/Transition id).
  Sent request(const std::string& instance, const std::string& name, std::uint8_t transition);
  /// Asks the process named `name` of node `instance` its state; the reply goes to stateIs.
  Sent askState(const std::string& instance, const std::string& name);
  /// A new process is to run as `name` of node `instance`: its request writers are made anew,
  /// so that nothing keel asked an earlier process of that name reaches it (a CycloneDDS writer
  /// hands a Fast DDS reader that joins late the requests it still holds, and the new process
  /// would perform them). Returns each writer replaced with its replacement (for keel's listing
  /// in the ROS 2 graph); none when `name` is not one of open()'s or CycloneDDS refused.
  std::vector<std::pair<std::int32_t, std::int32_t>> renew(const std::string& instance, const std::string& name);
  /// Deletes every writer and reader; no listener runs once it returns. Idempotent.
  void close();

  struct State;  // lifecycle.cpp

 private:
  std::unique_ptr<State> state_;
};

}  // namespace keel::dds
