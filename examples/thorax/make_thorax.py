#!/usr/bin/python3
"""Writes the synthetic thorax of the demo as closed ASCII STL surfaces.

    make_thorax.py [--out DIR] [--edge L]

No patient data: every surface is built procedurally (numpy only) and the
output is byte-stable (the same bytes for the same arguments on a given
platform). Coordinates are metres: x left-right (patient's left at -x, so
the right lung is at x > 0), y anterior-posterior, z cranio-caudal (head at
+z); z = 0 is the lowest point of the pleural cavity (the costophrenic
recesses), where the diaphragm meets the ribs.

Files written in DIR (default: the directory of this script):

  thorax.stl      the pleural cavity (the inner surface of the rib cage),
                  28 x 18 x 24 cm, in three named solids that share their
                  border vertices exactly:
                    apex       the top cap, z > 0.8 * height (fully fixed)
                    ribs       the lateral wall (held in x, y; slides in z)
                    diaphragm  the bottom, a shallow upward dome (driven in z)
  lung_left.stl   the lungs: the cavity shrunk by a margin and cut at
  lung_right.stl  x = -/+ 3 cm (the mediastinum between them), edges rounded
  tumour.stl      a sphere of radius 1.5 cm in the lower right lung
  thorax.json     the tumour's centre and radius, the suggested region of
                  interest, bounding boxes, volumes and triangle counts

The cavity is a surface of parallel rings: each horizontal section is an
inward offset of one stadium (a 10 cm segment along x thickened by 9 cm),
and a profile curve in the (offset, z) plane runs from the ridge of the
diaphragm dome down to the costophrenic rim, up the wall and over the
rounded top to the top ridge. Parallel offsets keep the spacing between
rings the same all around, so the triangles stitched between rings are
close to equilateral with edges about L, and the patch borders are rings.
The lungs are geodesic spheres projected along rays onto their implicit
surface and smoothed; the tumour is a geodesic sphere.

Self-check (on the files as written, read back): every edge shared by
exactly two triangles with opposite orientations, positive signed volume,
sensible volumes, no degenerate or folded triangles, no self-intersection,
lungs strictly inside the cavity, disjoint, and the tumour strictly inside
the right lung (ray-parity inside test of every vertex, plus an exact
edge-triangle intersection test between the surfaces). Exit status: 0 all
checks passed, 1 a check failed, 2 bad arguments.
"""
import argparse
import json
import math
import os
import sys

import numpy as np

# ---------------------------------------------------------------- geometry
WIDTH = 0.28        # x extent of the cavity (m)
DEPTH = 0.18        # y extent
HEIGHT = 0.24       # z extent, from the costophrenic rim (z = 0) to the top
DOME = 0.03         # rise of the diaphragm's ridge above the rim
TOP_ROUND = 0.10    # height of the rounded top (quarter ellipse in the profile)
APEX_FRACTION = 0.8  # the apex patch is z > APEX_FRACTION * HEIGHT

MEDIASTINUM = 0.06  # gap between the lungs (x in [-0.03, 0.03])
LUNG_MARGIN = 0.005  # lungs stay this far inside the cavity
LUNG_ROUND = 0.015  # radius rounding the lungs' medial edges

TUMOUR_CENTRE = (0.07, 0.0, 0.3 * HEIGHT)
TUMOUR_RADIUS = 0.015
ROI_RADIUS = 3 * TUMOUR_RADIUS  # suggested mesher region of interest around the tumour

HALF_LENGTH = (WIDTH - DEPTH) / 2  # the stadium's straight half-length (along x)
RADIUS = DEPTH / 2                 # the stadium's radius = the largest inward offset
Z_WALL = HEIGHT - TOP_ROUND        # top of the vertical wall
Z_APEX = APEX_FRACTION * HEIGHT    # apex / ribs border
BASE_PERIMETER = 4 * HALF_LENGTH + 2 * math.pi * RADIUS

DECIMALS = 7  # coordinates written to 0.1 micrometre


class CheckFailed(Exception):
    pass


# ---------------------------------------------------------------- profile
def dome_z(offset):
    """Height of the diaphragm at an inward offset from the rim: flat at the
    rim (a right angle with the wall) and at the ridge, rising by DOME."""
    return DOME * (1.0 - np.cos(math.pi * offset / RADIUS)) / 2


