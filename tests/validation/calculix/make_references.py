#!/usr/bin/env python3
"""Build the CalculiX reference solutions of the tensormass validation suite.

For every case (element type x linear/NLGEOM x gravity/tip load) this script

  1. builds a structured cantilever mesh itself (no mesher needed),
  2. writes ``mesh.msh`` (Gmsh 2.2 ASCII, physical groups clamp, tip, body,
     node order per ``elements/<type>.toml`` [gmsh] node_order),
  3. writes the CalculiX deck ``ccx.inp`` (node order per [calculix]
     node_order), runs ``ccx`` in a scratch directory,
  4. reads the displacements back (binary .frd, single precision, cross-checked
     against the .dat printout), checks that the clamp reactions balance the
     applied load and that 2D results stay in plane, and
  5. writes ``reference.csv`` (our node index, ux, uy, uz) and ``scene.yaml``
     (docs/scene.md contract) into ``cases/<case>/``.

Only mesh.msh, scene.yaml, reference.csv and ccx.inp are kept; CalculiX's
scratch files stay in a temporary directory.

``--self-check`` additionally re-solves every case with an independent small
NumPy finite-element code (Hooke: one linear solve; StVK: total-Lagrangian
Newton, both with the same quadrature rules as CalculiX and tensormass) and
compares it with the CalculiX results, reads every mesh.msh back with meshio
to check the Gmsh node ordering, and re-runs the NLGEOM decks with CalculiX's
default convergence controls to show that the tightened controls matter.

Usage:
  python3 tests/validation/calculix/make_references.py [--only CASE ...]
      [--self-check] [--ccx ccx]
"""

import argparse
import itertools
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
CASES_DIR = os.path.join(HERE, "cases")
ELEMENTS_DIR = os.path.join(ROOT, "elements")

# --- Problem data -----------------------------------------------------------

YOUNG = 1.0e6      # Pa
POISSON = 0.3
DENSITY = 1000.0   # kg/m^3
LENGTH = 1.0       # beam axis along x, clamped at x = 0, tip at x = LENGTH
WIDTH = 0.2        # y extent (3D and 2D)
DEPTH = 0.2        # z extent (3D only)
NLGEOM_INCREMENTS = 10  # equal increments, CalculiX *STATIC, DIRECT and tensormass load_steps
# tensormass solver.tolerance (relative residual).  Not 1e-12: the rounding
# floor of |r| / |f_ext| measured on these meshes in double precision is
# 0.3e-12 to 2.5e-12 (internal nodal forces are much larger than the net
# loads), while a 1e-10 residual moves the displacements by < 5e-10 relative.
SCENE_TOLERANCE = "1.0e-10"

# Direction of the loads (scaled by the per-case magnitude below).  The 3D
# loads have an out-of-plane z component so that both bending planes are
# exercised; the 2D tip load has a small tensile axial component.
GRAVITY_DIRECTION = {3: (0.0, -1.0, 0.25), 2: (0.0, -1.0, 0.0)}
TIP_DIRECTION = {3: (0.0, -1.0, 0.25), 2: (0.1, -1.0, 0.0)}

# Load magnitudes: gravity in m/s^2, tip force in N per tip node.  Chosen
# (see --calibrate) so that the linear (Hooke) solution has a largest nodal
# displacement of about 0.15 * LENGTH; the same load is used for the NLGEOM
# (StVK) case, which then differs from Hooke by several percent.
LOADS = {
    ("tet4", "gravity"): 6.64,
    ("tet4", "tip"): 11.1,
    ("tet10", "gravity"): 3.79,
    ("tet10", "tip"): 2.27,
    ("hex8", "gravity"): 4.32,
    ("hex8", "tip"): 7.2,
    ("hex20", "gravity"): 3.78,
    ("hex20", "tip"): 2.7,
    ("quad4", "gravity"): 4.39,
    ("quad4", "tip"): 66.1,
    ("tri3", "gravity"): 4.82,
    ("tri3", "tip"): 72.7,
}

# Structured grid of each mesh (cells along x, y[, z]); tets split each cube
# into 6 (Kuhn), tri3 split each square into 2.
GRIDS = {
    "tet4": (10, 2, 2),
    "tet10": (10, 2, 2),
    "hex8": (10, 2, 2),
    "hex20": (10, 2, 2),
    "quad4": (20, 4),
    "tri3": (20, 4),
}

ELEMENT_TYPES = ["tet4", "tet10", "hex8", "hex20", "quad4", "tri3"]
KINDS = ["linear", "nlgeom"]
LOAD_TYPES = ["gravity", "tip"]

# CalculiX Newton controls (*CONTROLS, PARAMETERS=FIELD): R_n^alpha, C_n^alpha,
# q_0^alpha, q_u^alpha, R_P^alpha, epsilon^alpha, C_epsilon^alpha, R_l^alpha.
# Defaults are 0.005, 0.01, -, -, 0.02, 1e-5, 1e-3, 1e-8: an increment is
# accepted when the largest residual force is below R_n (R_P after I_P = 9
# iterations) times the average force AND the largest solution correction is
# below C_n times the largest solution increment (or the residual is below
# R_l times the average force).  Tightened here by 8 to 10 orders.
CCX_FIELD_CONTROLS = "1.e-12, 1.e-10, , , 1.e-12, 1.e-5, 1.e-3, 1.e-14"

