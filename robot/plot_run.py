#!/usr/bin/env python3
"""Plots a run of keel: the fault timeline of any run; for the simulated test robot, its
trajectory with the faults, and the paper's Fig. 6.

Inputs:
  run.jsonl             keel's fault log (`keel run --log`, or the records `keel report --plots`
                        takes from a recording): `injected`, `detected`, `recovered`, `mission`...
  trace.csv             (--trace) the robot referee's trace, its `trace` property: one row per
                        referee execution (50 ms): simulated time, true pose, true, measured and
                        reference wheel rpm, clearance, collisions so far
  trace.csv.world.json  the world: boxes, target, start (override with --world)
  ports.jsonl           (--ports) port values from a recording, one {"port", "t_ns", "value"} a
                        line (`keel report --plots` writes it): the robot's measured and reference
                        wheel rpm, and the referee's `truth` (its true pose) and `world` ports

Outputs in --out DIR (created):
  timeline.svg    one row per component: each fault injected (x), detected (a marker per kind)
                  and recovered (o), over the run's time, with the detection latency (detected -
                  injected) and the recovery latency (the `recovered` record's latency_us)
  trajectory.svg  (with --trace, else from --ports when it has the referee's truth) the world, the path, the body at start and end, each detected
                  fault at the robot's position when it was detected (one marker per kind) and
                  each injected fault (x); the mission's outcome in the title
  estimation.svg  (with --ports from a run of robot/estimation.xml) the state estimator's test
                  statistic against its threshold, and each wheel's encoder beside its
                  estimate, with the injections and the estimator's detections
  fig6.svg        (with --trace, else from --ports when it has the robot's wheel ports) left
                  (and, lighter, right) wheel rpm, measured and reference, raw and filtered
                  (trailing moving average over --window rows), the threshold (--threshold x the
                  filtered reference), the injections and the `model` detections with their delay
Prints one line per file written; for the robot (a `mission` record, its wheel ports or a trace), a
plot its inputs cannot give is said on stderr.

Clocks: the trace's t_s is simulated time since the board started; the log's t_ns is time since
the keel engine started. Without --offset-s the two are assumed to start together: the earliest
log record is mapped to the trace's first row (offset = first t_s - earliest t_ns / 1e9). That is
an approximation, off by up to one board period (20 ms) plus the engine's start-up (tens of ms);
it only places the faults on the trajectory and on the time axis. Delays between an injection and
its detection are computed on the log's clock alone and are exact. Port values are on the log's
clock: Fig. 6 and the trajectory drawn from them need no offset. The timeline is on the log's clock.

A port is named component/port; in a system profile the component has its application's prefix
(navigation.actuator/left_rpm), and a port named here matches with or without one.

Bad input (a missing file, an empty trace, a malformed line) is reported on stderr with exit
code 2.
"""

import argparse
import csv
import json
import math
import os
import sys

TRACE_COLUMNS = ("t_s", "x_m", "y_m", "heading_rad", "rpm_left", "rpm_right", "measured_left",
                 "measured_right", "reference_left", "reference_right", "clearance_m", "collisions")
BODY_LENGTH_M = 0.210  # robot/world/world.hpp: kBodyLengthM, along the heading
BODY_WIDTH_M = 0.140   # kBodyWidthM
SYSTEM_PYTHON = "/usr/bin/python3"  # where Debian's python3-matplotlib (scripts/deps.sh) lives
REEXEC_GUARD = "KEEL_PLOT_RUN_REEXEC"

# Fig. 6's four signals: the referee's trace columns, and the ports of robot/navigation.xml that
# carry them (the referee takes its trace's from these very ports).
WHEEL_PORTS = {"measured_left": "actuator/left_rpm", "measured_right": "actuator/right_rpm",
               "reference_left": "wheel_model/left_reference", "reference_right": "wheel_model/right_reference"}
# The referee's ports (robot/components/mission_referee.hpp): its ground truth and its world.
TRUTH_PORT, TRUTH_VALUES = "referee/truth", ("t_s", "x_m", "y_m", "heading_rad", "rpm_left", "rpm_right",
                                             "clearance_m", "collisions")
WORLD_PORT = "referee/world"  # target x, y, r; start x, y, heading; boxes of 4, null after the last
# The state estimator's ports (robot/estimation.xml): its test statistic and threshold, and the
# left wheel as its encoder measures it and as the estimator estimates it.
ESTIMATION_PORTS = {"statistic": "estimator/statistic", "threshold": "estimator/threshold",
                    "encoder_left": "encoder_left/rpm", "estimate_left": "estimator/estimate0",
                    "encoder_right": "encoder_right/rpm", "estimate_right": "estimator/estimate1"}
TIMELINE_LABELLED = 40  # faults whose latencies are written on the timeline; more would overlap