def profile_polyline(samples=4000):
    """The cavity's profile in the (offset d, z) plane, dense, with its parts.

    From the bottom ridge (d = RADIUS, z = DOME) along the diaphragm
    z = dome_z(d) to the rim (0, 0), up the wall d = 0 to
    Z_WALL, then a quarter ellipse to the top ridge (RADIUS, HEIGHT). The dome
    and the top are horizontal at the ridges, so the surface is smooth there.
    Returns (d, z, s) arrays (s: arc length) and the arc lengths of the rim
    and of the apex border."""
    t = np.linspace(0.0, 1.0, samples + 1)
    d1 = RADIUS * (1.0 - t)
    z1 = dome_z(d1)
    z2 = np.linspace(0.0, Z_WALL, samples + 1)[1:]
    d2 = np.zeros_like(z2)
    theta = np.linspace(0.0, math.pi / 2, samples + 1)[1:]
    d3 = RADIUS * (1.0 - np.cos(theta))
    z3 = Z_WALL + TOP_ROUND * np.sin(theta)
    d = np.concatenate([d1, d2, d3])
    z = np.concatenate([z1, z2, z3])
    d[0], z[0], d[-1], z[-1] = RADIUS, DOME, RADIUS, HEIGHT
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(d), np.diff(z)))])
    s_rim = s[samples]
    upper = slice(samples, None)  # rim to top: z increases strictly
    s_apex = float(np.interp(Z_APEX, z[upper], s[upper]))
    return d, z, s, s_rim, s_apex


# ---------------------------------------------------------------- rings
def stadium_ring(offset, z, count, stagger):
    """`count` points evenly spaced on the stadium offset inward by `offset`.

    The loop runs counter-clockwise seen from +z, starting at (-l, -r). Also
    returns each point's base parameter (its position on the outermost
    stadium, which increases along every ring the same way) used to stitch
    neighbouring rings."""
    l, r, b = HALF_LENGTH, RADIUS - offset, RADIUS
    perimeter = 4 * l + 2 * math.pi * r
    s = (np.arange(count) + (0.5 if stagger else 0.0)) * perimeter / count
    x = np.empty(count)
    y = np.empty(count)
    beta = np.empty(count)
    bottom = s < 2 * l
    right = (s >= 2 * l) & (s < 2 * l + math.pi * r)
    top = (s >= 2 * l + math.pi * r) & (s < 4 * l + math.pi * r)
    left = s >= 4 * l + math.pi * r
    x[bottom], y[bottom], beta[bottom] = -l + s[bottom], -r, s[bottom]
    phi = -math.pi / 2 + (s[right] - 2 * l) / r
    x[right], y[right] = l + r * np.cos(phi), r * np.sin(phi)
    beta[right] = 2 * l + (phi + math.pi / 2) * b
    u = s[top] - 2 * l - math.pi * r
    x[top], y[top], beta[top] = l - u, r, 2 * l + math.pi * b + u
    phi = math.pi / 2 + (s[left] - 4 * l - math.pi * r) / r
    x[left], y[left] = -l + r * np.cos(phi), r * np.sin(phi)
    beta[left] = 4 * l + math.pi * b + (phi - math.pi / 2) * b
    return np.column_stack([x, y, np.full(count, z)]), beta


def ridge_ring(z, edge):
    """The degenerate ring at a ridge: the segment [-l, l] x {0} at height z.

    Its loop goes along the segment and back, so it visits every interior
    point twice (once per side); the ends get the base parameter of the
    middle of their semicircle, so the end fans are balanced."""
    l, b = HALF_LENGTH, RADIUS
    half = max(1, int(round(2 * l / edge)))
    x = -l + np.arange(half + 1) * (2 * l / half)
    points = np.column_stack([x, np.zeros(half + 1), np.full(half + 1, z)])
    loop = list(range(half + 1)) + list(range(half - 1, 0, -1))
    beta = [-math.pi * b / 2] + [x[k] + l for k in range(1, half)] + [2 * l + math.pi * b / 2]
    beta += [2 * l + math.pi * b + (l - x[k]) for k in range(half - 1, 0, -1)]
    return points, np.array(loop), np.array(beta)


