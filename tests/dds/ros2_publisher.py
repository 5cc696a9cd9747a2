#!/usr/bin/env python3
"""A ROS 2 node (rclpy) that publishes geometry_msgs/Twist, for ros2_peer_test.py to kill.

  ros2_publisher.py TOPIC PERIOD_MS DEADLINE_MS LEASE_MS [DELAY_MS [READERS]]

It offers the deadline and an automatic liveliness lease (a reader requesting them matches
only such writers), prints `publishing` once it has published, and runs until killed. With
DELAY_MS, its first message waits that long after the publisher is made (alive all along, as a
node still starting). With READERS, it also prints `heard by N` once a message it published while
N >= READERS readers were matched has been acknowledged by all of them: a keel reader
acknowledges only a writer it has matched itself, and only a reader that matched the writer can
tell that it was lost."""
import sys
import time

import rclpy
from rclpy.duration import Duration
from rclpy.qos import LivelinessPolicy, QoSProfile
from geometry_msgs.msg import Twist


def main():
    topic, period_ms, deadline_ms, lease_ms = sys.argv[1], *map(float, sys.argv[2:5])
    delay_ms = float(sys.argv[5]) if len(sys.argv) > 5 else 0
    readers = int(sys.argv[6]) if len(sys.argv) > 6 else 0
    rclpy.init()
    node = rclpy.create_node("keel_test_publisher")
    qos = QoSProfile(depth=10, deadline=Duration(nanoseconds=int(deadline_ms * 1e6)),
                     liveliness=LivelinessPolicy.AUTOMATIC,
                     liveliness_lease_duration=Duration(nanoseconds=int(lease_ms * 1e6)))
    pub = node.create_publisher(Twist, topic, qos)
    n, matched, heard = 0, 0, readers == 0

    def tick():
        nonlocal n, matched, heard
        # The last message went to `matched` readers: all of them acknowledged it?
        if not heard and matched >= readers and pub.wait_for_all_acked(Duration(seconds=0)):
            print(f"heard by {matched}", flush=True)
            heard = True
        matched = pub.get_subscription_count()
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