# One marker per detected kind (fault.hpp's kinds); others cycle through MORE_MARKERS.
KIND_MARKERS = {"model": "D", "signal": "o", "range": "s", "vote": "^", "heartbeat": "v",
                "exception": "P", "user": "*", "deadline": "<", "remote": ">", "error_code": "p",
                "process": "X", "start": "h", "reported": "8", "lifecycle": "x"}
MORE_MARKERS = ["d", "H", "1", "2"]


class InputError(Exception):
    """Bad input: reported without a traceback, exit code 2."""


# ---- reading ---------------------------------------------------------------------------------

def read_trace(path):
    """Returns the trace as a dict of column name -> list of floats (rows in time order)."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            lines = f.read().splitlines()
    except OSError as e:
        raise InputError(f"cannot read the trace {path}: {e.strerror}") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text file") from None
    if not lines or not lines[0].strip():
        raise InputError(f"{path}: empty trace (no header)")
    header = [h.strip() for h in next(csv.reader([lines[0]]))]
    missing = [c for c in TRACE_COLUMNS if c not in header]
    if missing:
        raise InputError(f"{path}:1: header lacks column(s) {', '.join(missing)}")
    index = {c: header.index(c) for c in TRACE_COLUMNS}
    columns = {c: [] for c in TRACE_COLUMNS}
    numbered = [(n, line) for n, line in enumerate(lines[1:], start=2) if line.strip()]
    for i, (n, line) in enumerate(numbered):
        fields = next(csv.reader([line]))
        try:
            if len(fields) != len(header):
                raise ValueError(f"{len(fields)} fields, the header has {len(header)}")
            values = {c: float(fields[index[c]]) for c in TRACE_COLUMNS}
            for c in ("t_s", "x_m", "y_m", "heading_rad"):
                if not math.isfinite(values[c]):
                    raise ValueError(f"{c} is {fields[index[c]]}")
        except ValueError as e:
            if i == len(numbered) - 1 and i > 0:  # a run killed mid-write leaves a partial last row
                print(f"plot_run: {path}:{n}: ignoring the incomplete last row ({e})", file=sys.stderr)
                break
            raise InputError(f"{path}:{n}: malformed row: {e}") from None
        for c in TRACE_COLUMNS:
            columns[c].append(values[c])
    if not columns["t_s"]:
        raise InputError(f"{path}: empty trace (a header and no rows)")
    if any(b < a for a, b in zip(columns["t_s"], columns["t_s"][1:])):
        raise InputError(f"{path}: t_s goes backwards")
    return columns


def read_world(path):
    """Returns the world dict, or None (with a warning) when there is none."""
    if not os.path.exists(path):
        print(f"plot_run: no world file {path}: plotting the path without the world", file=sys.stderr)
        return None
    try:
        with open(path, encoding="utf-8") as f:
            world = json.load(f)
    except OSError as e:
        raise InputError(f"cannot read the world {path}: {e.strerror}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise InputError(f"{path}: malformed JSON: {e}") from None
    try:
        boxes = [tuple(float(v) for v in b) for b in world.get("boxes", [])]
        if any(len(b) != 4 for b in boxes):
            raise ValueError("a box is not [min_x, min_y, max_x, max_y]")
        target = world.get("target")
        target = None if target is None else {k: float(target[k]) for k in ("x", "y", "r")}
        start = world.get("start")
        start = None if start is None else {k: float(start[k]) for k in ("x", "y", "heading")}
    except (AttributeError, KeyError, TypeError, ValueError) as e:
        raise InputError(f"{path}: not a world ({{boxes, target, start}}): {e}") from None
    return {"boxes": boxes, "target": target, "start": start}


def json_lines(path, what):
    """Yields (line number, parsed value) for each non-blank line of the JSON-lines file `path`;
    a line that is not JSON, an unreadable file or one that is not text is an InputError naming
    `what` the file is."""
    try:
        with open(path, encoding="utf-8") as f:
            for n, line in enumerate(f, start=1):
                if not line.strip():
                    continue
                try:
                    yield n, json.loads(line)
                except json.JSONDecodeError as e:
                    raise InputError(f"{path}:{n}: malformed JSON line: {e.msg} (column {e.colno})") from None
    except OSError as e:
        raise InputError(f"cannot read {what} {path}: {e.strerror}") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text file") from None


def read_log(path):
    """Returns (records in file order, each with its line number as '_line')."""
    records = []
    for n, rec in json_lines(path, "the log"):
        if not isinstance(rec, dict):
            raise InputError(f"{path}:{n}: malformed line: not a JSON object")
        t = rec.get("t_ns")
        if t is not None and (isinstance(t, bool) or not isinstance(t, (int, float))):
            raise InputError(f"{path}:{n}: t_ns is not a number")
        if rec.get("event") in ("injected", "detected") and t is None:
            raise InputError(f"{path}:{n}: '{rec['event']}' record without t_ns")
        rec["_line"] = n
        records.append(rec)
    return records


def number(v):
    """A port value's number; NaN for null, a boolean or anything else."""
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else math.nan