def stitch(a_ids, a_beta, b_ids, b_beta, points, period=BASE_PERIMETER):
    """Triangles between loop a (earlier in the profile) and loop b (later).

    Both loops start near base parameter 0 and run the same way round. At
    each step the shorter of the two diagonals closes the next triangle
    (the classic loft rule); a loop whose next point lies more than a
    quarter turn ahead of the other loop's (in base parameter) waits, so
    the stitching never crosses. (a_i, a_i+1, b_j) and (a_i, b_j+1, b_j)
    face outward when the profile runs from the bottom of the cavity to its
    top."""
    na, nb = len(a_ids), len(b_ids)

    def beta(values, k, n):
        return values[k % n] + period * (k // n)

    tris = []
    i = j = 0
    while i < na or j < nb:
        if j == nb:
            advance_a = True
        elif i == na:
            advance_a = False
        else:
            ba, bb = beta(a_beta, i + 1, na), beta(b_beta, j + 1, nb)
            if ba - bb > period / 4:
                advance_a = False
            elif bb - ba > period / 4:
                advance_a = True
            else:
                diag_a = np.linalg.norm(points[a_ids[(i + 1) % na]] - points[b_ids[j % nb]])
                diag_b = np.linalg.norm(points[a_ids[i % na]] - points[b_ids[(j + 1) % nb]])
                advance_a = diag_a <= diag_b
        if advance_a:
            tris.append((a_ids[i % na], a_ids[(i + 1) % na], b_ids[j % nb]))
            i += 1
        else:
            tris.append((a_ids[i % na], b_ids[(j + 1) % nb], b_ids[j % nb]))
            j += 1
    return tris


def make_cavity(edge):
    """The cavity: vertices, triangles and the patch name of each triangle."""
    d, z, s, s_rim, s_apex = profile_polyline()
    row = edge * math.sqrt(3) / 2  # equilateral rows
    stations = []  # (arc length, part) of every ring, bottom ridge to top ridge
    for start, stop, part in ((0.0, s_rim, "diaphragm"), (s_rim, s_apex, "ribs"), (s_apex, s[-1], "apex")):
        n = max(1, int(round((stop - start) / row)))
        for k in range(n + (1 if part == "apex" else 0)):
            stations.append((start + (stop - start) * k / n, part))
    points, tris, patches = [], [], []
    previous = None
    for index, (arc, part) in enumerate(stations):
        first, last = index == 0, index == len(stations) - 1
        if first or last:
            ring_z = DOME if first else HEIGHT
            pts, loop, beta = ridge_ring(ring_z, edge)
            ids = loop + sum(len(p) for p in points)
        else:
            offset = float(np.interp(arc, s, d))
            ring_z = float(np.interp(arc, s, z))
            if part == "ribs" and abs(arc - s_rim) < 1e-12:
                offset, ring_z = 0.0, 0.0
            r = RADIUS - offset
            count = max(3, int(round((4 * HALF_LENGTH + 2 * math.pi * r) / edge)))
            pts, beta = stadium_ring(offset, ring_z, count, stagger=index % 2 == 1)
            ids = np.arange(count) + sum(len(p) for p in points)
        if abs(arc - s_apex) < 1e-12:
            pts[:, 2] = Z_APEX
        points.append(pts)
        if previous is not None:
            new = stitch(previous[0], previous[1], ids, beta, np.vstack(points))
            tris += new
            patches += [previous[2]] * len(new)  # a band belongs to the part of its lower ring
        previous = (ids, beta, part)
    return np.vstack(points), np.array(tris, dtype=np.int64), patches


# ---------------------------------------------------------------- lungs
def lung_function(side):
    """Positive inside the lung on `side` (+1: right, x > 0; -1: left): the
    cavity shrunk by LUNG_MARGIN, cut at the mediastinum's border, the
    medial edges rounded. Each term is a lower bound of the distance to a
    part of the cavity's surface, in the (offset, z) plane of its rings."""
    m, xm, rho = LUNG_MARGIN, MEDIASTINUM / 2, LUNG_ROUND
    steepest = math.sqrt(1 + (math.pi * DOME / (2 * RADIUS)) ** 2)

    def f(p):
        dist_xy = np.hypot(np.maximum(np.abs(p[:, 0]) - HALF_LENGTH, 0.0), p[:, 1])
        offset = RADIUS - dist_xy  # depth inside the stadium: distance to the wall
        floor = (p[:, 2] - dome_z(np.clip(offset, 0.0, RADIUS))) / steepest
        ellipse = np.hypot(dist_xy / RADIUS, np.maximum(p[:, 2] - Z_WALL, 0.0) / TOP_ROUND)
        top = (1.0 - ellipse) * min(RADIUS, TOP_ROUND)
        a = np.minimum(np.minimum(offset, floor), top) - m
        b = side * p[:, 0] - xm
        return rho - np.hypot(np.maximum(rho - a, 0.0), np.maximum(rho - b, 0.0))

    return f


def ray_radius(f, centre, directions, r_max=0.5, iterations=48):
    """Where each ray from `centre` leaves {f > 0} (bisection); checks that
    the ray stays inside before that point and outside after it."""
    lo = np.zeros(len(directions))
    hi = np.full(len(directions), r_max)
    if not f(centre[None])[0] > 0:
        raise CheckFailed("a lung's centre is not inside it")
    if np.any(f(centre[None] + r_max * directions) > 0):
        raise CheckFailed("a lung reaches beyond the bisection bracket")
    for _ in range(iterations):
        mid = (lo + hi) / 2
        inside = f(centre[None] + mid[:, None] * directions) > 0
        lo = np.where(inside, mid, lo)
        hi = np.where(inside, hi, mid)
    for fraction in np.linspace(0.02, 0.98, 49):
        if np.any(f(centre[None] + (fraction * lo)[:, None] * directions) <= 0) or \
                np.any(f(centre[None] + (hi + fraction * (r_max - hi))[:, None] * directions) > 0):
            raise CheckFailed("a lung is not star-shaped about its centre")
    return lo


def neighbours(faces, n):
    pairs = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    pairs = np.unique(np.sort(pairs, axis=1), axis=0)
    rows = np.concatenate([pairs[:, 0], pairs[:, 1]])
    cols = np.concatenate([pairs[:, 1], pairs[:, 0]])
    return rows, cols, np.bincount(rows, minlength=n)


def make_lung(side, edge):
    """A lung: a geodesic sphere stretched to the lung's proportions, each
    vertex projected along its ray from the lung's centre onto the lung's
    surface, then smoothed (Laplacian steps, projected back the same way).
    The radial projection of a sphere's triangulation onto a star-shaped
    surface cannot fold over or intersect itself."""
    f = lung_function(side)
    m, xm = LUNG_MARGIN, MEDIASTINUM / 2
    half = np.array([(WIDTH / 2 - m - xm) / 2, RADIUS - m, (HEIGHT - DOME - 2 * m) / 2])
    centre = np.array([side * (xm + half[0]), 0.0, DOME + m + half[2]])
    level = int(min(6, max(2, round(math.log2(1.5 * float(np.cbrt(half.prod())) / edge)))))
    unit, faces = icosphere(level)
    directions = unit * half
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    points = centre + ray_radius(f, centre, directions)[:, None] * directions
    rows, cols, counts = neighbours(faces, len(points))
    for _ in range(10):
        mean = np.zeros_like(points)
        np.add.at(mean, rows, points[cols])
        moved = points + 0.5 * (mean / counts[:, None] - points)
        directions = moved - centre
        directions /= np.linalg.norm(directions, axis=1)[:, None]
        points = centre + ray_radius(f, centre, directions)[:, None] * directions
    return points, faces


def icosphere(level):
    """Unit geodesic sphere: the icosahedron, each face split in 4 `level` times."""
    g = (1 + math.sqrt(5)) / 2
    v = [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g), (0, -1, -g), (0, 1, -g),
         (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, dtype=float) / math.sqrt(1 + g * g) for p in v]
    for _ in range(level):
        middle = {}

        def mid(i, j):
            key = (min(i, j), max(i, j))
            if key not in middle:
                m = verts[i] + verts[j]
                verts.append(m / np.linalg.norm(m))
                middle[key] = len(verts) - 1
            return middle[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return np.array(verts), np.array(faces, dtype=np.int64)


def make_tumour(edge):
    level = int(min(5, max(2, math.ceil(math.log2(1.1 * TUMOUR_RADIUS / (edge / 2))))))
    directions, faces = icosphere(level)
    return np.array(TUMOUR_CENTRE) + TUMOUR_RADIUS * directions, faces


# ---------------------------------------------------------------- STL
def fmt(value):
    text = f"{value:.{DECIMALS}f}"
    return "0." + "0" * DECIMALS if text == "-0." + "0" * DECIMALS else text


def stl_text(solids):
    """ASCII STL of several named solids: [(name, points, triangles)]."""
    out = []
    for name, points, tris in solids:
        p = np.round(points, DECIMALS) + 0.0
        normals = np.cross(p[tris[:, 1]] - p[tris[:, 0]], p[tris[:, 2]] - p[tris[:, 0]])
        normals /= np.linalg.norm(normals, axis=1)[:, None]
        out.append(f"solid {name}\n")
        for t, n in zip(tris, normals):
            out.append(f"  facet normal {fmt(n[0])} {fmt(n[1])} {fmt(n[2])}\n    outer loop\n")
            for k in t:
                out.append(f"      vertex {fmt(p[k, 0])} {fmt(p[k, 1])} {fmt(p[k, 2])}\n")
            out.append("    endloop\n  endfacet\n")
        out.append(f"endsolid {name}\n")
    return "".join(out)


def write_atomically(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="ascii", newline="\n") as handle:
        handle.write(text)
    os.replace(tmp, path)


def read_stl(path):
    """Reads an ASCII STL back: points merged by their exact text, triangles,
    and the solid name of each triangle."""
    index, points, tris, names = {}, [], [], []
    solid, corner = None, []
    with open(path, encoding="ascii") as handle:
        for number, line in enumerate(handle, 1):
            words = line.split()
            if not words:
                continue
            if words[0] == "solid":
                solid = words[1] if len(words) > 1 else ""
            elif words[0] == "vertex":
                key = tuple(words[1:4])
                if key not in index:
                    index[key] = len(points)
                    points.append([float(w) for w in key])
                corner.append(index[key])
            elif words[0] == "endloop":
                if len(corner) != 3:
                    raise CheckFailed(f"{path}:{number}: a facet with {len(corner)} vertices")
                tris.append(corner)
                names.append(solid)
                corner = []
    return np.array(points), np.array(tris, dtype=np.int64), names


# ---------------------------------------------------------------- checks
def check_closed(name, tris):
    """Every edge in exactly two triangles, with opposite orientations."""
    directed = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    if np.any(directed[:, 0] == directed[:, 1]) or np.any(tris[:, 0] == tris[:, 2]):
        raise CheckFailed(f"{name}: a triangle repeats a vertex")
    unique, counts = np.unique(directed, axis=0, return_counts=True)
    if np.any(counts > 1):
        raise CheckFailed(f"{name}: {int((counts > 1).sum())} edges used twice in the same direction "
                          "(inconsistent orientation or non-manifold)")
    keys = set(map(tuple, unique))
    missing = sum((b, a) not in keys for a, b in keys)
    if missing:
        raise CheckFailed(f"{name}: {missing} edges have no opposite half-edge (open or non-manifold surface)")
    n = int(tris.max()) + 1
    euler = n - len(unique) // 2 + len(tris)
    if euler != 2:
        raise CheckFailed(f"{name}: Euler characteristic {euler}, not a sphere")


def signed_volume(points, tris):
    a, b, c = points[tris[:, 0]], points[tris[:, 1]], points[tris[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)


def triangle_quality(points, tris):
    """Edge lengths, smallest angle (degrees) and largest angle between the
    normals of adjacent triangles."""
    p = points[tris]
    e = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 1], p[:, 0] - p[:, 2]], axis=1)
    length = np.linalg.norm(e, axis=2)
    angles = []
    for k in range(3):
        u, v = -e[:, k - 1], e[:, k]
        cos = np.einsum("ij,ij->i", u, v) / (length[:, k - 1] * length[:, k])
        angles.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    normal = np.cross(e[:, 0], -e[:, 2])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    directed = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    owner = np.tile(np.arange(len(tris)), 3)
    key = {tuple(ed): t for ed, t in zip(directed.tolist(), owner.tolist())}
    other = np.array([key[(b, a)] for a, b in directed.tolist()])
    fold = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", normal[owner], normal[other]), -1, 1)))
    return length, np.min(angles, axis=0), float(fold.max())


