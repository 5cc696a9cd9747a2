#!/usr/bin/env python3
"""An ordinary ROS 2 node, written as any rclpy node is and knowing nothing of keel: it publishes
std_msgs/String "<greeting> <n>" on `chatter` (relative: in its namespace) every 100 ms, its
`greeting` a parameter (default "hello"). With `deadline_ms` (default 0: none) its publisher
offers that deadline and a lease of twice it, as a driver whose readers watch it would. With
`fail_at` (default -1: never) it dies at its `fail_at`th message as buggy nodes do, `fail_how`
saying how: `exception` (an uncaught ZeroDivisionError out of its callback, exit status 1) or
`exit` (sys.exit(3)). It says "talker up" on stdout once it publishes, and
ends cleanly on SIGINT or SIGTERM (rclpy's handlers)."""
import sys

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import LivelinessPolicy, QoSProfile
from std_msgs.msg import String


class Talker(Node):
    def __init__(self):
        super().__init__("talker")
        self.declare_parameter("greeting", "hello")
        deadline_ms = self.declare_parameter("deadline_ms", 0).value
        qos = QoSProfile(depth=10)
        if deadline_ms > 0:
            qos.deadline = Duration(nanoseconds=deadline_ms * 1_000_000)
            qos.liveliness = LivelinessPolicy.AUTOMATIC
            qos.liveliness_lease_duration = Duration(nanoseconds=2 * deadline_ms * 1_000_000)
        self.publisher = self.create_publisher(String, "chatter", qos)
        self.count = 0
        self.fail_at = self.declare_parameter("fail_at", -1).value
        self.fail_how = self.declare_parameter("fail_how", "exception").value
        self.create_timer(0.1, self.tick)

    def tick(self):
        self.count += 1
        greeting = self.get_parameter("greeting").value
        self.publisher.publish(String(data=f"{greeting} {self.count}"))
        if self.count == 1:
            print("talker up", flush=True)
        if self.count == self.fail_at:
            if self.fail_how == "exit":
                sys.exit(3)
            print(1 / (self.count - self.fail_at))


def main():
    rclpy.init(args=sys.argv)
    node = Talker()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
