#!/usr/bin/python3
"""Writes the closed test surfaces of the octree mesher tests with Gmsh's
OpenCASCADE kernel (python3-gmsh), as ASCII STL:

  sphere.stl      ball of radius 1, triangles of edge about 0.1
  torus.stl       torus of radii 1 and 0.4, edge about 0.08
  cut_ball.stl    ball of radius 1 cut flat at z = 0.4: patches `round` and `flat`

Usage: make_surfaces.py [OUT_DIR]   (default: this script's folder)
The files are committed; rerun this only to change them."""
import os
import sys

import gmsh


def write_stl(path, patches):
    """patches: list of (name, points dict tag->xyz, triangles as tag triples)."""
    with open(path + ".tmp", "w") as out:
        for name, points, triangles in patches:
            out.write(f"solid {name}\n")
            for t in triangles:
                a, b, c = (points[n] for n in t)
                out.write("facet normal 0 0 0\n outer loop\n")
                for p in (a, b, c):
                    out.write(f"  vertex {p[0]:.12g} {p[1]:.12g} {p[2]:.12g}\n")
                out.write(" endloop\nendfacet\n")
            out.write(f"endsolid {name}\n")
    os.replace(path + ".tmp", path)


def mesh_surfaces(size, names):
    """Meshes the model's surfaces; names: surface tag -> patch name."""
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    gmsh.model.mesh.generate(2)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    points = {int(t): coords[3 * i:3 * i + 3] for i, t in enumerate(tags)}
    by_name = {}
    for _, tag in gmsh.model.getEntities(2):
        _, nodes = gmsh.model.mesh.getElementsByType(2, tag)
        tris = [tuple(int(n) for n in nodes[k:k + 3]) for k in range(0, len(nodes), 3)]
        by_name.setdefault(names.get(tag, "surface"), []).extend(tris)
    return [(name, points, tris) for name, tris in sorted(by_name.items())]


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    shapes = {
        "sphere": (lambda: gmsh.model.occ.addSphere(0, 0, 0, 1), 0.1),
        "torus": (lambda: gmsh.model.occ.addTorus(0, 0, 0, 1, 0.4), 0.08),
        "cut_ball": (lambda: gmsh.model.occ.intersect([(3, gmsh.model.occ.addSphere(0, 0, 0, 1))],
                                                      [(3, gmsh.model.occ.addBox(-2, -2, -2, 4, 4, 2.4))])[0][0][1], 0.1),
    }
    for name, (make, size) in shapes.items():
        gmsh.model.add(name)
        make()
        gmsh.model.occ.synchronize()
        names = {}
        for _, tag in gmsh.model.getEntities(2):
            if name == "cut_ball":
                kind = gmsh.model.getType(2, tag)
                names[tag] = "flat" if kind == "Plane" else "round"
        write_stl(os.path.join(out, name + ".stl"), mesh_surfaces(size, names))
        gmsh.model.remove()
    gmsh.finalize()


if __name__ == "__main__":
    main()