def segment_hits(p0, p1, a, b, c, eps=1e-12):
    """Segment p0-p1 against triangle abc (arrays of the same length)."""
    d = p1 - p0
    e1, e2 = b - a, c - a
    h = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, h)
    ok = np.abs(det) > eps * np.linalg.norm(d, axis=1) * np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1)
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = p0 - a
    u = np.einsum("ij,ij->i", s, h) * inv
    q = np.cross(s, e1)
    v = np.einsum("ij,ij->i", d, q) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    return ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0) & (t <= 1)


def edge_triangle_intersections(pa, ta, pb, tb, same=False, chunk=256):
    """Number of (edge of A, triangle of B) pairs that intersect; with
    same=True (A is B) pairs sharing a vertex are skipped."""
    edges = np.unique(np.sort(np.concatenate([ta[:, [0, 1]], ta[:, [1, 2]], ta[:, [2, 0]]]), axis=1), axis=0)
    e0, e1 = pa[edges[:, 0]], pa[edges[:, 1]]
    elo, ehi = np.minimum(e0, e1), np.maximum(e0, e1)
    order = np.argsort((elo[:, 2] + ehi[:, 2]) / 2, kind="stable")
    tri = pb[tb]
    tlo, thi = tri.min(axis=1), tri.max(axis=1)
    hits = 0
    for start in range(0, len(order), chunk):
        sel = order[start:start + chunk]
        zlo, zhi = elo[sel, 2].min(), ehi[sel, 2].max()
        cand = np.nonzero((thi[:, 2] >= zlo) & (tlo[:, 2] <= zhi))[0]
        if len(cand) == 0:
            continue
        overlap = np.all((elo[sel][:, None, :] <= thi[cand][None]) & (ehi[sel][:, None, :] >= tlo[cand][None]), axis=2)
        ei, ti = np.nonzero(overlap)
        ei, ti = sel[ei], cand[ti]
        if same:
            shared = np.zeros(len(ei), dtype=bool)
            for k in range(3):
                shared |= (tb[ti, k] == edges[ei, 0]) | (tb[ti, k] == edges[ei, 1])
            ei, ti = ei[~shared], ti[~shared]
        if len(ei):
            hits += int(segment_hits(e0[ei], e1[ei], tri[ti, 0], tri[ti, 1], tri[ti, 2]).sum())
    return hits


