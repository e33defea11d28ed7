#!/usr/bin/python3
"""Volumetric locking: a cantilever under its weight as Poisson's ratio nears 1/2.

A 10 x 1 x 1 m beam (`tensormass beam --size 10,1,1`), clamped at x = 0,
Hooke (E = 1 MPa, density 10 kg/m^3), static, gravity -9.81 m/s^2 along y,
on a coarse mesh of 20 x 2 x 2 cubes cut into each element type, for each
Poisson's ratio; the largest displacement (summary.json's
max_displacement) against the reference: hex20 on 80 x 8 x 8 cubes at the
same ratio. Each run uses the default settings; the `fbar` rows set
`split: fbar` on the material (the mean-dilatation formulation), the `anp`
rows `split: anp` (the averaged nodal pressure).

The cost of the formulations: the median step of a neo-Hookean block of
24,000 cells (60 x 20 x 20 hex8; 40 x 10 x 10 cubes of 6 tet4) at
nu = 0.499 under gravity, implicit and explicit, plain and with the
locking-free split (fbar, anp), run one after the other in this process.

    /usr/bin/python3 bench/locking_cantilever.py --json docs/results/locking.json
    /usr/bin/python3 scripts/results/render_locking.py docs/results/locking.json > docs/results/locking.md
    /usr/bin/python3 bench/locking_cantilever.py --quick   # ctest: two elements, two ratios, a coarse reference
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_metadata import metadata, write_result  # noqa: E402

# element -> `tensormass beam` options making it
ELEMENTS = {
    "tet4": ["--type", "tet6"],
    "hex8": ["--type", "hex8"],
    "prism6": ["--type", "prism6"],
    "pyramid5": ["--type", "pyramid5"],
    "tet10": ["--type", "tet6", "--order", "2"],
    "hex20": ["--type", "hex20"],
}
# the rows: (label, element, split; "" is the default)
VARIANTS = [("tet4", "tet4", ""), ("hex8", "hex8", ""), ("prism6", "prism6", ""), ("pyramid5", "pyramid5", ""),
            ("tet4 anp", "tet4", "anp"), ("prism6 anp", "prism6", "anp"), ("hex8 fbar", "hex8", "fbar"),
            ("pyramid5 fbar", "pyramid5", "fbar"),
            ("tet10", "tet10", ""), ("hex20", "hex20", "")]
QUICK_VARIANTS = [("tet4", "tet4", ""), ("tet4 anp", "tet4", "anp"), ("hex8", "hex8", ""), ("hex8 fbar", "hex8", "fbar")]
RATIOS = [0.3, 0.45, 0.49, 0.499]
COARSE = (20, 2, 2)
FINE = (80, 8, 8)

SCENE = """mesh: {mesh}
materials: [{{region: all, law: hooke, young: 1.0e6, poisson: {poisson}, density: 10{split}}}]
fixed: [clamp]
loads: {{gravity: [0, -9.81, 0]}}
solver: {{type: static}}
output: {{directory: {out}}}
"""


def beam(binary, work, label, cells):
    path = os.path.join(work, f"{label}_{'x'.join(map(str, cells))}.msh")
    if not os.path.exists(path):
        subprocess.run([binary, "beam", "--dim", "3", "--cells", ",".join(map(str, cells)), "--size", "10,1,1",
                        *ELEMENTS[label], "-o", path], check=True, stdout=subprocess.DEVNULL)
    return path


def sag(binary, work, label, cells, poisson, split=""):
    """The run's summary.json figures: largest displacement, cells, dofs, wall seconds, warnings."""
    mesh = beam(binary, work, label, cells)
    name = f"{label}_{split or 'default'}_{'x'.join(map(str, cells))}_{poisson}"
    scene = os.path.join(work, name + ".yaml")
    out = os.path.join(work, "out_" + name)
    with open(scene, "w", encoding="utf-8") as handle:
        handle.write(SCENE.format(mesh=mesh, poisson=poisson, out=out, split=f", split: {split}" if split else ""))
    run = subprocess.run([binary, "run", "--quiet", scene], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"locking_cantilever: {binary} run {scene} exited {run.returncode}: {run.stderr}")
    with open(os.path.join(out, "summary.json"), encoding="utf-8") as handle:
        summary = json.load(handle)
    return {"element": label, "split": split or "whole", "cells": summary["elements"], "dofs": summary["dofs"],
            "poisson": poisson,
            "max_displacement": summary["max_displacement"]["value"], "seconds": summary["time_per_phase_s"]["total"],
            "warned": bool(summary["warnings"])}


