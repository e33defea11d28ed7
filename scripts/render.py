#!/usr/bin/python3
"""Draws a tensormass result (.vtu) to a PNG image.

    render.py FRAME.vtu -o IMAGE.png [--field NAME] [--deformed | --rest]
              [--width PX] [--title TEXT]

2D meshes are drawn cell by cell, 3D meshes by their boundary surface (faces
used by exactly one cell), at the deformed positions (rest + displacement)
by default. Colours: the cell array `state` when present (normalised
criterion from green, 0, to red, 1 = at the threshold; 2 = switched law, in
blue), else `law_id` (law names from the summary.json next to the file);
--field picks any cell array or a point array such as `displacement` (its
magnitude). Quadratic cells are drawn by their corners.

Exit status: 0 image written, 2 bad input (unreadable file, missing field;
nothing is written), 1 anything else. `tensormass render` runs this script.
"""
import argparse
import contextlib
import io
import json
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.colors import LinearSegmentedColormap, Normalize, to_rgba  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

# meshio cell type -> (corner count, boundary faces as corner indices in the
# VTK cell definitions, or None for a 2D cell).
CELLS = {
    "triangle": (3, None), "triangle6": (3, None),
    "quad": (4, None), "quad8": (4, None), "quad9": (4, None),
    "tetra": (4, [(0, 1, 3), (1, 2, 3), (2, 0, 3), (0, 2, 1)]),
    "hexahedron": (8, [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)]),
    "wedge": (6, [(0, 1, 2), (3, 5, 4), (0, 3, 4, 1), (1, 4, 5, 2), (2, 5, 3, 0)]),
    "pyramid": (5, [(0, 3, 2, 1), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]),
}
for quadratic, linear in (("tetra10", "tetra"), ("hexahedron20", "hexahedron"), ("hexahedron27", "hexahedron"),
                          ("wedge15", "wedge"), ("wedge18", "wedge"), ("pyramid13", "pyramid"),
                          ("pyramid14", "pyramid")):
    CELLS[quadratic] = CELLS[linear]

LAW_LABELS = {"hooke": "Hooke", "stvk": "StVK", "neohookean": "neo-Hookean"}
STATE_MAP = LinearSegmentedColormap.from_list("state", ["#1a9850", "#fee000", "#d73027"])
SWITCHED = "#2b6cc4"
EDGE = "#3a3a3a"


class BadInput(Exception):
    """Exit 2: the message names the file or field."""


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="tensormass render", description=__doc__.split("\n\n")[0])
    parser.add_argument("frame", help="a .vtu written by tensormass run")
    parser.add_argument("-o", "--output", required=True, help="the PNG to write")
    parser.add_argument("--field", help="cell array (state, law_id, R_EL, ...) or point array (displacement)")
    shape = parser.add_mutually_exclusive_group()
    shape.add_argument("--deformed", dest="deformed", action="store_true", default=None,
                       help="rest + displacement (the default)")
    shape.add_argument("--rest", dest="deformed", action="store_false", help="rest positions")
    parser.add_argument("--width", type=int, default=1600, help="image width in pixels (default 1600)")
    parser.add_argument("--title", help="replaces the generated title")
    args = parser.parse_args(argv)
    if not 100 <= args.width <= 20000:
        parser.error(f"--width {args.width}: expected 100 to 20000 pixels")
    return args


def read_result(path):
    import meshio  # late: its import is slow and a bad command line needs none of it

    if not os.path.isfile(path):
        raise BadInput(f"{path}: no such file")
    try:
        with contextlib.redirect_stdout(sys.stderr):  # meshio prints its reader errors
            mesh = meshio.read(path)
    except (Exception, SystemExit) as error:  # meshio raises many kinds, or exits
        detail = "" if isinstance(error, SystemExit) else f" ({error})"
        raise BadInput(f"{path}: not a readable mesh file{detail}") from None
    blocks = [block for block in mesh.cells if block.type in CELLS]
    if not blocks:
        raise BadInput(f"{path}: no cells to draw")
    return mesh, blocks


def cell_array(mesh, name):
    """The named cell array over the drawn blocks (magnitude if it has components), or None."""
    if name not in mesh.cell_data:
        return None
    parts = [np.asarray(data, dtype=float) for block, data in zip(mesh.cells, mesh.cell_data[name])
             if block.type in CELLS]
    values = np.concatenate([p.reshape(len(p), -1) for p in parts])
    return values[:, 0] if values.shape[1] == 1 else np.linalg.norm(values, axis=1)


def law_names(path):
    """law_id -> name from the summary.json beside the file, or {}."""
    summary = os.path.join(os.path.dirname(os.path.abspath(path)), "summary.json")
    try:
        with open(summary, encoding="utf-8") as stream:
            return {int(key): str(value) for key, value in json.load(stream)["law_ids"].items()}
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return {}


