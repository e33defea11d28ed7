"""Stage 4 (lower), elements: the reference-element facts elements.cpp prints.

Input: an `ElementSpec` and its `ElementTables`.
Output: an `ElementIR`: numbers as floats, tables flattened, face offsets and
the (load-validated, uniform) edge size computed.
"""
from __future__ import annotations

import itertools

from .ir import ElementIR
from .model import ElementSpec, ElementTables


def lower_element(element: ElementSpec, tables: ElementTables) -> ElementIR:
    face_sizes = [len(face) for face in element.faces]
    return ElementIR(
        name=element.name,
        description=element.description,
        dim=element.dim,
        order=element.order,
        node_count=element.node_count,
        vtk=element.vtk,
        gmsh=element.gmsh,
        calculix=element.calculix,
        edges=element.edges,
        edge_size=len(element.edges[0]),
        faces=element.faces,
        face_offsets=tuple(itertools.accumulate(face_sizes, initial=0))[:-1],
        reference_nodes=tuple(float(x) for node in element.nodes for x in node),
        weights=tables.weights,
        shape_values=tuple(v for row in tables.shape_values for v in row),
        corner_count=element.corner_count,
        reference_volume=float(element.reference_volume),
        shape_gradients=tuple(v for point in tables.reference_gradients for node in point for v in node),
        corner_gradients=tuple(v for corner in tables.corner_gradients for node in corner for v in node),
    )
