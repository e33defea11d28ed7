#!/usr/bin/python3
"""Reads a .msh with the Gmsh Python API and meshio and checks it against an expected JSON.

usage: check_msh.py FILE.msh EXPECTED.json
EXPECTED: {"dim": 2|3, "points": [x, y, z, ...] (node tag i+1 = point i),
           "cells": {meshio type name: count},          # distinct cells of dimension dim
           "groups": {name: {"dim": d, "count": n}}}      # distinct elements of the group
Checks: exact coordinates; cell counts per type; each group's dimension and
element count (elements counted once by node set, since format 2.2 repeats an
element once per group); positive Jacobian determinants of every 3D cell at
Gmsh's Gauss points, positive area (counter-clockwise) of every 2D cell;
meshio reads the file with the same cell counts and group names.
Exit 0 on success, 1 otherwise (the reason on stderr).
"""
import json
import sys

import gmsh
import meshio
from meshio.gmsh.common import _gmsh_to_meshio_type as gmsh_to_meshio


def fail(message):
    print("check_msh: " + message, file=sys.stderr)
    sys.exit(1)


def distinct_elements(dim, entities):
    """{meshio type: set of sorted node tuples} of the elements of these entities."""
    found = {}
    for entity in entities:
        types, element_tags, nodes = gmsh.model.mesh.getElements(dim, entity)
        for element_type, tags, flat in zip(types, element_tags, nodes):
            per = len(flat) // len(tags)
            keys = {tuple(sorted(flat[i:i + per])) for i in range(0, len(flat), per)}
            found.setdefault(gmsh_to_meshio[int(element_type)], set()).update(keys)
    return found


def check_points(expected):
    tags, coords, _ = gmsh.model.mesh.getNodes()
    points = expected["points"]
    if len(tags) * 3 != len(points):
        fail("%d nodes, expected %d" % (len(tags), len(points) // 3))
    for tag, index in zip(tags, range(len(tags))):
        tag = int(tag)
        if [float(c) for c in coords[3 * index:3 * index + 3]] != points[3 * (tag - 1):3 * tag]:
            fail("node %d has coordinates %s" % (tag, coords[3 * index:3 * index + 3]))


def check_cells(expected):
    dim = expected["dim"]
    cells = distinct_elements(dim, [tag for _, tag in gmsh.model.getEntities(dim)])
    counts = {name: len(keys) for name, keys in cells.items()}
    if counts != expected["cells"]:
        fail("cells %s, expected %s" % (counts, expected["cells"]))


def check_groups(expected):
    found = {}
    for dim, tag in gmsh.model.getPhysicalGroups():
        entities = gmsh.model.getEntitiesForPhysicalGroup(dim, tag)
        elements = distinct_elements(dim, entities)
        found[gmsh.model.getPhysicalName(dim, tag)] = {"dim": dim, "count": sum(map(len, elements.values()))}
    if found != expected["groups"]:
        fail("groups %s, expected %s" % (found, expected["groups"]))


def check_orientation(expected):
    dim = expected["dim"]
    types, tags, nodes = gmsh.model.mesh.getElements(dim)
    for element_type, flat in zip(types, nodes):
        if dim == 3:
            points, _ = gmsh.model.mesh.getIntegrationPoints(element_type, "Gauss2")
            _, determinants, _ = gmsh.model.mesh.getJacobians(element_type, points)
            if min(determinants) <= 0:
                fail("a %s cell has a non-positive Jacobian" % gmsh_to_meshio[int(element_type)])
        else:
            per = gmsh.model.mesh.getElementProperties(element_type)[3]
            p = expected["points"]
            for i in range(0, len(flat), per):
                a, b, c = (3 * (int(n) - 1) for n in flat[i:i + 3])
                area = (p[b] - p[a]) * (p[c + 1] - p[a + 1]) - (p[c] - p[a]) * (p[b + 1] - p[a + 1])
                if area <= 0:
                    fail("a %s cell is clockwise" % gmsh_to_meshio[int(element_type)])


def check_meshio(path, expected):
    mesh = meshio.read(path)
    counts = {}
    for block in mesh.cells:
        if block.dim == expected["dim"]:
            counts[block.type] = counts.get(block.type, 0) + len(block.data)
    names = set(mesh.field_data)
    if names != set(expected["groups"]):
        fail("meshio sees groups %s" % sorted(names))
    return counts


def main():
    path, expected = sys.argv[1], json.load(open(sys.argv[2]))
    gmsh.initialize(["check_msh", "-v", "2"])
    gmsh.open(path)
    check_points(expected)
    check_cells(expected)
    check_groups(expected)
    check_orientation(expected)
    gmsh.finalize()
    counts = check_meshio(path, expected)
    if all(counts.get(name, 0) >= count for name, count in expected["cells"].items()):
        print("check_msh: %s matches (%s)" % (path, expected["cells"]))
    else:
        fail("meshio cells %s" % counts)


main()
