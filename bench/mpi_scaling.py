#!/usr/bin/env python3
"""Strong scaling of `solver.backend: petsc` over MPI ranks on this machine.

3D StVK cantilevers (tet6 beams under gravity, clamped at x = 0), default
settings, one scene per size and integrator:
  static    `--load-steps` load steps, Newton tolerance 1e-8
  implicit  `--steps` steps of 0.01 s (one Newton iteration per step)
  explicit  `--explicit-steps` steps of 10 us (lumped mass, no linear solve)
each run with
  cholmod   the serial default (sparse Cholesky with factor reuse), not at 1M
  cg        serial Jacobi-preconditioned conjugate gradients
  petsc     PETSc CG + GAMG on one process (no mpirun)
  serial    explicit only: one process, no backend
  petsc xN  the same over N MPI ranks (mpirun -n N), one thread each
and prints, per run: wall time, mean ms per step and its assembly / solve
split, linear iterations, every rank's peak resident memory and the cells
each rank holds (from each run's summary.json). A run past `--timeout` seconds is stopped and
reported as such. Writes the rows as JSON with --json.

    /usr/bin/python3 bench/mpi_scaling.py [--binary build/tensormass] [--sizes 100k,1M] [--ranks 2]
    /usr/bin/python3 bench/mpi_scaling.py --smoke      # a 6k-tet run of each kind (ctest)
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

# cubes per axis (x 6 tets) and box size in metres
SIZES = {
    "6k": ((20, 5, 10), (4.0, 1.0, 2.0)),
    "100k": ((70, 12, 20), (7.0, 1.2, 2.0)),
    "1M": ((140, 30, 40), (7.0, 1.5, 2.0)),
}

SCENE = """mesh: {mesh}
materials: [{{region: all, law: stvk, young: 2.0e7, poisson: 0.3, density: 1000}}]
fixed: [clamp]
loads: {{gravity: [0, -9.81, 0]}}
solver: {solver}
output: {{directory: {out}}}
"""
SOLVERS = {
    "static": "{{type: static, load_steps: {load_steps}, tolerance: 1.0e-8}}",
    "implicit": "{{type: implicit, dt: 0.01, steps: {steps}}}",
    "explicit": "{{type: explicit, dt: 1.0e-5, steps: {explicit_steps}}}",
}


def run_one(args, work, mesh, size, kind, solver, ranks):
    out = f"out-{size}-{kind}-{solver}-{ranks}"
    scene = os.path.join(work, out + ".yaml")
    with open(scene, "w") as f:
        f.write(SCENE.format(mesh=mesh, out=out,
                             solver=SOLVERS[kind].format(load_steps=args.load_steps, steps=args.steps,
                                                         explicit_steps=args.explicit_steps)))
    command = [args.binary, "run", scene, "--quiet"]
    if solver in ("cholmod", "cg"):
        command += ["--set", f"solver.linear.type={solver}"]
    elif solver == "petsc":
        command += ["--set", "solver.backend=petsc"]
    if ranks > 1:
        command = ["mpirun", "-n", str(ranks)] + (["--oversubscribe"] if ranks > os.cpu_count() else []) + command
    row = {"size": size, "integrator": kind, "solver": solver, "ranks": ranks}
    start = time.perf_counter()
    try:
        result = subprocess.run(command, cwd=work, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        row["stopped_after_s"] = args.timeout
        return row
    row["wall_s"] = time.perf_counter() - start
    if result.returncode != 0:
        row["error"] = result.stderr.strip()[-500:]
        return row
    with open(os.path.join(work, out, "summary.json")) as f:
        summary = json.load(f)
    steps = max(1, summary["steps"])
    row.update({
        "cells": summary["elements"],
        "dofs": summary["free_dofs"],
        "ms_per_step": summary["time_per_step_ms"]["mean"],
        "assembly_ms": 1e3 * summary["time_per_phase_s"]["assembly"] / steps,
        "solve_ms": 1e3 * summary["time_per_phase_s"]["solve"] / steps,
        "newton": summary["newton_iterations"]["total"],
        "linear_iterations": summary["linear_iterations"],
        "peak_mib_per_rank": summary["peak_memory_mib_per_rank"],
        "cells_per_rank": summary["cells_per_rank"],
        "max_displacement": summary["max_displacement"]["value"],
    })
    shutil.rmtree(os.path.join(work, out), ignore_errors=True)
    return row


def describe(row):
    name = row["solver"] + (f" x{row['ranks']}" if row["ranks"] > 1 else "")
    head = f"| {row['size']} | {row['integrator']} | {name} |"
    if "stopped_after_s" in row:
        return head + f" stopped after {row['stopped_after_s']} s | | | | | |"
    if "error" in row:
        return head + f" failed: {row['error']} | | | | | |"
    memory = " / ".join(f"{m:.0f}" for m in row["peak_mib_per_rank"])
    return (head + f" {row['wall_s']:.1f} | {row['ms_per_step']:.0f} | {row['assembly_ms']:.0f} | "
            f"{row['solve_ms']:.0f} | {row['newton']} / {row['linear_iterations']} | {memory} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="build/tensormass")
    parser.add_argument("--sizes", default="100k,1M")
    parser.add_argument("--ranks", type=int, default=2, help="the largest rank count (runs 1 .. N)")
    parser.add_argument("--load-steps", type=int, default=2)
    parser.add_argument("--steps", type=int, default=5)
    parser.add_argument("--explicit-steps", type=int, default=20)
    parser.add_argument("--timeout", type=float, default=600)
    parser.add_argument("--json", help="write the rows here")
    parser.add_argument("--smoke", action="store_true", help="one 6k-tet run of each kind, 2 steps")
    args = parser.parse_args()
    args.binary = os.path.abspath(args.binary)
    sizes = ["6k"] if args.smoke else args.sizes.split(",")
    if args.smoke:
        args.load_steps, args.steps, args.explicit_steps, args.timeout = 1, 2, 5, 120
    if os.geteuid() == 0:
        os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
        os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    if not shutil.which("mpirun"):
        print("no mpirun: apt-get install openmpi-bin")
        return 1
    work = tempfile.mkdtemp(prefix="tm-mpi-bench-")
    rows = []
    print("| size | integrator | solver | wall s | ms/step | assembly ms/step | solve ms/step | "
          "Newton / linear its | peak MiB per rank |")
    print("|---|---|---|---:|---:|---:|---:|---:|---|")
    for size in sizes:
        cells, box = SIZES[size]
        mesh = os.path.join(work, f"beam-{size}.msh")
        subprocess.run([args.binary, "beam", "--dim", "3", "--type", "tet6", "--cells", ",".join(map(str, cells)),
                        "--size", ",".join(map(str, box)), "-o", mesh], check=True, capture_output=True)
        for kind in ("static", "implicit", "explicit"):
            if kind == "explicit":
                plan = [("serial", 1)]
            else:
                plan = ([] if size == "1M" else [("cholmod", 1)]) + [("cg", 1), ("petsc", 1)]
            plan += [("petsc", r) for r in range(2, args.ranks + 1)]
            for solver, ranks in plan:
                row = run_one(args, work, mesh, size, kind, solver, ranks)
                rows.append(row)
                print(describe(row), flush=True)
        os.remove(mesh)
    if args.json:
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        from bench_metadata import metadata
        settings = {"sizes": {size: {"cubes": list(SIZES[size][0]), "box_m": list(SIZES[size][1])} for size in SIZES},
                    "load_steps": args.load_steps, "steps": args.steps, "explicit_steps": args.explicit_steps}
        with open(args.json + ".tmp", "w") as f:
            json.dump({"metadata": metadata(os.path.abspath(args.binary)), "settings": settings, "rows": rows}, f,
                      indent=1)
            f.write("\n")
        os.replace(args.json + ".tmp", args.json)
    shutil.rmtree(work, ignore_errors=True)
    failed = [r for r in rows if "error" in r]
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
