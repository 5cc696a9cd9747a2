#!/usr/bin/env python3
"""rclpy's round trip, for the record beside keel's and the raw CycloneDDS program's in `keel bench
dds` (ROS 2 Kilted's rclpy from PyPI, its rmw Fast DDS; the tests' venv, scripts/peers.sh). The
same message (std_msgs/msg/Header, the stamp CLOCK_MONOTONIC right before the publish), topics
and QoS (reliable, keep last 10, volatile) as keel-bench-dds-raw:

  rclpy_pingpong.py pong TOPIC_IN TOPIC_OUT          echo each message back
  rclpy_pingpong.py ping TOPIC_OUT TOPIC_IN N PERIOD_US
      N + 100 stamps every PERIOD_US once the pong is matched; prints `rtt <ns>` for the last N
      echoes (arrival − stamp), then `done`

The domain is ROS_DOMAIN_ID's; Fast DDS's transport FASTDDS_DEFAULT_PROFILES_FILE's."""
import sys
import threading
import time

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Header

WARM_UP = 100
QOS = QoSProfile(depth=10, history=HistoryPolicy.KEEP_LAST, reliability=ReliabilityPolicy.RELIABLE,
                 durability=DurabilityPolicy.VOLATILE)


def now_ns():
    return time.clock_gettime_ns(time.CLOCK_MONOTONIC)


def topic(name):
    return name[3:] if name.startswith("rt/") else name  # ROS 2 names, as keel's <dds> topics


def pong(node, topic_in, topic_out):
    pub = node.create_publisher(Header, topic(topic_out), QOS)
    node.create_subscription(Header, topic(topic_in), pub.publish, QOS)
    rclpy.spin(node)


def ping(node, topic_out, topic_in, n, period_us):
    expected = n + WARM_UP
    rtt = []
    done = threading.Event()

    def echoed(h):
        arrival = now_ns()
        if len(rtt) < expected:
            rtt.append(arrival - (h.stamp.sec * 1_000_000_000 + h.stamp.nanosec))
        if len(rtt) >= expected:
            done.set()

    pub = node.create_publisher(Header, topic(topic_out), QOS)
    sub = node.create_subscription(Header, topic(topic_in), echoed, QOS)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    bound = time.monotonic() + 20
    while (pub.get_subscription_count() == 0 or sub.get_publisher_count() == 0) and time.monotonic() < bound:
        time.sleep(0.001)
    if pub.get_subscription_count() == 0:
        print("rclpy_pingpong: ping: no pong matched within 20 s", file=sys.stderr)
        return 1
    time.sleep(0.1)
    h = Header(frame_id="0")
    next_ns = now_ns()
    for _ in range(expected):
        next_ns += period_us * 1000
        delay = (next_ns - now_ns()) / 1e9
        if delay > 0:
            time.sleep(delay)
        t = now_ns()
        h.stamp.sec, h.stamp.nanosec = t // 1_000_000_000, t % 1_000_000_000
        pub.publish(h)
    done.wait(timeout=30)
    print("".join(f"rtt {v}\n" for v in rtt[WARM_UP:]) + "done", flush=True)
    return 0


def main(argv):
    if len(argv) == 4 and argv[1] == "pong":
        run, args = pong, (argv[2], argv[3])
    elif len(argv) == 6 and argv[1] == "ping":
        run, args = ping, (argv[2], argv[3], int(argv[4]), int(argv[5]))
    else:
        print(__doc__, file=sys.stderr)
        return 2
    rclpy.init()
    node = rclpy.create_node(f"keel_bench_{argv[1]}")
    try:
        return run(node, *args) or 0
    except KeyboardInterrupt:
        return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