def read_ports(path):
    """Returns {port: [(t_ns, value)]} from a ports.jsonl: a value is a float, or a list of floats
    for an array (anything that is not a number is NaN)."""
    ports = {}
    for n, rec in json_lines(path, "the port values"):
        if not isinstance(rec, dict) or not isinstance(rec.get("port"), str) \
                or isinstance(rec.get("t_ns"), bool) or not isinstance(rec.get("t_ns"), (int, float)):
            raise InputError(f"{path}:{n}: not a port value ({{port, t_ns, value}})")
        v = rec.get("value")
        value = [number(e) for e in v] if isinstance(v, list) else number(v)
        ports.setdefault(rec["port"], []).append((rec["t_ns"], value))
    return ports


def port_values(ports, name):
    """The values of the port `name` (component/port), in time order: the port of that name, else
    the one port whose component ends with ".component" (an application's prefix); None when there
    is none, or when several applications have it (said on stderr)."""
    if name in ports:
        return sorted(ports[name], key=lambda tv: tv[0])
    found = [p for p in ports if p.endswith("." + name)]
    if len(found) > 1:
        print(f"plot_run: ignoring {name}: several ports match it ({', '.join(sorted(found))})", file=sys.stderr)
    return sorted(ports[found[0]], key=lambda tv: tv[0]) if len(found) == 1 else None


def truth_trace(ports):
    """The trajectory's columns from the referee's truth port (t_s: the log's clock, when the
    referee sent it); None without one. Values that are not 8 numbers with a finite pose are
    skipped."""
    values = port_values(ports, TRUTH_PORT)
    columns = {c: [] for c in TRUTH_VALUES}
    for t_ns, v in values or []:
        if not isinstance(v, list) or len(v) != len(TRUTH_VALUES) or not all(map(math.isfinite, v[1:4])):
            continue
        columns["t_s"].append(t_ns / 1e9)
        for c, e in zip(TRUTH_VALUES[1:], v[1:]):
            columns[c].append(e)
    return columns if columns["t_s"] else None


def port_world(ports):
    """The world from the referee's world port (its last value), as read_world gives it; None
    without one."""
    values = port_values(ports, WORLD_PORT)
    v = values[-1][1] if values else None
    if not isinstance(v, list) or len(v) < 6 or (len(v) - 6) % 4 or not all(map(math.isfinite, v[:6])):
        return None
    boxes = [tuple(v[i:i + 4]) for i in range(6, len(v), 4) if all(map(math.isfinite, v[i:i + 4]))]
    return {"boxes": boxes, "target": {"x": v[0], "y": v[1], "r": v[2]},
            "start": {"x": v[3], "y": v[4], "heading": v[5]}}


def wheel_trace(ports):
    """Fig. 6's columns rebuilt from the wheel ports, one row per measured left value, each other
    signal its latest value then (t_s: the log's clock); None when a port is missing."""
    series = {c: port_values(ports, p) for c, p in WHEEL_PORTS.items()}
    if any(v is None for v in series.values()):
        return None
    at = {c: 0 for c in series}
    columns = {"t_s": [], **{c: [] for c in series}}
    for t_ns, _ in series["measured_left"]:
        row = {}
        for c, values in series.items():
            while at[c] < len(values) and values[at[c]][0] <= t_ns:
                at[c] += 1
            if at[c] == 0:
                break  # no value of this signal yet
            row[c] = values[at[c] - 1][1]
        if len(row) == len(series):
            columns["t_s"].append(t_ns / 1e9)
            for c, v in row.items():
                columns[c].append(v)
    return columns if columns["t_s"] else None


def estimation_trace(ports):
    """The estimator's columns, each its own (t_s, values) on the log's clock; None without its
    statistic."""
    series = {c: port_values(ports, p) or [] for c, p in ESTIMATION_PORTS.items()}
    if not series["statistic"] or not series["threshold"]:
        return None
    return {c: ([t / 1e9 for t, _ in v], [x if isinstance(x, float) else math.nan for _, x in v])
            for c, v in series.items()}


# ---- the run, on the trace's clock -----------------------------------------------------------

def text(v):
    return "" if v is None else str(v)


