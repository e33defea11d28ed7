"""Regenerates the test meshes of tests/runtime/io and tests/runtime/mesh from the .geo files.

Run through make_meshes.sh (Debian's python3 with python3-gmsh and meshio).
Every mesh is generated once and written by Gmsh in four encodings
(MSH 2.2 and 4.1, ASCII and binary); expected.json records what Gmsh itself
reports about it (element counts per type, nodes, groups), computed through
the Gmsh API, plus the exact volume of the geometry. A few meshes are also
converted by meshio to VTU (XML) and legacy VTK files.
"""
import json
import os
import sys

import gmsh
import meshio
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

# Gmsh element type -> tensormass element name (cells and facets).
OUR_NAMES = {2: "tri3", 3: "quad4", 4: "tet4", 5: "hex8", 6: "prism6", 7: "pyramid5",
             9: "tri6", 11: "tet10", 16: "quad8", 17: "hex20"}

# (geo file, dimension, orders, exact volume or area)
MESHES = [
    ("box_tet", 3, (1, 2), 0.2),
    ("box_hex", 3, (1, 2), 0.2),
    ("plate2d", 2, (1, 2), 3.0),
    ("hybrid", 3, (1,), 1.0),
]

ENCODINGS = {  # suffix -> (MshFileVersion, Binary)
    "msh22": (2.2, 0), "msh22b": (2.2, 1), "msh41": (4.1, 0), "msh41b": (4.1, 1),
}


def element_nodes(dim, tag=-1):
    """Unique node tags of the elements of entity (dim, tag) (all entities of dim if tag < 0)."""
    _, _, node_tags = gmsh.model.mesh.getElements(dim, tag)
    return set(int(n) for block in node_tags for n in block)


def element_counts(dim, tag=-1):
    types, tags, _ = gmsh.model.mesh.getElements(dim, tag)
    return {int(t): len(e) for t, e in zip(types, tags)}


def expected_for(dim, volume):
    cells = {OUR_NAMES[t]: n for t, n in element_counts(dim).items()}
    groups = {}
    for gdim, gtag in gmsh.model.getPhysicalGroups():
        name = gmsh.model.getPhysicalName(gdim, gtag) or str(gtag)
        nodes, ncells, nfacets = set(), 0, 0
        for entity in gmsh.model.getEntitiesForPhysicalGroup(gdim, gtag):
            nodes |= element_nodes(gdim, entity)
            count = sum(element_counts(gdim, entity).values())
            ncells += count if gdim == dim else 0
            nfacets += count if gdim == dim - 1 else 0
        groups[name] = {"tag": gtag, "dim": gdim, "nodes": len(nodes), "cells": ncells, "facets": nfacets}
    return {"dim": dim, "nodes": len(element_nodes(dim)), "cells": cells, "volume": volume, "groups": groups}


def generate(geo, dim, order):
    gmsh.clear()
    gmsh.open(os.path.join(HERE, geo + ".geo"))
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1)
    gmsh.model.mesh.generate(dim)
    if order == 2:
        gmsh.model.mesh.setOrder(2)


def write_encodings(stem):
    for suffix, (version, binary) in ENCODINGS.items():
        gmsh.option.setNumber("Mesh.MshFileVersion", version)
        gmsh.option.setNumber("Mesh.Binary", binary)
        gmsh.write(os.path.join(HERE, f"{stem}.{suffix}.msh"))


def vtk_mesh(stem):
    """meshio's reading of the 4.1 file, keeping only the gmsh:physical cell array."""
    mesh = meshio.read(os.path.join(HERE, f"{stem}.msh41.msh"))
    # meshio keeps Gmsh's prism orientation for its "wedge" and converts it to
    # VTK's (nodes 1-2 and 4-5 swapped) itself when writing VTK files.
    cells = [(block.type, block.data) for block in mesh.cells]
    physical = [np.asarray(a, dtype=np.int32) for a in mesh.cell_data["gmsh:physical"]]
    return meshio.Mesh(mesh.points, cells, cell_data={"gmsh:physical": physical})


def write_vtk(stem, variants):
    mesh = vtk_mesh(stem)
    for name, kwargs in variants:
        path = os.path.join(HERE, f"{stem}.{name}")
        if name.endswith(".vtu"):
            meshio.vtu.write(path, mesh, **kwargs)
        else:
            meshio.vtk.write(path, mesh, **kwargs)


# (stem, [(file suffix, meshio writer arguments)])
VTK_FILES = [
    ("box_tet_o2", [("ascii.vtu", {"binary": False})]),
    ("box_tet_o1", [("v51b.vtk", {"binary": True, "fmt_version": "5.1"})]),
    ("plate2d_o1", [("b64u64.vtu", {"binary": True, "compression": None, "header_type": "UInt64"})]),
    ("plate2d_o2", [("v42.vtk", {"binary": False, "fmt_version": "4.2"})]),
    ("hybrid_o1", [("b64.vtu", {"binary": True, "compression": None}),
                   ("v42b.vtk", {"binary": True, "fmt_version": "4.2"})]),
    ("box_hex_o2", [("v51.vtk", {"binary": False, "fmt_version": "5.1"})]),
]


def main():
    gmsh.initialize(["-v", "2"])
    gmsh.option.setNumber("General.Terminal", 1)
    expected = {}
    for geo, dim, orders, volume in MESHES:
        for order in orders:
            stem = f"{geo}_o{order}"
            generate(geo, dim, order)
            write_encodings(stem)
            expected[stem] = expected_for(dim, volume)
    gmsh.finalize()
    for stem, variants in VTK_FILES:
        write_vtk(stem, variants)
    with open(os.path.join(HERE, "expected.json"), "w") as out:
        json.dump(expected, out, indent=1, sort_keys=True)
        out.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
