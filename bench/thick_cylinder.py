#!/usr/bin/python3
"""A pressurised thick cylinder, nearly incompressible, against the closed form (Lamé).

A long cylinder of inner radius a = 1 and outer radius b = 2 under an
internal pressure p = 0.01 E, in plane strain, linear elastic (Hooke,
E = 1000, nu = 0.4999): a quarter of its section, u_y = 0 on y = 0 and
u_x = 0 on x = 0, the pressure on the inner arc (the scene's `pressure`
load). Lamé's solution gives the radial displacement

    u_r(r) = (1 + nu) p a^2 / (E (b^2 - a^2)) ((1 - 2 nu) r + b^2 / r).

Each element type meshes the quarter with N x N cells (radial by
circumferential, mapped from the unit square; tri3 cuts each quad in two,
tet4 each hex8 in six), the 3D meshes one cell thick with u_z = 0 at every
node. For each mesh: u_r at the inner radius over Lamé's, and the largest
error of u_r over the nodes, over Lamé's u_r(a). Each run uses the default
settings but the `split`.

    /usr/bin/python3 bench/thick_cylinder.py --json docs/results/thick_cylinder.json
    /usr/bin/python3 scripts/results/render_thick_cylinder.py docs/results/thick_cylinder.json > docs/results/thick_cylinder.md
    /usr/bin/python3 bench/thick_cylinder.py --quick   # ctest: N = 2 and 4
"""
import argparse
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_metadata import metadata, write_result  # noqa: E402
from mapped_meshes import SOLIDS, mapped_grid, run_tensormass, write_msh  # noqa: E402

INNER, OUTER = 1.0, 2.0
YOUNG, POISSON = 1000.0, 0.4999
PRESSURE = 0.01 * YOUNG
VARIANTS = [("quad4", "quad4", "whole"), ("quad4 fbar", "quad4", "fbar"), ("tri3", "tri3", "whole"),
            ("tri3 anp", "tri3", "anp"), ("hex8", "hex8", "whole"), ("hex8 fbar", "hex8", "fbar"),
            ("tet4", "tet4", "whole"), ("tet4 anp", "tet4", "anp")]
SIZES = [4, 8, 16, 32, 64]
QUICK_SIZES = [2, 4]


def lame(r):
    """Lamé's radial displacement at radius r (plane strain)."""
    return ((1 + POISSON) * PRESSURE * INNER ** 2 / (YOUNG * (OUTER ** 2 - INNER ** 2)) *
            ((1 - 2 * POISSON) * r + OUTER ** 2 / r))


def point(xi, eta):
    """The unit square on the quarter section: xi radial, eta the angle from 0 to pi/2."""
    r, angle = INNER + (OUTER - INNER) * xi, 0.5 * math.pi * eta
    return r * math.cos(angle), r * math.sin(angle)


def inner_facets(element, n, index):
    """The cells' facets on the inner arc (i = 0): lines in 2D; quads, or the two
    triangles the hex8's cut leaves on that face, in 3D."""
    if element not in SOLIDS:
        return "line2", [[index[(0, j, 0)], index[(0, j + 1, 0)]] for j in range(n)]
    faces = []
    for j in range(n):
        h0, h3, h4, h7 = index[(0, j, 0)], index[(0, j + 1, 0)], index[(0, j, 1)], index[(0, j + 1, 1)]
        faces += [[h0, h3, h7, h4]] if element == "hex8" else [[h0, h3, h7], [h0, h7, h4]]
    return ("quad4" if element == "hex8" else "tri3"), faces


def run(binary, work, element, split, n):
    points, cells, index = mapped_grid(element, n, point)
    kind, facets = inner_facets(element, n, index)
    on_x_axis = sorted({node for (i, j, k), node in index.items() if j == 0})  # y = 0: u_y = 0
    on_y_axis = sorted({node for (i, j, k), node in index.items() if j == n})  # x = 0: u_x = 0
    z = ", 0" if element in SOLIDS else ", null"
    groups = [("on_x_axis", on_x_axis), ("on_y_axis", on_y_axis)]
    prescribed = [f"{{region: on_x_axis, displacement: [null, 0{z}]}}", f"{{region: on_y_axis, displacement: [0, null{z}]}}"]
    if element in SOLIDS:  # u_z = 0 at every other node: plane strain
        held = set(on_x_axis) | set(on_y_axis)
        groups.append(("plane", [node for node in range(len(points)) if node not in held]))
        prescribed.append("{region: plane, displacement: [null, null, 0]}")
    stem = os.path.join(work, f"{element}_{split}_{n}")
    write_msh(stem + ".msh", points, element, cells, groups, [("inner", kind, facets)])
    scene = (f"mesh: {stem}.msh\n"
             f"materials: [{{region: all, law: hooke, young: {YOUNG}, poisson: {POISSON}, density: 1, split: {split}}}]\n"
             f"prescribed: [{', '.join(prescribed)}]\n"
             f"loads: {{pressure: [{{region: inner, pressure: {PRESSURE!r}}}]}}\n"
             f"solver: {{type: static}}\n"
             f"output: {{directory: {stem}_out}}\n")
    displacement, summary = run_tensormass(binary, stem, scene, "thick_cylinder")
    worst = 0.0
    for (i, j, k), node in index.items():
        x, y, _ = points[node]
        r = math.hypot(x, y)
        radial = (displacement[node][0] * x + displacement[node][1] * y) / r
        worst = max(worst, abs(radial - lame(r)))
    inner = displacement[index[(0, 0, 0)]][0]  # on y = 0 at r = a, u_r = u_x
    return {"inner": float(inner), "inner_ratio": float(inner) / lame(INNER), "field_error": worst / lame(INNER),
            "cells": summary["elements"], "dofs": summary["dofs"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="build/tensormass")
    parser.add_argument("--json", help="write the rows here")
    parser.add_argument("--quick", action="store_true", help="N = 2 and 4")
    parser.add_argument("--work", help="a directory for meshes and runs (default: a temporary one)")
    args = parser.parse_args()
    binary = os.path.abspath(args.binary)
    sizes = QUICK_SIZES if args.quick else SIZES
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        work = os.path.abspath(args.work or scratch)
        os.makedirs(work, exist_ok=True)
        for label, element, split in VARIANTS:
            for n in sizes:
                row = run(binary, work, element, split, n)
                row.update(label=label, element=element, split=split, size=n)
                rows.append(row)
                print(f"{label:10} {n:3} x {n:<3} u_r(a) {row['inner']:.6f}  {row['inner_ratio']:.4f} of Lame's, "
                      f"field error {row['field_error']:.4f}", flush=True)
    result = {
        "metadata": metadata(binary),
        "settings": {"inner": INNER, "outer": OUTER, "young": YOUNG, "poisson": POISSON, "pressure": PRESSURE,
                     "sizes": sizes, "quick": args.quick, "lame_inner": lame(INNER)},
        "rows": rows,
    }
    if args.json:
        write_result(args.json, result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