GMSH_TYPES = {"line2": 1, "tri3": 2, "quad4": 3, "tet4": 4, "hex8": 5,
              "tri6": 9, "tet10": 11, "quad8": 16, "hex20": 17}

# Local facets of each cell type, tensormass (VTK) node indices, outward
# normal (corners counter-clockwise seen from outside, then mid-edge nodes).
FACETS = {
    "tet4": ("tri3", [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]),
    "tet10": ("tri6", [[0, 2, 1, 6, 5, 4], [0, 1, 3, 4, 8, 7],
                       [1, 2, 3, 5, 9, 8], [2, 0, 3, 6, 7, 9]]),
    "hex8": ("quad4", [[0, 4, 7, 3], [1, 2, 6, 5], [0, 1, 5, 4],
                       [3, 7, 6, 2], [0, 3, 2, 1], [4, 5, 6, 7]]),
    "hex20": ("quad8", [[0, 4, 7, 3, 16, 15, 19, 11], [1, 2, 6, 5, 9, 18, 13, 17],
                        [0, 1, 5, 4, 8, 17, 12, 16], [3, 7, 6, 2, 19, 14, 18, 10],
                        [0, 3, 2, 1, 11, 10, 9, 8], [4, 5, 6, 7, 12, 13, 14, 15]]),
    "quad4": ("line2", [[0, 1], [1, 2], [2, 3], [3, 0]]),
    "tri3": ("line2", [[0, 1], [1, 2], [2, 0]]),
}

# Mid-edge nodes of the quadratic types, VTK order (corner, corner).
QUADRATIC_EDGES = {
    "tet10": ("tet4", [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]),
    "hex20": ("hex8", [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7),
                       (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]),
}


def dim_of(etype):
    return 2 if etype in ("quad4", "tri3") else 3


def case_name(etype, kind, load):
    return f"{etype}_{kind}_{load}"


def all_cases():
    return [(e, k, l) for e in ELEMENT_TYPES for k in KINDS for l in LOAD_TYPES]


def load_vector(etype, load):
    d = dim_of(etype)
    direction = GRAVITY_DIRECTION[d] if load == "gravity" else TIP_DIRECTION[d]
    mag = LOADS[(etype, load)]
    return [float(repr_round(mag * c)) for c in direction]


def repr_round(x):
    # Loads are short decimals; keep them exactly as written in the deck
    # and the scene (e.g. 0.25 * 11.4 -> 2.85, not 2.8500000000000001).
    return float(f"{x:.12g}")


def read_node_orders(etype):
    with open(os.path.join(ELEMENTS_DIR, f"{etype}.toml"), "rb") as f:
        data = tomllib.load(f)
    gmsh = data["gmsh"]["node_order"]
    ccx = data["calculix"]["node_order"]
    n = len(data["nodes"])
    assert sorted(gmsh) == list(range(n)) and sorted(ccx) == list(range(n)), etype
    assert data["gmsh"]["type"] == GMSH_TYPES[etype], etype
    return gmsh, ccx, data["calculix"]["type"]


# --- Structured meshes ------------------------------------------------------

def structured_3d(nx, ny, nz):
    """Vertices of an nx x ny x nz box grid; hex8 cells in VTK order."""
    xs = np.linspace(0.0, LENGTH, nx + 1)
    ys = np.linspace(0.0, WIDTH, ny + 1)
    zs = np.linspace(0.0, DEPTH, nz + 1)

    def vid(i, j, k):
        return (k * (ny + 1) + j) * (nx + 1) + i

    pts = np.array([[xs[i], ys[j], zs[k]] for k in range(nz + 1)
                    for j in range(ny + 1) for i in range(nx + 1)])
    hexes = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                b = [vid(i, j, k), vid(i + 1, j, k), vid(i + 1, j + 1, k), vid(i, j + 1, k)]
                t = [vid(i, j, k + 1), vid(i + 1, j, k + 1), vid(i + 1, j + 1, k + 1), vid(i, j + 1, k + 1)]
                hexes.append(b + t)
    return pts, np.array(hexes), vid


def structured_2d(nx, ny):
    xs = np.linspace(0.0, LENGTH, nx + 1)
    ys = np.linspace(0.0, WIDTH, ny + 1)

    def vid(i, j):
        return j * (nx + 1) + i

    pts = np.array([[xs[i], ys[j], 0.0] for j in range(ny + 1) for i in range(nx + 1)])
    quads = [[vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)]
             for j in range(ny) for i in range(nx)]
    return pts, np.array(quads)


def signed_volume(pts, tet):
    a, b, c, d = (pts[n] for n in tet)
    return np.dot(np.cross(b - a, c - a), d - a) / 6.0


