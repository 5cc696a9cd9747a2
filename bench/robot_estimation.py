#!/usr/bin/env python3
"""Diagnosis by state estimation over many seeds, beside the paper's sliding-window monitor on the
same runs. Each seed runs the simulated robot three times with robot/estimation.xml, to which
this script adds the two sliding-window monitors of robot/navigation.xml as observers (their
faults name themselves, so the estimator's handling alone acts):
  encoder_left_dead    the left encoder reads 0 from t = 1000 ms (robot/scenarios/encoder_left_dead.xml):
                       right when the estimator accuses encoder_left; the monitor can only say actuator
  fig6_left_motor_off  the left driver loses power at t = 1000 ms (Fig. 6): right when the estimator
                       accuses actuator
  nominal              no fault: any fault of either detector is a false alarm
From each fault log: the detection delay (detected - injected, on the log's own clock), whether
the accused component is the right one, a missed detection, false alarms (a detection before the
injection, or on a nominal run), and the mission's outcome; the nominal runs' driving time gives
false alarms per hour. Prints one line per run and a summary; --json FILE writes the rows.
  bench/robot_estimation.py [--runs 100] [--jobs 3] [--build build] [--json out.json]
"""
import argparse
import concurrent.futures
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXPERIMENTS = ("encoder_left_dead", "fig6_left_motor_off", "nominal")
RIGHT = {"encoder_left_dead": "encoder_left", "fig6_left_motor_off": "actuator"}

MONITORS = """
    <subcomponent><name>monitor_left</name><reference>{c}/components/monitors/SlidingWindowMonitor.xml</reference>
      <properties><property name="window">9</property><property name="threshold">0.5</property>
        <property name="min_reference">30</property><property name="min_consecutive">2</property></properties></subcomponent>
    <subcomponent><name>monitor_right</name><reference>{c}/components/monitors/SlidingWindowMonitor.xml</reference>
      <properties><property name="window">9</property><property name="threshold">0.5</property>
        <property name="min_reference">30</property><property name="min_consecutive">2</property></properties></subcomponent>
"""
CONNECTIONS = """
    <port_connection port_type="data"><source component_name="actuator" port_name="left_rpm"/><target component_name="monitor_left" port_name="target"/></port_connection>
    <port_connection port_type="data"><source component_name="wheel_model" port_name="left_reference"/><target component_name="monitor_left" port_name="reference"/></port_connection>
    <port_connection port_type="data"><source component_name="actuator" port_name="right_rpm"/><target component_name="monitor_right" port_name="target"/></port_connection>
    <port_connection port_type="data"><source component_name="wheel_model" port_name="right_reference"/><target component_name="monitor_right" port_name="reference"/></port_connection>
"""


def observed_profile(tmp):
    """robot/estimation.xml with the sliding-window monitors beside the estimator, observing only:
    without `monitored`, a monitor's fault is about itself, which has no policy (contained)."""
    text = open(os.path.join(ROOT, "robot/estimation.xml")).read()
    robot = os.path.join(ROOT, "robot")
    text = re.sub(r"<reference>components/", f"<reference>{robot}/components/", text)
    text = text.replace('reference="components/', f'reference="{robot}/components/')  # an <alternative>
    text = text.replace("<reference>../components/", f"<reference>{ROOT}/components/")
    text = text.replace("    <!-- outside the robot: the experimenter -->", MONITORS.format(c=ROOT) +
                        "    <!-- outside the robot: the experimenter -->", 1)
    text = text.replace("  </port_connections>", CONNECTIONS + "  </port_connections>", 1)
    text = text.replace('<member component="estimator"/>',
                        '<member component="estimator"/>\n      <member component="monitor_left"/>'
                        '<member component="monitor_right"/>', 1)
    path = os.path.join(tmp, "estimation_observed.xml")
    with open(path, "w") as f:
        f.write(text)
    return path


def first(records, pred):
    return next((r for r in records if pred(r)), None)


