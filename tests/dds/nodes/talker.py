#!/usr/bin/env python3
"""An ordinary ROS 2 node, written as any rclpy node is and knowing nothing of keel: it publishes
std_msgs/String "<greeting> <n>" on `chatter` (relative: in its namespace) every 100 ms, its
`greeting` a parameter (default "hello"). It says "talker up" on stdout once it publishes, and
ends cleanly on SIGINT or SIGTERM (rclpy's handlers)."""
import sys

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_msgs.msg import String


class Talker(Node):
    def __init__(self):
        super().__init__("talker")
        self.declare_parameter("greeting", "hello")
        self.publisher = self.create_publisher(String, "chatter", 10)
        self.count = 0
        self.create_timer(0.1, self.tick)

    def tick(self):
        self.count += 1
        greeting = self.get_parameter("greeting").value
        self.publisher.publish(String(data=f"{greeting} {self.count}"))
        if self.count == 1:
            print("talker up", flush=True)


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