def geometry(mesh, blocks, deformed):
    """Polygons (corner node lists), the cell of each, and the node positions."""
    points = np.asarray(mesh.points, dtype=float)
    points = np.pad(points, ((0, 0), (0, 3 - points.shape[1])))
    if deformed:
        points = points + np.asarray(mesh.point_data["displacement"], dtype=float)[:, :3]
    volume = any(CELLS[b.type][1] for b in blocks)
    faces, owners, first = {}, {}, 0
    for block in blocks:
        corners, local_faces = CELLS[block.type]
        nodes = np.asarray(block.data)[:, :corners]
        cells = first + np.arange(len(nodes))
        first += len(nodes)
        if not volume:
            faces.setdefault(corners, []).append(nodes)
            owners.setdefault(corners, []).append(cells)
            continue
        for face in local_faces or ():
            faces.setdefault(len(face), []).append(nodes[:, face])
            owners.setdefault(len(face), []).append(cells)
    polygons, polygon_cells = [], []
    for size, parts in faces.items():
        nodes, cells = np.concatenate(parts), np.concatenate(owners[size])
        if volume:  # keep the faces that exactly one cell uses
            _, index, counts = np.unique(np.sort(nodes, axis=1), axis=0, return_index=True, return_counts=True)
            keep = np.sort(index[counts == 1])
            nodes, cells = nodes[keep], cells[keep]
        polygons.extend(nodes)
        polygon_cells.append(cells)
    return polygons, np.concatenate(polygon_cells), points, volume


def colouring(mesh, blocks, field, path):
    """Face colouring: ('state'|'law'|'cell'|'point', values, label, title counts)."""
    cells = sum(len(b.data) for b in blocks)
    if field is None:
        field = "state" if "state" in mesh.cell_data else "law_id" if "law_id" in mesh.cell_data else None
        if field is None:
            return "none", None, "", f"{cells} elements"
    values = cell_array(mesh, field)
    if values is not None:
        if field == "state":
            switched = int(np.count_nonzero(np.isclose(values, 2.0)))
            return "state", values, "state", f"{cells} elements, {switched} switched"
        if field == "law_id":
            names = law_names(path)
            ids, counts = np.unique(values[np.isfinite(values)].astype(int), return_counts=True)
            parts = ", ".join(f"{c} {names.get(i, f'law {i}')}" for i, c in zip(ids, counts))
            return "law", values, "law", f"{cells} elements ({parts})"
        finite = values[np.isfinite(values)]
        span = f", {finite.min():.4g} to {finite.max():.4g}" if finite.size else ""
        return "cell", values, field, f"{cells} elements{span}"
    if field in mesh.point_data:
        data = np.asarray(mesh.point_data[field], dtype=float).reshape(len(mesh.points), -1)
        values = data[:, 0] if data.shape[1] == 1 else np.linalg.norm(data, axis=1)
        label = field if data.shape[1] == 1 else f"|{field}|"
        return "point", values, label, f"{cells} elements, max {label} {np.nanmax(values):.4g}"
    available = sorted(set(mesh.cell_data) | set(mesh.point_data))
    raise BadInput(f"{path}: no cell or point array '{field}' (available: {', '.join(available)})")


def value_range(values):
    """Normalize over the finite values (a unit range when they are all equal)."""
    finite = values[np.isfinite(values)]
    low, high = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
    return Normalize(low, high if high > low else low + 1.0)


def face_colours(mesh, kind, values, polygon_cells, polygons, path):
    """RGBA per polygon, and the legend pieces: (ScalarMappable or None, patches)."""
    if kind == "none":
        return np.tile(to_rgba("#c8c8c8"), (len(polygons), 1)), None, []
    if kind == "point":
        mappable = plt.cm.ScalarMappable(value_range(values), plt.cm.viridis)
        return mappable.to_rgba(np.array([values[p].mean() for p in polygons])), mappable, []
    per_face = values[polygon_cells]
    if kind == "state":
        switched = np.isclose(per_face, 2.0)
        mappable = plt.cm.ScalarMappable(Normalize(0.0, 1.0), STATE_MAP)
        colours = mappable.to_rgba(np.clip(per_face, 0.0, 1.0))
        colours[switched] = to_rgba(SWITCHED)
        colours[~np.isfinite(per_face)] = to_rgba("#c8c8c8")
        names = law_names(path)
        law = cell_array(mesh, "law_id")
        targets = sorted({names.get(int(i), "") for i in law[np.isclose(values, 2.0)]}) if law is not None else []
        target = " / ".join(LAW_LABELS.get(t, t) for t in targets if t) or "StVK"
        return colours, mappable, [Patch(facecolor=SWITCHED, edgecolor=EDGE, label=f"switched to {target}")]
    if kind == "law":
        names = law_names(path)
        ids = sorted({int(i) for i in values[np.isfinite(values)]})
        palette = {i: plt.cm.tab10(i % 10) for i in ids}  # by id: the same colours in every frame
        colours = np.array([palette.get(int(v), to_rgba("#c8c8c8")) if np.isfinite(v) else to_rgba("#c8c8c8")
                            for v in per_face])
        patches = [Patch(facecolor=palette[i], edgecolor=EDGE,
                         label=LAW_LABELS.get(names.get(i, ""), names.get(i, f"law {i}"))) for i in ids]
        return colours, None, patches
    mappable = plt.cm.ScalarMappable(value_range(values), plt.cm.viridis)
    colours = mappable.to_rgba(per_face)
    colours[~np.isfinite(per_face)] = to_rgba("#c8c8c8")
    return colours, mappable, []