def build_run(records, trace, offset_s):
    """Injections, detections (times in the trace's seconds) and the mission record."""
    timed = [r["t_ns"] for r in records if r.get("t_ns") is not None]
    if offset_s is None:  # without a trace: the log's clock
        offset_s = 0.0 if trace is None else trace["t_s"][0] - (min(timed) / 1e9 if timed else 0.0)
    armed = {r.get("fault_id"): r for r in records if r.get("event") == "armed"}
    injections, detections, recoveries, seen, mission = [], [], {}, set(), None
    for r in records:
        ev = r.get("event")
        if ev == "injected":
            key = (r.get("fault_id"), r["t_ns"])
            if key in seen:
                continue
            seen.add(key)
            arm = armed.get(r.get("fault_id"), {}) if r.get("fault_id") is not None else {}
            injections.append({
                "t_ns": r["t_ns"], "t": r["t_ns"] / 1e9 + offset_s, "fault_id": r.get("fault_id"),
                # keel's own injections name their kind in the `armed` record of the same fault_id
                "kind": text(r.get("kind") or arm.get("kind") or "fault"),
                "component": text(r.get("component") or arm.get("component") or "?"),
                "detail": text(r.get("detail")), "hardware": bool(r.get("hardware"))})
        elif ev == "detected":
            detections.append({
                "t_ns": r["t_ns"], "t": r["t_ns"] / 1e9 + offset_s, "fault_id": r.get("fault_id"),
                "kind": text(r.get("kind") or "fault"), "component": text(r.get("component") or "?"),
                "detector": text(r.get("detector")), "detail": text(r.get("detail"))})
        elif ev == "recovered" and r.get("t_ns") is not None:
            latency = r.get("latency_us")
            recoveries[r.get("fault_id")] = {
                "t": r["t_ns"] / 1e9 + offset_s,
                "latency_us": latency if isinstance(latency, (int, float)) and not isinstance(latency, bool) else None}
        elif ev == "mission":
            mission = r.get("fields") if isinstance(r.get("fields"), dict) else r
    injections.sort(key=lambda i: i["t_ns"])
    detections.sort(key=lambda d: d["t_ns"])
    for d in detections:  # the injection it answers: the same fault_id, else the latest before it
        same = [i for i in injections if d["fault_id"] is not None and i["fault_id"] == d["fault_id"]]
        before = [i for i in injections if i["t_ns"] <= d["t_ns"]]
        cause = same[0] if same else (before[-1] if before else None)
        d["delay_ms"] = None if cause is None else (d["t_ns"] - cause["t_ns"]) / 1e6
        d["recovered"] = recoveries.get(d["fault_id"]) if d["fault_id"] is not None else None
    link_causes(injections, detections)
    span = (min(timed) / 1e9 + offset_s, max(timed) / 1e9 + offset_s) if timed else None
    return {"offset_s": offset_s, "injections": injections, "detections": detections, "mission": mission,
            "span": span}


def link_causes(injections, detections):
    """Sets each detection's "cause" for the timeline: the injection of its fault_id (keel's own
    injections share it), else, for a hardware fault (whose detection gets an id of its own), the
    latest injection into the same component before it that no other detection answers."""
    answered = {d["fault_id"] for d in detections if d["fault_id"] is not None}
    open_ = [i for i in injections if i["fault_id"] not in answered]
    for d in detections:
        same = [i for i in injections if d["fault_id"] is not None and i["fault_id"] == d["fault_id"]]
        before = [i for i in open_ if i["component"] == d["component"] and i["t_ns"] <= d["t_ns"]]
        d["cause"] = same[0] if same else (before[-1] if before else None)
        if not same and before:
            open_.remove(before[-1])


def mission_outcome(mission):
    if mission is None:
        return "no mission record in the log"
    try:
        goal = mission.get("goal_reached")
        parts = ["goal reached" if goal else "goal not reached"]
        if mission.get("ended"):
            parts[0] += f" (ended: {mission['ended']})"
        if mission.get("collisions") is not None:
            n = int(mission["collisions"])
            parts.append(f"{n} collision{'' if n == 1 else 's'}")
        if mission.get("min_clearance_cm") is not None:
            c = float(mission["min_clearance_cm"])
            parts.append(f"min clearance {c:.1f} cm" if c >= 0 else "min clearance n/a")
        if mission.get("duration_s") is not None:
            parts.append(f"{float(mission['duration_s']):.1f} s")
    except (TypeError, ValueError) as e:
        raise InputError(f"log line {mission.get('_line', '?')}: malformed mission record: {e}") from None
    return ", ".join(parts)


def interp(ts, vs, t):
    """Linear interpolation of vs over ts at t, clamped to the ends."""
    if t <= ts[0]:
        return vs[0]
    if t >= ts[-1]:
        return vs[-1]
    lo, hi = 0, len(ts) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if ts[mid] <= t:
            lo = mid
        else:
            hi = mid
    span = ts[hi] - ts[lo]
    a = 0.0 if span <= 0 else (t - ts[lo]) / span
    return vs[lo] + a * (vs[hi] - vs[lo])


