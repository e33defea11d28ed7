#!/usr/bin/python3
"""The cost of viscoelasticity: the median step of a viscoelastic block against the same elastic block.

A block of 24,000 cells (40 x 10 x 10 cubes of 6 tet4; 60 x 20 x 20 hex8)
clamped at x = 0 under gravity, implicit and explicit, default settings,
run one after the other in this process: `viscoelastic_neohookean` (mu =
3.4 kPa, kappa = 16 kPa, two Prony terms) against `mooney_rivlin` with
c10 = mu/2, c01 = 0 and the same kappa, whose elastic energy is the same
(mu/2 (I1bar - 3) + kappa/2 (J - 1)^2). The ratio is what the viscous part
costs: its per-point history terms and, on tet4, the cells leaving the
batched kernels.

    /usr/bin/python3 bench/viscous_cost.py --json docs/results/viscous.json
    /usr/bin/python3 scripts/results/render_viscous.py docs/results/viscous.json > docs/results/viscous.md
    /usr/bin/python3 bench/viscous_cost.py --quick   # ctest: small blocks
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_metadata import metadata, write_result  # noqa: E402

MU, KAPPA = 3.4e3, 1.6e4
# (element, beam cut, cubes, quick cubes): 24,000 cells each
CASES = [("tet4", "tet6", (40, 10, 10), (8, 2, 2)), ("hex8", "hex8", (60, 20, 20), (12, 4, 4))]
SOLVERS = {"implicit": "{type: implicit, dt: 0.01, steps: 30}", "explicit": "{type: explicit, dt: 2.0e-4, steps: 500}"}
LAWS = {"elastic": f"law: mooney_rivlin, c10: {MU / 2}, c01: 0, kappa: {KAPPA}",
        "viscoelastic": f"law: viscoelastic_neohookean, mu: {MU}, kappa: {KAPPA}, g1: 0.3, tau1: 0.05, g2: 0.2, "
                        "tau2: 0.5, k1: 0, k2: 0"}
SCENE = """mesh: {mesh}
materials: [{{region: all, {law}, density: 1000}}]
fixed: [clamp]
loads: {{gravity: [0, -9.81, 0]}}
solver: {solver}
output: {{directory: {out}}}
"""


def block(binary, work, cut, cells):
    path = os.path.join(work, f"{cut}_{'x'.join(map(str, cells))}.msh")
    if not os.path.exists(path):
        subprocess.run([binary, "beam", "--dim", "3", "--cells", ",".join(map(str, cells)), "--size",
                        f"{cells[0] / cells[1]},1,{cells[2] / cells[1]}", "--type", cut, "-o", path], check=True,
                       stdout=subprocess.DEVNULL)
    return path


def median_step(binary, work, mesh, solver, law):
    """The run's summary.json: cells, steps, median step (ms)."""
    name = f"{os.path.basename(mesh)}_{solver}_{law}"
    scene, out = os.path.join(work, name + ".yaml"), os.path.join(work, "out_" + name)
    with open(scene, "w", encoding="utf-8") as handle:
        handle.write(SCENE.format(mesh=mesh, law=LAWS[law], solver=SOLVERS[solver], out=out))
    run = subprocess.run([binary, "run", "--quiet", scene], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"viscous_cost: {binary} run {scene} exited {run.returncode}: {run.stderr}")
    with open(os.path.join(out, "summary.json"), encoding="utf-8") as handle:
        summary = json.load(handle)
    return summary["elements"], summary["steps"], summary["time_per_step_ms"]["median"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="build/tensormass")
    parser.add_argument("--json", help="write the rows here")
    parser.add_argument("--quick", action="store_true", help="blocks of 192 cells")
    args = parser.parse_args()
    binary = os.path.abspath(args.binary)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for element, cut, cells, quick_cells in CASES:
            mesh = block(binary, work, cut, quick_cells if args.quick else cells)
            for solver in SOLVERS:
                count, steps, elastic = median_step(binary, work, mesh, solver, "elastic")
                _, _, viscous = median_step(binary, work, mesh, solver, "viscoelastic")
                rows.append({"element": element, "solver": solver, "cells": count, "steps": steps,
                             "elastic_ms": elastic, "viscoelastic_ms": viscous, "ratio": viscous / elastic})
                print(f"{element} {solver}: elastic {elastic:.2f} ms, viscoelastic {viscous:.2f} ms "
                      f"({rows[-1]['ratio']:.2f}x)", flush=True)
    result = {"metadata": metadata(binary), "settings": {"mu": MU, "kappa": KAPPA, "quick": args.quick},
              "rows": rows}
    if args.json:
        write_result(args.json, result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
