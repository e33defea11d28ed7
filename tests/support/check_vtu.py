#!/usr/bin/python3
"""Reads a .vtu with meshio and compares it exactly with an expected JSON.

usage: check_vtu.py FILE.vtu EXPECTED.json
EXPECTED: {"points": [x, y, z, ...], "cell_types": [vtk type, ...],
           "connectivity": [[node, ...], ...] (VTK order),
           "point_data": {name: {"components": c, "values": [...]}},
           "cell_data": {name: {"components": c, "values": [...]}}}
Exit 0 when everything matches bit for bit, 1 otherwise (the reason on stderr).
"""
import json
import sys

import meshio
import numpy
from meshio._vtk_common import meshio_to_vtk_order, vtk_to_meshio_type


def fail(message):
    print("check_vtu: " + message, file=sys.stderr)
    sys.exit(1)


def flat(array):
    return [float(v) for v in array.reshape(-1)]


def check_cells(mesh, expected):
    types, connectivity = [], []
    for block in mesh.cells:
        types += [block.type] * len(block.data)
        order = meshio_to_vtk_order(block.type)  # meshio turns VTK wedges into Gmsh's order
        data = block.data if order is None else block.data[:, order]
        connectivity += [list(map(int, row)) for row in data]
    wanted = [vtk_to_meshio_type[t] for t in expected["cell_types"]]
    if types != wanted:
        fail("cell types differ: %s... vs %s..." % (types[:5], wanted[:5]))
    if connectivity != expected["connectivity"]:
        fail("connectivity differs")


def check_data(name, arrays, expected, count):
    for field, want in expected.items():
        if field not in arrays:
            fail("missing %s field %s (have %s)" % (name, field, list(arrays)))
        data = arrays[field]
        components = 1 if data.ndim == 1 else data.shape[1]
        if len(data) != count or components != want["components"]:
            fail("%s field %s has shape %s" % (name, field, data.shape))
        if flat(data) != want["values"]:
            fail("%s field %s values differ" % (name, field))


def main():
    mesh = meshio.read(sys.argv[1])
    expected = json.load(open(sys.argv[2]))
    if flat(mesh.points) != expected["points"]:
        fail("points differ")
    check_cells(mesh, expected)
    check_data("point", mesh.point_data, expected["point_data"], len(mesh.points))
    cell_data = {name: numpy.concatenate(blocks) for name, blocks in mesh.cell_data.items()}
    check_data("cell", cell_data, expected["cell_data"], len(expected["cell_types"]))
    print("check_vtu: %s matches (%d points, %d cells)" % (sys.argv[1], len(mesh.points), len(expected["cell_types"])))


main()
