"""Structured meshes of a mapped square, written as Gmsh 2.2, and one tensormass run: what the
validation benchmarks of nearly incompressible panels (cooks_membrane.py, thick_cylinder.py) share.

A panel is the image of the unit square under a map (xi, eta) -> (x, y); it
is cut into n x n quad4, tri3 (each quad in two) or quad8 cells, or extruded
one unit along z into hex8 or tet4 (each hex8 in six around its diagonal:
conforming when every cell is cut alike) cells.
"""
import json
import os
import subprocess
import sys

import meshio

GMSH_TYPES = {"quad4": 3, "tri3": 2, "hex8": 5, "tet4": 4, "quad8": 16, "line2": 1, "point": 15}
SOLIDS = ("hex8", "tet4")
# The six tets of a hex8 (corners h0..h7) around its diagonal h0-h6.
KUHN = ((1, 2), (2, 3), (3, 7), (7, 4), (4, 5), (5, 1))


def mapped_grid(element, n, point):
    """(points, cells, index) of an n x n mesh of `element` on the panel `point(xi, eta) -> (x, y)`.

    points are (x, y, z); index maps the grid position (i, j, k) to a point,
    i and j from 0 to n (0 to 2n for quad8, which has no centre nodes), k the
    layer (0, and 1 for the solids)."""
    quadratic = element == "quad8"
    m = 2 * n if quadratic else n
    layers = (0, 1) if element in SOLIDS else (0,)
    index, points = {}, []
    for k in layers:
        for j in range(m + 1):
            for i in range(m + 1):
                if quadratic and i % 2 == 1 and j % 2 == 1:
                    continue
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
            q = [index[c + (0,)] for c in square]
            if element == "quad4":
                cells.append(q)
            elif element == "tri3":
                cells += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
            else:
                h = q + [index[c + (1,)] for c in square]
                cells += [h] if element == "hex8" else [[h[0], h[a], h[b], h[6]] for a, b in KUHN]
    return points, cells, index


def write_msh(path, points, element, cells, node_groups=(), facet_groups=()):
    """Gmsh 2.2 ASCII: the cells, node groups [(name, nodes)] as points and
    facet groups [(name, gmsh element name, facets)] (lines in 2D, faces in 3D)."""
    names = [name for name, _ in node_groups] + [name for name, _, _ in facet_groups]
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    lines += [f'0 {t + 1} "{name}"' for t, (name, _) in enumerate(node_groups)]
    dim = 3 if element in SOLIDS else 2
    lines += [f'{dim - 1} {len(node_groups) + t + 1} "{name}"' for t, (name, _, _) in enumerate(facet_groups)]
    lines += ["$EndPhysicalNames", "$Nodes", str(len(points))]
    lines += [f"{i + 1} {x!r} {y!r} {z!r}" for i, (x, y, z) in enumerate(points)]
    rows = [(GMSH_TYPES["point"], t + 1, [node]) for t, (_, nodes) in enumerate(node_groups) for node in nodes]
    rows += [(GMSH_TYPES[kind], len(node_groups) + t + 1, facet)
             for t, (_, kind, facets) in enumerate(facet_groups) for facet in facets]
    rows += [(GMSH_TYPES[element], len(names) + 1, cell) for cell in cells]
    lines += ["$EndNodes", "$Elements", str(len(rows))]
    lines += [f"{number + 1} {kind} 2 {tag} {tag} {' '.join(str(c + 1) for c in nodes)}"
              for number, (kind, tag, nodes) in enumerate(rows)]
    lines.append("$EndElements")
    with open(path, "w", encoding="utf-8") as handle:
        handle.write("\n".join(lines) + "\n")


def run_tensormass(binary, stem, scene, caller):
    """Writes stem.yaml (`scene`, whose output directory must be stem_out), runs it and
    returns (the final displacements, node by 3, and summary.json); exits naming `caller` on failure."""
    with open(stem + ".yaml", "w", encoding="utf-8") as handle:
        handle.write(scene)
    run = subprocess.run([binary, "run", "--quiet", stem + ".yaml"], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"{caller}: {binary} run {stem}.yaml exited {run.returncode}: {run.stderr}")
    result = meshio.read(os.path.join(stem + "_out", "final.vtu"))
    with open(os.path.join(stem + "_out", "summary.json"), encoding="utf-8") as handle:
        summary = json.load(handle)
    return result.point_data["displacement"], summary