def moving_average(values, window):
    """Trailing mean of the last `window` values (of those so far at the start), as the monitor's."""
    out, acc = [], 0.0
    for i, v in enumerate(values):
        acc += v
        if i >= window:
            acc -= values[i - window]
        out.append(acc / min(i + 1, window))
    return out


# ---- plotting --------------------------------------------------------------------------------

def find_matplotlib():
    """Whether matplotlib imports; if not, reruns the script under the system interpreter if that may
    have it. scripts/deps.sh installs Debian's python3-matplotlib, which only /usr/bin/python3 sees;
    a python3 earlier on PATH (pyenv, a venv) does not. Called before reading any input, so that
    nothing is reported twice."""
    try:
        import matplotlib  # noqa: F401
        return True
    except ImportError:
        pass
    if (os.environ.get(REEXEC_GUARD) is None and os.access(SYSTEM_PYTHON, os.X_OK)
            and os.path.realpath(sys.executable) != os.path.realpath(SYSTEM_PYTHON)):
        os.environ[REEXEC_GUARD] = "1"
        sys.stdout.flush()
        sys.stderr.flush()
        os.execv(SYSTEM_PYTHON, [SYSTEM_PYTHON, os.path.abspath(__file__)] + sys.argv[1:])
    return False


def import_matplotlib():
    import matplotlib
    matplotlib.use("Agg")
    matplotlib.rcParams["svg.fonttype"] = "none"  # text stays text: searchable, and smaller
    matplotlib.rcParams["svg.hashsalt"] = "keel"  # reproducible ids
    import matplotlib.pyplot as plt
    return plt


def marker_for(kind, assigned):
    if kind in KIND_MARKERS:
        return KIND_MARKERS[kind]
    if kind not in assigned:
        assigned[kind] = MORE_MARKERS[len(assigned) % len(MORE_MARKERS)]
    return assigned[kind]


def body_outline(x, y, heading):
    c, s = math.cos(heading), math.sin(heading)
    hl, hw = BODY_LENGTH_M / 2, BODY_WIDTH_M / 2
    corners = [(hl, hw), (-hl, hw), (-hl, -hw), (hl, -hw), (hl, hw)]
    return ([x + c * a - s * b for a, b in corners], [y + s * a + c * b for a, b in corners])


def plot_trajectory(plt, trace, world, run, path):
    from matplotlib.patches import Circle, Rectangle
    fig, ax = plt.subplots(figsize=(9, 8))
    xs, ys, ts = trace["x_m"], trace["y_m"], trace["t_s"]
    if world:
        for (x0, y0, x1, y1) in world["boxes"]:
            ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, facecolor="0.6", edgecolor="0.35", lw=0.6, zorder=1))
        if world["target"]:
            tg = world["target"]
            ax.add_patch(Circle((tg["x"], tg["y"]), tg["r"], facecolor="red", edgecolor="darkred", alpha=0.8, zorder=2))
            ax.plot([], [], "o", color="red", label="target")
        if world["start"]:
            st = world["start"]
            ax.plot(st["x"], st["y"], marker="^", color="green", ms=9, ls="none", zorder=5, label="start")
            ax.annotate("", xy=(st["x"] + 0.3 * math.cos(st["heading"]), st["y"] + 0.3 * math.sin(st["heading"])),
                        xytext=(st["x"], st["y"]), arrowprops={"arrowstyle": "->", "color": "green"}, zorder=5)
    ax.plot(xs, ys, "-", color="tab:blue", lw=1.5, zorder=3, label="path")
    bx, by = body_outline(xs[0], ys[0], trace["heading_rad"][0])
    ax.plot(bx, by, "-", color="green", lw=1.2, zorder=4, label="body at start")
    bx, by = body_outline(xs[-1], ys[-1], trace["heading_rad"][-1])
    ax.plot(bx, by, "-", color="black", lw=1.2, zorder=4, label="body at end")

    assigned, legend_kinds, labelled = {}, set(), []

    def label_once(text_, x, y, color, k):
        # the same label within 0.3 m of where it was already written: marker only
        if any(t == text_ and math.hypot(x - lx, y - ly) < 0.3 for t, lx, ly in labelled):
            return
        labelled.append((text_, x, y))
        dx, dy = [(8, 8), (8, -12), (-8, 8), (-8, -12)][k % 4]
        ax.annotate(text_, (x, y), xytext=(dx, dy), textcoords="offset points", fontsize=7, color=color,
                    ha="left" if dx > 0 else "right", zorder=7)

    for k, d in enumerate(run["detections"]):
        x, y = interp(ts, xs, d["t"]), interp(ts, ys, d["t"])
        legend = f"detected: {d['kind']}" if d["kind"] not in legend_kinds else None
        legend_kinds.add(d["kind"])
        ax.plot(x, y, marker=marker_for(d["kind"], assigned), color="darkorange", mec="black", mew=0.6,
                ms=7, ls="none", zorder=6, label=legend)
        label_once(f"{d['kind']}@{d['component']}", x, y, "black", k)
    first = True
    for k, i in enumerate(run["injections"]):
        x, y = interp(ts, xs, i["t"]), interp(ts, ys, i["t"])
        ax.plot(x, y, marker="x", color="crimson", mew=2, ms=9, ls="none", zorder=6,
                label="injected" if first else None)
        first = False
        label_once(f"{i['kind']}@{i['component']}" + (" (hw)" if i["hardware"] else ""), x, y, "crimson", k + 1)

    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.grid(True, lw=0.3, alpha=0.5)
    ax.set_title("Mission: " + mission_outcome(run["mission"]), fontsize=10)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0)
    fig.savefig(path, format="svg", bbox_inches="tight", metadata={"Date": None})
    plt.close(fig)


