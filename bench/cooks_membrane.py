#!/usr/bin/python3
"""Cook's membrane, nearly incompressible: the tip's vertical displacement as the mesh refines.

The tapered panel of Cook (1974), corners (0, 0), (48, 44), (48, 60),
(0, 44), clamped at x = 0 and sheared by a total vertical force of 100 spread
uniformly over its right edge (x = 48), in plane strain, linear elastic
(Hooke, E = 250, nu = 0.4999). Each element type meshes it with N x N cells
(mapped from the unit square; tri3 cuts each quad in two, tet4 each hex8 in
six) for each N; the 3D meshes are one cell thick with u_z = 0 at every node,
which is plane strain. The reference is CalculiX's (`ccx`) CPE8 (eight-node
plane-strain quads) on the finest of three quad8 meshes this script writes,
run in the same process: a solver no one here wrote. Each run uses the default settings
but the `split`.

    /usr/bin/python3 bench/cooks_membrane.py --json docs/results/cooks_membrane.json
    /usr/bin/python3 scripts/results/render_cooks_membrane.py docs/results/cooks_membrane.json > docs/results/cooks_membrane.md
    /usr/bin/python3 bench/cooks_membrane.py --quick   # ctest: N = 2, 4 and a coarse reference
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_metadata import metadata, write_result  # noqa: E402
from mapped_meshes import SOLIDS, mapped_grid, run_tensormass, write_msh  # noqa: E402

YOUNG, POISSON, FORCE = 250.0, 0.4999, 100.0
# (label, element, split): the plain and the locking-free formulation of each first-order element
VARIANTS = [("quad4", "quad4", "whole"), ("quad4 fbar", "quad4", "fbar"), ("tri3", "tri3", "whole"),
            ("tri3 anp", "tri3", "anp"), ("hex8", "hex8", "whole"), ("hex8 fbar", "hex8", "fbar"),
            ("tet4", "tet4", "whole"), ("tet4 anp", "tet4", "anp")]
SIZES = [4, 8, 16, 32, 64, 128]
QUICK_SIZES = [2, 4]
# CalculiX's meshes: the last is the reference, the others show how far it has converged.
REFERENCE_SIZES, QUICK_REFERENCE_SIZES = [32, 64, 128], [4, 8]


def point(xi, eta):
    """The unit square's (xi, eta) on the panel: x = 48 xi between the bottom and top edges."""
    x = 48.0 * xi
    bottom, top = 44.0 * xi, 44.0 + 16.0 * xi
    return x, bottom + eta * (top - bottom)


def panel_mesh(element, n):
    """(points, cells, clamp nodes, right-edge nodes with their share of the force, tip node) of an n x n mesh."""
    points, cells, index = mapped_grid(element, n, point)
    quadratic = element == "quad8"
    m = 2 * n if quadratic else n
    layers = (0, 1) if element in SOLIDS else (0,)
    clamp = sorted({index[key] for key in index if key[0] == 0})
    # The consistent nodal forces of a uniform traction on the right edge: linear edges
    # give their ends half the edge's force each, quadratic ones 1/6, 2/3, 1/6.
    edge = {}
    for j in range(0, m, 2 if quadratic else 1):
        if quadratic:
            weights = {(m, j): 1 / 6, (m, j + 1): 4 / 6, (m, j + 2): 1 / 6}
        else:
            weights = {(m, j): 0.5, (m, j + 1): 0.5}
        for key, weight in weights.items():
            for k in layers:
                node = index[key + (k,)]
                edge[node] = edge.get(node, 0.0) + weight * FORCE / n / len(layers)
    return points, cells, clamp, edge, index[(m, m, 0)]


def tensormass_tip(binary, work, element, split, n):
    """The tip's vertical displacement and the run's cells and dofs."""
    points, cells, clamp, edge, tip = panel_mesh(element, n)
    stem = os.path.join(work, f"{element}_{split}_{n}")
    loads = sorted(set(round(f, 12) for f in edge.values()))
    groups = [("clamp", clamp)] + [(f"load_{k}", [node for node, f in edge.items() if round(f, 12) == load])
                                   for k, load in enumerate(loads)]
    plane = ""
    if element in SOLIDS:  # u_z = 0 at every node: plane strain
        fixed = set(clamp)
        groups.append(("plane", [node for node in range(len(points)) if node not in fixed]))
        plane = "\nprescribed: [{region: plane, displacement: [null, null, 0]}]"
    write_msh(stem + ".msh", points, element, cells, groups)
    forces = ", ".join(f"{{region: load_{k}, force: [0, {f!r}, 0]}}" for k, f in enumerate(loads))
    scene = (f"mesh: {stem}.msh\n"
             f"materials: [{{region: all, law: hooke, young: {YOUNG}, poisson: {POISSON}, density: 1, split: {split}}}]\n"
             f"fixed: [clamp]{plane}\n"
             f"loads: {{nodal_forces: [{forces}]}}\n"
             f"solver: {{type: static}}\n"
             f"output: {{directory: {stem}_out}}\n")
    displacement, summary = run_tensormass(binary, stem, scene, "cooks_membrane")
    return {"tip": float(displacement[tip][1]), "cells": summary["elements"], "dofs": summary["dofs"]}


