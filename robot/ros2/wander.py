#!/usr/bin/env python3
"""A ROS 2 node (rclpy) that drives keel's simulated robot (robot/ros2.xml): it wanders the
room, planning from the robot's sonar ranges that keel publishes, and reads keel's health.

  wander.py [--lifecycle] [--stats FILE] [--speed M_S] [--turn RAD_S] [--ros-args ...]

- subscribes /sonar/a, /sonar/b, /sonar/c (sensor_msgs/msg/Range, sensor-data QoS) and
  /diagnostics (diagnostic_msgs/msg/DiagnosticArray);
- publishes /cmd_vel (geometry_msgs/msg/Twist) at 20 Hz: ahead at --speed while the nearest front
  range is clear, turning in place (--turn, to the left) from 0.6 m until it is 0.9 m; nothing
  moves until ranges come. The publisher offers a 300 ms deadline and a 600 ms automatic
  liveliness lease: keel's subscription requests them (DDS matches a reader only with writers
  that offer what it requests) and makes a lost node a fault;
- on SIGUSR1 (the experiment's stand-in for a bug), its next command is corrupted: 5 m/s ahead,
  ten times what it ever commands, once;
- prints what it sees: the first range, once a second what came, each change of a keel
  component's diagnostic level; with --stats (default: $WANDER_STATS), the same as JSON in
  FILE, rewritten each second (what a kill -9 leaves is the last second's); `{pid}` in FILE is
  its process id, so that each life has a file of its own.

With --lifecycle it is a managed node (rclpy.lifecycle), as a standby needs: Unconfigured at
start; on_configure makes its subscriptions, its /cmd_vel (a lifecycle publisher) and its timers,
so that an Inactive process already has the ranges; it publishes only while Active, and says so
at each activation.

An ordinary ROS 2 node, named `keel_wander` unless remapped (`--ros-args -r __node:=NAME`):
`keel run robot/ros2.xml` starts it from robot/ros2/wander.xml with ROS 2's environment
(ROS_DOMAIN_ID, the rmw's configuration, a python3 with rclpy on PATH); robot/ros2/experiment.py
runs that and kills it."""
import argparse
import json
import os
import signal
import sys
import time

import rclpy
import rclpy.lifecycle
from rclpy.duration import Duration
from rclpy.qos import LivelinessPolicy, QoSProfile, qos_profile_sensor_data
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Range

LEVELS = {0: "OK", 1: "WARN", 2: "ERROR", 3: "STALE"}
SONARS = ("a", "b", "c")
PERIOD_S = 0.05
FRESH_S = 0.5  # older ranges are not planned on
TURN_AT_M, CLEAR_AT_M = 0.6, 0.9


def level_of(status):
    lv = status.level
    return LEVELS.get(lv[0] if isinstance(lv, (bytes, bytearray)) else int(lv), str(lv))