def one_run(keel, profile, experiment, seed, tmp):
    log = os.path.join(tmp, f"{experiment}_{seed}.jsonl")
    cmd = [keel, "run", profile, "--duration", "40", "--log", log,
           "--set", f"actuator.seed={seed}", "--set", f"camera.seed={seed}"]
    if experiment != "nominal":
        cmd += ["--inject", os.path.join(ROOT, f"robot/scenarios/{experiment}.xml")]
    ran = subprocess.run(cmd, capture_output=True, text=True)
    if ran.returncode != 0:
        sys.exit(f"{experiment} seed {seed}: keel run exited {ran.returncode}: {ran.stderr.strip()}")
    records = [json.loads(line) for line in open(log) if line.strip()]
    injected = first(records, lambda r: r.get("event") == "injected")
    t_inj = injected["t_ns"] if injected else None
    detected = [r for r in records if r.get("event") == "detected"]
    mission = records[-1] if records and records[-1].get("event") == "mission" else {}
    row = {"experiment": experiment, "seed": seed, "ended": mission.get("ended"),
           "goal": mission.get("goal_reached"), "collisions": mission.get("collisions"),
           "driving_s": mission.get("duration_s")}
    for name, by in (("estimator", lambda r: r.get("detector") == "estimator"),
                     ("monitor", lambda r: r.get("detector") in ("monitor_left", "monitor_right"))):
        mine = [r for r in detected if by(r)]
        before = [r for r in mine if t_inj is None or r["t_ns"] < t_inj]
        after = [r for r in mine if t_inj is not None and r["t_ns"] >= t_inj]
        hit = after[0] if after else None
        accused = None
        if hit is not None:
            accused = hit["component"] if name == "estimator" else "actuator"  # a monitor watches the actuator
        row[name] = {"false_alarms": len(before),
                     "delay_ms": (hit["t_ns"] - t_inj) / 1e6 if hit else None,
                     "accused": accused,
                     "right": accused == RIGHT.get(experiment) if hit else None}
    return row


def summary(rows, experiment, name):
    mine = [r for r in rows if r["experiment"] == experiment]
    delays = sorted(r[name]["delay_ms"] for r in mine if r[name]["delay_ms"] is not None)
    right = sum(1 for r in mine if r[name]["right"])
    missed = sum(1 for r in mine if r[name]["delay_ms"] is None)
    false = sum(r[name]["false_alarms"] for r in mine)
    line = f"{experiment:<20} {name:<9} runs {len(mine)}: detected {len(delays)}, missed {missed}, " \
           f"isolated right {right}, false alarms {false}"
    if delays:
        p99 = delays[min(len(delays) - 1, int(round(0.99 * (len(delays) - 1))))]
        line += f"; delay ms median {statistics.median(delays):.0f}, p99 {p99:.0f}, max {delays[-1]:.0f}"
    return line


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--jobs", type=int, default=3, help="runs at once (each is mostly idle, in real time)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--json")
    a = ap.parse_args()
    keel = os.path.join(a.build, "bin", "keel")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        profile = observed_profile(tmp)
        jobs = [(e, s) for s in range(1, a.runs + 1) for e in EXPERIMENTS]
        with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
            for row in pool.map(lambda j: one_run(keel, profile, j[0], j[1], tmp), jobs):
                rows.append(row)
                print(json.dumps(row), flush=True)
    for e in EXPERIMENTS:
        for name in ("estimator", "monitor"):
            print(summary(rows, e, name))
    for e in EXPERIMENTS:
        mine = [r for r in rows if r["experiment"] == e]
        print(f"{e:<20} missions: goal {sum(1 for r in mine if r['goal'])}, stopped "
              f"{sum(1 for r in mine if r['ended'] == 'stopped')}, collisions {sum(r['collisions'] or 0 for r in mine)}")
    nominal = [r for r in rows if r["experiment"] == "nominal"]
    hours = sum(r["driving_s"] or 0 for r in nominal) / 3600
    for name in ("estimator", "monitor"):
        false = sum(r[name]["false_alarms"] for r in nominal)
        print(f"nominal driving {hours * 60:.1f} min: {name} false alarms {false} ({false / hours if hours else 0:.2f}/h)")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
