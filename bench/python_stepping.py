#!/usr/bin/env python3
"""Stepping from Python against the CLI on the same implicit run.

A 3D StVK cantilever of 10,080 tets (20 x 6 x 14 cubes x 6 tets, 2,835
nodes), implicit Euler, `--steps` steps, default solver settings. Runs, in
alternation, `--repeats` times each:
  cli      tensormass run SCENE --quiet (a subprocess; its wall time)
  python   tm.Simulation(SCENE); while sim.step(): sim.displacement
           (construction to the end, the state read as NumPy after every step)
and prints the medians, the ratio python / cli, and both runs' own loop
time (summary.json time_loop_seconds: the steps alone).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_stepping.py [--binary build/tensormass] [--json FILE]
    /usr/bin/python3 scripts/results/render_python.py FILE > docs/results/python.md
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import tensormass as tm

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_metadata import metadata  # noqa: E402

SCENE = """mesh: beam.msh
materials: [{{law: stvk, young: 1.0e6, poisson: 0.3, density: 1000}}]
fixed: [clamp]
loads: {{gravity: [0, -9.81, 0]}}
solver: {{type: implicit, dt: 0.01, steps: {steps}}}
output: {{directory: {out}}}
"""


def loop_seconds(directory):
    with open(os.path.join(directory, "summary.json")) as f:
        return json.load(f)["time_loop_seconds"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="build/tensormass")
    parser.add_argument("--steps", type=int, default=40)
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("--json", help="write the runs, their medians and the run's metadata here")
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="tm-python-bench-")
    subprocess.run([args.binary, "beam", "--dim", "3", "--cells", "20,6,14", "--size", "2,0.6,1.4", "--type", "tet6",
                    "-o", os.path.join(work, "beam.msh")], check=True, capture_output=True)
    scenes = {}
    for name in ("cli", "python"):
        scenes[name] = os.path.join(work, name + ".yaml")
        with open(scenes[name], "w") as f:
            f.write(SCENE.format(steps=args.steps, out="out-" + name))
    wall = {"cli": [], "python": []}
    loop = {"cli": [], "python": []}
    for _ in range(args.repeats):
        start = time.perf_counter()
        subprocess.run([args.binary, "run", scenes["cli"], "--quiet"], check=True, capture_output=True)
        wall["cli"].append(time.perf_counter() - start)
        loop["cli"].append(loop_seconds(os.path.join(work, "out-cli")))

        start = time.perf_counter()
        sim = tm.Simulation(scenes["python"])
        while sim.step():
            sim.displacement
        wall["python"].append(time.perf_counter() - start)
        loop["python"].append(loop_seconds(os.path.join(work, "out-python")))
        del sim
    median = {k: statistics.median(v) for k, v in wall.items()}
    median_loop = {k: statistics.median(v) for k, v in loop.items()}
    print(f"10,080 tets, implicit StVK, {args.steps} steps, {args.repeats} runs each (alternating), medians:")
    print(f"  cli     wall {median['cli']:.3f} s   loop {median_loop['cli']:.3f} s")
    print(f"  python  wall {median['python']:.3f} s   loop {median_loop['python']:.3f} s")
    print(f"  python / cli: wall {median['python'] / median['cli']:.3f}, loop "
          f"{median_loop['python'] / median_loop['cli']:.3f}")
    print("  all wall times: cli " + " ".join(f"{t:.3f}" for t in wall["cli"]) + "; python " +
          " ".join(f"{t:.3f}" for t in wall["python"]))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump({"metadata": metadata(os.path.abspath(args.binary)),
                       "settings": {"steps": args.steps, "repeats": args.repeats, "tets": 10080, "nodes": 2835},
                       "wall_s": wall, "loop_s": loop, "median_wall_s": median, "median_loop_s": median_loop},
                      handle, indent=1)
            handle.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
