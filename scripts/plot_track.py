#!/usr/bin/python3
"""Plots centroid tracks written by `tensormass run` (output.track).

    plot_track.py A.csv [B.csv ...] [--label NAME ...] -o OUT.png [--title T]
                  [--displacement]

Top panel: the displacement ux, uy, uz of each track's centroid (mm, the
mesh in metres) against time (seconds; the load factor for a static solve),
one colour per component, a solid line for the first file and dashed lines
for the others. With two files or more, a second panel shows the distance
between each later track's centroid and the first one's, |x_B(t) - x_A(t)|
(mm; --displacement: |u_B(t) - u_A(t)|, the motion alone), and for each
later file one line is printed:

    max difference: 0.0123 mm (B vs A)

--label names the files in the legend, one per file in order (default: the
file names). All files must have the same time column (see compare_tracks.py,
which also prints the max and RMS distance of two tracks without plotting).
The PNG is written to a temporary file and renamed over OUT.png.

Exit status: 0 image written, 2 bad input (missing or malformed CSV,
mismatched time columns, wrong --label count; nothing is written), 1
anything else.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from compare_tracks import BadInput, distances, read_track  # noqa: E402

COMPONENTS = [("ux", "C0"), ("uy", "C1"), ("uz", "C2")]
LATER_STYLES = ["--", (0, (6, 2, 1, 2)), (0, (2, 2)), (0, (8, 3))]


def style(index):
    """Solid for the first track, dashed patterns for the others."""
    return "-" if index == 0 else LATER_STYLES[(index - 1) % len(LATER_STYLES)]


def plot(tracks, labels, title, displacement):
    """The figure, and the max difference of each later track (mm)."""
    compare = len(tracks) > 1
    figure, axes = plt.subplots(2 if compare else 1, 1, figsize=(8, 6.5 if compare else 4), sharex=True,
                                squeeze=False)
    top = axes[0][0]
    for k, track in enumerate(tracks):
        for c, (name, colour) in enumerate(COMPONENTS):
            top.plot(track.time, 1e3 * track.displacement[:, c], color=colour, linestyle=style(k), linewidth=1.4)
    handles = [Line2D([], [], color=colour, label=name) for name, colour in COMPONENTS]
    handles += [Line2D([], [], color="0.3", linestyle=style(k), label=label) for k, label in enumerate(labels)]
    top.legend(handles=handles, fontsize=8, ncol=2)
    top.set_ylabel("centroid displacement (mm)")
    top.grid(alpha=0.3)
    if title:
        top.set_title(title)
    differences = []
    if compare:
        bottom = axes[1][0]
        for k in range(1, len(tracks)):
            d = 1e3 * distances(tracks[0], tracks[k], displacement)
            differences.append(float(d.max()))
            bottom.plot(tracks[k].time, d, color="0.2", linestyle=style(k), label=f"{labels[k]} vs {labels[0]}")
        bottom.set_ylabel(("displacement" if displacement else "centroid") + " difference (mm)")
        bottom.legend(fontsize=8)
        bottom.grid(alpha=0.3)
    axes[-1][0].set_xlabel("time (s)")
    figure.tight_layout()
    return figure, differences


def save_atomically(figure, path):
    """Writes the PNG next to `path` under a temporary name, then renames it."""
    temporary = f"{path}.tmp-{os.getpid()}"
    try:
        figure.savefig(temporary, format="png", dpi=120)
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.remove(temporary)
        raise


def main(argv=None):
    parser = argparse.ArgumentParser(description="Plot centroid tracks (track_<group>.csv) against time.")
    parser.add_argument("tracks", nargs="+", help="track CSV files; the first is the reference")
    parser.add_argument("--label", action="append", default=[], help="legend name of each file, in order")
    parser.add_argument("-o", "--output", required=True, help="PNG to write")
    parser.add_argument("--title", default="", help="figure title")
    parser.add_argument("--displacement", action="store_true",
                        help="difference panel: compare displacements instead of centroid positions")
    args = parser.parse_args(argv)
    try:
        if args.label and len(args.label) != len(args.tracks):
            raise BadInput(f"{len(args.label)} --label for {len(args.tracks)} files: give one per file or none")
        tracks = [read_track(path) for path in args.tracks]
        for track in tracks[1:]:
            distances(tracks[0], track, args.displacement)  # checks the time columns before plotting
    except BadInput as e:
        print(f"plot_track.py: {e}", file=sys.stderr)
        return 2
    labels = args.label or [os.path.basename(path) for path in args.tracks]
    figure, differences = plot(tracks, labels, args.title, args.displacement)
    save_atomically(figure, args.output)
    for k, value in enumerate(differences, start=1):
        print(f"max difference: {value:.6g} mm ({labels[k]} vs {labels[0]})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
