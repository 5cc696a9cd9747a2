#!/usr/bin/env python3
"""A ROS 2 node (rclpy) that publishes geometry_msgs/Twist, for ros2_peer_test.py to kill.

  ros2_publisher.py TOPIC PERIOD_MS DEADLINE_MS LEASE_MS [DELAY_MS]

It offers the deadline and an automatic liveliness lease (a reader requesting them matches
only such writers), prints `publishing` once it has published, and runs until killed. With
DELAY_MS, its first message waits that long after the publisher is made (alive all along, as a
node still starting)."""
import sys
import time

import rclpy
from rclpy.duration import Duration
from rclpy.qos import LivelinessPolicy, QoSProfile
from geometry_msgs.msg import Twist


def main():
    topic, period_ms, deadline_ms, lease_ms = sys.argv[1], *map(float, sys.argv[2:5])
    delay_ms = float(sys.argv[5]) if len(sys.argv) > 5 else 0
    rclpy.init()
    node = rclpy.create_node("keel_test_publisher")
    qos = QoSProfile(depth=10, deadline=Duration(nanoseconds=int(deadline_ms * 1e6)),
                     liveliness=LivelinessPolicy.AUTOMATIC,
                     liveliness_lease_duration=Duration(nanoseconds=int(lease_ms * 1e6)))
    pub = node.create_publisher(Twist, topic, qos)
    n = 0

    def tick():
        nonlocal n
        t = Twist()
        t.linear.x = 0.01 * n
        pub.publish(t)
        if n == 0:
            print("publishing", flush=True)
        n += 1
    if delay_ms:
        print("alive", flush=True)
        time.sleep(delay_ms / 1000.0)
    node.create_timer(period_ms / 1000.0, tick)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