def plot_fig6(plt, trace, run, window, threshold, path, clock="simulated time"):
    fig, ax = plt.subplots(figsize=(11, 6))
    t_ms = [t * 1000.0 for t in trace["t_s"]]
    ml, rl = trace["measured_left"], trace["reference_left"]
    fml, frl = moving_average(ml, window), moving_average(rl, window)
    ax.plot(t_ms, trace["measured_right"], "-", color="tab:blue", lw=0.8, alpha=0.25, label="measured right")
    ax.plot(t_ms, trace["reference_right"], "-", color="tab:orange", lw=0.8, alpha=0.25, label="reference right")
    ax.plot(t_ms, ml, ".-", color="tab:blue", lw=0.6, ms=2.5, alpha=0.55, label="measured left")
    ax.plot(t_ms, rl, ".-", color="tab:orange", lw=0.6, ms=2.5, alpha=0.55, label="reference left")
    ax.plot(t_ms, fml, "-", color="tab:blue", lw=2.0, label=f"measured left, filtered ({window} samples)")
    ax.plot(t_ms, frl, "-", color="tab:orange", lw=2.0, label=f"reference left, filtered ({window} samples)")
    ax.plot(t_ms, [threshold * r for r in frl], ":", color="tab:red", lw=1.6,
            label=f"threshold ({threshold:g} x filtered reference)")

    trans = ax.get_xaxis_transform()  # x in data, y in axes fraction
    first = True
    for i in run["injections"]:
        x = i["t"] * 1000.0
        ax.axvline(x, color="crimson", ls="--", lw=1.2, label="injected" if first else None)
        first = False
        detail = i["detail"] if len(i["detail"]) <= 40 else i["detail"][:39] + "…"
        ax.text(x, 0.98, f" {i['kind']}" + (f": {detail}" if detail else ""), transform=trans, rotation=90,
                va="top", ha="right", fontsize=8, color="crimson")
    first = True
    for d in (d for d in run["detections"] if d["kind"] == "model"):
        x = d["t"] * 1000.0
        ax.axvline(x, color="black", ls="-", lw=1.2, label="detected (model)" if first else None)
        first = False
        label = (f" {d['kind']}@{d['component']}: " +
                 ("no injection before" if d["delay_ms"] is None else f"{d['delay_ms']:.0f} ms after injection"))
        ax.text(x, 0.02, label, transform=trans, rotation=90, va="bottom", ha="left", fontsize=8, color="black")

    ax.set_xlabel(f"{clock} (ms)")
    ax.set_ylabel("wheel speed (rpm)")
    ax.grid(True, lw=0.3, alpha=0.5)
    ax.set_title(f"Fig. 6: wheel rpm and the process-model detection (window {window}, threshold {threshold:g})",
                 fontsize=10)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0)
    fig.savefig(path, format="svg", bbox_inches="tight", metadata={"Date": None})
    plt.close(fig)