ROTATIONS = [np.linalg.qr(np.array(m, dtype=float))[0] for m in (
    [[0.83, 0.31, 0.46], [-0.27, 0.95, 0.13], [-0.49, -0.02, 0.87]],
    [[0.61, -0.52, 0.59], [0.44, 0.85, 0.29], [-0.66, 0.11, 0.74]],
    [[0.92, 0.18, -0.35], [-0.07, 0.94, 0.33], [0.39, -0.28, 0.88]])]


def inside(points, surface_points, surface_tris, chunk=128):
    """Ray-parity inside test: rays along a generic direction (three
    directions, majority vote; a ray through an edge counts no crossing
    there and is outvoted by the other two)."""
    votes = np.zeros(len(points), dtype=int)
    for rotation in ROTATIONS:
        p = points @ rotation
        tri = (surface_points @ rotation)[surface_tris]
        lo, hi = tri[:, :, :2].min(axis=1), tri[:, :, :2].max(axis=1)
        crossings = np.zeros(len(p), dtype=int)
        order = np.argsort(p[:, 0], kind="stable")
        for start in range(0, len(p), chunk):
            sel = order[start:start + chunk]
            q = p[sel]
            near = np.nonzero((hi[:, 0] >= q[:, 0].min()) & (lo[:, 0] <= q[:, 0].max()))[0]
            box = np.all((q[:, None, :2] >= lo[near][None]) & (q[:, None, :2] <= hi[near][None]), axis=2)
            qi, ti = np.nonzero(box)
            ti = near[ti]
            a, b, c = tri[ti, 0], tri[ti, 1], tri[ti, 2]
            x, y = q[qi, 0], q[qi, 1]

            def side(u, v):
                return (v[:, 0] - u[:, 0]) * (y - u[:, 1]) - (v[:, 1] - u[:, 1]) * (x - u[:, 0])

            s1, s2, s3 = side(a, b), side(b, c), side(c, a)
            within = ((s1 > 0) & (s2 > 0) & (s3 > 0)) | ((s1 < 0) & (s2 < 0) & (s3 < 0))
            area = s1 + s2 + s3
            zt = (s2 * a[:, 2] + s3 * b[:, 2] + s1 * c[:, 2]) / np.where(area == 0, 1.0, area)
            hit = within & (zt > q[qi, 2])
            np.add.at(crossings, sel[qi[hit]], 1)
        votes += crossings % 2
    return votes >= 2


