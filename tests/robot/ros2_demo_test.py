#!/usr/bin/env python3
"""The demo's `ros2` experiment (docs/robot.md), run as scripts/demo.sh runs it
(robot/ros2/experiment.py): an rclpy node from PyPI drives keel's simulated robot, is killed
with kill -9, and is started again. One run; each test checks one thing it must show, from the
files the run leaves — keel's fault log, the referee's trace, the node's own stats — and the
moments the experiment saw things happen (OUT.summary.json, one clock).

  ros2_demo_test.py KEEL_CLI [unittest options]      (with the test peers' venv: scripts/peers.sh)"""
import csv
import json
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
KEEL = None
DEADLINE_S = 0.3  # robot/ros2.xml's <subscribe deadline>
SLACK_S = 1.5  # a busy 2-core machine: listener, fault thread, log, this test's 10 ms polling


class Ros2Demo(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = Path(tempfile.mkdtemp(prefix="keel_ros2_demo_"))
        out = cls.dir / "ros2"
        # ROS_DOMAIN_ID unset: the experiment holds a domain of the DDS tests' pool.
        env = {k: v for k, v in __import__("os").environ.items() if k != "ROS_DOMAIN_ID"}
        cls.run_ = subprocess.run([sys.executable, str(ROOT / "robot" / "ros2" / "experiment.py"), "--keel", KEEL,
                                   "--python", sys.executable, "--out", str(out), "--drive", "4", "--gone", "2",
                                   "--after", "4"], env=env, capture_output=True, text=True, timeout=150)
        if cls.run_.returncode != 0:  # a step did not happen: which, and what the run printed
            raise AssertionError(f"experiment.py failed ({cls.run_.returncode}):\n{cls.run_.stdout}\n{cls.run_.stderr}")
        cls.summary = json.loads(Path(f"{out}.summary.json").read_text())
        cls.records = [json.loads(line) for line in Path(f"{out}.jsonl").read_text().splitlines() if line.strip()]
        with open(f"{out}.csv") as f:
            cls.rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
        cls.nodes = [json.loads(Path(f"{out}.node{k}.json").read_text()) for k in (1, 2)]

    def context(self):
        return f"experiment's output:\n{self.run_.stdout}\n{self.run_.stderr}"

    def test_the_experiment_runs_to_its_end(self):
        self.assertEqual(self.run_.returncode, 0, self.context())
        self.assertEqual(self.summary["keel_exit"], 0, self.context())

    def test_the_node_receives_keels_sonar_ranges_and_diagnostics(self):
        """Before its kill the node took Range samples on all three topics (the sonars publish
        every 20 ms) and /diagnostics with every component of the robot, all OK."""
        first = self.nodes[0]
        for sonar in "abc":
            self.assertGreater(first["ranges"][sonar], 50, first)
        self.assertGreaterEqual(first["diagnostics_arrays"], 2, first)
        self.assertIn("keel/robot/teleop", first["levels"])
        self.assertIn("keel/robot/actuator", first["levels"])
        self.assertEqual(len(first["levels"]), 16, first["levels"])
        self.assertEqual(set(first["levels"].values()), {"OK"}, first["levels"])

    def test_the_robot_drives_on_the_nodes_commands(self):
        """Motion starts only once the node runs, and the wheels turn at the kill: the node's
        0.2 m/s ahead is 59 rpm, or a turn in place."""
        self.assertIsNotNone(self.summary.get("moving"), self.context())
        self.assertGreater(max(abs(r) for r in self.summary["rpm_at_kill"]), 15, self.summary["rpm_at_kill"])
        self.assertEqual(self.summary["remote_faults_before_kill"], 0, self.summary)

    def test_the_kill_is_a_remote_fault_of_the_teleop_within_its_deadline(self):
        fault = self.summary["fault"]
        self.assertEqual((fault["component"], fault["kind"], fault["detector"]), ("teleop", "remote", "dds"))
        self.assertEqual(fault["detail"], "no sample on /cmd_vel within its deadline of 300 ms")  # before the lease
        waited = self.summary["fault_seen"] - self.summary["killed"]
        self.assertGreater(waited, 0)
        self.assertLess(waited, DEADLINE_S + SLACK_S, self.context())

    def test_its_policy_resets_the_teleop_and_the_wheels_stop_until_the_node_is_back(self):
        """The reset is the stop command: both wheels at rest soon after the kill (the motors'
        150 ms lag), and nothing turns them until the node is started again."""
        action = self.summary["action"]
        self.assertEqual((action["action"], action["outcome"]), ("reset", "ok"), action)
        self.assertEqual(self.summary["recovered"]["fault_id"], self.summary["fault"]["fault_id"])
        self.assertLess(self.summary["at_rest"] - self.summary["killed"], DEADLINE_S + 0.8 + SLACK_S, self.context())
        self.assertEqual(self.summary["rows_moving_while_gone"], 0, self.context())

    def test_the_robot_drives_again_once_the_node_is_back(self):
        self.assertGreater(self.summary["moving_again"], self.summary["restarted"], self.context())
        moving = [r for r in self.rows if max(abs(r["rpm_left"]), abs(r["rpm_right"])) > 20]
        self.assertGreater(len(moving), 50)  # rows of 20 ms: a second of driving at least
        second = self.nodes[1]
        self.assertGreater(sum(second["ranges"].values()), 50, second)

    def test_the_restarted_node_reads_the_outage_in_keels_diagnostics(self):
        """keel's /diagnostics says WARN for a component with a fault in the last 5 s: the node,
        back within that, sees the teleop's."""
        self.assertGreater(self.nodes[1]["level_counts"].get("WARN", 0), 0, self.nodes[1])

    def test_the_outage_is_one_remote_fault_handled_by_a_reset(self):
        """One outage, one fault: the new node's writer is alive before its first sample comes,
        and the deadline firing meanwhile belongs to the same outage (docs/dds.md)."""
        remote = [r["fault_id"] for r in self.records if r.get("event") == "detected" and r.get("kind") == "remote"]
        self.assertEqual(len(remote), 1, self.records)
        resets = {r["fault_id"] for r in self.records if r.get("event") == "action" and r.get("action") == "reset"}
        self.assertEqual(set(remote) - resets, set(), self.records)

    def test_no_remote_fault_after_the_node_drives_again(self):
        """The fault belongs to the outage: none once the new node's commands flow."""
        offset = self.summary["fault_seen"] - self.summary["fault"]["t_ns"] / 1e9  # log time -> the run's
        for f in self.summary["remote_faults"]:
            at = f["t_ns"] / 1e9 + offset
            self.assertGreater(at, self.summary["killed"], f)
            self.assertLess(at, self.summary["moving_again"] + 0.05, f)


if __name__ == "__main__":
    KEEL = sys.argv[1]
    unittest.main(argv=[sys.argv[0]] + sys.argv[2:], verbosity=2)