def plot_estimation(plt, est, run, path):
    fig, (wheels, test) = plt.subplots(2, 1, figsize=(11, 8), sharex=True, gridspec_kw={"height_ratios": [1, 1.2]})
    for c, style, color, label in (("encoder_right", "-", "tab:blue", "encoder_right (rpm)"),
                                   ("estimate_right", "--", "tab:cyan", "its estimate"),
                                   ("encoder_left", "-", "tab:red", "encoder_left (rpm)"),
                                   ("estimate_left", "--", "tab:orange", "its estimate")):
        t, v = est[c]
        if t:
            wheels.plot([x * 1000 for x in t], v, style, color=color, lw=1.0, label=label)
    wheels.set_ylabel("wheel speed (rpm)")
    wheels.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0)
    wheels.grid(True, lw=0.3, alpha=0.5)
    t, v = est["statistic"]
    test.semilogy([x * 1000 for x in t], [max(x, 1e-3) for x in v], "-", color="tab:blue", lw=1.0,
                  label="test statistic: normalised innovations squared, summed over the window")
    t, v = est["threshold"]
    test.semilogy([x * 1000 for x in t], v, ":", color="tab:red", lw=1.6, label="threshold (chi-square quantile)")
    for ax in (wheels, test):
        trans = ax.get_xaxis_transform()
        for i in run["injections"]:
            ax.axvline(i["t"] * 1000.0, color="crimson", ls="--", lw=1.2)
            if ax is test:
                ax.text(i["t"] * 1000.0, 0.98, f" {i['kind']}: {i['detail']}"[:48], transform=trans, rotation=90,
                        va="top", ha="right", fontsize=8, color="crimson")
        for d in (d for d in run["detections"] if d.get("detector") == "estimator"):
            ax.axvline(d["t"] * 1000.0, color="black", lw=1.2)
            if ax is test:
                label = (f" {d['kind']}@{d['component']}: " +
                         ("no injection before" if d["delay_ms"] is None else f"{d['delay_ms']:.0f} ms after injection"))
                ax.text(d["t"] * 1000.0, 0.02, label, transform=trans, rotation=90, va="bottom", ha="left",
                        fontsize=8)
    test.set_xlabel("time since the run started (ms)")
    test.set_ylabel("statistic (log)")
    test.grid(True, lw=0.3, alpha=0.5)
    test.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0)
    wheels.set_title("Diagnosis by state estimation: the wheels as measured and estimated, the test and its threshold",
                     fontsize=10)
    fig.savefig(path, format="svg", bbox_inches="tight", metadata={"Date": None})
    plt.close(fig)


def duration_text(us):
    return f"{us:.0f} us" if us < 1000 else f"{us / 1000:.1f} ms"


def latency_text(d):
    parts = []
    if d["cause"] is not None:
        parts.append(f"detected after {duration_text((d['t_ns'] - d['cause']['t_ns']) / 1e3)}")
    rec = d["recovered"]
    if rec is not None and rec["latency_us"] is not None:
        parts.append(f"recovered after {duration_text(rec['latency_us'])}")
    return ", ".join(parts)


def plot_timeline(plt, run, path):
    """One row per component with a fault: injected (x) -> detected (marker per kind) -> recovered (o)."""
    faults = run["detections"] + run["injections"]
    rows = sorted({f["component"] for f in faults})
    y = {c: k for k, c in enumerate(rows)}
    fig, ax = plt.subplots(figsize=(11, max(2.5, 1.0 + 0.6 * len(rows))))
    assigned, legend = {}, set()

    def once(label):
        if label in legend:
            return None
        legend.add(label)
        return label

    for i in run["injections"]:
        ax.plot(i["t"], y[i["component"]], marker="x", color="crimson", mew=2, ms=9, ls="none", zorder=4,
                label=once("injected"))
    for k, d in enumerate(run["detections"]):
        row = y[d["component"]]
        if d["cause"] is not None:
            ax.plot([d["cause"]["t"], d["t"]], [row, row], "-", color="crimson", lw=1.2, zorder=3)
        rec = d["recovered"]
        if rec is not None:
            ax.plot([d["t"], rec["t"]], [row, row], "-", color="tab:green", lw=2.5, zorder=3)
            ax.plot(rec["t"], row, marker="o", mfc="none", color="tab:green", mew=1.5, ms=8, ls="none", zorder=5,
                    label=once("recovered"))
        ax.plot(d["t"], row, marker=marker_for(d["kind"], assigned), color="darkorange", mec="black", mew=0.6,
                ms=8, ls="none", zorder=6, label=once(f"detected: {d['kind']}"))
        text_ = latency_text(d)
        if k < TIMELINE_LABELLED:
            ax.annotate(f"#{d['fault_id']} {d['kind']}" + (f": {text_}" if text_ else ""), (d["t"], row), xytext=(6, 8 if k % 2 else -12),
                        textcoords="offset points", fontsize=7, zorder=7)
    if len(run["detections"]) > TIMELINE_LABELLED:
        ax.text(1.0, -0.12, f"latencies written for the first {TIMELINE_LABELLED} of {len(run['detections'])} faults",
                transform=ax.transAxes, ha="right", fontsize=7)
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels(rows)
    ax.set_ylim(-0.7, len(rows) - 0.3)
    if run["span"] and run["span"][1] > run["span"][0]:  # the whole run, not only its faults
        margin = 0.02 * (run["span"][1] - run["span"][0])
        ax.set_xlim(run["span"][0] - margin, run["span"][1] + margin)
    ax.set_xlabel("time since the run started (s)")
    ax.grid(True, axis="x", lw=0.3, alpha=0.5)
    n = len(run["detections"])
    ax.set_title(f"Fault timeline: {n} fault{'' if n == 1 else 's'} detected, {len(run['injections'])} injected"
                 if faults else "Fault timeline: no faults", fontsize=10)
    if legend:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0)
    fig.savefig(path, format="svg", bbox_inches="tight", metadata={"Date": None})
    plt.close(fig)