def clearance(points, surface_points, surface_tris, chunk=64):
    """Smallest distance from the points to the surface's triangles. Each
    point's nearest surface vertex bounds its distance from above, so a
    compact chunk of points is measured only against the triangles whose
    boxes come that close."""
    nearest = np.empty(len(points))
    for start in range(0, len(points), 256):
        diff = points[start:start + 256, None, :] - surface_points[None]
        nearest[start:start + 256] = np.sqrt((diff * diff).sum(-1).min(axis=1))
    tri = surface_points[surface_tris]
    tlo, thi = tri.min(axis=1), tri.max(axis=1)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1)[:, None]
    centre = points.mean(axis=0)
    order = np.lexsort((np.arctan2(points[:, 1] - centre[1], points[:, 0] - centre[0]),
                        np.floor((points[:, 2] - points[:, 2].min()) / 0.02)))
    best = np.inf
    for start in range(0, len(points), chunk):
        sel = order[start:start + chunk]
        reach = min(nearest[sel].max(), best)
        lo, hi = points[sel].min(axis=0) - reach, points[sel].max(axis=0) + reach
        near = np.nonzero(np.all((thi >= lo) & (tlo <= hi), axis=1))[0]
        if len(near) == 0:
            continue
        p = points[sel][:, None, :]
        an, bn, cn, nn = a[near], b[near], c[near], n[near]
        h = ((p - an[None]) * nn[None]).sum(-1)
        foot = p - h[..., None] * nn[None]
        inside_tri = np.ones(h.shape, dtype=bool)
        for u, v in ((an, bn), (bn, cn), (cn, an)):
            inside_tri &= (np.cross(v - u, foot - u[None]) * nn[None]).sum(-1) >= 0
        dist = np.where(inside_tri, np.abs(h), np.inf)
        for u, v in ((an, bn), (bn, cn), (cn, an)):
            uv = v - u
            t = np.clip(((p - u[None]) * uv[None]).sum(-1) / (uv * uv).sum(-1)[None], 0, 1)
            dist = np.minimum(dist, np.linalg.norm(p - (u[None] + t[..., None] * uv[None]), axis=-1))
        best = min(best, float(dist.min()))
    return best


