#!/usr/bin/python3
"""Compares two centroid tracks written by `tensormass run` (output.track).

    compare_tracks.py A.csv B.csv [--json] [--displacement]

A track is `track_<group>.csv`: header `time,x,y,z,ux,uy,uz`, one row per
step (time in seconds, or the load factor of a static solve), (x, y, z) the
group's centroid and (ux, uy, uz) its displacement from the first row, in
the mesh's length unit (metres assumed: distances are printed in mm).

Prints the largest and the root-mean-square distance between the two
centroids over the rows, d(t) = |x_B(t) - x_A(t)| (with --displacement,
|u_B(t) - u_A(t)|: the motion alone, for runs on different meshes of the
same body whose rest centroids differ slightly):

    max distance: 0.0123 mm
    rms distance: 0.0045 mm

--json prints {"max_mm", "rms_mm", "samples", "quantity", "a", "b"} instead.
Both files must have the same time column (same row count, times equal to
1e-9 relative).

Exit status: 0 compared, 2 bad input (missing or malformed CSV, mismatched
time columns), 1 anything else. plot_track.py reads tracks with this module.
"""
import argparse
import json
import math
import sys

import numpy as np

HEADER = ["time", "x", "y", "z", "ux", "uy", "uz"]


class BadInput(Exception):
    """Exit 2: the message names the file and line."""


class Track:
    """One CSV: time (n), position (n, 3), displacement (n, 3)."""

    def __init__(self, path, time, position, displacement):
        self.path = path
        self.time = time
        self.position = position
        self.displacement = displacement


def read_track(path):
    """Reads and checks a track CSV; BadInput names the file and line."""
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except OSError as e:
        raise BadInput(f"{path}: cannot read: {e.strerror or e}") from None
    except UnicodeDecodeError:
        raise BadInput(f"{path}: not a text file") from None
    if not lines or [c.strip() for c in lines[0].split(",")] != HEADER:
        raise BadInput(f"{path}:1: expected the header '{','.join(HEADER)}' of a tensormass track")
    rows = []
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        fields = line.split(",")
        if len(fields) != len(HEADER):
            raise BadInput(f"{path}:{number}: expected {len(HEADER)} values, got {len(fields)}")
        try:
            values = [float(x) for x in fields]
        except ValueError:
            raise BadInput(f"{path}:{number}: not a number in '{line}'") from None
        if not all(math.isfinite(x) for x in values):
            raise BadInput(f"{path}:{number}: non-finite value in '{line}'")
        rows.append(values)
    if not rows:
        raise BadInput(f"{path}: no rows after the header")
    data = np.array(rows)
    return Track(path, data[:, 0], data[:, 1:4], data[:, 4:7])


def check_same_times(first, other):
    """BadInput unless `other` has the time column of `first`."""
    if len(other.time) != len(first.time):
        raise BadInput(f"{other.path}: {len(other.time)} rows, but {first.path} has {len(first.time)}: "
                       "the time columns must match")
    scale = np.maximum(1.0, np.maximum(abs(first.time), abs(other.time)))
    mismatch = np.nonzero(abs(other.time - first.time) > 1e-9 * scale)[0]
    if len(mismatch):
        row = int(mismatch[0])
        raise BadInput(f"{other.path}:{row + 2}: time {other.time[row]:.17g} differs from {first.path}'s "
                       f"{first.time[row]:.17g}: the time columns must match")


def distances(first, other, displacement=False):
    """|x_other - x_first| per row (or of the displacements), in the file's unit."""
    check_same_times(first, other)
    a, b = (first.displacement, other.displacement) if displacement else (first.position, other.position)
    return np.linalg.norm(b - a, axis=1)


def main(argv=None):
    parser = argparse.ArgumentParser(description="Max and RMS distance between two centroid tracks, in mm.")
    parser.add_argument("a", help="reference track CSV")
    parser.add_argument("b", help="track CSV to compare")
    parser.add_argument("--json", action="store_true", help="print a JSON object")
    parser.add_argument("--displacement", action="store_true",
                        help="compare the displacements (ux, uy, uz) instead of the positions")
    args = parser.parse_args(argv)
    try:
        first, other = read_track(args.a), read_track(args.b)
        d = 1e3 * distances(first, other, args.displacement)
    except BadInput as e:
        print(f"compare_tracks.py: {e}", file=sys.stderr)
        return 2
    largest, rms = float(d.max()), float(np.sqrt(np.mean(d * d)))
    if args.json:
        print(json.dumps({"max_mm": largest, "rms_mm": rms, "samples": len(d),
                          "quantity": "displacement" if args.displacement else "position",
                          "a": args.a, "b": args.b}))
    else:
        print(f"max distance: {largest:.6g} mm")
        print(f"rms distance: {rms:.6g} mm")
    return 0


if __name__ == "__main__":
    sys.exit(main())