def calculix_tip(work, n, ccx):
    """CalculiX CPE8 on the n x n quad8 mesh: the tip's vertical displacement."""
    points, cells, clamp, edge, tip = panel_mesh("quad8", n)
    deck = ["*NODE, NSET=NALL"] + [f"{i + 1}, {x!r}, {y!r}" for i, (x, y, _) in enumerate(points)]
    deck += ["*ELEMENT, TYPE=CPE8, ELSET=EALL"] + [f"{e + 1}, " + ", ".join(str(c + 1) for c in cell)
                                                 for e, cell in enumerate(cells)]
    deck += ["*NSET, NSET=CLAMP"] + [str(node + 1) for node in clamp]
    deck += ["*BOUNDARY", "CLAMP, 1, 2", "*MATERIAL, NAME=M", "*ELASTIC", f"{YOUNG!r}, {POISSON!r}",
             "*SOLID SECTION, ELSET=EALL, MATERIAL=M", "1.0", "*STEP", "*STATIC", "*CLOAD"]
    deck += [f"{node + 1}, 2, {force!r}" for node, force in sorted(edge.items())]
    deck += ["*NSET, NSET=TIP", str(tip + 1), "*NODE PRINT, NSET=TIP", "U", "*END STEP"]
    directory = tempfile.mkdtemp(dir=work)
    with open(os.path.join(directory, "cook.inp"), "w", encoding="utf-8") as handle:
        handle.write("\n".join(deck) + "\n")
    run = subprocess.run([ccx, "cook"], cwd=directory, capture_output=True, text=True,
                         env=dict(os.environ, OMP_NUM_THREADS="1"))
    dat = os.path.join(directory, "cook.dat")
    if run.returncode != 0 or not os.path.exists(dat):
        sys.exit(f"cooks_membrane: ccx exited {run.returncode}: {run.stdout[-2000:]}")
    with open(dat, encoding="utf-8") as handle:
        rows = [line.split() for line in handle if re.match(r"^\s+\d+\s+[-+0-9.E]+\s+[-+0-9.E]+", line)]
    values = [row for row in rows if int(row[0]) == tip + 1]
    if not values:
        sys.exit(f"cooks_membrane: no displacement of node {tip + 1} in {dat}")
    return {"tip": float(values[-1][2]), "cells": len(cells), "dofs": 2 * len(points)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="build/tensormass")
    parser.add_argument("--ccx", default=os.environ.get("TENSORMASS_CCX", "ccx"))
    parser.add_argument("--json", help="write the rows here")
    parser.add_argument("--quick", action="store_true", help="N = 2 and 4, the reference on 8 x 8 quad8")
    parser.add_argument("--work", help="a directory for meshes and runs (default: a temporary one)")
    args = parser.parse_args()
    binary = os.path.abspath(args.binary)
    if not shutil.which(args.ccx):
        sys.exit(f"cooks_membrane: no CalculiX executable '{args.ccx}' (install calculix-ccx: scripts/install-deps.sh, "
                 "or give --ccx PATH)")
    sizes = QUICK_SIZES if args.quick else SIZES
    reference_sizes = QUICK_REFERENCE_SIZES if args.quick else REFERENCE_SIZES
    with tempfile.TemporaryDirectory() as scratch:
        work = os.path.abspath(args.work or scratch)
        os.makedirs(work, exist_ok=True)
        references = []
        for size in reference_sizes:
            references.append(dict(calculix_tip(work, size, args.ccx), size=size))
            print(f"CalculiX CPE8 {size} x {size}: tip {references[-1]['tip']:.4f}", flush=True)
        reference = references[-1]
        rows = []
        for label, element, split in VARIANTS:
            for n in sizes:
                row = tensormass_tip(binary, work, element, split, n)
                row.update(label=label, element=element, split=split, size=n,
                           ratio=row["tip"] / reference["tip"])
                rows.append(row)
                print(f"{label:10} {n:3} x {n:<3} tip {row['tip']:.4f}  {row['ratio']:.4f} of the reference",
                      flush=True)
    result = {
        "metadata": metadata(binary),
        "settings": {"young": YOUNG, "poisson": POISSON, "force": FORCE, "sizes": sizes, "quick": args.quick},
        "reference": reference,
        "calculix": references,
        "rows": rows,
    }
    if args.json:
        write_result(args.json, result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