# (element, beam cut, cubes, quick cubes, locking-free split): 24,000 cells each.
COST_CASES = [("hex8", "hex8", (60, 20, 20), (12, 4, 4), "fbar"),
              ("tet4", "tet6", (40, 10, 10), (8, 2, 2), "anp")]
COST_SOLVERS = {"implicit": "{type: implicit, dt: 0.01, steps: 10}",
                "explicit": "{type: explicit, dt: 1.0e-5, steps: 200}"}
COST_SCENE = """mesh: {mesh}
materials: [{{region: all, law: neohookean, young: 1.0e4, poisson: 0.499, density: 1000, split: {split}}}]
fixed: [clamp]
loads: {{gravity: [0, -9.81, 0]}}
solver: {solver}
output: {{directory: {out}}}
"""


def step_cost(binary, work, cut, cells, solver, split):
    """The median step (ms) of the cost block of `cut` cubes under `solver` with `split`."""
    path = os.path.join(work, f"cost_{cut}_{'x'.join(map(str, cells))}.msh")
    if not os.path.exists(path):
        subprocess.run([binary, "beam", "--dim", "3", "--cells", ",".join(map(str, cells)), "--size",
                        f"{cells[0] / cells[1]},1,{cells[2] / cells[1]}", "--type", cut, "-o", path], check=True,
                       stdout=subprocess.DEVNULL)
    scene = os.path.join(work, f"cost_{cut}_{solver}_{split}.yaml")
    out = os.path.join(work, f"out_cost_{cut}_{solver}_{split}")
    with open(scene, "w", encoding="utf-8") as handle:
        handle.write(COST_SCENE.format(mesh=path, split=split, solver=COST_SOLVERS[solver], out=out))
    run = subprocess.run([binary, "run", "--quiet", scene], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"locking_cantilever: {binary} run {scene} exited {run.returncode}: {run.stderr}")
    with open(os.path.join(out, "summary.json"), encoding="utf-8") as handle:
        summary = json.load(handle)
    return {"solver": solver, "split": split, "cells": summary["elements"], "steps": summary["steps"],
            "median_step_ms": summary["time_per_step_ms"]["median"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="build/tensormass")
    parser.add_argument("--json", help="write the rows here")
    parser.add_argument("--quick", action="store_true",
                        help="tet4, tet4 anp, hex8 and hex8 fbar at 0.3 and 0.499, hex20 reference on 20 x 2 x 2")
    parser.add_argument("--work", help="a directory for meshes and runs (default: a temporary one)")
    args = parser.parse_args()
    binary = os.path.abspath(args.binary)
    variants = QUICK_VARIANTS if args.quick else VARIANTS
    ratios = [0.3, 0.499] if args.quick else RATIOS
    fine = COARSE if args.quick else FINE
    with tempfile.TemporaryDirectory() as scratch:
        work = os.path.abspath(args.work or scratch)
        os.makedirs(work, exist_ok=True)
        references = {nu: sag(binary, work, "hex20", fine, nu) for nu in ratios}
        rows = []
        for label, element, split in variants:
            for nu in ratios:
                row = sag(binary, work, element, COARSE, nu, split)
                row["label"] = label
                row["ratio"] = row["max_displacement"] / references[nu]["max_displacement"]
                rows.append(row)
                print(f"{label:9} nu {nu:<6} sag {row['max_displacement']:.4f} m  "
                      f"{row['ratio']:.3f} of hex20 {'x'.join(map(str, fine))}", flush=True)
        costs = []
        for element, cut, full_cells, quick_cells, free in COST_CASES:
            cells = quick_cells if args.quick else full_cells
            for solver in COST_SOLVERS:
                plain, other = (step_cost(binary, work, cut, cells, solver, split) for split in ("whole", free))
                costs.append({"element": element, "split": free, "solver": solver, "cells": plain["cells"],
                              "steps": plain["steps"], "whole_ms": plain["median_step_ms"],
                              "split_ms": other["median_step_ms"],
                              "ratio": other["median_step_ms"] / plain["median_step_ms"]})
                print(f"{element} {solver} step: whole {plain['median_step_ms']:.2f} ms, {free} "
                      f"{other['median_step_ms']:.2f} ms ({costs[-1]['ratio']:.2f}x)", flush=True)
    result = {
        "metadata": metadata(binary),
        "settings": {"coarse_cubes": list(COARSE), "reference_cubes": list(fine), "size_m": [10, 1, 1],
                     "law": "hooke", "young": 1.0e6, "density": 10, "gravity": 9.81, "quick": args.quick},
        "references": [references[nu] for nu in ratios],
        "rows": rows,
        "costs": costs,
    }
    if args.json:
        write_result(args.json, result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
