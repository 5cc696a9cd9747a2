#!/usr/bin/env python3
"""`keel bench ros2`'s node: an ordinary rclpy node (ROS 2 Kilted from PyPI, Fast DDS; the tests'
venv, scripts/peers.sh) that knows nothing of keel. It publishes std_msgs/msg/Header on `beat`
(relative: in its namespace) every `period_ms` (a parameter, default 10), the stamp
CLOCK_MONOTONIC, and with `deadline_ms` > 0 offers that deadline and a lease of twice it. Right
after its first publish it prints `first <CLOCK_MONOTONIC ns> <pid>`: the moment a restart or a
respawn has the node back, on the clock every other time of the benchmark is on.

With `--lifecycle` it is a managed node (rclpy.lifecycle): Unconfigured at start, its publisher
a lifecycle publisher made by on_configure, publishing while Active, and `first ...` printed at
its first publish after each activation (a standby's, once promoted).

  ros2_bench_node.py [--lifecycle] [--ros-args -r __node:=NAME -r __ns:=NS -p period_ms:=10 ...]"""
import os
import sys
import time

import rclpy
import rclpy.lifecycle
from rclpy.duration import Duration
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import LivelinessPolicy, QoSProfile
from std_msgs.msg import Header


def now_ns():
    return time.clock_gettime_ns(time.CLOCK_MONOTONIC)


class Beat(Node):
    def __init__(self):
        super().__init__("beat_node")
        period_ms = self.declare_parameter("period_ms", 10).value
        deadline_ms = self.declare_parameter("deadline_ms", 0).value
        qos = QoSProfile(depth=10)
        if deadline_ms > 0:
            qos.deadline = Duration(nanoseconds=deadline_ms * 1_000_000)
            qos.liveliness = LivelinessPolicy.AUTOMATIC
            qos.liveliness_lease_duration = Duration(nanoseconds=2 * deadline_ms * 1_000_000)
        self.publisher = self.create_publisher(Header, "beat", qos)
        self.first = True
        self.create_timer(period_ms / 1000.0, self.tick)

    def tick(self):
        beat(self)


def beat(node):
    """`node`'s message of this tick, stamped now; its first of a life (or an activation) said."""
    t = now_ns()
    msg = Header()
    msg.stamp.sec, msg.stamp.nanosec = divmod(t, 1_000_000_000)
    node.publisher.publish(msg)
    if node.first:
        node.first = False
        print(f"first {t} {os.getpid()}", flush=True)


class LifecycleBeat(rclpy.lifecycle.Node):
    def __init__(self):
        super().__init__("beat_node")
        self.period_ms = self.declare_parameter("period_ms", 10).value
        self.publisher = None
        self.first = True

    def on_configure(self, state):
        self.publisher = self.create_lifecycle_publisher(Header, "beat", QoSProfile(depth=10))
        self.create_timer(self.period_ms / 1000.0, self.tick)
        return rclpy.lifecycle.TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        self.first = True
        return super().on_activate(state)

    def tick(self):
        if self.publisher is not None and self.publisher.is_activated:
            beat(self)


def main():
    managed = "--lifecycle" in sys.argv
    args = [a for a in sys.argv if a != "--lifecycle"]
    rclpy.init(args=args)
    node = LifecycleBeat() if managed else Beat()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
