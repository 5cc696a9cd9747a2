#!/usr/bin/env python3
"""The demo's `ros2` experiment (docs/robot.md), run as scripts/demo.sh runs it
(robot/ros2/experiment.py): an rclpy node from PyPI, started and supervised by keel from the
robot's profile, drives keel's simulated robot, is killed with kill -9 and restarted by keel,
then sends one corrupted command, a `range` fault of it, and is restarted again; and its
`ros2_standby` experiment (--standby): the node a lifecycle node with a hot standby, which takes
over from the killed node and from the one that sent garbage. One run each; each test checks one thing it must show, from the files the run leaves — keel's fault log,
the referee's trace, the node's own stats — and the moments the experiment saw things happen
(OUT.summary.json, one clock).

  ros2_demo_test.py KEEL_CLI [unittest options]      (with the test peers' venv: scripts/peers.sh)"""
import csv
import json
import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
KEEL = None
DEADLINE_MS = 300  # robot/ros2.xml's <subscribe deadline>: keel must not wait for it
SOON_MS = 250  # generous on a busy 2-core machine, and still before that deadline


class Ros2Demo(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = Path(tempfile.mkdtemp(prefix="keel_ros2_demo_"))
        out = cls.dir / "ros2"
        # ROS_DOMAIN_ID unset: the experiment holds a domain of the DDS tests' pool.
        env = {k: v for k, v in os.environ.items() if k != "ROS_DOMAIN_ID"}
        cls.run_ = subprocess.run([sys.executable, str(ROOT / "robot" / "ros2" / "experiment.py"), "--keel", KEEL,
                                   "--python", sys.executable, "--out", str(out), "--drive", "4", "--after", "4"],
                                  env=env, capture_output=True, text=True, timeout=150)
        if cls.run_.returncode != 0:  # a step did not happen: which, and what the run printed
            raise AssertionError(f"experiment.py failed ({cls.run_.returncode}):\n{cls.run_.stdout}\n{cls.run_.stderr}")
        cls.summary = json.loads(Path(f"{out}.summary.json").read_text())
        cls.records = [json.loads(line) for line in Path(f"{out}.jsonl").read_text().splitlines() if line.strip()]
        with open(f"{out}.csv") as f:
            cls.rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
        cls.lives = [json.loads(Path(f"{out}.wander-{cls.summary[k]}.json").read_text()) for k in ("pid", "pid_again")]

    def context(self):
        return f"experiment's output:\n{self.run_.stdout}\n{self.run_.stderr}"

    def test_the_experiment_runs_to_its_end(self):
        self.assertEqual(self.run_.returncode, 0, self.context())
        self.assertEqual(self.summary["keel_exit"], 0, self.context())

    def test_keel_starts_the_node_and_it_receives_keels_sonar_ranges_and_diagnostics(self):
        """keel started the node from the robot's profile (its first `node` record), and before
        its kill the node took Range samples on all three topics (the sonars publish every 20 ms)
        and /diagnostics with every component of the robot, the node's stand-in too, all OK."""
        phases = [r["phase"] for r in self.summary["node_records"]]
        self.assertEqual(phases[:2], ["started", "up"], self.summary["node_records"])
        first = self.lives[0]
        self.assertEqual(first["pid"], self.summary["pid"])
        for sonar in "abc":
            self.assertGreater(first["ranges"][sonar], 50, first)
        self.assertGreaterEqual(first["diagnostics_arrays"], 2, first)
        for name in ("teleop", "actuator", "wander"):
            self.assertIn(f"keel/robot/{name}", first["levels"])
        self.assertEqual(len(first["levels"]), 17, first["levels"])
        self.assertEqual(set(first["levels"].values()), {"OK"}, first["levels"])

    def test_the_robot_drives_on_the_nodes_commands(self):
        """Motion starts only once the node runs, and the wheels turn at the kill: the node's
        0.2 m/s ahead is 59 rpm, or a turn in place. No fault before the kill."""
        self.assertIsNotNone(self.summary.get("moving"), self.context())
        self.assertGreater(max(abs(r) for r in self.summary["rpm_at_kill"]), 15, self.summary["rpm_at_kill"])
        self.assertEqual(self.summary["faults_before_kill"], [])

    def test_keel_sees_the_kill_as_the_nodes_process_fault_at_once(self):
        """The node's death is a `process` fault of it, seen when it happened (keel's clock, lined
        up with the experiment's): not at any deadline."""
        death = self.summary["death"]
        self.assertEqual((death["component"], death["kind"], death["detector"]), ("wander", "process", "supervisor"))
        self.assertTrue(death["detail"].startswith(f"node '/wander' (pid {self.summary['pid']}) killed by signal 9"),
                        death["detail"])
        self.assertGreater(self.summary["death_seen_ms"], 0)
        self.assertLess(self.summary["death_seen_ms"], SOON_MS, self.context())
        faults = self.summary["node_faults"]
        self.assertEqual([(f["fault_id"], f["kind"]) for f in faults],
                         [(death["fault_id"], "process"), (self.summary["range_fault"]["fault_id"], "range")], faults)

    def test_the_teleop_loses_its_writer_with_the_node_not_at_its_deadline(self):
        fault = self.summary["fault"]
        self.assertEqual((fault["component"], fault["kind"], fault["detector"]), ("teleop", "remote", "dds"))
        self.assertEqual(fault["detail"], "the writer of /cmd_vel died: "
                         f"node '/wander' (pid {self.summary['pid']}) killed by signal 9 (SIGKILL)")
        after_ms = (fault["t_ns"] - self.summary["death"]["t_ns"]) / 1e6
        self.assertGreaterEqual(after_ms, 0)
        self.assertLess(after_ms, SOON_MS, self.context())

    def test_its_policy_resets_the_teleop_and_the_wheels_slow_down_until_the_node_is_back(self):
        """The teleop's reset is the stop command: the wheels slow down (the motors' 150 ms lag)
        from the kill until the restarted node drives them again."""
        action = self.summary["action"]
        self.assertEqual((action["action"], action["outcome"]), ("reset", "ok"), action)
        self.assertEqual(self.summary["recovered"]["fault_id"], self.summary["fault"]["fault_id"])
        at_kill = max(abs(r) for r in self.summary["rpm_at_kill"])
        self.assertLess(self.summary["slowest_rpm_while_gone"], at_kill / 2, self.context())

    def test_keel_restarts_the_node_and_the_robot_drives_again(self):
        phases = [r["phase"] for r in self.summary["node_records"]]
        self.assertEqual(phases, ["started", "up", "exited", "restarted", "up", "stopped", "restarted", "up", "stopped"],
                         self.summary["node_records"])
        self.assertNotEqual(self.summary["pid_again"], self.summary["pid"])
        self.assertGreater(self.summary["moving_again"], self.summary["up_again"], self.context())
        moving = [r for r in self.rows if max(abs(r["rpm_left"]), abs(r["rpm_right"])) > 20]
        self.assertGreater(len(moving), 50)  # rows of 20 ms: a second of driving at least
        self.assertGreater(sum(self.lives[1]["ranges"].values()), 50, self.lives[1])

    def test_the_restarted_node_reads_the_outage_in_keels_diagnostics(self):
        """keel's /diagnostics says WARN for a component with a fault in the last 5 s: the node,
        back within that, sees its own stand-in's and the teleop's."""
        self.assertGreater(self.lives[1]["level_counts"].get("WARN", 0), 0, self.lives[1])

    def test_a_corrupted_command_is_a_range_fault_of_the_node_which_is_restarted(self):
        """The node's one command of 5 m/s (its profile allows 0.5) is a `range` fault of the
        node, from the value it published on /cmd_vel and nothing else (it was alive and well);
        its reset stops the live node and starts it again, and the robot drives on."""
        fault = self.summary["range_fault"]
        self.assertEqual((fault["component"], fault["kind"]), ("wander", "range"), fault)
        self.assertEqual(fault["detail"], "value 5 pushed on port 'cmd' field 'linear.x' outside [-0.5, 0.5]")
        stopped = [r for r in self.summary["node_records"] if r["phase"] == "stopped"]
        self.assertEqual(stopped[0]["pid"], self.summary["pid_again"], "the live node was not stopped")
        self.assertGreater(stopped[0]["t_ns"], fault["t_ns"])
        self.assertNotIn(self.summary["pid_third"], (self.summary["pid"], self.summary["pid_again"]))
        self.assertIsNotNone(self.summary.get("moving_after_range"), self.context())
        resets = {r["fault_id"] for r in self.records if r.get("event") == "action" and r.get("action") == "reset"}
        self.assertIn(fault["fault_id"], resets)

    def test_each_outage_is_one_remote_fault_handled_by_a_reset(self):
        """One outage, one fault: the new node's writer is alive before its first sample comes,
        and the deadline firing meanwhile belongs to the same outage (docs/dds.md). The kill's
        outage is a fault (its writer died); the restart's after the range fault is one when the
        new node's first command comes more than the 300 ms deadline after the old one's last
        (its start takes 0.3-0.9 s on this machine): never more than one each."""
        remote = [r for r in self.records if r.get("event") == "detected" and r.get("kind") == "remote"]
        self.assertIn([r["component"] for r in remote], (["teleop"], ["teleop", "teleop"]), remote)
        self.assertEqual(remote[0]["fault_id"], self.summary["fault"]["fault_id"])
        if len(remote) == 2:
            self.assertGreater(remote[1]["t_ns"], self.summary["range_fault"]["t_ns"])
        remote = [r["fault_id"] for r in remote]
        resets = {r["fault_id"] for r in self.records if r.get("event") == "action" and r.get("action") == "reset"}
        self.assertEqual(set(remote) - resets, set(), self.records)

    def test_no_node_is_left_when_keel_run_ends(self):
        """keel stopped the node it started when it ended (its last `node` record), and the
        process is gone."""
        last = self.summary["node_records"][-1]
        pid = self.summary["pid_third"]
        self.assertEqual((last["phase"], last["pid"]), ("stopped", pid))
        self.assertFalse(Path(f"/proc/{pid}").exists() and "Z" not in Path(f"/proc/{pid}/stat").read_text().split()[2])


def experiment(out, *extra):
    """robot/ros2/experiment.py run as the demo runs it; its summary, log and trace."""
    # ROS_DOMAIN_ID unset: the experiment holds a domain of the DDS tests' pool.
    env = {k: v for k, v in os.environ.items() if k != "ROS_DOMAIN_ID"}
    run = subprocess.run([sys.executable, str(ROOT / "robot" / "ros2" / "experiment.py"), "--keel", KEEL,
                          "--python", sys.executable, "--out", str(out), "--drive", "4", "--after", "4", *extra],
                         env=env, capture_output=True, text=True, timeout=150)
    if run.returncode != 0:  # a step did not happen: which, and what the run printed
        raise AssertionError(f"experiment.py failed ({run.returncode}):\n{run.stdout}\n{run.stderr}")
    summary = json.loads(Path(f"{out}.summary.json").read_text())
    records = [json.loads(line) for line in Path(f"{out}.jsonl").read_text().splitlines() if line.strip()]
    with open(f"{out}.csv") as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    return run, summary, records, rows


class Ros2StandbyDemo(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = Path(tempfile.mkdtemp(prefix="keel_ros2_standby_demo_"))
        cls.run_, cls.summary, cls.records, cls.rows = experiment(cls.dir / "ros2_standby", "--standby")

    def context(self):
        return f"experiment's output:\n{self.run_.stdout}\n{self.run_.stderr}"

    def phases(self):
        return [(r["phase"], r["pid"]) for r in self.summary["node_records"]]

    def test_the_node_is_configured_and_activated_and_its_standby_waits_configured(self):
        s = self.summary
        self.assertEqual(s["keel_exit"], 0, self.context())
        phases = self.phases()
        self.assertIn(("activated", s["pid"]), phases)
        self.assertIn(("standby_ready", s["standby_pid"]), phases)
        self.assertLess(phases.index(("configured", s["pid"])), phases.index(("activated", s["pid"])))
        self.assertEqual(s["faults_before_kill"], [])
        standby = next(r for r in s["node_records"] if r["phase"] == "standby_started")
        self.assertEqual(standby["node"], "/wander_standby_1")

    def test_the_killed_node_is_taken_over_by_its_standby_before_the_wheels_deadman(self):
        """kill -9 of the active: its `process` fault, then its standby promoted (no restart) and
        Active well before /cmd_vel's 300 ms deadline: no `remote` fault of the teleop, and the
        wheels never slowed to half their speed at the kill."""
        s = self.summary
        death = s["death"]
        self.assertEqual((death["component"], death["kind"]), ("wander", "process"))
        self.assertLess(s["death_seen_ms"], SOON_MS, self.context())
        self.assertEqual(s["promoted"]["pid"], s["standby_pid"])
        self.assertEqual(s["promoted"]["detail"], "its process had ended")
        self.assertLess(s["takeover_ms"], DEADLINE_MS, self.context())
        self.assertEqual(s["remote_after_kill"], [], self.context())
        at_kill = max(abs(r) for r in s["rpm_at_kill"])
        self.assertGreater(at_kill, 15, s["rpm_at_kill"])
        self.assertGreater(s["slowest_rpm_after_kill"], at_kill / 2, self.context())
        self.assertNotIn("restarted", [p for p, _ in self.phases()])

    def test_a_fresh_standby_is_ready_behind_the_promoted_one(self):
        s = self.summary
        self.assertNotIn(s["standby_again"], (s["pid"], s["standby_pid"]))
        self.assertIn(("standby_ready", s["standby_again"]), self.phases())

    def test_a_corrupted_command_is_a_range_fault_and_the_standby_takes_over_after_the_fence(self):
        """The promoted node's 5 m/s: a `range` fault; the live faulty node is deactivated first,
        and only then is the fresh standby activated; the faulty one is ended."""
        s = self.summary
        fault = s["range_fault"]
        self.assertEqual((fault["component"], fault["kind"]), ("wander", "range"))
        second = s["promoted_again"]
        self.assertEqual(second["pid"], s["standby_again"])
        self.assertEqual(second["detail"],
                         f"in place of pid {s['standby_pid']} (/wander_standby_1), deactivated, then ended")
        records = s["node_records"]
        deactivated = next(r for r in records if r["phase"] == "deactivated" and r["pid"] == s["standby_pid"])
        activated = next(r for r in records if r["phase"] == "activated" and r["pid"] == second["pid"])
        self.assertLess(deactivated["t_ns"], activated["t_ns"])
        self.assertIn(("stopped", s["standby_pid"]), self.phases())

    def test_two_faults_both_recovered_and_none_of_the_teleop(self):
        s = self.summary
        self.assertEqual([f["kind"] for f in s["node_faults"]], ["process", "range"], s["node_faults"])
        self.assertEqual(s["remote_faults"], [], self.context())
        recovered = {r["fault_id"] for r in self.records if r.get("event") == "recovered"}
        self.assertEqual({f["fault_id"] for f in s["node_faults"]} - recovered, set())

    def test_no_node_nor_standby_is_left_when_keel_run_ends(self):
        pids = {r["pid"] for r in self.summary["node_records"]}
        for pid in pids:
            alive = Path(f"/proc/{pid}").exists() and "Z" not in Path(f"/proc/{pid}/stat").read_text().split()[2]
            self.assertFalse(alive, f"pid {pid} outlived keel run")


if __name__ == "__main__":
    KEEL = sys.argv[1]
    unittest.main(argv=[sys.argv[0]] + sys.argv[2:], verbosity=2)