def shade(colours, polygons, points):
    """Two-sided diffuse lighting from above the viewer."""
    light = np.array([0.35, -0.6, 0.72])
    light /= np.linalg.norm(light)
    normals = np.array([np.cross(points[p[2]] - points[p[0]], points[p[-1]] - points[p[1]]) for p in polygons])
    normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
    normals = normals[:, [0, 2, 1]]  # world (x, y, z) -> plot axes (x, z, y)
    factor = 0.5 + 0.5 * np.abs(normals @ light)
    shaded = colours.copy()
    shaded[:, :3] *= factor[:, None]
    return shaded


def draw(args):
    mesh, blocks = read_result(args.frame)
    has_displacement = "displacement" in mesh.point_data
    if args.deformed and not has_displacement:
        raise BadInput(f"{args.frame}: --deformed needs the point array 'displacement', which it lacks")
    deformed = has_displacement if args.deformed is None else args.deformed
    kind, values, label, counts = colouring(mesh, blocks, args.field, args.frame)
    polygons, polygon_cells, points, volume = geometry(mesh, blocks, deformed)
    colours, mappable, patches = face_colours(mesh, kind, values, polygon_cells, polygons, args.frame)

    low, high = points.min(axis=0), points.max(axis=0)
    extent = np.maximum(high - low, 1e-12 * max(np.max(high - low), 1e-300))
    if volume:
        height = 6.0
    else:
        height = float(np.clip(7.6 * extent[1] / extent[0], 1.6, 8.0)) + (1.7 if mappable else 1.0)
    figure = plt.figure(figsize=(8.0, height), dpi=args.width / 8.0, layout="constrained")
    if volume:
        axes = figure.add_subplot(projection="3d")
        faces = [points[p][:, [0, 2, 1]] for p in polygons]  # y up: plot (x, z, y)
        axes.add_collection3d(Poly3DCollection(faces, facecolors=shade(colours, polygons, points),
                                               edgecolors=EDGE, linewidths=0.25))
        centre, half = (low + high) / 2, extent / 2
        axes.set_xlim(centre[0] - half[0], centre[0] + half[0])
        axes.set_ylim(centre[2] + half[2], centre[2] - half[2])  # reversed: keeps the frame right-handed
        axes.set_zlim(centre[1] - half[1], centre[1] + half[1])
        axes.set_box_aspect((extent[0], extent[2], extent[1]), zoom=1.1)
        for axis, size in zip((axes.xaxis, axes.yaxis, axes.zaxis), extent[[0, 2, 1]]):
            axis.set_major_locator(MaxNLocator(int(np.clip(round(8 * size / extent.max()), 2, 5))))
            axis.labelpad = 10
        axes.set_xlabel("x")
        axes.set_ylabel("z")
        axes.set_zlabel("y")
        axes.view_init(elev=22, azim=-58)
    else:
        axes = figure.add_subplot()
        if kind == "point":  # smooth: fan triangles of every polygon, values at the nodes
            triangles = [(p[0], p[k], p[k + 1]) for p in polygons for k in range(1, len(p) - 1)]
            axes.tripcolor(points[:, 0], points[:, 1], triangles, values, shading="gouraud",
                           cmap=mappable.cmap, norm=mappable.norm)
            colours = "none"
        axes.add_collection(PolyCollection([points[p][:, :2] for p in polygons], facecolors=colours,
                                           edgecolors=EDGE, linewidths=0.3))
        margin = 0.03 * max(extent[0], extent[1])
        axes.set_xlim(low[0] - margin, high[0] + margin)
        axes.set_ylim(low[1] - margin, high[1] + margin)
        axes.set_aspect("equal")
        axes.set_xlabel("x")
        axes.set_ylabel("y")
    if mappable is not None:
        bar = figure.colorbar(mappable, ax=axes, orientation="horizontal", shrink=0.55, aspect=40,
                              pad=0.02 if volume else 0.06)
        bar.set_label("criterion / threshold" if kind == "state" else label)
    if patches:
        axes.legend(handles=patches, loc="upper right" if volume else "best", framealpha=0.9)
    position = "deformed" if deformed else "rest"
    axes.set_title(args.title if args.title is not None else
                   f"{os.path.basename(args.frame)}: {label or 'mesh'}, {counts} ({position})")

    buffer = io.BytesIO()  # render fully before touching the output
    figure.savefig(buffer, format="png", dpi=args.width / 8.0)
    with open(args.output, "wb") as stream:
        stream.write(buffer.getvalue())


def main(argv=None):
    args = parse_arguments(argv)
    directory = os.path.dirname(os.path.abspath(args.output))
    try:
        if not os.path.isdir(directory):
            raise BadInput(f"{args.output}: directory {directory} does not exist")
        draw(args)
    except BadInput as error:
        print(f"tensormass: error: render: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
