#!/usr/bin/env python3
"""An ordinary ROS 2 sonar driver, written as any rclpy node is and knowing nothing of keel: it
publishes sensor_msgs/Range on `range` (relative: in its namespace) every 50 ms, `distance`
metres (a parameter, default 1.0). Two parameters make it misbehave as broken drivers do, each
from its `n`th message on (-1: never): `lie_at`, after which it reads `lie` (default -1.0: a
cable come loose) while running normally; `stall_at`, after which it publishes nothing more
but stays alive (a hung driver); `error_at`, after which its own status on /diagnostics
("sonar: driver", published with each message, OK before) is at ERROR ("no echo") while it
goes on publishing. With `warm_up_s` (default 0) its first message comes that long after its
start, as a driver's that opens its device first. It ends cleanly on SIGINT or SIGTERM (rclpy's handlers)."""
import sys
import time

import rclpy
from rclpy.executors import ExternalShutdownException
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.node import Node
from sensor_msgs.msg import Range


class Sonar(Node):
    def __init__(self):
        super().__init__("sonar")
        self.declare_parameter("distance", 1.0)
        self.declare_parameter("lie_at", -1)
        self.declare_parameter("lie", -1.0)
        self.declare_parameter("stall_at", -1)
        self.declare_parameter("error_at", -1)
        self.ready_at = time.monotonic() + self.declare_parameter("warm_up_s", 0.0).value
        self.publisher = self.create_publisher(Range, "range", 10)
        self.diagnostics = self.create_publisher(DiagnosticArray, "/diagnostics", 10)
        self.count = 0
        self.create_timer(0.05, self.tick)

    def tick(self):
        if time.monotonic() < self.ready_at:
            return
        self.count += 1
        stall_at = self.get_parameter("stall_at").value
        if 0 <= stall_at <= self.count:
            return
        lie_at = self.get_parameter("lie_at").value
        lying = 0 <= lie_at <= self.count
        msg = Range(radiation_type=Range.ULTRASOUND, field_of_view=0.5, min_range=0.02, max_range=4.0)
        msg.header.frame_id = "sonar"
        msg.range = float(self.get_parameter("lie" if lying else "distance").value)
        self.publisher.publish(msg)
        error_at = self.get_parameter("error_at").value
        failing = 0 <= error_at <= self.count
        status = DiagnosticStatus(level=DiagnosticStatus.ERROR if failing else DiagnosticStatus.OK,
                                  name="sonar: driver", message="no echo" if failing else "ok", hardware_id="sonar")
        self.diagnostics.publish(DiagnosticArray(status=[status]))


def main():
    rclpy.init(args=sys.argv)
    node = Sonar()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