def kuhn_tets(pts, hexes):
    """Split each hex (VTK order) into 6 tets around its 0-6 diagonal.

    The split is the same translated pattern in every cube (Kuhn /
    Freudenthal), hence conforming: every face diagonal of the grid is
    shared by the tets of both cubes."""
    # Local hex corner of bit pattern (dx, dy, dz) in VTK order.
    corner = {(0, 0, 0): 0, (1, 0, 0): 1, (1, 1, 0): 2, (0, 1, 0): 3,
              (0, 0, 1): 4, (1, 0, 1): 5, (1, 1, 1): 6, (0, 1, 1): 7}
    tets = []
    for h in hexes:
        for perm in itertools.permutations(range(3)):
            p = [0, 0, 0]
            path = [corner[tuple(p)]]
            for axis in perm:
                p[axis] = 1
                path.append(corner[tuple(p)])
            tet = [h[n] for n in path]
            if signed_volume(pts, tet) < 0:
                tet[1], tet[2] = tet[2], tet[1]
            tets.append(tet)
    return np.array(tets)


def add_midnodes(pts, cells, edges):
    """Quadratic cells from linear ones: shared mid-edge nodes appended."""
    pts = [p for p in pts]
    mid = {}
    out = []
    for c in cells:
        row = list(c)
        for a, b in edges:
            key = (min(c[a], c[b]), max(c[a], c[b]))
            if key not in mid:
                mid[key] = len(pts)
                pts.append(0.5 * (pts[c[a]] + pts[c[b]]))
            row.append(mid[key])
        out.append(row)
    return np.array(pts), np.array(out)


def build_mesh(etype):
    """Points (n x 3) and cells (tensormass/VTK node order) of the case mesh."""
    grid = GRIDS[etype]
    if dim_of(etype) == 3:
        pts, hexes, _ = structured_3d(*grid)
        if etype == "hex8":
            cells = hexes
        elif etype == "hex20":
            pts, cells = add_midnodes(pts, hexes, QUADRATIC_EDGES["hex20"][1])
        else:
            cells = kuhn_tets(pts, hexes)
            if etype == "tet10":
                pts, cells = add_midnodes(pts, cells, QUADRATIC_EDGES["tet10"][1])
    else:
        pts, quads = structured_2d(*grid)
        if etype == "quad4":
            cells = quads
        else:
            nx = grid[0]
            tris = []
            for q_index, q in enumerate(quads):
                i, j = q_index % nx, q_index // nx
                if (i + j) % 2 == 0:
                    tris += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
                else:
                    tris += [[q[0], q[1], q[3]], [q[1], q[2], q[3]]]
            cells = np.array(tris)
    return np.asarray(pts, dtype=float), np.asarray(cells, dtype=int)


def boundary_facets(etype, pts, cells, x):
    """Cell facets lying on the plane (3D) / line (2D) at abscissa x."""
    ftype, local = FACETS[etype]
    out = []
    for c in cells:
        centroid = pts[c].mean(axis=0)
        for f in local:
            nodes = c[f]
            if np.all(np.abs(pts[nodes, 0] - x) < 1e-12):
                # Outward orientation check.
                fp = pts[nodes]
                if dim_of(etype) == 3:
                    n = np.cross(fp[1] - fp[0], fp[2] - fp[0])
                else:
                    t = fp[1] - fp[0]
                    n = np.array([t[1], -t[0], 0.0])
                assert np.dot(n, fp.mean(axis=0) - centroid) > 0, (etype, f)
                out.append(list(nodes))
    return ftype, np.array(out)


# --- Writers ----------------------------------------------------------------

def fmt(x):
    return repr(float(x))


def write_msh(path, etype, pts, cells, clamp, tip, ftype, gmsh_order):
    dim = dim_of(etype)
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "3",
             f'{dim - 1} 1 "clamp"', f'{dim - 1} 2 "tip"', f'{dim} 3 "body"',
             "$EndPhysicalNames", "$Nodes", str(len(pts))]
    for i, p in enumerate(pts):
        lines.append(f"{i + 1} {fmt(p[0])} {fmt(p[1])} {fmt(p[2])}")
    lines.append("$EndNodes")
    # Facets: Gmsh orders of tri3/tri6/quad4/quad8/line2 equal VTK's.
    elems = []
    for f in clamp:
        elems.append((GMSH_TYPES[ftype], 1, 1, f))
    for f in tip:
        elems.append((GMSH_TYPES[ftype], 2, 2, f))
    for c in cells:
        elems.append((GMSH_TYPES[etype], 3, 3, [c[k] for k in gmsh_order]))
    lines += ["$Elements", str(len(elems))]
    for n, (t, phys, geo, nodes) in enumerate(elems):
        lines.append(f"{n + 1} {t} 2 {phys} {geo} " + " ".join(str(v + 1) for v in nodes))
    lines.append("$EndElements")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def nodes_of(facets):
    return sorted(set(int(v) for f in facets for v in f))


