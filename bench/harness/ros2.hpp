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

}  // namespace keel::bench
