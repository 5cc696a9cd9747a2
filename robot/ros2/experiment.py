#!/usr/bin/env python3
"""The `ros2` experiment of scripts/demo.sh (docs/robot.md): a ROS 2 node that keel started and
supervises drives keel's simulated robot, is killed with kill -9 mid-run, and keel restarts it.

  experiment.py --keel build/bin/keel --python tests/peers/venv/bin/python --out demo/ros2
                [--monitor 127.0.0.1:8765] [--drive 5] [--after 5]

keel runs robot/ros2.xml, which starts robot/ros2/wander.py, an rclpy node (the --python's
folder first on its PATH, as sourcing ROS 2 would put it): it plans from the sonar ranges keel
publishes and sends /cmd_vel. Once the robot has driven `--drive` s on the node's commands, this
script sends the node SIGKILL; keel sees the death, stops the wheels and restarts the node. Once
the restarted node has driven `--drive`/2 s, it makes the node send one corrupted command
(SIGUSR1: 5 m/s where its profile allows 0.5): a `range` fault of the node from its value alone;
keel restarts it too, and the robot drives `--after` s more. Both sides are on one ROS domain — ROS_DOMAIN_ID if set, else one held
from the DDS tests' pool (tests/dds/domains.py) — and on the loopback unless CYCLONEDDS_URI /
FASTDDS_DEFAULT_PROFILES_FILE say otherwise (tests/dds/*-lo.xml). It watches keel's fault log and
the referee's trace as they are written (every 10 ms) and prints the story; keel's own times
(the log's t_ns, lined up with this script's clock by the log's epoch_ns) say how soon keel saw
the kill. OUT.summary.json holds it for tests/robot/ros2_demo_test.py. Files: OUT.jsonl (the fault
log), OUT.csv (the trace), OUT.mcap, OUT.out (keel run's output), OUT.wander.out (the node's
output, all its lives under its own name, as keel keeps it; a standby's in
OUT.wander.<its name>.out), OUT.wander-PID.json (each life's stats: the node's view).
Exit 1 when a step did not happen."""
import argparse
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MOVING_RPM = 20.0  # a wheel this fast: the robot drives


class Watch:
    """keel's fault log and the referee's trace, read as they grow; each record or row with the
    monotonic time this process first saw it."""

    def __init__(self, log, trace):
        self.files = {log: [], trace: []}
        self.log, self.trace = log, trace
        self.offsets = {log: 0, trace: 0}
        self.partial = {log: "", trace: ""}

    def poll(self):
        now = time.monotonic()
        for path, out in self.files.items():
            if not path.exists():
                continue
            with open(path) as f:
                f.seek(self.offsets[path])
                text = f.read()
                self.offsets[path] = f.tell()
            text = self.partial[path] + text
            lines = text.split("\n")
            self.partial[path] = lines.pop()
            for line in lines:
                if not line.strip():
                    continue
                if path == self.log:
                    try:
                        out.append((now, json.loads(line)))
                    except json.JSONDecodeError:
                        pass
                elif not line.startswith("t_s"):
                    v = line.split(",")
                    out.append((now, {"t_s": float(v[0]), "rpm_left": float(v[4]), "rpm_right": float(v[5]),
                                      "collisions": float(v[11])}))

    def records(self):
        return self.files[self.log]

    def rows(self):
        return self.files[self.trace]

    def first(self, pred, rows, after=0.0):
        return next(((t, r) for t, r in rows if t >= after and pred(r)), None)


def moving(r):
    return max(abs(r["rpm_left"]), abs(r["rpm_right"])) > MOVING_RPM


def environment(args, out):
    env = dict(os.environ)
    # What sourcing ROS 2 does for the node keel starts: its python3 first on PATH.
    env["PATH"] = f"{Path(args.python).absolute().parent}:{env.get('PATH', '')}"
    env["WANDER_STATS"] = f"{out}.wander-{{pid}}.json"
    held = None
    if not env.get("ROS_DOMAIN_ID"):
        sys.path.insert(0, str(ROOT / "tests" / "dds"))
        from domains import domain  # held by this process until it exits
        held = domain()
        env["ROS_DOMAIN_ID"] = str(held)
    env.setdefault("CYCLONEDDS_URI", (ROOT / "tests" / "dds" / "cyclonedds-lo.xml").as_uri())
    env.setdefault("FASTDDS_DEFAULT_PROFILES_FILE", str(ROOT / "tests" / "dds" / "fastdds-lo.xml"))
    env.pop("ROS_LOCALHOST_ONLY", None)
    env.pop("ROS_AUTOMATIC_DISCOVERY_RANGE", None)
    return env


