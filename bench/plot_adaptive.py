#!/usr/bin/python3
"""Error against cost for `tensormass bench adaptive` (docs/results/adaptive.md).

usage: plot_adaptive.py ADAPTIVE.json OUT.png

One panel per scene of the JSON that `tensormass-bench adaptive --json`
writes: every run as a point, its mean step over the pure rich law's (x)
against its error in % of the rich run's largest displacement (y, log
scale); pure laws as squares, adaptive runs on the two-rung ladder as
circles labelled with their R_NL threshold (diamonds: R_P), three-rung runs as triangles; the
benchmark's targets as dashed lines (1 % error, the scene's cost target).
Failed runs (an inverted element) are left out and counted in the title.
The PNG is written atomically (OUT.tmp.png, then renamed).
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ERROR_TARGET = 1.0  # %
FLOOR = 1e-3  # % : the rich run itself (error 0) is drawn here
PURE = {"hooke": "black", "corotational": "tab:orange", "stvk": "tab:purple", "neohookean": "tab:purple",
        "stable_neohookean": "tab:green"}


def cost_target(scene):
    """The benchmark's cost target: 0.7x on the beams, 0.5x on the indentation scenes."""
    return 0.7 if scene.startswith(("cantilever", "quad-beam")) else 0.5


def rich_of(runs):
    """The pure rich run: the second run the benchmark makes (linear, rich, ...)."""
    return runs[1]


def draw(axis, scene):
    runs = scene["runs"]
    rich = rich_of(runs)
    failed = 0
    for run in runs:
        if run["failed"]:
            failed += 1
            continue
        if not run.get("screened", True):
            continue  # the criteria screen's baseline: same trajectory as its screened run
        # The median of each round's ratio, its range as a bar (older files: one round, the plain ratio).
        x = run.get("ratio", run["ms_per_step"] / rich["ms_per_step"])
        y = max(100.0 * run["error"], FLOOR)
        if "ratio_low" in run and run["ratio_high"] > run["ratio_low"]:
            axis.plot([run["ratio_low"], run["ratio_high"]], [y, y], "-", color="grey", linewidth=0.8)
        label = run["label"]
        if run["threshold"] is None:
            axis.plot(x, y, "s", color=PURE.get(label, "grey"), markersize=7)
            axis.annotate(label, (x, y), textcoords="offset points", xytext=(5, 3), fontsize=7)
        elif label.startswith("3 rungs"):
            axis.plot(x, y, "^", color="tab:red", markersize=7)
        elif label.startswith("adaptive R_P"):
            axis.plot(x, y, "D", color="tab:green", markersize=6)
            axis.annotate(f"{run['threshold']:g}", (x, y), textcoords="offset points", xytext=(5, -9), fontsize=7)
        else:
            axis.plot(x, y, "o", color="tab:blue", markersize=7)
            axis.annotate(f"{run['threshold']:g}", (x, y), textcoords="offset points", xytext=(5, -9), fontsize=7)
    axis.axhline(ERROR_TARGET, color="grey", linestyle="--", linewidth=0.8)
    axis.axvline(cost_target(scene["name"]), color="grey", linestyle="--", linewidth=0.8)
    axis.set_yscale("log")
    axis.set_xlim(left=0)
    title = f"{scene['name']} ({scene['cells']} cells)"
    if failed:
        title += f", {failed} failed"
    axis.set_title(title, fontsize=9)
    axis.set_xlabel("mean step / pure rich law's", fontsize=8)
    axis.set_ylabel("error, % of the largest displacement", fontsize=8)
    axis.tick_params(labelsize=7)
    axis.grid(True, which="both", linewidth=0.3)


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    try:
        with open(argv[1]) as source:
            scenes = json.load(source)["scenes"]
    except (OSError, ValueError, KeyError) as error:
        print(f"plot_adaptive.py: cannot read {argv[1]}: {error}", file=sys.stderr)
        return 1
    if not scenes:
        print(f"plot_adaptive.py: {argv[1]} has no scenes", file=sys.stderr)
        return 1
    columns = min(4, len(scenes))
    rows = math.ceil(len(scenes) / columns)
    figure, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.6 * rows), squeeze=False)
    for axis, scene in zip(axes.flat, scenes):
        draw(axis, scene)
    for axis in list(axes.flat)[len(scenes):]:
        axis.axis("off")
    figure.suptitle("tensormass bench adaptive: error against cost (squares: pure laws; circles: adaptive "
                    "[linear, rich] at its R_NL threshold; diamonds: the same at its R_P threshold; triangles: 3 rungs; "
                    "dashed: targets)", fontsize=9)
    figure.tight_layout(rect=(0, 0, 1, 0.96))
    tmp = argv[2] + ".tmp.png"
    figure.savefig(tmp, dpi=100)
    plt.close(figure)
    os.replace(tmp, argv[2])
    print(f"wrote {argv[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