def write_ccx_deck(path, name, etype, kind, load, pts, cells, clamp_nodes, tip_nodes,
                   ccx_order, ccx_type, controls=True):
    dim = dim_of(etype)
    vec = load_vector(etype, load)
    out = ["*HEADING", f"tensormass validation case {name} (generated by make_references.py)",
           "*NODE, NSET=NALL"]
    for i, p in enumerate(pts):
        out.append(f"{i + 1}, {fmt(p[0])}, {fmt(p[1])}, {fmt(p[2])}")
    out.append(f"*ELEMENT, TYPE={ccx_type}, ELSET=EALL")
    for e, c in enumerate(cells):
        ids = [str(e + 1)] + [str(c[k] + 1) for k in ccx_order]
        # At most 16 entries on a data line; a trailing comma continues it.
        rows = [ids[i:i + 16] for i in range(0, len(ids), 16)]
        for r, row in enumerate(rows):
            out.append(", ".join(row) + ("," if r + 1 < len(rows) else ""))

    def nset(setname, nodes):
        out.append(f"*NSET, NSET={setname}")
        for i in range(0, len(nodes), 16):
            out.append(", ".join(str(n + 1) for n in nodes[i:i + 16]))

    nset("CLAMP", clamp_nodes)
    nset("TIP", tip_nodes)
    out += ["*MATERIAL, NAME=TISSUE", "*ELASTIC", f"{fmt(YOUNG)}, {fmt(POISSON)}",
            "*DENSITY", fmt(DENSITY),
            "*SOLID SECTION, ELSET=EALL, MATERIAL=TISSUE"]
    if dim == 2:
        out.append("1.0")  # plane strain thickness: loads and results per unit thickness
    out += ["*BOUNDARY", f"CLAMP, 1, {dim}"]
    if kind == "nlgeom":
        out += ["*STEP, NLGEOM, INC=1000", "*STATIC, DIRECT",
                f"{fmt(1.0 / NLGEOM_INCREMENTS)}, 1.0"]
        if controls:
            out += ["*CONTROLS, PARAMETERS=FIELD", CCX_FIELD_CONTROLS]
    else:
        out += ["*STEP", "*STATIC", "1.0, 1.0"]
    if load == "gravity":
        g = math.sqrt(sum(c * c for c in vec))
        out += ["*DLOAD", f"EALL, GRAV, {fmt(g)}, " + ", ".join(fmt(c / g) for c in vec)]
    else:
        out.append("*CLOAD")
        for d in range(3):
            if vec[d] != 0.0:
                out.append(f"TIP, {d + 1}, {fmt(vec[d])}")
    out += ["*NODE PRINT, NSET=NALL", "U",
            "*NODE PRINT, NSET=CLAMP, TOTALS=ONLY", "RF",
            "*NODE OUTPUT", "U", "*END STEP"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def write_scene(path, etype, kind, load):
    vec = load_vector(etype, load)
    law = "stvk" if kind == "nlgeom" else "hooke"
    steps = NLGEOM_INCREMENTS if kind == "nlgeom" else 1
    v = ", ".join(fmt(c) for c in vec)
    if load == "gravity":
        loads = f"loads:\n  gravity: [{v}]\n"
    else:
        loads = f"loads:\n  nodal_forces: [{{region: tip, force: [{v}]}}]\n"
    text = (
        f"# tensormass validation against CalculiX 2.20: {etype}, "
        f"{'NLGEOM (St Venant-Kirchhoff)' if kind == 'nlgeom' else 'linear (Hooke)'}, "
        f"{'gravity' if load == 'gravity' else 'tip load on each tip node'}.\n"
        "# Generated by tests/validation/calculix/make_references.py; see README.md.\n"
        "mesh: mesh.msh\n"
        "materials:\n"
        f"  - {{region: all, law: {law}, young: {fmt(YOUNG)}, poisson: {fmt(POISSON)}, "
        f"density: {fmt(DENSITY)}}}\n"
        "fixed: [clamp]\n"
        f"{loads}"
        "solver:\n"
        "  type: static\n"
        f"  load_steps: {steps}\n"
        f"  tolerance: {SCENE_TOLERANCE}\n"
        "output: {directory: out, every: 0}\n")
    with open(path, "w") as f:
        f.write(text)


def write_reference(path, u):
    with open(path, "w") as f:
        f.write("node,ux,uy,uz\n")
        for i, row in enumerate(u):
            f.write(f"{i},{fmt(row[0])},{fmt(row[1])},{fmt(row[2])}\n")


def read_reference(path):
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    assert np.array_equal(data[:, 0], np.arange(len(data)))
    return data[:, 1:4]


# --- CalculiX ---------------------------------------------------------------

class CcxError(RuntimeError):
    pass


def run_ccx(ccx, deck_path, workdir):
    shutil.copy(deck_path, os.path.join(workdir, "job.inp"))
    proc = subprocess.run([ccx, "-i", "job"], cwd=workdir, capture_output=True, text=True,
                          env=dict(os.environ, OMP_NUM_THREADS="1"))
    log = proc.stdout + proc.stderr
    if proc.returncode != 0 or "*ERROR" in log or "Job finished" not in log:
        raise CcxError(f"ccx failed on {deck_path}:\n{log[-3000:]}")
    return log


def parse_frd_displacements(path, nnodes):
    """Last DISP block of a binary (*NODE OUTPUT) .frd: {node id: (ux, uy, uz)}.

    Binary result blocks (format flag 2) store, per node, an int32 node id
    and the components as float32."""
    with open(path, "rb") as f:
        data = f.read()
    blocks = [m.start() for m in re.finditer(rb"\n -4  DISP ", data)]
    if not blocks:
        raise CcxError(f"no DISP block in {path}")
    start = blocks[-1]
    # The 100CL header line before the block gives the node count and format.
    header_start = data.rfind(b"\n  100C", 0, start) + 1
    header = data[header_start:start].decode("ascii")
    numnod = int(header[24:36])
    fmtflag = int(header.split()[-1])
    if fmtflag != 2:
        raise CcxError(f"{path}: expected a binary float result block, format {fmtflag}")
    pos = start + 1
    # Skip the -4 line and the -5 component lines.
    while True:
        eol = data.index(b"\n", pos)
        line = data[pos:eol]
        pos = eol + 1
        if line.startswith(b" -4") or line.startswith(b" -5"):
            if data[pos:pos + 3] != b" -5":
                break
        else:
            raise CcxError(f"{path}: unexpected line {line!r}")
    rec = np.frombuffer(data, dtype=np.dtype([("id", "<i4"), ("u", "<f4", 3)]),
                        count=numnod, offset=pos)
    if numnod != nnodes:
        raise CcxError(f"{path}: {numnod} nodes in DISP block, expected {nnodes}")
    u = np.zeros((nnodes, 3))
    u[rec["id"] - 1] = rec["u"].astype(np.float64)
    if sorted(rec["id"]) != list(range(1, nnodes + 1)):
        raise CcxError(f"{path}: DISP block does not list every node once")
    return u


def parse_dat(path, nnodes):
    """Last displacement printout and last clamp reaction total of the .dat."""
    with open(path) as f:
        text = f.read()
    disp_blocks = text.split(" displacements (vx,vy,vz) for set NALL")
    if len(disp_blocks) < 2:
        raise CcxError(f"no displacement printout in {path}")
    last = disp_blocks[-1]
    time = float(last.split("time", 1)[1].split()[0])
    u = np.zeros((nnodes, 3))
    seen = 0
    for line in last.splitlines()[1:]:
        parts = line.split()
        if len(parts) == 4 and parts[0].isdigit():
            u[int(parts[0]) - 1] = [float(v) for v in parts[1:]]
            seen += 1
        elif seen and not parts:
            break
        elif parts and not parts[0].isdigit():
            break
    if seen != nnodes:
        raise CcxError(f"{path}: {seen} displacement rows, expected {nnodes}")
    rf_blocks = text.split(" total force (fx,fy,fz) for set CLAMP")
    rf = np.array([float(v) for v in rf_blocks[-1].split("\n")[2].split()])
    return time, u, rf


def ccx_solve(ccx, deck_path, nnodes):
    with tempfile.TemporaryDirectory(prefix="ccx_") as work:
        log = run_ccx(ccx, deck_path, work)
        u_frd = parse_frd_displacements(os.path.join(work, "job.frd"), nnodes)
        time, u_dat, rf = parse_dat(os.path.join(work, "job.dat"), nnodes)
        sta = open(os.path.join(work, "job.sta")).read()
    if abs(time - 1.0) > 1e-12:
        raise CcxError(f"{deck_path}: last printout at time {time}, step did not finish")
    # The .dat printout (7 significant digits) must agree with the binary
    # float32 values to its own rounding.
    scale = np.max(np.abs(u_frd))
    if np.max(np.abs(u_dat - u_frd)) > 1e-6 * scale:
        raise CcxError(f"{deck_path}: .dat and .frd displacements disagree")
    return u_frd, rf, log, sta


def newton_iterations(sta):
    """Iterations per increment from the .sta file."""
    its = []
    for line in sta.splitlines():
        parts = line.split()
        if len(parts) >= 5 and parts[0].isdigit():
            its.append(int(parts[3]))
    return its


# --- Independent NumPy finite elements (self-check) ------------------------

def shape_functions(etype, xi):
    """N (n_nodes,) at the reference point xi (complex allowed), VTK order."""
    if etype == "tet4":
        r, s, t = xi
        return [1 - r - s - t, r, s, t]
    if etype == "tet10":
        r, s, t = xi
        L = [1 - r - s - t, r, s, t]
        corner = [L[i] * (2 * L[i] - 1) for i in range(4)]
        pairs = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
        return corner + [4 * L[a] * L[b] for a, b in pairs]
    if etype in ("hex8", "hex20"):
        r, s, t = xi
        cs = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
              (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
        if etype == "hex8":
            return [(1 + r * a) * (1 + s * b) * (1 + t * c) / 8 for a, b, c in cs]
        N = [(1 + r * a) * (1 + s * b) * (1 + t * c) * (r * a + s * b + t * c - 2) / 8
             for a, b, c in cs]
        for p, q in QUADRATIC_EDGES["hex20"][1]:
            m = [(cs[p][k] + cs[q][k]) / 2 for k in range(3)]
            f = 1 / 4
            for coord, mk in zip((r, s, t), m):
                f = f * ((1 - coord * coord) if mk == 0 else (1 + coord * mk))
            N.append(f)
        return N
    if etype == "quad4":
        r, s = xi
        return [(1 + r * a) * (1 + s * b) / 4 for a, b in [(-1, -1), (1, -1), (1, 1), (-1, 1)]]
    if etype == "tri3":
        r, s = xi
        return [1 - r - s, r, s]
    raise ValueError(etype)


def quadrature(etype):
    if etype == "tet4":
        return np.array([[0.25, 0.25, 0.25]]), np.array([1 / 6])
    if etype == "tet10":
        a, b = (5 - math.sqrt(5)) / 20, (5 + 3 * math.sqrt(5)) / 20
        return np.array([[a, a, a], [b, a, a], [a, b, a], [a, a, b]]), np.full(4, 1 / 24)
    if etype == "tri3":
        return np.array([[1 / 3, 1 / 3]]), np.array([0.5])
    if etype in ("hex8", "quad4"):
        g, w = [-1 / math.sqrt(3), 1 / math.sqrt(3)], [1.0, 1.0]
    else:
        g, w = [-math.sqrt(0.6), 0.0, math.sqrt(0.6)], [5 / 9, 8 / 9, 5 / 9]
    d = dim_of(etype)
    pts = np.array(list(itertools.product(g, repeat=d)))
    wts = np.array([np.prod(c) for c in itertools.product(w, repeat=d)])
    return pts, wts


def shape_data(etype):
    """N (nq, nn) and dN/dxi (nq, nn, d) at the quadrature points.

    Derivatives by complex step (exact to rounding for these polynomials)."""
    qp, qw = quadrature(etype)
    d = dim_of(etype)
    h = 1e-30
    Ns, dNs = [], []
    for x in qp:
        Ns.append(np.real(np.array(shape_functions(etype, list(x)), dtype=complex)))
        cols = []
        for k in range(d):
            xc = np.array(x, dtype=complex)
            xc[k] += 1j * h
            cols.append(np.imag(np.array(shape_functions(etype, list(xc)), dtype=complex)) / h)
        dNs.append(np.stack(cols, axis=1))
    N, dN = np.array(Ns), np.array(dNs)
    assert np.allclose(N.sum(axis=1), 1.0) and np.allclose(dN.sum(axis=1), 0.0)
    return N, dN, qw


class NumpyFE:
    """Total-Lagrangian FE (Hooke or St Venant-Kirchhoff), plane strain in 2D."""

    def __init__(self, etype, pts, cells):
        self.d = d = dim_of(etype)
        self.cells = cells
        self.nn = len(pts)
        N, dN, qw = shape_data(etype)
        X = pts[cells][:, :, :d]                                   # (ne, nen, d)
        J = np.einsum("eai,qaj->eqij", X, dN)                      # dX/dxi
        detJ = np.linalg.det(J)
        if np.any(detJ <= 0):
            raise AssertionError(f"{etype}: non-positive Jacobian in the mesh")
        self.G = np.einsum("qak,eqkj->eqaj", dN, np.linalg.inv(J))  # dN/dX
        self.wdet = detJ * qw[None, :]
        self.N = N
        lam = YOUNG * POISSON / ((1 + POISSON) * (1 - 2 * POISSON))
        mu = YOUNG / (2 * (1 + POISSON))
        self.lam, self.mu = lam, mu
        nen = cells.shape[1]
        self.dofs = (cells[:, :, None] * d + np.arange(d)[None, None, :]).reshape(len(cells), nen * d)

    def gravity_force(self, g):
        f = np.zeros((self.nn, self.d))
        w = np.einsum("eq,qa->ea", self.wdet, self.N)               # integral of N_a
        for k in range(self.d):
            np.add.at(f[:, k], self.cells, DENSITY * g[k] * w)
        return f.reshape(-1)

    def _assemble(self, Ke, fe):
        n = self.nn * self.d
        r = self.dofs[:, :, None] * n + self.dofs[:, None, :]
        K = np.bincount(r.reshape(-1), weights=Ke.reshape(-1), minlength=n * n).reshape(n, n)
        f = np.bincount(self.dofs.reshape(-1), weights=fe.reshape(-1), minlength=n)
        return K, f

    def internal(self, u, law):
        d, lam, mu = self.d, self.lam, self.mu
        ue = u.reshape(self.nn, d)[self.cells]                     # (ne, nen, d)
        I = np.eye(d)
        H = np.einsum("eai,eqaJ->eqiJ", ue, self.G)                # grad u
        if law == "hooke":
            F = np.broadcast_to(I, H.shape)
            eps = 0.5 * (H + np.swapaxes(H, -1, -2))
            S = lam * np.trace(eps, axis1=-2, axis2=-1)[..., None, None] * I + 2 * mu * eps
            P = S
        else:
            F = I + H
            E = 0.5 * (np.einsum("eqkI,eqkJ->eqIJ", F, F) - I)
            S = lam * np.trace(E, axis1=-2, axis2=-1)[..., None, None] * I + 2 * mu * E
            P = np.einsum("eqiK,eqKJ->eqiJ", F, S)
        fe = np.einsum("eq,eqiJ,eqaJ->eai", self.wdet, P, self.G)
        # Tangent: material part with D_aiIJ = sym(F_iI G_aJ), geometric part.
        D = np.einsum("eqiI,eqaJ->eqaiIJ", F, self.G)
        D = 0.5 * (D + np.swapaxes(D, -1, -2))
        trD = np.trace(D, axis1=-2, axis2=-1)
        Km = (lam * np.einsum("eqai,eqbk->eqaibk", trD, trD)
              + 2 * mu * np.einsum("eqaiIJ,eqbkIJ->eqaibk", D, D))
        Ke = np.einsum("eq,eqaibk->eaibk", self.wdet, Km)
        if law != "hooke":
            Kg = np.einsum("eq,eqaJ,eqJL,eqbL->eab", self.wdet, self.G, S, self.G)
            Ke = Ke + np.einsum("eab,ik->eaibk", Kg, I)
        ne, nen = self.cells.shape
        return Ke.reshape(ne, nen * d, nen * d), fe.reshape(ne, nen * d)

    def solve(self, fixed_nodes, fext, law, steps):
        d = self.d
        n = self.nn * d
        fixed = np.zeros(n, dtype=bool)
        for node in fixed_nodes:
            fixed[node * d:(node + 1) * d] = True
        free = ~fixed
        u = np.zeros(n)
        nsteps = 1 if law == "hooke" else steps
        for step in range(1, nsteps + 1):
            lf = fext * step / nsteps
            extra = 0
            for it in range(50):
                K, fint = self._assemble(*self.internal(u, law))
                r = lf - fint
                # Rounding floor of the residual is ~1e-12 relative; once
                # below 1e-10 (quadratic convergence), one more correction
                # lands on the floor.
                if np.linalg.norm(r[free]) <= 1e-10 * np.linalg.norm(fext[free]):
                    extra += 1
                    if extra > 1:
                        break
                du = np.linalg.solve(K[np.ix_(free, free)], r[free])
                u[free] += du
            else:
                raise RuntimeError("NumPy Newton did not converge")
        out = np.zeros((self.nn, 3))
        out[:, :d] = u.reshape(self.nn, d)
        return out


def numpy_solution(etype, kind, load, pts, cells, clamp_nodes, tip_nodes):
    fe = NumpyFE(etype, pts, cells)
    vec = load_vector(etype, load)[:fe.d]
    if load == "gravity":
        fext = fe.gravity_force(vec)
    else:
        f = np.zeros((fe.nn, fe.d))
        f[tip_nodes] = vec
        fext = f.reshape(-1)
    return fe.solve(clamp_nodes, fext, "stvk" if kind == "nlgeom" else "hooke", NLGEOM_INCREMENTS)


def rel_error(u, ref):
    return np.max(np.linalg.norm(u - ref, axis=1)) / np.max(np.linalg.norm(ref, axis=1))


# --- Driver -----------------------------------------------------------------

def make_case(ccx, etype, kind, load, self_check, report):
    name = case_name(etype, kind, load)
    gmsh_order, ccx_order, ccx_type = read_node_orders(etype)
    pts, cells = build_mesh(etype)
    ftype, clamp = boundary_facets(etype, pts, cells, 0.0)
    _, tip = boundary_facets(etype, pts, cells, LENGTH)
    clamp_nodes, tip_nodes = nodes_of(clamp), nodes_of(tip)
    # Every node is used by a cell.
    assert len(np.unique(cells)) == len(pts)

    case_dir = os.path.join(CASES_DIR, name)
    os.makedirs(case_dir, exist_ok=True)
    for old in os.listdir(case_dir):
        os.remove(os.path.join(case_dir, old))
    msh = os.path.join(case_dir, "mesh.msh")
    deck = os.path.join(case_dir, "ccx.inp")
    write_msh(msh, etype, pts, cells, clamp, tip, ftype, gmsh_order)
    write_ccx_deck(deck, name, etype, kind, load, pts, cells, clamp_nodes, tip_nodes,
                   ccx_order, ccx_type)
    write_scene(os.path.join(case_dir, "scene.yaml"), etype, kind, load)

    u, rf, log, sta = ccx_solve(ccx, deck, len(pts))

    # Checks on the CalculiX answer itself.
    # CalculiX's RF is the internal force at the supports, so it balances
    # the load on the free nodes; gravity also loads the clamp nodes
    # directly (consistent nodal loads rho g integral N_i, of total
    # rho g V; their clamp share is computed here by exact quadrature).
    d = dim_of(etype)
    vec = np.array(load_vector(etype, load))
    if load == "gravity":
        volume = LENGTH * WIDTH * (DEPTH if d == 3 else 1.0)
        f_nodes = NumpyFE(etype, pts, cells).gravity_force(vec[:d]).reshape(-1, d)
        assert np.allclose(f_nodes.sum(axis=0), DENSITY * volume * vec[:d], rtol=1e-12, atol=0)
        applied = np.zeros(3)
        applied[:d] = f_nodes.sum(axis=0) - f_nodes[clamp_nodes].sum(axis=0)
    else:
        applied = len(tip_nodes) * vec
    rf_err = np.max(np.abs(rf + applied)) / np.max(np.abs(applied))
    if rf_err > 2e-6:
        raise CcxError(f"{name}: clamp reactions {rf} do not balance the load on the free nodes {applied}")
    if dim_of(etype) == 2 and np.max(np.abs(u[:, 2])) != 0.0:
        raise CcxError(f"{name}: out-of-plane displacement in a plane strain case")
    if np.max(np.abs(u[clamp_nodes])) != 0.0:
        raise CcxError(f"{name}: clamp nodes moved")
    write_reference(os.path.join(case_dir, "reference.csv"), u)

    tip_defl = np.max(np.linalg.norm(u[tip_nodes], axis=1))
    its = newton_iterations(sta) if kind == "nlgeom" else []
    line = (f"{name:24s} nodes {len(pts):4d} cells {len(cells):4d}  max|u| {np.max(np.linalg.norm(u, axis=1)):.6f}"
            f"  tip max|u| {tip_defl:.6f}  reaction err {rf_err:.1e}")
    if its:
        line += f"  increments {len(its)}, Newton its {its}"
    entry = {"name": name, "tip": tip_defl, "umax": np.max(np.linalg.norm(u, axis=1)),
             "rf_err": rf_err, "its": its}

    if self_check:
        # Gmsh file read back by meshio (which converts Gmsh node order to VTK).
        import contextlib
        import io
        import meshio
        with contextlib.redirect_stdout(io.StringIO()):  # meshio prints a blank line
            m = meshio.read(msh)
        ctype = {"tet4": "tetra", "tet10": "tetra10", "hex8": "hexahedron",
                 "hex20": "hexahedron20", "quad4": "quad", "tri3": "triangle"}[etype]
        back = np.concatenate([c.data for c in m.cells if c.type == ctype])
        assert np.array_equal(back, cells), f"{name}: meshio reads another connectivity"
        assert np.array_equal(m.points, pts)
        # Independent NumPy solution.
        u_np = numpy_solution(etype, kind, load, pts, cells, clamp_nodes, tip_nodes)
        err_np = rel_error(u, u_np)
        entry["numpy"] = err_np
        line += f"  |ccx-numpy| {err_np:.2e}"
        if kind == "nlgeom":
            u_lin = numpy_solution(etype, "linear", load, pts, cells, clamp_nodes, tip_nodes)
            entry["nonlinearity"] = rel_error(u_lin, u)
            line += f"  |hooke-stvk| {entry['nonlinearity']:.3f}"
            # Same deck with CalculiX's default convergence controls.
            with tempfile.TemporaryDirectory(prefix="ccxdef_") as work:
                d2 = os.path.join(work, "default.inp")
                write_ccx_deck(d2, name, etype, kind, load, pts, cells, clamp_nodes, tip_nodes,
                               ccx_order, ccx_type, controls=False)
                u_def, _, _, sta_def = ccx_solve(ccx, d2, len(pts))
            entry["default_controls"] = rel_error(u_def, u)
            entry["default_numpy"] = rel_error(u_def, u_np)
            line += (f"  default controls: its {newton_iterations(sta_def)},"
                     f" |default-tight| {entry['default_controls']:.2e},"
                     f" |default-numpy| {entry['default_numpy']:.2e}")
    print(line, flush=True)
    report.append(entry)
    return entry


def calibrate():
    """Print the load magnitudes that give max|u| = 0.15 L in the Hooke solution."""
    for etype in ELEMENT_TYPES:
        pts, cells = build_mesh(etype)
        _, clamp = boundary_facets(etype, pts, cells, 0.0)
        _, tip = boundary_facets(etype, pts, cells, LENGTH)
        for load in LOAD_TYPES:
            saved = LOADS[(etype, load)]
            LOADS[(etype, load)] = 1.0
            u = numpy_solution(etype, "linear", load, pts, cells, nodes_of(clamp), nodes_of(tip))
            LOADS[(etype, load)] = saved
            umax = np.max(np.linalg.norm(u, axis=1))
            mag = 0.15 * LENGTH / umax
            print(f'    ("{etype}", "{load}"): {float(f"{mag:.3g}")},')


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ccx", default=os.environ.get("CCX", "ccx"), help="CalculiX binary (default: ccx)")
    ap.add_argument("--only", nargs="*", help="case names to (re)build (default: all 24)")
    ap.add_argument("--self-check", action="store_true",
                    help="compare with an independent NumPy FE solve, read meshes back with "
                         "meshio, and re-run NLGEOM decks with default ccx controls")
    ap.add_argument("--calibrate", action="store_true", help="print the load magnitudes table")
    args = ap.parse_args()
    if args.calibrate:
        calibrate()
        return 0
    version = subprocess.run([args.ccx, "-v"], capture_output=True, text=True).stdout
    print(f"CalculiX: {' '.join(version.split())}", flush=True)
    cases = all_cases()
    if args.only:
        names = {case_name(*c): c for c in cases}
        unknown = [n for n in args.only if n not in names]
        if unknown:
            ap.error(f"unknown case(s): {', '.join(unknown)}")
        cases = [names[n] for n in args.only]
    report = []
    for etype, kind, load in cases:
        make_case(args.ccx, etype, kind, load, args.self_check, report)
    if args.self_check:
        worst = max(e["numpy"] for e in report)
        print(f"self-check: largest |ccx - numpy| / max|u| = {worst:.2e} "
              "(CalculiX results are float32: ~6e-8 relative rounding)")
        if worst > 3e-7:
            print("self-check FAILED")
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
