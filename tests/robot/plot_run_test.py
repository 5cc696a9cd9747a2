#!/usr/bin/env python3
"""Tests robot/plot_run.py on a small synthetic run: a robot driving straight along +x whose left
wheel loses power at t = 1.0 s (injected motor_power_off) and is detected by the process model at
t = 1.2 s; with the referee's trace, and with port values as `keel report --plots` writes them from
a recording. Runs the script as a subprocess, as a user would.
Run: python3 tests/robot/plot_run_test.py (or python3 -m unittest from tests/robot)."""

import json
import math
import os
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "robot", "plot_run.py")
HEADER = ("t_s,x_m,y_m,heading_rad,rpm_left,rpm_right,measured_left,measured_right,"
          "reference_left,reference_right,clearance_m,collisions")


def have_matplotlib():
    """The script reruns itself under /usr/bin/python3 when this interpreter lacks matplotlib."""
    for py in (sys.executable, "/usr/bin/python3"):
        if os.access(py, os.X_OK) and subprocess.run([py, "-c", "import matplotlib"],
                                                     capture_output=True).returncode == 0:
            return True
    return False


def svg_texts(path):
    """Every <text> element's full text (matplotlib writes text as text with svg.fonttype none)."""
    root = ET.parse(path).getroot()  # raises on invalid XML
    return ["".join(e.itertext()) for e in root.iter() if e.tag.endswith("}text") or e.tag == "text"]


class PlotRunTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name
        self.trace = os.path.join(self.dir, "trace.csv")
        self.log = os.path.join(self.dir, "run.jsonl")
        self.out = os.path.join(self.dir, "plots")
        rows = [HEADER]
        for k in range(41):  # 0 .. 2 s, one row per 50 ms; the trace starts at t = 0.05 s
            t = 0.05 + 0.05 * k
            ref = 60.0
            left = ref if t < 1.0 else ref * math.exp(-(t - 1.0) / 0.15)  # coasts down after 1 s
            rows.append(f"{t:.3f},{0.5 + 0.2 * t:.4f},1.0000,0.0000,{left:.2f},{ref:.2f},{left:.2f},{ref:.2f},"
                        f"{ref:.2f},{ref:.2f},0.8000,0")
        with open(self.trace, "w") as f:
            f.write("\n".join(rows) + "\n")
        with open(self.trace + ".world.json", "w") as f:
            json.dump({"boxes": [[0, 0, 3, 0.1], [0, 1.9, 3, 2], [0, 0, 0.1, 2], [2.9, 0, 3, 2], [1.5, 1.4, 1.7, 1.6]],
                       "target": {"x": 2.5, "y": 1.0, "r": 0.15},
                       "start": {"x": 0.5, "y": 1.0, "heading": 0.0}}, f)
        # the engine starts 50 ms before the trace's first row on its own clock: t_ns 0 <-> t_s 0.05
        log = [
            {"event": "engine", "phase": "load", "t_ns": 0},
            {"event": "injected", "kind": "motor_power_off", "component": "actuator", "detail": "left",
             "fault_id": 1, "hardware": True, "t_ns": 950_000_000},
            {"event": "detected", "kind": "model", "component": "actuator", "detector": "monitor_left",
             "detail": "rpm 21.3 below 0.5 x reference 60.0", "fault_id": 2, "t_ns": 1_150_000_000},
            {"event": "action", "action": "emergency_stop", "component": "actuator", "fault_id": 2,
             "t_ns": 1_150_100_000},
            {"event": "recovered", "component": "actuator", "fault_id": 2, "latency_us": 350.0,
             "t_ns": 1_150_450_000},
            {"event": "mission", "goal_reached": False, "collisions": 0, "min_clearance_cm": 42.5,
             "duration_s": 1.96, "ended": "stopped", "t_ns": 1_990_000_000},
        ]
        with open(self.log, "w") as f:
            f.write("".join(json.dumps(r) + "\n" for r in log))

    def tearDown(self):
        self.tmp.cleanup()

    def run_script(self, *args):
        return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True, timeout=120)

    def test_plots_a_run(self):
        if not have_matplotlib():
            self.skipTest("matplotlib is not installed (scripts/deps.sh: python3-matplotlib)")
        r = self.run_script("--trace", self.trace, "--log", self.log, "--out", self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        trajectory, fig6 = os.path.join(self.out, "trajectory.svg"), os.path.join(self.out, "fig6.svg")
        timeline = os.path.join(self.out, "timeline.svg")
        self.assertEqual(r.stdout.split(), [timeline, trajectory, fig6])
        texts = svg_texts(timeline)
        self.assertIn("#2 model: detected after 200.0 ms, recovered after 350 us", texts)
        self.assertIn("actuator", texts)  # its row
        texts = svg_texts(trajectory)
        self.assertIn("model@actuator", texts)                   # the detection, labelled
        self.assertIn("motor_power_off@actuator (hw)", texts)    # the injected hardware fault
        title = [t for t in texts if t.startswith("Mission: ")]
        self.assertEqual(title, ["Mission: goal not reached (ended: stopped), 0 collisions, "
                                 "min clearance 42.5 cm, 2.0 s"])
        texts = svg_texts(fig6)
        self.assertTrue(any("200 ms after injection" in t for t in texts), texts)
        self.assertTrue(any("motor_power_off: left" in t for t in texts), texts)

    def write_ports(self, skip=None, referee=None):
        """The wheel ports of a recording, every 20 ms on the log's clock: the left wheel fails at 1 s.
        With `referee` (its name), the referee's world once and its truth: driving along +x."""
        ports = os.path.join(self.dir, "ports.jsonl")
        nan = float("nan")
        with open(ports, "w") as f:
            if referee:
                world = [2.5, 1.0, 0.15, 0.5, 1.0, 0.0, 0, 0, 3, 0.1, 1.5, 1.4, 1.7, 1.6] + [nan] * 40
                f.write(json.dumps({"port": f"{referee}/world", "t_ns": 0, "value": world}).replace("NaN", "null")
                        + "\n")
            for k in range(100):
                t_ns = 20_000_000 * k
                left = 60.0 if t_ns < 1_000_000_000 else 5.0
                for port, value in (("actuator/left_rpm", left), ("actuator/right_rpm", 60.0),
                                    ("wheel_model/left_reference", 60.0), ("wheel_model/right_reference", 60.0)):
                    if port != skip:
                        f.write(json.dumps({"port": port, "t_ns": t_ns, "value": value}) + "\n")
                if referee:
                    truth = [0.01 + t_ns / 1e9, 0.5 + 0.2 * t_ns / 1e9, 1.0, 0.0, left, 60.0, 0.8, 0]
                    f.write(json.dumps({"port": f"{referee}/truth", "t_ns": t_ns, "value": truth}) + "\n")
        return ports

    def test_plots_a_recording_without_a_trace(self):
        if not have_matplotlib():
            self.skipTest("matplotlib is not installed (scripts/deps.sh: python3-matplotlib)")
        r = self.run_script("--ports", self.write_ports(), "--log", self.log, "--out", self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        fig6 = os.path.join(self.out, "fig6.svg")
        self.assertEqual(r.stdout.split(), [os.path.join(self.out, "timeline.svg"), fig6])
        self.assertIn("no trajectory.svg: neither a trace (--trace) nor the referee's true pose", r.stderr)
        texts = svg_texts(fig6)
        self.assertIn("time since the run started (ms)", texts)
        self.assertTrue(any("200 ms after injection" in t for t in texts), texts)

    def test_plots_the_state_estimators_test_against_its_threshold_from_a_recording(self):
        """A recording of robot/estimation.xml: estimation.svg, the estimator's statistic against
        its threshold (log scale) and each wheel's encoder beside its estimate, with the
        estimator's detection and its delay."""
        if not have_matplotlib():
            self.skipTest("matplotlib is not installed (scripts/deps.sh: python3-matplotlib)")
        ports = os.path.join(self.dir, "ports.jsonl")
        with open(ports, "w") as f:
            for k in range(100):
                t_ns = 20_000_000 * k
                dead = t_ns >= 1_000_000_000
                for port, value in (("estimator/statistic", 900.0 if dead else 12.0), ("estimator/threshold", 56.5),
                                    ("encoder_left/rpm", 0.0 if dead else 60.0), ("estimator/estimate0", 60.0),
                                    ("encoder_right/rpm", 60.0), ("estimator/estimate1", 60.0)):
                    f.write(json.dumps({"port": port, "t_ns": t_ns, "value": value}) + "\n")
        log = [{"event": "engine", "phase": "load", "t_ns": 0},
               {"event": "injected", "kind": "encoder_dead", "component": "actuator", "detail": "left",
                "fault_id": 1, "hardware": True, "t_ns": 1_000_000_000},
               {"event": "detected", "kind": "model", "component": "encoder_left", "detector": "estimator",
                "measurement": "encoder_left", "detail": "measurement 'encoder_left' disagrees", "fault_id": 2,
                "t_ns": 1_100_000_000}]
        with open(self.log, "w") as f:
            f.write("".join(json.dumps(r) + "\n" for r in log))
        r = self.run_script("--ports", ports, "--log", self.log, "--out", self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        estimation = os.path.join(self.out, "estimation.svg")
        self.assertIn(estimation, r.stdout.split())
        texts = svg_texts(estimation)
        self.assertTrue(any("model@encoder_left: 100 ms after injection" in t for t in texts), texts)
        self.assertIn("threshold (chi-square quantile)", texts)
        self.assertIn("encoder_left (rpm)", texts)
        # Without the estimator's ports (a run of navigation.xml), there is none.
        r = self.run_script("--ports", self.write_ports(), "--log", self.log, "--out", self.out + "2")
        self.assertNotIn(os.path.join(self.out + "2", "estimation.svg"), r.stdout.split())

    def test_plots_the_trajectory_from_a_recordings_referee(self):
        if not have_matplotlib():
            self.skipTest("matplotlib is not installed (scripts/deps.sh: python3-matplotlib)")
        # a system profile's referee: its application's prefix (robot/system.xml)
        r = self.run_script("--ports", self.write_ports(referee="hri.referee"), "--log", self.log, "--out", self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        trajectory = os.path.join(self.out, "trajectory.svg")
        self.assertEqual(r.stdout.split(), [os.path.join(self.out, n) for n in ("timeline.svg", "trajectory.svg",
                                                                               "fig6.svg")])
        texts = svg_texts(trajectory)
        self.assertIn("model@actuator", texts)
        self.assertIn("target", texts)  # the world, from the world port
        root = ET.parse(trajectory).getroot()
        boxes = [e for e in root.iter() if e.get("id", "").startswith("patch") and "fill: #999999" in e.get(
            "style", "") + "".join(c.get("style", "") for c in e)]
        self.assertEqual(len(boxes), 2, "the world's two boxes; none from the nulls past them")

    def test_a_referee_in_two_applications_is_not_guessed(self):
        if not have_matplotlib():
            self.skipTest("matplotlib is not installed (scripts/deps.sh: python3-matplotlib)")
        ports = self.write_ports(referee="a.referee")
        with open(ports) as f:
            lines = f.read()
        with open(ports, "a") as f:
            f.write(lines.replace("a.referee", "b.referee"))
        r = self.run_script("--ports", ports, "--log", self.log, "--out", self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("several ports match it (a.referee/truth, b.referee/truth)", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.out, "trajectory.svg")))

    def test_a_recording_without_the_wheel_ports_gets_the_timeline_only(self):
        if not have_matplotlib():
            self.skipTest("matplotlib is not installed (scripts/deps.sh: python3-matplotlib)")
        r = self.run_script("--ports", self.write_ports(skip="wheel_model/left_reference"), "--log", self.log,
                            "--out", self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout.split(), [os.path.join(self.out, "timeline.svg")])
        self.assertIn("no fig6.svg", r.stderr)
        self.assertIn("wheel_model/left_reference", r.stderr)

    def test_missing_trace(self):
        r = self.run_script("--trace", os.path.join(self.dir, "nope.csv"), "--log", self.log, "--out", self.out)
        self.assertEqual(r.returncode, 2)
        self.assertIn("cannot read the trace", r.stderr)
        self.assertIn("nope.csv", r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assertFalse(os.path.exists(self.out))

    def test_empty_trace(self):
        with open(self.trace, "w") as f:
            f.write(HEADER + "\n")
        r = self.run_script("--trace", self.trace, "--log", self.log, "--out", self.out)
        self.assertEqual(r.returncode, 2)
        self.assertIn("empty trace", r.stderr)
        self.assertNotIn("Traceback", r.stderr)

    def test_malformed_log_line(self):
        with open(self.log, "a") as f:
            f.write('{"event": "detected", "t_ns": \n')  # line 7
        r = self.run_script("--trace", self.trace, "--log", self.log, "--out", self.out)
        self.assertEqual(r.returncode, 2)
        self.assertIn("run.jsonl:7: malformed JSON line", r.stderr)
        self.assertNotIn("Traceback", r.stderr)


class MarkerTest(unittest.TestCase):
    """Each fault kind keel reports (include/keel/fault_event.hpp) has a marker of its own."""

    def test_every_kind_has_its_own_marker(self):
        import importlib.util
        import re
        spec = importlib.util.spec_from_file_location("plot_run", SCRIPT)
        plot_run = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(plot_run)
        header = os.path.join(os.path.dirname(SCRIPT), "..", "include", "keel", "fault_event.hpp")
        with open(header, encoding="utf-8") as f:
            kinds = re.findall(r'case FaultKind::\w+: return "(\w+)";', f.read())
        self.assertGreaterEqual(len(kinds), 11, "the kinds were not found in fault_event.hpp")
        for kind in kinds:
            self.assertIn(kind, plot_run.KIND_MARKERS, f"fault kind '{kind}' has no marker of its own")
        markers = list(plot_run.KIND_MARKERS.values()) + plot_run.MORE_MARKERS
        self.assertEqual(len(markers), len(set(markers)), "two kinds share a marker")


if __name__ == "__main__":
    unittest.main()
