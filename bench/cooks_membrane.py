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
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

import meshio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_metadata import metadata  # noqa: E402

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


def grid_mesh(element, n):
    """(points, cells, clamp nodes, right-edge nodes with their share of the force, tip node) of an n x n mesh.

    Points are 3D; quad8 takes the mid-edge nodes of a (2n+1) x (2n+1) grid,
    the 3D elements a second layer at z = 1."""
    quadratic = element == "quad8"
    m = 2 * n if quadratic else n
    index, points = {}, []
    layers = (0, 1) if element in ("hex8", "tet4") else (0,)
    for k in layers:
        for j in range(m + 1):
            for i in range(m + 1):
                if quadratic and i % 2 == 1 and j % 2 == 1:
                    continue  # no centre node
                x, y = point(i / m, j / m)
                index[(i, j, k)] = len(points)
                points.append((x, y, float(k)))
    cells = []
    for j in range(n):
        for i in range(n):
            if quadratic:
                a, b = 2 * i, 2 * j
                corners = [(a, b), (a + 2, b), (a + 2, b + 2), (a, b + 2)]
                mids = [(a + 1, b), (a + 2, b + 1), (a + 1, b + 2), (a, b + 1)]
                cells.append([index[c + (0,)] for c in corners + mids])
                continue
            square = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            if element == "quad4":
                cells.append([index[c + (0,)] for c in square])
            elif element == "tri3":
                q = [index[c + (0,)] for c in square]
                cells += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
            else:
                h = [index[c + (0,)] for c in square] + [index[c + (1,)] for c in square]
                if element == "hex8":
                    cells.append(h)
                else:  # six tets around the diagonal h0-h6 (Kuhn): conforming when every cube is cut alike
                    for path in ((1, 2), (2, 3), (3, 7), (7, 4), (4, 5), (5, 1)):
                        cells.append([h[0], h[path[0]], h[path[1]], h[6]])
    clamp = sorted({index[key] for key in index if key[0] == 0})
    # The consistent nodal forces of a uniform traction on the right edge: linear edges
    # give their ends half the edge's force each, quadratic ones 1/6, 2/3, 1/6.
    edge = {}
    for j in range(m):
        ends = [(m, j), (m, j + 1)]
        if quadratic:
            if j % 2 == 1:
                continue
            ends = [(m, j), (m, j + 2)]
            weights = {(m, j): 1 / 6, (m, j + 1): 4 / 6, (m, j + 2): 1 / 6}
        else:
            weights = {ends[0]: 0.5, ends[1]: 0.5}
        share = FORCE / n
        for key, weight in weights.items():
            for k in layers:
                edge[index[key + (k,)]] = edge.get(index[key + (k,)], 0.0) + weight * share / len(layers)
    tip = index[(m, m, 0)]
    return points, cells, clamp, edge, tip


GMSH_TYPES = {"quad4": 3, "tri3": 2, "hex8": 5, "tet4": 4, "quad8": 16}


def write_msh(path, points, cells, element, clamp, edge):
    """Gmsh 2.2 ASCII: the cells, and node groups `clamp`, one `load_<k>` per
    distinct nodal force and, in 3D, `plane` (every node but the clamp's)."""
    loads = sorted(set(round(f, 12) for f in edge.values()))
    names = ["clamp"] + [f"load_{k}" for k in range(len(loads))] + (["plane"] if element in ("hex8", "tet4") else [])
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    lines += [f'0 {t + 1} "{name}"' for t, name in enumerate(names)]
    lines += ["$EndPhysicalNames", "$Nodes", str(len(points))]
    lines += [f"{i + 1} {x!r} {y!r} {z!r}" for i, (x, y, z) in enumerate(points)]
    groups = [(1, node) for node in clamp] + [(2 + loads.index(round(f, 12)), node) for node, f in edge.items()]
    if "plane" in names:
        fixed = set(clamp)
        groups += [(len(names), node) for node in range(len(points)) if node not in fixed]
    lines += ["$EndNodes", "$Elements", str(len(groups) + len(cells))]
    number = 0
    for tag, node in groups:
        number += 1
        lines.append(f"{number} 15 2 {tag} {tag} {node + 1}")
    volume_tag = len(names) + 1
    for cell in cells:
        number += 1
        lines.append(f"{number} {GMSH_TYPES[element]} 2 {volume_tag} {volume_tag} {' '.join(str(c + 1) for c in cell)}")
    lines.append("$EndElements")
    with open(path, "w", encoding="utf-8") as handle:
        handle.write("\n".join(lines) + "\n")
    return loads


def tensormass_tip(binary, work, element, split, n):
    """The tip's vertical displacement and the run's cells and dofs."""
    points, cells, clamp, edge, tip = grid_mesh(element, n)
    stem = os.path.join(work, f"{element}_{split}_{n}")
    loads = write_msh(stem + ".msh", points, cells, element, clamp, edge)
    forces = ", ".join(f"{{region: load_{k}, force: [0, {f!r}, 0]}}" for k, f in enumerate(loads))
    plane = "\nprescribed: [{region: plane, displacement: [null, null, 0]}]" if element in ("hex8", "tet4") else ""
    scene = (f"mesh: {stem}.msh\n"
             f"materials: [{{region: all, law: hooke, young: {YOUNG}, poisson: {POISSON}, density: 1, split: {split}}}]\n"
             f"fixed: [clamp]{plane}\n"
             f"loads: {{nodal_forces: [{forces}]}}\n"
             f"solver: {{type: static}}\n"
             f"output: {{directory: {stem}_out}}\n")
    with open(stem + ".yaml", "w", encoding="utf-8") as handle:
        handle.write(scene)
    run = subprocess.run([binary, "run", "--quiet", stem + ".yaml"], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"cooks_membrane: {binary} run {stem}.yaml exited {run.returncode}: {run.stderr}")
    result = meshio.read(os.path.join(stem + "_out", "final.vtu"))
    with open(os.path.join(stem + "_out", "summary.json"), encoding="utf-8") as handle:
        summary = json.load(handle)
    return {"tip": float(result.point_data["displacement"][tip][1]), "cells": summary["elements"],
            "dofs": summary["dofs"]}


def calculix_tip(work, n, ccx):
    """CalculiX CPE8 on the n x n quad8 mesh: the tip's vertical displacement."""
    points, cells, clamp, edge, tip = grid_mesh("quad8", n)
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
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump(result, handle, indent=1)
            handle.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