class Experiment:
    def __init__(self, args):
        self.args = args
        self.out = Path(args.out).absolute()  # the node runs in its profile's folder: WANDER_STATS must not be relative
        self.out.parent.mkdir(parents=True, exist_ok=True)
        self.env = environment(args, self.out)
        self.log, self.trace = Path(f"{self.out}.jsonl"), Path(f"{self.out}.csv")
        for p in (self.log, self.trace):
            p.unlink(missing_ok=True)
        self.watch = Watch(self.log, self.trace)
        self.t0 = time.monotonic()
        self.events = []  # (t, text): what this process did and saw
        self.summary = {"domain": int(self.env["ROS_DOMAIN_ID"])}
        self.keel = None
        self.epoch_ns = None  # the log's t_ns 0 on this script's clock (CLOCK_MONOTONIC)
        self.profile = ROOT / "robot" / "ros2.xml"

    def note(self, text, t=None):
        t = time.monotonic() if t is None else t
        self.events.append((t, text))
        print(f"  {t - self.t0:5.1f} s  {text}", flush=True)

    def wait(self, what, seconds, pred):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.watch.poll()
            found = pred()
            if found:
                return found
            if self.keel.poll() is not None:
                raise RuntimeError(f"keel run ended ({self.keel.returncode}) while waiting for {what}")
            time.sleep(0.01)
        raise RuntimeError(f"no {what} within {seconds} s")

    def idle(self, seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.watch.poll()
            time.sleep(0.01)

    def start_keel(self):
        cmd = [self.args.keel, "run", str(self.profile), "--duration", "120", "--log", str(self.log),
               "--set", f"referee.trace={self.trace}", "--record", f"{self.out}.mcap"]
        if self.args.monitor:
            cmd += ["--monitor", self.args.monitor]
        self.keel_out = open(f"{self.out}.out", "w")
        self.keel = subprocess.Popen(cmd, env=self.env, stdout=self.keel_out, stderr=subprocess.STDOUT)
        self.wait("start of keel run", 30, lambda: self.watch.first(
            lambda r: r.get("event") == "engine" and r.get("phase") == "started", self.watch.records()))
        self.epoch_ns = next(r for _, r in self.watch.records() if r.get("phase") == "load")["epoch_ns"]
        if self.args.monitor:
            for line in Path(f"{self.out}.out").read_text().splitlines():
                if line.startswith("monitor: "):
                    print(f"  {line}")
        self.note(f"keel run {self.profile.name}: publishes /sonar/a, /sonar/b, /sonar/c and /diagnostics, "
                  "subscribes /cmd_vel (deadline 300 ms, lease 600 ms), starts the node wander")

    def log_time(self, t_ns):
        """A log record's t_ns on this script's clock (s)."""
        return (t_ns + self.epoch_ns) / 1e9

    def node_record(self, phase, after=None):
        return self.watch.first(lambda r: r.get("event") == "node" and r.get("component") == "wander"
                                and r.get("phase") == phase and (after is None or r["pid"] != after),
                                self.watch.records())

    def run(self):
        w = self.watch
        self.start_keel()
        _, started = self.wait("the node's start", 10, lambda: self.node_record("started"))
        self.note(f"keel: started the ROS 2 node /wander (robot/ros2/wander.py), pid {started['pid']}",
                  self.log_time(started["t_ns"]))
        _, up = self.wait("the node up", 40, lambda: self.node_record("up"))
        self.note(f"keel: /wander is up, {up['after_ms']:.0f} ms after its start: its process publishes /cmd_vel",
                  self.log_time(up["t_ns"]))
        pid = up["pid"]
        t, _ = self.wait("motion (keel obeying the node's /cmd_vel)", 30,
                         lambda: w.first(moving, w.rows(), after=self.log_time(up["t_ns"])))
        self.note("the robot drives on the node's /cmd_vel", t)
        self.summary.update(moving=t - self.t0, pid=pid)
        self.idle(self.args.drive)

        faults = [r for _, r in w.records() if r.get("event") == "detected"]
        self.summary["faults_before_kill"] = faults
        last = w.rows()[-1][1]
        killed = time.monotonic()
        os.kill(pid, signal.SIGKILL)
        self.note(f"kill -9 of the ROS 2 node, pid {pid} (the wheels at {last['rpm_left']:.0f} / "
                  f"{last['rpm_right']:.0f} rpm)", killed)
        self.summary.update(killed=killed - self.t0, rpm_at_kill=[last["rpm_left"], last["rpm_right"]])

        _, death = self.wait("the node's process fault", 10, lambda: w.first(
            lambda r: r.get("event") == "detected" and r.get("component") == "wander", w.records()))
        seen_ms = (self.log_time(death["t_ns"]) - killed) * 1e3
        self.note(f"keel: {death['detail']} — a `{death['kind']}` fault of wander, {seen_ms:.2f} ms after the kill "
                  "(keel's clock)", self.log_time(death["t_ns"]))
        seen, fault = self.wait("remote fault", 10, lambda: w.first(
            lambda r: r.get("event") == "detected" and r.get("kind") == "remote", w.records(), after=killed))
        self.note(f"keel: {fault['detail']} — a `remote` fault of {fault['component']}, "
                  f"{(fault['t_ns'] - death['t_ns']) / 1e3:.0f} us after the node's (not at its 300 ms deadline)",
                  self.log_time(fault["t_ns"]))
        self.summary.update(death=death, death_seen_ms=seen_ms)
        fid = fault["fault_id"]
        seen_r, rec = self.wait("recovery", 5, lambda: w.first(
            lambda r: r.get("event") == "recovered" and r.get("fault_id") == fid, w.records()))
        # The action is logged before `recovered` but may come after the detection was read.
        action = next((r for _, r in w.records() if r.get("fault_id") == fid and r.get("event") == "action"), None)
        if action:
            self.note(f"keel: its policy: {action['action']} ({action.get('detail', '')}), "
                      f"{(action['t_ns'] - fault['t_ns']) / 1e3:.0f} us after the detection"
                      + (": the velocity command zeroed" if action["action"] == "reset" else ""), seen)
        self.note(f"keel: `recovered` {(rec['t_ns'] - fault['t_ns']) / 1e3:.0f} us after the detection: the "
                  "teleop runs again, holding the robot still until a Twist comes", seen_r)
        self.summary.update(fault=fault, fault_seen=seen - self.t0, action=action, recovered=rec)

        _, restarted = self.wait("the node's restart", 10, lambda: self.node_record("restarted"))
        self.note(f"keel: restarted /wander (its policy: reset), pid {restarted['pid']}, "
                  f"{(restarted['t_ns'] - death['t_ns']) / 1e3:.0f} us after its death", self.log_time(restarted["t_ns"]))
        _, up2 = self.wait("the node up again", 40, lambda: self.node_record("up", after=pid))
        self.note(f"keel: /wander is up again, {up2['after_ms']:.0f} ms after its restart",
                  self.log_time(up2["t_ns"]))
        again, _ = self.wait("motion after the restart", 30,
                             lambda: w.first(moving, w.rows(), after=self.log_time(up2["t_ns"])))
        # The motors' lag is 150 ms: they slow down from the stop command on, towards rest.
        gone = [max(abs(r["rpm_left"]), abs(r["rpm_right"])) for t, r in w.rows()
                if killed < t < self.log_time(up2["t_ns"])]
        self.summary["slowest_rpm_while_gone"] = min(gone, default=None)
        if gone:
            self.note(f"while no node drove it the wheels slowed to {min(gone):.0f} rpm (from "
                      f"{max(abs(v) for v in self.summary['rpm_at_kill']):.0f} at the kill)")
        self.note(f"keel hears /cmd_vel again: the robot drives, {again - killed:.1f} s after the kill", again)
        self.summary.update(restarted=self.log_time(restarted["t_ns"]) - self.t0, pid_again=up2["pid"],
                            up_again=self.log_time(up2["t_ns"]) - self.t0, moving_again=again - self.t0)
        self.idle(self.args.drive / 2)
        self.corrupt(up2["pid"])
        self.idle(self.args.after)

        self.keel.send_signal(signal.SIGINT)
        self.keel.wait(30)
        self.note(f"keel run stopped (SIGINT), exit {self.keel.returncode}; it stopped the node with it")
        self.watch.poll()
        records = [r for _, r in w.records()]
        self.summary.update(keel_exit=self.keel.returncode,
                            remote_faults=[r for r in records if r.get("event") == "detected"
                                           and r.get("kind") == "remote"],
                            node_faults=[r for r in records if r.get("event") == "detected"
                                         and r.get("component") == "wander"],
                            node_records=[r for r in records if r.get("event") == "node"],
                            mission=next((r for r in records if r.get("event") == "mission"), None),
                            collisions=max((r["collisions"] for _, r in w.rows()), default=0))
        return 0

    def corrupt(self, pid):
        """The node's next command is garbage (SIGUSR1: 5 m/s, its profile allows 0.5): a `range`
        fault of the node, from its value alone; its policy restarts it and the robot drives on."""
        w = self.watch
        sent = time.monotonic()
        os.kill(pid, signal.SIGUSR1)
        self.note(f"the ROS 2 node (pid {pid}) sends a corrupted command: /cmd_vel 5 m/s ahead", sent)
        _, fault = self.wait("the node's range fault", 10, lambda: w.first(
            lambda r: r.get("event") == "detected" and r.get("component") == "wander" and r.get("kind") == "range",
            w.records()))
        self.note(f"keel: {fault['detail']} — a `range` fault of wander, from the value the node published "
                  "(its profile: linear.x within [-0.5, 0.5])", self.log_time(fault["t_ns"]))
        _, restarted = self.wait("the node's restart after its range fault", 10, lambda: w.first(
            lambda r: r.get("event") == "node" and r.get("phase") == "restarted" and r.get("pid") != pid
            and r["t_ns"] > fault["t_ns"], w.records()))
        self.note(f"keel: stopped the node (alive, but its values are wrong) and restarted it, pid {restarted['pid']}",
                  self.log_time(restarted["t_ns"]))
        _, up = self.wait("the node up after its range fault", 40, lambda: w.first(
            lambda r: r.get("event") == "node" and r.get("phase") == "up" and r.get("pid") == restarted["pid"],
            w.records()))
        again, _ = self.wait("motion after the range fault", 30,
                             lambda: w.first(moving, w.rows(), after=self.log_time(up["t_ns"])))
        self.note(f"the robot drives again, {again - sent:.1f} s after the corrupted command", again)
        self.summary.update(range_fault=fault, pid_third=restarted["pid"], moving_after_range=again - self.t0)

    def close(self):
        if self.keel and self.keel.poll() is None:
            self.keel.kill()
            self.keel.wait()
        summary = dict(self.summary, events=[[round(t - self.t0, 3), text] for t, text in self.events])
        Path(f"{self.out}.summary.json").write_text(json.dumps(summary, indent=1))

def standby_profile(out):
    """robot/ros2.xml with its node a lifecycle node with one standby (ros2/wander_lifecycle.xml,
    <process standby="1"/>), written to OUT.xml: the same robot, its references made absolute."""
    robot = ROOT / "robot"
    text = (robot / "ros2.xml").read_text()
    text = re.sub(r"(<reference>|reference=\")([^<\"]+)", lambda m: m.group(1) + str((robot / m.group(2)).resolve()),
                  text)
    node = f"<reference>{(robot / 'ros2' / 'wander.xml').resolve()}</reference>"
    if node not in text:
        raise RuntimeError("robot/ros2.xml has no subcomponent of ros2/wander.xml")
    text = text.replace(node, f"<reference>{(robot / 'ros2' / 'wander_lifecycle.xml').resolve()}</reference>"
                              '<process name="wander" standby="1"/>')
    path = Path(f"{out}.xml")
    path.write_text(text)
    return path


class StandbyExperiment(Experiment):
    """The `ros2_standby` experiment: the node a lifecycle node with a standby; its kill -9 and its
    corrupted command are each taken over by the standby, the wheels never stopped."""

    def __init__(self, args):
        super().__init__(args)
        self.profile = standby_profile(self.out)
        self.summary["standby"] = True

    def ready_standby(self, serving, after_ns=0):
        return self.watch.first(lambda r: r.get("event") == "node" and r.get("component") == "wander"
                                and r.get("phase") == "standby_ready" and r["pid"] != serving
                                and r["t_ns"] >= after_ns, self.watch.records())

    def run(self):
        w = self.watch
        self.start_keel()
        _, active = self.wait("the node active", 40, lambda: self.node_record("activated"))
        pid = active["pid"]
        self.note(f"keel: configured and activated /wander (robot/ros2/wander.py --lifecycle), pid {pid}",
                  self.log_time(active["t_ns"]))
        _, ready = self.wait("its standby ready", 40, lambda: self.ready_standby(pid))
        self.note(f"keel: its standby {ready['node']}, pid {ready['pid']}, configured and inactive "
                  f"{ready['after_ms']:.0f} ms after its start: it hears the sonars, publishes nothing",
                  self.log_time(ready["t_ns"]))
        t, _ = self.wait("motion (keel obeying the node's /cmd_vel)", 30,
                         lambda: w.first(moving, w.rows(), after=self.log_time(active["t_ns"])))
        self.note("the robot drives on the node's /cmd_vel", t)
        self.summary.update(moving=t - self.t0, pid=pid, standby_pid=ready["pid"])
        self.idle(self.args.drive)
        self.summary["faults_before_kill"] = [r for _, r in w.records() if r.get("event") == "detected"]

        last = w.rows()[-1][1]
        killed = time.monotonic()
        os.kill(pid, signal.SIGKILL)
        self.note(f"kill -9 of the active node, pid {pid} (the wheels at {last['rpm_left']:.0f} / "
                  f"{last['rpm_right']:.0f} rpm)", killed)
        self.summary.update(killed=killed - self.t0, rpm_at_kill=[last["rpm_left"], last["rpm_right"]])
        _, death = self.wait("the node's process fault", 10, lambda: w.first(
            lambda r: r.get("event") == "detected" and r.get("component") == "wander", w.records()))
        seen_ms = (self.log_time(death["t_ns"]) - killed) * 1e3
        self.note(f"keel: {death['detail']} — a `{death['kind']}` fault of wander, {seen_ms:.2f} ms after the kill",
                  self.log_time(death["t_ns"]))
        _, promoted = self.wait("the standby's promotion", 10, lambda: self.node_record("promoted", after=pid))
        _, activated = self.wait("the standby active", 10, lambda: w.first(
            lambda r: r.get("event") == "node" and r.get("phase") == "activated" and r["pid"] == promoted["pid"],
            w.records()))
        took_ms = (self.log_time(activated["t_ns"]) - killed) * 1e3
        self.note(f"keel: its policy (reset) promoted the standby {promoted['node']} ({promoted['detail']}); "
                  f"Active {took_ms:.1f} ms after the kill, its commands on /cmd_vel from its next tick (every 50 ms)",
                  self.log_time(activated["t_ns"]))
        self.summary.update(death=death, death_seen_ms=seen_ms, promoted=promoted, takeover_ms=took_ms,
                            pid_again=promoted["pid"])
        self.idle(1.0)
        after = [max(abs(r["rpm_left"]), abs(r["rpm_right"])) for t, r in w.rows() if killed < t < killed + 1.0]
        self.summary["slowest_rpm_after_kill"] = min(after, default=None)
        remote = [r for _, r in w.records() if r.get("event") == "detected" and r.get("kind") == "remote"]
        self.summary["remote_after_kill"] = remote
        self.note(f"in the second after the kill the wheels turned at {min(after, default=0):.0f} rpm at the least "
                  f"(the deadman: /cmd_vel's 300 ms deadline; {len(remote)} `remote` fault of the teleop)")
        _, fresh = self.wait("a fresh standby ready", 40,
                             lambda: self.ready_standby(promoted["pid"], after_ns=promoted["t_ns"]))
        self.note(f"keel: a fresh standby {fresh['node']}, pid {fresh['pid']}, ready behind it",
                  self.log_time(fresh["t_ns"]))
        self.summary["standby_again"] = fresh["pid"]
        self.idle(self.args.drive / 2)

        sent = time.monotonic()
        os.kill(promoted["pid"], signal.SIGUSR1)
        self.note(f"the active node (pid {promoted['pid']}) sends a corrupted command: /cmd_vel 5 m/s ahead", sent)
        _, fault = self.wait("the node's range fault", 10, lambda: w.first(
            lambda r: r.get("event") == "detected" and r.get("component") == "wander" and r.get("kind") == "range",
            w.records()))
        self.note(f"keel: {fault['detail']} — a `range` fault of wander", self.log_time(fault["t_ns"]))
        _, second = self.wait("the second promotion", 10, lambda: w.first(
            lambda r: r.get("event") == "node" and r.get("phase") == "promoted" and r["t_ns"] > fault["t_ns"],
            w.records()))
        self.note(f"keel: promoted {second['node']} ({second['detail']})", self.log_time(second["t_ns"]))
        self.summary.update(range_fault=fault, promoted_again=second, pid_third=second["pid"])
        self.idle(self.args.after)

        self.keel.send_signal(signal.SIGINT)
        self.keel.wait(30)
        self.note(f"keel run stopped (SIGINT), exit {self.keel.returncode}; it stopped the node and its standby")
        self.watch.poll()
        records = [r for _, r in w.records()]
        self.summary.update(keel_exit=self.keel.returncode,
                            node_faults=[r for r in records if r.get("event") == "detected"
                                         and r.get("component") == "wander"],
                            remote_faults=[r for r in records if r.get("event") == "detected"
                                           and r.get("kind") == "remote"],
                            node_records=[r for r in records if r.get("event") == "node"],
                            collisions=max((r["collisions"] for _, r in w.rows()), default=0))
        return 0


def show(out):
    """The node's view and keel's, as the demo prints them after the run."""
    out = Path(out)
    # One file per name the node's processes ran under (a standby's is its own).
    for path in sorted(out.parent.glob(f"{out.name}.wander*.out")):
        lines = path.read_text().splitlines()
        if not lines:
            continue  # a standby started as the run ended
        print(f"--- the ROS 2 node's view, all its lives under one name ({path}, kept by keel):")
        for line in lines if len(lines) <= 20 else lines[:8] + ["  ..."] + lines[-10:]:
            print(f"  {line}")
    print(f"--- keel's view: detections, actions, recoveries ({out}.jsonl):")
    lines = [line for line in Path(f"{out}.jsonl").read_text().splitlines()
             if any(f'"event":"{e}"' in line for e in ("detected", "action", "recovered"))]
    for line in lines or ["(none)"]:
        print(f"  {line[:200]}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--keel", default=str(ROOT / "build" / "bin" / "keel"))
    p.add_argument("--python", default=str(ROOT / "tests" / "peers" / "venv" / "bin" / "python"),
                   help="a Python with rclpy (scripts/peers.sh python makes it)")
    p.add_argument("--out", default=str(ROOT / "demo" / "ros2"))
    p.add_argument("--monitor", default="", help="keel run's --monitor address (none by default)")
    p.add_argument("--drive", type=float, default=5.0, help="s of driving before the kill")
    p.add_argument("--after", type=float, default=5.0, help="s of driving after the restart")
    p.add_argument("--standby", action="store_true",
                   help="the node a lifecycle node with a standby, which takes over (robot/ros2/wander_lifecycle.xml)")
    args = p.parse_args()
    e = StandbyExperiment(args) if args.standby else Experiment(args)
    print(f"  ROS_DOMAIN_ID={e.summary['domain']}; keel on CycloneDDS, the node on rclpy's Fast DDS", flush=True)
    rc = 1
    try:
        rc = e.run()
    except (RuntimeError, subprocess.TimeoutExpired) as x:
        print(f"experiment.py: {x}", file=sys.stderr)
    finally:
        e.close()
    if Path(f"{args.out}.out").exists():
        tail = [ln for ln in Path(f"{args.out}.out").read_text().splitlines() if not ln.startswith("monitor: ")]
        print(f"--- keel run's summary ({args.out}.out):")
        for line in tail[-8:]:
            print(f"  {line}")
    if Path(f"{args.out}.jsonl").exists():
        show(args.out)
    return rc


if __name__ == "__main__":
    sys.exit(main())
