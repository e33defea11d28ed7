#!/usr/bin/env python3
"""Compare tensormass with the CalculiX reference solutions.

For each case directory (default: every directory under cases/), copy the case
to a temporary directory, run

    TENSORMASS run scene.yaml --set output.directory=OUTDIR

read OUTDIR/final.vtu (point data ``displacement``, 3 components) and compare
it with the case's reference.csv:

    error = max_i |u_i - u_ref_i| / max_i |u_ref_i|     (|.|: nodal vector norm)

A case passes when error <= tolerance (default 1e-6).  One line is printed per
case; the exit status is 1 if any case fails.

Usage:
  compare.py [--binary PATH] [--tolerance 1e-6] [--keep] [CASE_DIR_OR_NAME ...]

The binary defaults to $TENSORMASS, else <repo>/build/tensormass.
"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
CASES_DIR = os.path.join(HERE, "cases")


class CaseFailure(Exception):
    pass


def read_reference(path):
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.shape[1] != 4 or not np.array_equal(data[:, 0], np.arange(len(data))):
        raise CaseFailure(f"{path}: expected columns node,ux,uy,uz with nodes 0..n-1")
    return data[:, 1:4]


def read_msh_nodes(path):
    """Node coordinates of a Gmsh 2.2 ASCII file, in file order (tags 1..n)."""
    with open(path) as f:
        lines = f.read().splitlines()
    start = lines.index("$Nodes")
    n = int(lines[start + 1])
    rows = [line.split() for line in lines[start + 2:start + 2 + n]]
    if [int(r[0]) for r in rows] != list(range(1, n + 1)):
        raise CaseFailure(f"{path}: node tags are not 1..{n} in order")
    return np.array([[float(v) for v in r[1:4]] for r in rows])


def tail(text, lines=15):
    rows = text.rstrip().splitlines()
    return "\n".join("      | " + r for r in rows[-lines:])


def match_points(points, mesh_points):
    """Index map vtu point -> mesh node (identity when the order is kept).

    Coordinates are compared to 1e-6 of the model size, so that single
    precision VTU points still match; mesh nodes are >= 0.05 apart."""
    scale = max(1.0, float(np.max(np.abs(mesh_points))))
    tol = 1e-6 * scale
    if points.shape == mesh_points.shape and np.max(np.abs(points - mesh_points)) <= tol:
        return np.arange(len(points)), None
    if points.ndim != 2 or points.shape[1] != 3:
        raise CaseFailure(f"final.vtu points have shape {points.shape}")
    dist = np.linalg.norm(points[:, None, :] - mesh_points[None, :, :], axis=2)
    idx = np.argmin(dist, axis=1)
    far = np.flatnonzero(dist[np.arange(len(points)), idx] > tol)
    if len(far):
        raise CaseFailure(f"final.vtu point {points[far[0]].tolist()} is not a node of mesh.msh")
    if len(points) != len(mesh_points) or len(set(idx.tolist())) != len(mesh_points):
        raise CaseFailure(f"final.vtu has {len(points)} points that do not match the "
                          f"{len(mesh_points)} mesh nodes one to one")
    return idx, "final.vtu points are not in mesh order; matched by coordinates"


def run_case(binary, case_dir, tolerance, keep, timeout):
    import meshio

    name = os.path.basename(os.path.normpath(case_dir))
    ref = read_reference(os.path.join(case_dir, "reference.csv"))
    work = tempfile.mkdtemp(prefix=f"tensormass_validation_{name}_")
    notes = []
    try:
        for entry in os.listdir(case_dir):
            src = os.path.join(case_dir, entry)
            if os.path.isfile(src):
                shutil.copy(src, work)
        outdir = os.path.join(work, "compare_out")
        cmd = [binary, "run", "scene.yaml", "--set", f"output.directory={outdir}"]
        t0 = time.monotonic()
        try:
            proc = subprocess.run(cmd, cwd=work, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise CaseFailure(f"tensormass did not finish within {timeout} s: {' '.join(cmd)}")
        except OSError as exc:
            raise CaseFailure(f"cannot run {binary}: {exc}")
        elapsed = time.monotonic() - t0
        output = (proc.stdout or "") + (proc.stderr or "")
        vtu = os.path.join(outdir, "final.vtu")
        if not os.path.isfile(vtu):
            listing = sorted(os.listdir(outdir)) if os.path.isdir(outdir) else None
            msg = [f"final.vtu is MISSING: tensormass did not write {vtu}",
                   f"    command: {' '.join(cmd)}  (in {work})",
                   f"    exit code: {proc.returncode}",
                   f"    output directory: {'does not exist' if listing is None else (listing or 'empty')}"]
            if output.strip():
                msg.append("    tensormass output (last lines):\n" + tail(output))
            raise CaseFailure("\n".join(msg))
        if proc.returncode != 0:
            raise CaseFailure(f"tensormass exited with code {proc.returncode} "
                              f"(final.vtu was written)\n" + tail(output))
        try:
            result = meshio.read(vtu)
        except Exception as exc:  # meshio raises various types
            raise CaseFailure(f"cannot read {vtu}: {exc}")
        if "displacement" not in result.point_data:
            raise CaseFailure(f"final.vtu has no point data 'displacement' "
                              f"(has: {sorted(result.point_data) or 'none'})")
        u = np.asarray(result.point_data["displacement"], dtype=float)
        if u.ndim != 2 or u.shape[1] not in (2, 3):
            raise CaseFailure(f"'displacement' has shape {u.shape}, expected (n, 3)")
        if u.shape[1] == 2:
            notes.append("'displacement' has 2 components (contract: 3)")
            u = np.hstack([u, np.zeros((len(u), 1))])
        mesh_points = read_msh_nodes(os.path.join(case_dir, "mesh.msh"))
        if len(mesh_points) != len(ref):
            raise CaseFailure(f"mesh.msh has {len(mesh_points)} nodes, reference.csv {len(ref)} rows")
        idx, note = match_points(np.asarray(result.points, dtype=float), mesh_points)
        if note:
            notes.append(note)
        u_nodes = np.full_like(ref, np.nan)
        u_nodes[idx] = u
        if not np.all(np.isfinite(u_nodes)):
            raise CaseFailure("final.vtu displacement has NaN or infinite values")
        diff = np.linalg.norm(u_nodes - ref, axis=1)
        scale = np.max(np.linalg.norm(ref, axis=1))
        err = float(np.max(diff) / scale)
        worst = int(np.argmax(diff))
        return err, worst, scale, elapsed, notes
    finally:
        if keep:
            print(f"    (kept {work})")
        else:
            shutil.rmtree(work, ignore_errors=True)


def resolve_cases(args):
    if not args:
        if not os.path.isdir(CASES_DIR):
            return []
        return [os.path.join(CASES_DIR, d) for d in sorted(os.listdir(CASES_DIR))
                if os.path.isfile(os.path.join(CASES_DIR, d, "scene.yaml"))]
    out = []
    for a in args:
        if os.path.isdir(a):
            out.append(os.path.abspath(a))
        elif os.path.isdir(os.path.join(CASES_DIR, a)):
            out.append(os.path.join(CASES_DIR, a))
        else:
            raise SystemExit(f"compare.py: no case directory {a!r}")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cases", nargs="*", help="case directories or names under cases/ (default: all)")
    ap.add_argument("--binary", default=os.environ.get("TENSORMASS", os.path.join(ROOT, "build", "tensormass")),
                    help="tensormass executable (default: $TENSORMASS or build/tensormass)")
    ap.add_argument("--tolerance", type=float, default=1e-6, help="relative error bound (default 1e-6)")
    ap.add_argument("--timeout", type=float, default=280.0, help="seconds per tensormass run")
    ap.add_argument("--keep", action="store_true", help="keep the temporary run directories")
    args = ap.parse_args()

    binary = os.path.abspath(args.binary) if os.sep in args.binary else (shutil.which(args.binary) or args.binary)
    if not (os.path.isfile(binary) and os.access(binary, os.X_OK)):
        print(f"FAIL: tensormass binary not found or not executable: {binary}")
        return 1
    cases = resolve_cases(args.cases)
    if not cases:
        print("FAIL: no validation cases found")
        return 1
    failed = 0
    for case_dir in cases:
        name = os.path.basename(os.path.normpath(case_dir))
        try:
            err, worst, scale, elapsed, notes = run_case(binary, case_dir, args.tolerance,
                                                         args.keep, args.timeout)
        except CaseFailure as exc:
            failed += 1
            print(f"FAIL {name}: {exc}", flush=True)
            continue
        ok = err <= args.tolerance
        failed += 0 if ok else 1
        print(f"{'PASS' if ok else 'FAIL'} {name}: relative error {err:.3e} (tolerance {args.tolerance:.0e}; "
              f"max|u_ref| {scale:.6g}, worst node {worst}; {elapsed:.2f} s)", flush=True)
        for n in notes:
            print(f"    note: {n}")
    print(f"{len(cases) - failed}/{len(cases)} cases passed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