# ---- main ------------------------------------------------------------------------------------

def parse_args(argv):
    p = argparse.ArgumentParser(description="Plots a run of keel: timeline.svg; for the test robot trajectory.svg "
                                            "and fig6.svg.")
    p.add_argument("--log", required=True, help="keel's fault log (run.jsonl)")
    p.add_argument("--out", required=True, help="directory for the SVGs (created)")
    p.add_argument("--trace", help="the robot referee's CSV trace (trace.csv): the trajectory and Fig. 6")
    p.add_argument("--ports", help="port values of a recording (ports.jsonl, from keel report --plots): the "
                                   "trajectory and Fig. 6 without a trace")
    p.add_argument("--world", help="the world JSON (default: TRACE.world.json, else the referee's world port)")
    p.add_argument("--window", type=int, default=9, help="moving-average window, in trace rows (default 9)")
    p.add_argument("--threshold", type=float, default=0.5, help="threshold as a fraction of the filtered reference (default 0.5)")
    p.add_argument("--offset-s", type=float, default=None,
                   help="trace time = t_ns / 1e9 + OFFSET (default: the earliest log record at the trace's first row)")
    return p.parse_args(argv)  # usage errors exit 2 too


def read_inputs(args):
    """(trace, world, run, fig6 columns and their clock), or InputError."""
    if args.window < 1:
        raise InputError("--window must be at least 1")
    if not math.isfinite(args.threshold) or (args.offset_s is not None and not math.isfinite(args.offset_s)):
        raise InputError("--threshold and --offset-s must be finite numbers")
    trace = read_trace(args.trace) if args.trace else None
    world = read_world(args.world or args.trace + ".world.json") if args.trace else None
    records = read_log(args.log)
    run = build_run(records, trace, args.offset_s if trace else None)
    mission_outcome(run["mission"])  # a malformed mission record is an input error, before plotting
    wheels, clock = (trace, "simulated time") if trace else (None, None)
    estimation = None
    robot = trace is not None or run["mission"] is not None  # the referee's record
    if not trace and args.ports:  # a recording: everything on the log's clock
        ports = read_ports(args.ports)
        trace, world = truth_trace(ports), (read_world(args.world) if args.world else port_world(ports))
        wheels, clock = wheel_trace(ports), "time since the run started"
        estimation = estimation_trace(ports)
        robot = robot or trace is not None or any(port_values(ports, p) for p in WHEEL_PORTS.values())
    try:
        os.makedirs(args.out, exist_ok=True)
    except OSError as e:
        raise InputError(f"cannot create the output directory {args.out}: {e.strerror}") from None
    return trace, world, run, wheels, clock, robot, estimation


def main(argv=None):
    args = parse_args(argv)
    have_matplotlib = find_matplotlib()
    try:
        trace, world, run, wheels, clock, robot, estimation = read_inputs(args)
    except InputError as e:
        print(f"plot_run: {e}", file=sys.stderr)
        return 2
    if not have_matplotlib:  # after the input's errors, which need no matplotlib
        print(f"plot_run: matplotlib is not installed for {sys.executable} "
              "(scripts/deps.sh installs python3-matplotlib for /usr/bin/python3)", file=sys.stderr)
        return 1
    plt = import_matplotlib()
    plots = [("timeline.svg", lambda f: plot_timeline(plt, run, f))]
    if trace:
        plots.append(("trajectory.svg", lambda f: plot_trajectory(plt, trace, world, run, f)))
    elif robot:  # another application has neither plot to miss
        print(f"plot_run: no trajectory.svg: neither a trace (--trace) nor the referee's true pose (--ports: "
              f"{TRUTH_PORT})", file=sys.stderr)
    if wheels:
        plots.append(("fig6.svg", lambda f: plot_fig6(plt, wheels, run, args.window, args.threshold, f, clock)))
    elif robot:
        print("plot_run: no fig6.svg: neither a trace (--trace) nor the robot's wheel ports (--ports: "
              + ", ".join(WHEEL_PORTS.values()) + ")", file=sys.stderr)
    if estimation:
        plots.append(("estimation.svg", lambda f: plot_estimation(plt, estimation, run, f)))
    for name, draw in plots:
        out = os.path.join(args.out, name)
        try:
            draw(out)
        except OSError as e:
            print(f"plot_run: cannot write {out}: {e.strerror}", file=sys.stderr)
            return 2
        print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
