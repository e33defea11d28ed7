#!/usr/bin/python3
"""Resident memory of a long explicit run: flat after its first steps.

Runs one small explicit scene (a 2D beam of 8 x 2 quads, no frames, the
body's centroid tracked, the adaptive model evaluated at every step, a
checkpoint every 100,000 steps) for a thousand steps and for many more,
each in its own process, and compares their peak resident memory
(ru_maxrss of the child, from os.wait4). A run keeps its per-step records
in bounded memory (integrators/step_series.hpp) and streams its track rows
and adaptivity records to their files (io/streamed_file.hpp), so the long
run's peak must stay within 1 % of the short one's. With --baseline BINARY the same runs of another build
are measured side by side.

usage: /usr/bin/python3 scripts/soak_steps.py [--binary build/tensormass]
           [--steps 1000000] [--baseline OTHER_BINARY --baseline-label TEXT]
           [--json FILE] [--work DIR]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "bench"))
from bench_metadata import metadata  # noqa: E402

SCENE = """mesh: beam.msh
materials:
  - {{region: all, law: stvk, young: 1.0e7, poisson: 0.3, density: 1000}}
fixed: [clamp]
loads: {{gravity: [0, -9.81]}}
solver: {{type: explicit, dt: 1.0e-5, steps: {steps}, damping: {{mass: 5}}}}
output: {{directory: out_{steps}, track: [body], checkpoint_every: 100000}}
adaptivity: {{criteria: [{{name: R_NL, threshold: 0.01}}], ladder: [stvk, neohookean]}}
"""


def peak_mib(binary, work, steps):
    """The peak resident memory (MiB) and wall time (s) of `binary run` over `steps` steps."""
    scene = os.path.join(work, f"scene_{steps}.yaml")
    with open(scene, "w", encoding="utf-8") as handle:
        handle.write(SCENE.format(steps=steps))
    started = time.monotonic()
    child = subprocess.Popen([binary, "run", "--quiet", scene], cwd=work, stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode != 0:
        sys.exit(f"soak_steps: {binary} run {scene} exited {child.returncode}: {child.stderr.read().decode()}")
    return usage.ru_maxrss / 1024.0, time.monotonic() - started


def measure(binary, label, work, steps):
    """The row of one binary: peak MiB at 1,000 and at `steps` steps, growth in %, the long run's seconds."""
    short, _ = peak_mib(binary, work, 1000)
    long, seconds = peak_mib(binary, work, steps)
    growth = 100.0 * (long - short) / short
    print(f"| {label} | {short:.1f} | {long:.1f} | {growth:+.2f} % | {seconds:.1f} s |")
    return {"label": label, "short_mib": short, "long_mib": long, "growth_percent": growth, "long_seconds": seconds}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="build/tensormass")
    parser.add_argument("--steps", type=int, default=1000000)
    parser.add_argument("--baseline", help="another tensormass binary measured the same way")
    parser.add_argument("--baseline-label", default="baseline", help="what the baseline binary is (for the page)")
    parser.add_argument("--json", help="write the rows and the run's metadata here")
    parser.add_argument("--work", help="a directory for the mesh, scenes and outputs (default: a temporary one)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        work = os.path.abspath(args.work or scratch)
        os.makedirs(work, exist_ok=True)
        subprocess.run([os.path.abspath(args.binary), "beam", "--dim", "2", "--cells", "8,2", "--size", "4,1", "-o",
                        os.path.join(work, "beam.msh")], check=True, stdout=subprocess.DEVNULL)
        print(f"peak resident memory, 1000 steps against {args.steps} explicit steps (2D beam, 16 quads)\n")
        print(f"| binary | 1000 steps (MiB) | {args.steps} steps (MiB) | growth | long run's wall time |")
        print("|---|--:|--:|--:|--:|")
        rows = [measure(os.path.abspath(args.binary), "this build", work, args.steps)]
        if args.baseline:
            rows.append(measure(os.path.abspath(args.baseline), args.baseline_label, work, args.steps))
    growth = rows[0]["growth_percent"]
    print(f"\ntarget: growth within 1 %: {'PASS' if abs(growth) <= 1.0 else 'MISS'} ({growth:+.2f} %)")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump({"metadata": metadata(os.path.abspath(args.binary)),
                       "settings": {"short_steps": 1000, "long_steps": args.steps, "dt": 1.0e-5, "cells": 16},
                       "rows": rows}, handle, indent=1)
            handle.write("\n")
    return 0 if abs(growth) <= 1.0 else 1


if __name__ == "__main__":
    sys.exit(main())
