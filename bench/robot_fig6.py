#!/usr/bin/env python3
"""Fig. 6 of the paper over many seeds: the left wheel's driver loses power at t = 1000 ms while
the simulated robot drives (robot/scenarios/fig6_left_motor_off.xml); keel's sliding-window
monitor must report a `model` fault. For each seed it runs `keel run robot/navigation.xml` and
takes from the fault log the detection delay (detected - injected, the log's own clock) and the
false positives: `model` faults detected before the injection, or about the right wheel.
Prints one line per run and a summary (median, p99, min, max); --json FILE writes the rows.
  bench/robot_fig6.py [--runs 100] [--build build] [--json out.json]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def one_run(keel, seed, tmp):
    log = os.path.join(tmp, f"fig6_{seed}.jsonl")
    cmd = [keel, "run", os.path.join(ROOT, "robot/navigation.xml"), "--duration", "30", "--log", log,
           "--inject", os.path.join(ROOT, "robot/scenarios/fig6_left_motor_off.xml"),
           "--set", f"actuator.seed={seed}", "--set", f"camera.seed={seed}"]
    ran = subprocess.run(cmd, capture_output=True, text=True)
    if ran.returncode != 0:
        sys.exit(f"seed {seed}: keel run exited {ran.returncode}: {ran.stderr.strip()}")
    records = [json.loads(line) for line in open(log) if line.strip()]
    injected = [r["t_ns"] for r in records if r.get("event") == "injected"]
    model = [r for r in records if r.get("event") == "detected" and r.get("kind") == "model"]
    t_inj = injected[0] if injected else None
    true_hits = [r for r in model if t_inj is not None and r["t_ns"] >= t_inj and r.get("detector") == "monitor_left"]
    false_pos = [r for r in model if r not in true_hits]
    mission = records[-1] if records and records[-1].get("event") == "mission" else {}
    delay = (true_hits[0]["t_ns"] - t_inj) / 1e6 if true_hits else None
    return {"seed": seed, "delay_ms": delay, "false_positives": len(false_pos),
            "collisions": mission.get("collisions"), "ended": mission.get("ended")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--json")
    a = ap.parse_args()
    keel = os.path.join(a.build, "bin", "keel")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, a.runs + 1):
            row = one_run(keel, seed, tmp)
            rows.append(row)
            print(json.dumps(row), flush=True)
    delays = sorted(r["delay_ms"] for r in rows if r["delay_ms"] is not None)
    missed = sum(1 for r in rows if r["delay_ms"] is None)
    fps = sum(r["false_positives"] for r in rows)
    collisions = sum(r["collisions"] or 0 for r in rows)
    p99 = delays[min(len(delays) - 1, int(round(0.99 * (len(delays) - 1))))] if delays else float("nan")
    print(f"runs {len(rows)}; detected {len(delays)}, missed {missed}; false positives {fps}; "
          f"collisions {collisions}")
    if delays:
        print(f"detection delay ms: median {statistics.median(delays):.0f}, p99 {p99:.0f}, "
              f"min {delays[0]:.0f}, max {delays[-1]:.0f}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0 if missed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
