#!/usr/bin/python3
"""Which linear solver when: `cholmod`, `cg` and `petsc` (one process) on the same implicit runs.

Beams made by `tensormass beam`, clamped at x = 0, under gravity, implicit
Euler with dt 0.01 s and the default solver settings but
`solver.linear.type`; each scene runs with each solver, in alternation,
`--rounds` times (medians of the ms per step of summary.json):

  neo-Hookean 24k   24,000 tets (40 x 10 x 10 cubes, 6 x 1.5 x 1.5 m), E = 1 MPa: a tangent that changes every step
  StVK 8.6k         8,640 tets (30 x 8 x 6 cubes, 5 x 1 x 1 m), E = 10 MPa
  StVK 600 quads    the origin report's 60 x 10 quad beam, E = 10 MPa
  Hooke 24k         the 24,000-tet beam under Hooke: a constant matrix

    /usr/bin/python3 bench/linear_solver_choice.py --json docs/results/linear_solvers.json
    /usr/bin/python3 scripts/results/render_linear_solvers.py docs/results/linear_solvers.json > docs/results/linear_solvers.md
    /usr/bin/python3 bench/linear_solver_choice.py --quick   # ctest: small meshes, one round
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_metadata import metadata  # noqa: E402

# label -> (beam options, quick beam options, law, young, steps)
SCENES = {
    "neo-Hookean 24k": (["--dim", "3", "--cells", "40,10,10", "--size", "6,1.5,1.5", "--type", "tet6"],
                        ["--dim", "3", "--cells", "10,3,3", "--size", "6,1.5,1.5", "--type", "tet6"],
                        "neohookean", 1.0e6, 30),
    "StVK 8.6k": (["--dim", "3", "--cells", "30,8,6", "--size", "5,1,1", "--type", "tet6"],
                  ["--dim", "3", "--cells", "10,3,3", "--size", "5,1,1", "--type", "tet6"], "stvk", 1.0e7, 60),
    "StVK 600 quads": (["--dim", "2", "--cells", "60,10", "--size", "6,1"], ["--dim", "2", "--cells", "12,2", "--size", "6,1"],
                       "stvk", 1.0e7, 100),
    "Hooke 24k": (["--dim", "3", "--cells", "40,10,10", "--size", "6,1.5,1.5", "--type", "tet6"],
                  ["--dim", "3", "--cells", "10,3,3", "--size", "6,1.5,1.5", "--type", "tet6"], "hooke", 1.0e6, 30),
}
SOLVERS = ["cholmod", "cg", "petsc"]

SCENE = """mesh: {mesh}
materials: [{{region: all, law: {law}, young: {young}, poisson: 0.3, density: 1000}}]
fixed: [clamp]
loads: {{gravity: [0, -9.81{z}]}}
solver: {{type: implicit, dt: 0.01, steps: {steps}, linear: {{type: {solver}}}}}
output: {{directory: {out}}}
"""


def run(binary, work, label, solver, quick):
    beam, quick_beam, law, young, steps = SCENES[label]
    options = quick_beam if quick else beam
    name = label.replace(" ", "_").replace(".", "")
    mesh = os.path.join(work, name + ".msh")
    if not os.path.exists(mesh):
        subprocess.run([binary, "beam", *options, "-o", mesh], check=True, stdout=subprocess.DEVNULL)
    out = os.path.join(work, f"out_{name}_{solver}")
    scene = os.path.join(work, f"{name}_{solver}.yaml")
    with open(scene, "w", encoding="utf-8") as handle:
        handle.write(SCENE.format(mesh=mesh, law=law, young=young, steps=5 if quick else steps, solver=solver, out=out,
                                  z=", 0" if options[1] == "3" else ""))
    result = subprocess.run([binary, "run", "--quiet", scene], capture_output=True, text=True)
    if result.returncode != 0:
        return None, result.stderr.strip()[-300:]
    with open(os.path.join(out, "summary.json"), encoding="utf-8") as handle:
        summary = json.load(handle)
    return summary, ""


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="build/tensormass")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--json", help="write the rows and the run's metadata here")
    args = parser.parse_args()
    binary = os.path.abspath(args.binary)
    rounds = 1 if args.quick else args.rounds
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for label in SCENES:
            times = {solver: [] for solver in SOLVERS}
            last = {}
            for _ in range(rounds):
                for solver in SOLVERS:
                    summary, error = run(binary, work, label, solver, args.quick)
                    if summary is None:
                        last[solver] = {"error": error}
                        continue
                    times[solver].append(summary["time_per_step_ms"]["mean"])
                    last[solver] = summary
            row = {"scene": label, "law": SCENES[label][2]}
            for solver in SOLVERS:
                summary = last.get(solver, {})
                if "error" in summary or not times[solver]:
                    row[solver] = {"error": summary.get("error", "not run")}
                    continue
                row[solver] = {"ms_per_step": statistics.median(times[solver]), "samples": times[solver],
                               "cells": summary["elements"], "linear_solver": summary["solver"]["linear"]
                               if isinstance(summary.get("solver"), dict) and "linear" in summary["solver"] else solver,
                               "max_displacement": summary["max_displacement"]["value"]}
            rows.append(row)
            print(f"{label:16} " + "  ".join(
                f"{s} {row[s]['ms_per_step']:.2f} ms" if "ms_per_step" in row[s] else f"{s} failed" for s in SOLVERS),
                flush=True)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump({"metadata": metadata(binary), "settings": {"rounds": rounds, "quick": args.quick},
                       "rows": rows}, handle, indent=1)
            handle.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