def check_all(directory):
    """Reads the files back and checks them; returns the report."""
    surfaces = {}
    report = {}
    for name in ("thorax", "lung_left", "lung_right", "tumour"):
        points, tris, solids = read_stl(os.path.join(directory, name + ".stl"))
        check_closed(name + ".stl", tris)
        volume = signed_volume(points, tris)
        if not volume > 0:
            raise CheckFailed(f"{name}.stl: signed volume {volume:.6g} m^3 is not positive (inward orientation)")
        length, min_angle, fold = triangle_quality(points, tris)
        self_hits = edge_triangle_intersections(points, tris, points, tris, same=True)
        if self_hits:
            raise CheckFailed(f"{name}.stl: {self_hits} edge-triangle self-intersections")
        if min_angle.min() < 15.0:
            raise CheckFailed(f"{name}.stl: a triangle with a {min_angle.min():.1f} degree angle (sliver)")
        if fold > 120.0:  # the costophrenic rim is a right-angle crease
            raise CheckFailed(f"{name}.stl: adjacent triangles fold by {fold:.0f} degrees")
        counts = {s: solids.count(s) for s in dict.fromkeys(solids)}
        surfaces[name] = (points, tris, solids)
        report[name] = {"triangles": len(tris), "vertices": len(points), "volume_m3": volume,
                        "volume_litres": volume * 1e3, "edge_min": float(length.min()),
                        "edge_mean": float(length.mean()), "edge_max": float(length.max()),
                        "min_angle_deg": float(min_angle.min()), "max_fold_deg": fold, "solids": counts}

    # the cavity's patches
    points, tris, solids = surfaces["thorax"]
    if list(report["thorax"]["solids"]) != ["apex", "ribs", "diaphragm"]:
        raise CheckFailed(f"thorax.stl: solids {list(report['thorax']['solids'])}, expected apex, ribs, diaphragm")
    solids = np.array(solids)
    zc = points[tris][:, :, 2]
    tol = 1e-6
    if zc[solids == "apex"].min() < Z_APEX - tol or zc[solids == "ribs"].max() > Z_APEX + tol:
        raise CheckFailed("thorax.stl: the apex / ribs border is not the ring z = %.4f" % Z_APEX)
    if zc[solids == "diaphragm"].max() > DOME + tol or zc[solids == "ribs"].min() < -tol:
        raise CheckFailed("thorax.stl: the ribs / diaphragm border is not the rim z = 0")
    shared = {}
    for a, b in (("apex", "ribs"), ("ribs", "diaphragm"), ("apex", "diaphragm")):
        common = np.intersect1d(tris[solids == a], tris[solids == b])
        shared[f"{a}/{b}"] = len(common)
    if shared["apex/ribs"] < 3 or shared["ribs/diaphragm"] < 3 or shared["apex/diaphragm"]:
        raise CheckFailed(f"thorax.stl: patch borders share {shared} vertices")
    report["thorax"]["border_vertices"] = shared

    # volumes
    sphere = 4 / 3 * math.pi * TUMOUR_RADIUS ** 3
    checks = [("thorax", 4e-3, 10e-3), ("lung_left", 1.2e-3, 4e-3), ("lung_right", 1.2e-3, 4e-3),
              ("tumour", 0.9 * sphere, 1.0001 * sphere)]
    for name, low, high in checks:
        v = report[name]["volume_m3"]
        if not low <= v <= high:
            raise CheckFailed(f"{name}.stl: volume {v * 1e3:.4f} L outside the sensible range "
                              f"[{low * 1e3:.4f}, {high * 1e3:.4f}] L")
    if report["lung_left"]["volume_m3"] + report["lung_right"]["volume_m3"] >= report["thorax"]["volume_m3"]:
        raise CheckFailed("the lungs are larger than the cavity")

    # nesting: inner strictly inside outer, lungs disjoint
    nesting = {}
    for inner, outer, want in (("lung_left", "thorax", True), ("lung_right", "thorax", True),
                               ("tumour", "lung_right", True), ("tumour", "lung_left", False),
                               ("lung_left", "lung_right", False), ("lung_right", "lung_left", False)):
        pi, ti, _ = surfaces[inner]
        po, to, _ = surfaces[outer]
        flags = inside(pi, po, to)
        if want and not flags.all():
            raise CheckFailed(f"{inner}.stl: {int((~flags).sum())} vertices outside {outer}.stl")
        if not want and flags.any():
            raise CheckFailed(f"{inner}.stl: {int(flags.sum())} vertices inside {outer}.stl")
        crossings = edge_triangle_intersections(pi, ti, po, to) + edge_triangle_intersections(po, to, pi, ti)
        if crossings:
            raise CheckFailed(f"{inner}.stl and {outer}.stl intersect ({crossings} edge-triangle crossings)")
        nesting[f"{inner} {'in' if want else 'outside'} {outer}"] = clearance(pi, po, to)
    report["clearance_m"] = nesting
    return report


