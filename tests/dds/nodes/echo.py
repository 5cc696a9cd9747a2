#!/usr/bin/env python3
"""An ordinary ROS 2 node, written as any rclpy node is and knowing nothing of keel: each
std_msgs/String it hears on `in` (relative: in its namespace) it publishes on `out` as
"echo: <what it heard>". It ends cleanly on SIGINT or SIGTERM (rclpy's handlers)."""
import sys

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_msgs.msg import String


class Echo(Node):
    def __init__(self):
        super().__init__("echo")
        self.publisher = self.create_publisher(String, "out", 10)
        self.create_subscription(String, "in", self.heard, 10)

    def heard(self, msg):
        self.publisher.publish(String(data=f"echo: {msg.data}"))


def main():
    rclpy.init(args=sys.argv)
    node = Echo()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
