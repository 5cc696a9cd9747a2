#!/usr/bin/env python3
"""Plots a `keel bench` JSON file (a list of cells) as SVG or PNG, with matplotlib.

    plot_bench.py recovery|detection CELLS.json OUT.svg

One panel per scheduling policy; x: the load level (the achieved machine load in the tick
labels); y: latency in µs on a log scale; per mechanism (recovery) or injected kind (detection)
the p99 as a solid line with markers and the p50 dashed; the machine's floor (floor_wake,
floor_timer: a thread wake-up, a timer wake-up; floor_signal, floor_throw: a bare signal handler,
a bare catch) as grey dotted p99 lines. Skipped cells are
left out.
keel-bench runs it after each benchmark."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) != 4 or argv[1] not in ("recovery", "detection"):
        print(__doc__, file=sys.stderr)
        return 2
    kind, src, out = argv[1], argv[2], argv[3]
    with open(src, encoding="utf-8") as f:
        cells = [c for c in json.load(f) if c.get("n", 0) > 0 and not c.get("skipped")]
    if not cells:
        print(f"plot_bench.py: no measured cell in {src}", file=sys.stderr)
        return 1
    key = "mechanism" if kind == "recovery" else "kind"
    policies = [p for p in ("other", "fifo") if any(c["policy"] == p for c in cells)]
    fig, axes = plt.subplots(1, len(policies), figsize=(6.5 * len(policies), 4.8), squeeze=False, sharey=True)
    for ax, policy in zip(axes[0], policies):
        mine = [c for c in cells if c["policy"] == policy]
        loads = sorted({c["load"] for c in mine})
        achieved = {c["load"]: c["load_achieved"] for c in mine}
        names = list(dict.fromkeys(c[key] for c in mine))
        others = [n for n in names if not n.startswith("floor_")]
        for name in names:
            pts = sorted((c["load"], c["p50_us"], c["p99_us"]) for c in mine if c[key] == name)
            xs = [p[0] for p in pts]
            if name.startswith("floor_"):  # the machine's floor: grey, beneath the rest
                colour = "0.35" if name in ("floor_wake", "floor_signal") else "0.65"
                ax.plot(xs, [p[2] for p in pts], "x:", color=colour, label=f"{name} p99 (machine)")
                continue
            colour = f"C{others.index(name)}"
            ax.plot(xs, [p[2] for p in pts], "o-", color=colour, label=f"{name} p99")
            ax.plot(xs, [p[1] for p in pts], "--", color=colour, alpha=0.7, label=f"{name} p50")
        ax.set_xticks(loads)
        ax.set_xticklabels([f"{l}%\n({achieved[l]:.0f}%)" for l in loads])
        ax.set_yscale("log")
        ax.set_xlabel("load asked (achieved machine load)")
        ax.set_title(f"SCHED_{policy.upper()}")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("µs: keel recovered − detected; peers crash → ready" if kind == "recovery"
                          else "detected − injected, µs")
    axes[0][-1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle(f"keel bench {kind}: p99 (solid) and p50 (dashed) per cell")
    fig.tight_layout()
    fig.savefig(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