# ---------------------------------------------------------------- main
def rounded(value):
    """Floats of the JSON report to 9 significant digits."""
    if isinstance(value, float):
        return float(f"{value:.9g}")
    if isinstance(value, dict):
        return {k: rounded(v) for k, v in value.items()}
    if isinstance(value, list):
        return [rounded(v) for v in value]
    return value


def bbox(points):
    return {"min": [float(v) for v in points.min(axis=0)], "max": [float(v) for v in points.max(axis=0)]}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)),
                        help="directory to write into (default: this script's directory)")
    parser.add_argument("--edge", type=float, default=0.012, help="target triangle edge L in metres (default 0.012)")
    args = parser.parse_args(argv)
    if not (0.005 <= args.edge <= 0.03):
        parser.error("--edge must be between 0.005 and 0.03 m")
    os.makedirs(args.out, exist_ok=True)

    points, tris, patches = make_cavity(args.edge)
    patches = np.array(patches)
    solids = [(name, points, tris[patches == name]) for name in ("apex", "ribs", "diaphragm")]
    files = {"thorax": solids}
    lung_edge = 1.25 * args.edge
    files["lung_left"] = [("lung_left",) + make_lung(-1, lung_edge)]
    files["lung_right"] = [("lung_right",) + make_lung(+1, lung_edge)]
    files["tumour"] = [("tumour",) + make_tumour(args.edge)]
    for name, content in files.items():
        write_atomically(os.path.join(args.out, name + ".stl"), stl_text(content))

    try:
        report = check_all(args.out)
    except CheckFailed as error:
        print(f"make_thorax.py: check failed: {error}", file=sys.stderr)
        return 1

    centre = [float(v) for v in TUMOUR_CENTRE]
    roi = centre + [ROI_RADIUS]
    summary = {
        "units": "m",
        "axes": "x left-right (right lung at x > 0), y anterior-posterior, z cranio-caudal (head +z)",
        "edge": args.edge,
        "tumour": {"centre": centre, "radius": TUMOUR_RADIUS},
        "roi": roi,
        "roi_arg": ",".join(f"{v:g}" for v in roi),
        "cavity": {"width": WIDTH, "depth": DEPTH, "height": HEIGHT, "dome": DOME, "apex_z": Z_APEX,
                   "patches": ["apex", "ribs", "diaphragm"]},
        "bbox": {name: bbox(read_stl(os.path.join(args.out, name + ".stl"))[0]) for name in files},
        "surfaces": report,
    }
    text = json.dumps(rounded(summary), indent=2, sort_keys=True) + "\n"
    write_atomically(os.path.join(args.out, "thorax.json"), text)

    print(f"thorax: L = {args.edge:g} m, files in {args.out}")
    for name in files:
        r = report[name]
        extra = "  " + ", ".join(f"{k} {v}" for k, v in r["solids"].items()) if name == "thorax" else ""
        print(f"  {name + '.stl':15s} {r['triangles']:6d} triangles {r['vertices']:6d} vertices "
              f"volume {r['volume_litres']:7.4f} L  edges {1e3 * r['edge_min']:.1f}/{1e3 * r['edge_mean']:.1f}/"
              f"{1e3 * r['edge_max']:.1f} mm  min angle {r['min_angle_deg']:.1f} deg{extra}")
    for pair, value in report["clearance_m"].items():
        print(f"  clearance {pair}: {1e3 * value:.1f} mm")
    box = summary["bbox"]["thorax"]
    print("  thorax bbox: min (%.4f, %.4f, %.4f) max (%.4f, %.4f, %.4f)" % tuple(box["min"] + box["max"]))
    print(f"  tumour: centre ({centre[0]:g}, {centre[1]:g}, {centre[2]:g}) radius {TUMOUR_RADIUS:g}")
    print(f"  roi: {summary['roi_arg']}")
    print("checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
