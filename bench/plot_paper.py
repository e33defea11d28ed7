#!/usr/bin/python3
"""Plots of `tensormass bench paper` (docs/results/paper.md).

usage: plot_paper.py PAPER.json OUTDIR

Writes OUTDIR/paper_threshold.png (error against threshold per criterion,
one panel per beam: the origin report's Figure 12) and
OUTDIR/paper_error_time.png (error against mean ms per step for every run,
one panel per beam). PNGs are written atomically (FILE.tmp, then renamed).
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"hooke": "black", "stvk": "tab:purple", "R_EL": "tab:red", "R_V": "tab:orange",
           "R_S": "tab:green", "R_NL": "tab:blue"}
MARKERS = {"R_EL": "o", "R_V": "s", "R_S": "^", "R_NL": "D"}
CRITERIA = ["R_EL", "R_V", "R_S", "R_NL"]


def save(figure, path):
    tmp = path + ".tmp.png"
    figure.savefig(tmp, dpi=110)
    plt.close(figure)
    os.replace(tmp, path)


def beams_of(rows):
    seen = []
    for row in rows:
        if row["beam"] not in seen:
            seen.append(row["beam"])
    return seen


def floor(value, bottom=1e-7):
    """Errors of 0 (pure StVK) drawn at `bottom` on a log axis."""
    return value if value and value > 0 else bottom


def bottom_of(runs):
    """A third of the smallest positive error of a panel (where StVK's 0 is drawn)."""
    positive = [r["error"] for r in runs if r["error"] is not None and r["error"] > 0]
    return min(positive) / 3 if positive else 1e-7


def panels(count):
    columns = min(count, 3)
    lines = (count + columns - 1) // columns
    figure, axes = plt.subplots(lines, columns, figsize=(5.2 * columns, 4.0 * lines), squeeze=False)
    for extra in axes.flat[count:]:
        extra.set_visible(False)
    return figure, list(axes.flat[:count])


def plot_threshold(rows, beams, path):
    figure, axes = panels(len(beams))
    for axis, beam in zip(axes, beams):
        mine = [r for r in rows if r["beam"] == beam]
        hooke = next((r for r in mine if r["mode"] == "hooke"), None)
        for criterion in CRITERIA:
            runs = sorted((r for r in mine if r["mode"] == criterion and r["threshold"] is not None),
                          key=lambda r: r["threshold"])
            if not runs:
                continue
            # R_S is a force per volume: scale its thresholds by the smallest so
            # that the three sit on the same axis as the strain-like criteria.
            scale = 0.015 / runs[0]["threshold"] if criterion == "R_S" else 1.0
            label = criterion if criterion != "R_S" else "R_S (x %.3g)" % scale
            axis.plot([r["threshold"] * scale for r in runs], [floor(r["error"]) for r in runs],
                      marker=MARKERS[criterion], color=COLOURS[criterion], label=label)
        if hooke is not None:
            axis.axhline(floor(hooke["error"]), color="black", linestyle="--", linewidth=1, label="pure Hooke")
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("threshold")
        axis.set_ylabel("error (max nodal distance to StVK / L)")
        axis.set_title("%s (%d elements)" % (beam, mine[0]["elements"]))
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize=8)
    figure.suptitle("Error against threshold (origin report, Figure 12)")
    figure.tight_layout()
    save(figure, path)


def plot_error_time(rows, beams, path):
    figure, axes = panels(len(beams))
    for axis, beam in zip(axes, beams):
        mine = [r for r in rows if r["beam"] == beam]
        bottom = bottom_of(mine)
        for mode in ["hooke", "stvk"] + CRITERIA:
            runs = [r for r in mine if r["mode"] == mode]
            if not runs:
                continue
            axis.scatter([r["ms_per_step"] for r in runs], [floor(r["error"], bottom) for r in runs],
                         color=COLOURS[mode], marker=MARKERS.get(mode, "*"), s=50 if mode in MARKERS else 120,
                         label=mode, zorder=3)
            for r in runs:
                if r["threshold"] is not None:
                    axis.annotate("%.3g" % r["threshold"], (r["ms_per_step"], floor(r["error"], bottom)), fontsize=6,
                                  xytext=(3, 3), textcoords="offset points")
        axis.set_yscale("log")
        axis.set_xlabel("mean ms per step (median of repetitions)")
        axis.set_ylabel("error (max nodal distance to StVK / L)")
        axis.set_title("%s (%d elements)" % (beam, mine[0]["elements"]))
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize=8)
    figure.suptitle("Error against time per step, every run (StVK's error is 0, drawn at the bottom)")
    figure.tight_layout()
    save(figure, path)


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    with open(argv[1]) as file:
        data = json.load(file)
    rows = data["rows"]
    beams = beams_of(rows)
    if not beams:
        print("plot_paper.py: no rows", file=sys.stderr)
        return 1
    os.makedirs(argv[2], exist_ok=True)
    plot_threshold(rows, beams, os.path.join(argv[2], "paper_threshold.png"))
    plot_error_time(rows, beams, os.path.join(argv[2], "paper_error_time.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
