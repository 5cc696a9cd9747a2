// `keel bench ros2`: ROS 2 nodes under keel (docs/ros2-nodes.md), measured as a user runs them —
// the real engine, in the harness's process, supervising an ordinary rclpy node
// (bench/peers/ros2_bench_node.py: std_msgs/msg/Header every 10 ms on /keel_bench/beat, which
// prints the moment of its first message) — beside what the machine and a user's other tools
// give, in one run:
//   death          kill -9 of the node keel supervises: keel's `process` fault's detection − the kill
//   floor_death    the same node started by the harness and killed: its pidfd readable − the
//                  kill (the kernel's teardown of the process and one wake-up: the machine's floor)
//   restart        kill -9 of the node keel supervises: the first message of its next life − the
//                  kill (keel sees the death, restarts the node, the node starts)
//   respawn        the same with the harness as a plain respawn loop: wait for the exit, start
//                  again (what `ros2 launch`'s respawn does), beside keel's engine reading the
//                  node's topic, so that the node starts among the same DDS participants
//   deadline_only  a keel <subscribe> with a deadline of kNodeDeadlineMs on the node's topic, the
//                  node started by the harness: the `remote` fault − the kill (the watch a
//                  subscriber has without supervision)
//   idle_cpu       keel's CPU while it supervises kIdleNodes idle nodes (a message a second
//                  each), beside the nodes' own, over kIdleWindow
//   takeover       the node as a lifecycle node (--lifecycle) with one standby: kill -9 of the
//                  active → the standby's first message (keel sees the death, fences nothing,
//                  activates the standby, which publishes at its next tick)
//   cold           the same lifecycle node without a standby: kill -9 → the restarted node's
//                  first message (start, configure, activate, first message)
//   standby_cost   the standby's CPU while it waits and its memory, beside the active's
// Every node and keel's engine are on one domain, on the loopback (DdsEnvironment).
#pragma once

#include <chrono>
#include <string>

#include "dds.hpp"
#include "paths.hpp"

namespace keel::bench {

inline constexpr int kNodeDeadlineMs = 300;  // deadline_only: the subscription's deadline
inline constexpr int kIdleNodes = 10;        // idle_cpu: how many nodes keel supervises
inline constexpr std::chrono::seconds kIdleWindow{10};

/// A death and what follows it: keel's detection and restart, or the floor and a respawn.
struct Ros2Kills {
  DdsCell death;  // death or floor_death
  DdsCell back;   // restart or respawn: the node's first message again − the kill
};

/// `n` kills (and a first one, not counted) of a node keel supervises with policy `reset`.
Ros2Kills measureSupervised(const Paths& paths, const std::string& python, int n);
/// `n` kills (and a first one, not counted) of the same node, the harness its respawn loop.
Ros2Kills measureRespawnLoop(const Paths& paths, const std::string& python, int n);
/// `n` kills of the node started by the harness, watched by a keel subscription's deadline.
DdsCell measureDeadlineOnly(const Paths& paths, const std::string& python, int n);

struct IdleCpu {
  double keel_percent = 0;   // keel's engine: % of one CPU
  double nodes_percent = 0;  // the nodes together: % of one CPU
  std::string error;
};
/// keel supervising kIdleNodes idle nodes, once every one is up, over kIdleWindow.
IdleCpu measureIdleCpu(const Paths& paths, const std::string& python);

/// `n` kills (and a first one, not counted) of the active process of a lifecycle node keel
/// supervises with policy `reset`, with `standby` standbys (each kill once one is ready).
/// `back`: the kill → the next active's first message; `death` is not measured.
Ros2Kills measureManaged(const Paths& paths, const std::string& python, int n, int standby);

struct StandbyCost {
  double standby_cpu_percent = 0;  // the standby waiting, over kIdleWindow: % of one CPU
  double active_cpu_percent = 0;   // the active publishing every 10 ms, the same window
  double standby_rss_mib = 0;      // resident memory
  double active_rss_mib = 0;
  std::string error;
};
StandbyCost measureStandbyCost(const Paths& paths, const std::string& python);

}  // namespace keel::bench