class Wander:
    def __init__(self, node, args, managed=False):
        self.node, self.args = node, args
        self.t0 = time.monotonic()
        self.ranges = {s: None for s in SONARS}  # (metres, arrival)
        self.counts = {s: 0 for s in SONARS}
        self.levels = {}  # component -> its last level
        self.level_counts = {}  # level -> statuses seen at it
        self.arrays = 0
        self.sent = 0
        self.corrupt = False  # SIGUSR1: the next command is garbage
        self.turning = False
        self.said = {}
        for s in SONARS:
            node.create_subscription(Range, f"/sonar/{s}", lambda m, s=s: self.on_range(s, m), qos_profile_sensor_data)
        node.create_subscription(DiagnosticArray, "/diagnostics", self.on_diagnostics, 10)
        qos = QoSProfile(depth=10, deadline=Duration(nanoseconds=300_000_000), liveliness=LivelinessPolicy.AUTOMATIC,
                         liveliness_lease_duration=Duration(nanoseconds=600_000_000))
        self.managed = managed
        self.cmd_vel = (node.create_lifecycle_publisher if managed else node.create_publisher)(Twist, "/cmd_vel", qos)
        node.create_timer(PERIOD_S, self.tick)
        node.create_timer(1.0, self.report)
        self.say(f"up, pid {os.getpid()}: /cmd_vel at {1 / PERIOD_S:.0f} Hz (deadline 300 ms, lease 600 ms offered); "
                 f"listening to /sonar/a, /sonar/b, /sonar/c and /diagnostics")

    def say(self, text):
        print(f"wander {time.monotonic() - self.t0:5.1f} s  {text}", flush=True)

    def on_range(self, sonar, m):
        if not any(self.counts.values()):
            self.say(f"first Range from keel: /sonar/{sonar} {m.range:.2f} m (frame {m.header.frame_id}, "
                     f"field of view {m.field_of_view:.2f} rad)")
        self.counts[sonar] += 1
        self.ranges[sonar] = (m.range, time.monotonic())

    def on_diagnostics(self, array):
        self.arrays += 1
        changed = []
        for s in array.status:
            level = level_of(s)
            self.level_counts[level] = self.level_counts.get(level, 0) + 1
            if self.levels.get(s.name) != level:
                changed.append((s.name, self.levels.get(s.name), level, s.message))
                self.levels[s.name] = level
        if self.arrays == 1:
            by_level = {}
            for name, _, level, _ in changed:
                by_level.setdefault(level, []).append(name)
            self.say(f"first /diagnostics from keel: {len(array.status)} components, "
                     + ", ".join(f"{len(v)} {k}" for k, v in sorted(by_level.items())))
            changed = [c for c in changed if c[2] != "OK"]
        for name, before, level, message in changed:
            self.say(f"/diagnostics: {name} {before or '-'} -> {level}: {message}")

    def front(self):
        now = time.monotonic()
        fresh = [r for r, t in filter(None, self.ranges.values()) if now - t <= FRESH_S]
        return min(fresh) if fresh else None

    def active(self):
        return not self.managed or self.cmd_vel.is_activated

    def tick(self):
        if not self.active():
            return  # a standby: it plans nothing and publishes nothing until it is activated
        t = Twist()
        d = self.front()
        if d is not None:
            if not self.turning and d < TURN_AT_M:
                self.turning = True
            elif self.turning and d > CLEAR_AT_M:
                self.turning = False
            if self.turning:
                t.angular.z = self.args.turn
            else:
                t.linear.x = self.args.speed
        if self.corrupt:
            self.corrupt = False
            t = Twist()
            t.linear.x = 5.0
            self.say("a corrupted command: 5.00 m/s ahead (SIGUSR1)")
        self.cmd_vel.publish(t)
        self.sent += 1
        self.last = t

    def stats(self):
        return {"pid": os.getpid(), "t_s": round(time.monotonic() - self.t0, 3), "ranges": self.counts,
                "diagnostics_arrays": self.arrays, "levels": self.levels, "level_counts": self.level_counts,
                "cmd_vel_sent": self.sent}

    def report(self):
        d = self.front()
        what = ("inactive: publishing nothing" if not self.active() else
                "no fresh range: standing still" if d is None else
                f"nearest {d:.2f} m: " + ("turning" if self.turning else f"ahead {self.args.speed:.2f} m/s"))
        worst = sorted(set(self.levels.values()) - {"OK"})
        self.say(f"{sum(self.counts.values())} ranges, {self.arrays} diagnostics, {self.sent} cmd_vel sent; {what}; "
                 f"keel's {len(self.levels)} components: " + (", ".join(
                     f"{n.rsplit('/', 1)[-1]} {lv}" for n, lv in sorted(self.levels.items()) if lv != "OK")
                     if worst else "all OK"))
        if self.args.stats:
            tmp = self.args.stats + ".tmp"
            with open(tmp, "w") as f:
                json.dump(self.stats(), f)
            os.replace(tmp, self.args.stats)


class ManagedWander(rclpy.lifecycle.Node):
    """Wander as a lifecycle node: made by on_configure, publishing while Active."""

    def __init__(self, args):
        super().__init__("keel_wander")
        self.args = args
        self.wander = None

    def on_configure(self, state):
        self.wander = Wander(self, self.args, managed=True)
        self.wander.say("configured: inactive, listening, publishing nothing")
        return rclpy.lifecycle.TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        result = super().on_activate(state)
        self.wander.say(f"activated, pid {os.getpid()}: driving")
        return result

    def on_deactivate(self, state):
        self.wander.cmd_vel.publish(Twist())  # still active here: its last command stops the wheels
        result = super().on_deactivate(state)
        self.wander.say("deactivated")
        return result


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--lifecycle", action="store_true", help="a managed (lifecycle) node")
    p.add_argument("--stats", default=os.environ.get("WANDER_STATS"),
                   help="write what it saw to this JSON file, each second ({pid}: its pid)")
    p.add_argument("--speed", type=float, default=0.2, help="m/s ahead (default 0.2)")
    p.add_argument("--turn", type=float, default=1.2, help="rad/s when turning (default 1.2)")
    args = p.parse_args(remove_ros_args(sys.argv)[1:])
    if args.stats:
        args.stats = args.stats.replace("{pid}", str(os.getpid()))
    rclpy.init(args=sys.argv, signal_handler_options=SignalHandlerOptions.NO)  # SIGINT, SIGTERM: ours, below
    if args.lifecycle:
        node = ManagedWander(args)
    else:
        node = rclpy.create_node("keel_wander")
        node.wander = Wander(node, args)
    stop = []
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, lambda *_: stop.append(1))
    signal.signal(signal.SIGUSR1, lambda *_: node.wander and setattr(node.wander, "corrupt", True))
    while not stop:
        rclpy.spin_once(node, timeout_sec=0.1)
    if node.wander:
        if node.wander.active():
            node.wander.cmd_vel.publish(Twist())  # a polite node stops what it drives
        node.wander.report()
        node.wander.say("stopped")
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
