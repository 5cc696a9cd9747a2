#!/usr/bin/env python3
"""An ordinary ROS 2 managed (lifecycle) node, written as any rclpy.lifecycle node is and knowing
nothing of keel. It starts Unconfigured; on_configure makes a lifecycle publisher of
std_msgs/String on `chatter` (relative: in its namespace) and a 100 ms timer; while Active it
publishes "<greeting> <n> <pid>" (`greeting` a parameter, default "hello"; n counts from 1 in
each activation; pid its process's, so that a listener tells the writers apart) and std_msgs/Float64 1.0 on `level`, while Inactive nothing (a lifecycle publisher
drops what it is given). Each callback
prints one line on stdout, `lifecycle <transition> <pid>` (configure, activate, deactivate,
cleanup, shutdown, error), so that a test sees which process went through what.

Parameters to misbehave as nodes do:
  fail_configure  (bool, default false)  on_configure returns FAILURE: back to Unconfigured
  error_configure (bool, default false)  on_configure raises: ErrorProcessing, then Unconfigured
  configure_ms    (int, default 0)       on_configure takes this long first (a transition timing out)
  finalize_at     (int, default -1)      at its `finalize_at`th message, the node shuts itself
                                         down (Finalized) and goes on living
  lie_at          (int, default -1)      its `lie_at`th message's level is 100.0 (once a process:
                                         a glitch the process has only once)
It ends cleanly on SIGINT or SIGTERM (rclpy's handlers)."""
import os
import sys
import time

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.lifecycle import Node, TransitionCallbackReturn
from std_msgs.msg import Float64, String


class LifecycleTalker(Node):
    def __init__(self):
        super().__init__("lifecycle_talker")
        self.declare_parameter("greeting", "hello")
        self.declare_parameter("fail_configure", False)
        self.declare_parameter("error_configure", False)
        self.declare_parameter("configure_ms", 0)
        self.declare_parameter("finalize_at", -1)
        self.declare_parameter("lie_at", -1)
        self.lied = False
        self.publisher = None
        self.level = None
        self.timer = None
        self.count = 0

    def say(self, what):
        print(f"lifecycle {what} {os.getpid()}", flush=True)

    def on_configure(self, state):
        self.say("configure")
        delay_ms = self.get_parameter("configure_ms").value
        if delay_ms > 0:
            time.sleep(delay_ms / 1000.0)
        if self.get_parameter("error_configure").value:
            raise RuntimeError("cannot configure")
        if self.get_parameter("fail_configure").value:
            return TransitionCallbackReturn.FAILURE
        self.publisher = self.create_lifecycle_publisher(String, "chatter", 10)
        self.level = self.create_lifecycle_publisher(Float64, "level", 10)
        self.timer = self.create_timer(0.1, self.tick)
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        self.say("activate")
        self.count = 0
        return super().on_activate(state)

    def on_deactivate(self, state):
        self.say("deactivate")
        return super().on_deactivate(state)

    def on_cleanup(self, state):
        self.say("cleanup")
        self.destroy_timer(self.timer)
        self.destroy_lifecycle_publisher(self.publisher)
        self.destroy_lifecycle_publisher(self.level)
        self.timer = self.publisher = self.level = None
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state):
        self.say("shutdown")
        return TransitionCallbackReturn.SUCCESS

    def on_error(self, state):
        self.say("error")
        return TransitionCallbackReturn.SUCCESS

    def tick(self):
        if self.publisher is None or not self.publisher.is_activated:
            return
        self.count += 1
        greeting = self.get_parameter("greeting").value
        self.publisher.publish(String(data=f"{greeting} {self.count} {os.getpid()}"))
        lie = self.count == self.get_parameter("lie_at").value and not self.lied
        self.lied = self.lied or lie
        self.level.publish(Float64(data=100.0 if lie else 1.0))
        if self.count == self.get_parameter("finalize_at").value:
            self.trigger_shutdown()


def main():
    rclpy.init(args=sys.argv)
    node = LifecycleTalker()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
