#!/usr/bin/python3
"""docs/results/mpi.md from tests/runtime/parallel/check_mpi_runs.py's and bench/mpi_scaling.py's JSON.

usage: /usr/bin/python3 scripts/results/render_mpi.py mpi_agreement.json mpi_scaling.json > docs/results/mpi.md
"""
import sys

from results_common import bold, load, table, thousands

# scene name of check_mpi_runs.py -> what its row says
SCENES = {
    "static_stvk": "static StVK, 3 load steps, CG + GAMG",
    "static_mumps_direct": "static StVK, MUMPS direct Cholesky (`-ksp_type preonly -pc_type cholesky "
                           "-pc_factor_mat_solver_type mumps`)",
    "implicit_damped": "implicit StVK, Rayleigh damping (mass and stiffness), 15 steps",
    "static_mixed": "static neo-Hookean, mixed hex8/tet4/prism6 mesh",
    "implicit_switching": "implicit, adaptive `[hooke, neohookean]` (cells switch laws)",
    "explicit": "explicit StVK, 300 steps",
    "explicit_switching": "explicit, adaptive (cells switch laws, criteria screen on)",
    "static_loads_tet10": "static StVK, tet10 beam, pressure and nodal forces on the tip",
    "implicit_loads_2d": "implicit StVK, 2D quad plate, pressure and nodal forces on the tip",
    "implicit_refining": "implicit, refining the mesh (whole mesh on every rank)",
    "static_refining_mixed": "static, refining the mixed mesh (whole mesh on every rank)",
}

PAGE = """# Several MPI ranks: `solver.backend: petsc`

`mpirun -n N tensormass run SCENE --set solver.backend=petsc` shares a run
among N ranks: each assembles the cells of its part of the mesh (cut by Scotch)
into its rows of a PETSc MPIAIJ matrix, PETSc's KSP solves (CG + GAMG by
default), and each rank takes its own rows of the solution and its ghost
nodes' values from their owners. How it works:
[architecture](../architecture.md#data-flow-of-a-run); the keys:
[scene reference](../scene.md#several-mpi-ranks-solverbackend-petsc); where
the memory of the first step goes and how CG fares on a large-deflection
static tangent: [profiles.md](profiles.md#mpi-the-first-steps-memory).

The agreement: measured on {a_machine} ({a_threads} threads) on {a_date},
tensormass {a_version}, commit `{a_commit}`. The strong scaling: measured on
{s_machine} ({s_threads} threads) on {s_date}, tensormass {s_version}, commit
`{s_commit}`, load average {s_load} at its start. The commands that remake
them:

```sh
/usr/bin/python3 tests/runtime/parallel/check_mpi_runs.py build/tensormass /tmp/mpi-runs --json docs/results/mpi_agreement.json   # ctest parallel.mpirun, 2 minutes
/usr/bin/python3 bench/mpi_scaling.py --sizes 100k,1M --timeout 300 --json docs/results/mpi_scaling.json   # 6 to 12 minutes
/usr/bin/python3 scripts/results/render_mpi.py docs/results/mpi_agreement.json docs/results/mpi_scaling.json > docs/results/mpi.md
```

## Agreement with the serial solver

ctest `parallel.mpirun` (`tests/runtime/parallel/check_mpi_runs.py`) runs
each scene on the serial solver (CHOLMOD) and under `mpirun -n 1, 2, 3`
with `solver.backend=petsc`, reads `final.vtu` or the `final.pvtu` pieces
(joined by `global_node`), and compares. Largest nodal difference over the
largest displacement (target {tolerance:g}):

{agreement}

Each rank holds its part of the mesh and of the state, numbered in the
part, except in the refining runs. A run on 2 ranks stopped after 10 steps
and resumed from its checkpoint ends where a straight run does, and its
track (its nodes' displacements gathered to rank 0 each step) is the
serial run's within {track:.1e} of its largest displacement. The same
adaptive implicit run made twice on 2 ranks writes byte-identical pieces:
the mesh is cut by sequential Scotch in a deterministic context.{switching}{mixed}

Each rank evaluates the criteria of its own cells only and decides them; on
mesh parts each owner sends its cells' moves to the neighbours that hold
them, and where every rank holds the whole mesh one sum over the ranks per
evaluation gives every rank every move. Either way the laws stay the same
everywhere, and the counts in `summary.json` are the ranks' decisions added
up. Explicit runs agree to round-off: each rank sums its own rows' cell
contributions in its part's numbering. The same test checks that the
pieces hold every cell exactly once, that a bad scene exits 2 on both ranks
with its message printed once, and that a numerical failure exits 3 with
one message and leaves `last_good.pvtu`, its pieces and `summary.json`.
The distribution itself is tested in one process with simulated ranks
(`tests/runtime/parallel/test_distribution.cpp`): each rank's own rows of
the tangent and of the forces equal the serial assembly bit for bit, for 1,
2 and 3 ranks, on a mixed mesh, with and without the folded linear part.

## Strong scaling on this machine

`bench/mpi_scaling.py` (`--smoke` is the 6k-tet version run by ctest
`bench.mpi_scaling.smoke`): 3D StVK cantilevers of tet6 beams under
gravity, E = 20 MPa ({sizes}). Static: {load_steps} load steps, Newton
tolerance 1e-8. Implicit: {steps} steps of 0.01 s, one Newton iteration
each. Explicit: {explicit_steps} steps of 10 us ("serial" is one process
with no backend, both cores in the assembly). Default settings otherwise:
the serial runs use both cores for assembly (OpenMP) and one for the solve;
the runs on several ranks one thread per rank. ms per step is the mean over
the steps (the first one includes GAMG's setup or CHOLMOD's analysis); wall
includes reading the mesh, building the model and the cut.

{scaling}

CHOLMOD is not run at a million tets: its factorisation grows about as n^2
on these meshes ([scaling.md](scaling.md)).

## What the table says

{speedups}

## Towards 10 million cells

A step's work beyond PETSc is over the rank's part: each rank holds the
nodes its cells use and every vector of the run over them, computes its own
rows, receives its ghost nodes' values from their owners (one message per
neighbour), and sums its dot products and norms over the ranks (one double
each). What still involves the whole mesh on some rank: rank 0 reads the
whole file and cuts it on one process (a parallel reader would remove it);
the rank-by-rank numbering sums one whole-length vector over the ranks
once; runs with tracks sum the tracked nodes' displacements over the ranks
at each step (to rank 0's tracks); checkpoints and the final report gather
the whole state; runs that refine the mesh, adaptive runs that write or
resume checkpoints, and Python scripts keep the whole mesh and state on
every rank. How the step time would scale is not measured: GAMG's
iterations per step would have to stay near constant as the mesh and the
rank count grow together, the weak scaling smoothed aggregation is designed
for.
"""


def difference(row):
    if row is None:
        return "-"
    return "0" if row["difference"] == 0 else f"{row['difference']:.1e}"


def agreement(data):
    by_scene = {}
    for r in data["rows"]:
        by_scene.setdefault(r["scene"], {})[r["ranks"]] = r
    ranks = sorted({r["ranks"] for r in data["rows"] if r["scene"] in SCENES})
    rows = []
    for scene, label in SCENES.items():
        if scene not in by_scene:
            continue
        rows.append([label] + [difference(by_scene[scene].get(n)) for n in ranks])
    return table(["scene"] + [f"{n} rank{'s' if n > 1 else ''}" for n in ranks], rows, ["l"] + ["r"] * len(ranks))


def scaling_rows(data):
    rows = []
    for r in data["rows"]:
        solver = r["solver"] + (f" x{r['ranks']}" if r["ranks"] > 1 else "")
        if "ms_per_step" not in r:
            why = f"stopped after {r['stopped_after_s']:g} s" if "stopped_after_s" in r else "failed"
            rows.append([r["size"], r["integrator"], solver, why, "", "", "", "", ""])
            continue
        rows.append([r["size"], r["integrator"], solver, f"{r['wall_s']:.1f}", f"{r['ms_per_step']:.0f}",
                     f"{r['assembly_ms']:.0f}", f"{r['solve_ms']:.0f}", f"{r['newton']} / {r['linear_iterations']}",
                     " / ".join(f"{m:.0f}" for m in r["peak_mib_per_rank"])])
    return table(["size", "integrator", "solver", "wall s", "ms/step", "assembly ms/step", "solve ms/step",
                  "Newton / linear its", "peak MiB per rank"], rows, ["l", "l", "l", "r", "r", "r", "r", "r", "l"])


def find(rows, size, integrator, solver, ranks):
    for r in rows:
        if (r["size"], r["integrator"], r["solver"], r["ranks"]) == (size, integrator, solver, ranks) and "ms_per_step" in r:
            return r
    return None


def speedups(data):
    rows = data["rows"]
    most = max(r["ranks"] for r in rows)
    lines = []
    for size in dict.fromkeys(r["size"] for r in rows):
        parts, memory = [], []
        for integrator, solver in (("static", "petsc"), ("implicit", "petsc"), ("explicit", "serial")):
            one = find(rows, size, integrator, solver, 1)
            many = find(rows, size, integrator, "petsc", most)
            if one and many:
                parts.append(f"{integrator} {one['ms_per_step'] / many['ms_per_step']:.2f}x")
                memory.append(f"{integrator} {max(many['peak_mib_per_rank']) / max(one['peak_mib_per_rank']):.2f}x")
        if parts:
            lines.append(f"- **{size}, {most} ranks against one process**: step {', '.join(parts)} faster; peak "
                         f"memory per rank {', '.join(memory)} the one process's.")
    lines.append("- The assembly runs on both cores (OpenMP) in the one-process runs too, so the gain of the ranks is "
                 "PETSc's solve; the ranks share the machine's memory bandwidth.")
    return "\n".join(lines)


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    agree, scale = load(argv[1]), load(argv[2])
    am, sm = agree["metadata"], scale["metadata"]
    track = [r["difference"] for r in agree["rows"] if r["scene"] == "resumed_track"]
    switching = [r for r in agree["rows"] if r["scene"] in ("implicit_switching", "explicit_switching")]
    switched = (" In the switching runs every cell ends under the same law as in the serial run."
                if switching and all(r["laws_equal"] for r in switching) else "")
    mixed = sorted(r["difference"] for r in agree["rows"] if r["scene"] == "static_mixed")
    mixed_note = (f" The mixed static run's {mixed[0]:.1e} is the same on one rank: it is PETSc's CG against CHOLMOD "
                  "within the Newton tolerance, not the ranks." if mixed and mixed[-1] - mixed[0] <= 0.1 * mixed[-1]
                  and mixed[-1] > 1e-12 else "")
    settings = scale["settings"]
    sizes = "; ".join(f"{size}: {' x '.join(map(str, s['cubes']))} cubes over {' x '.join(f'{x:g}' for x in s['box_m'])} m"
                      for size, s in settings["sizes"].items() if any(r["size"] == size for r in scale["rows"]))
    print(PAGE.format(
        a_machine=am["machine"], a_threads=am["threads"], a_date=am["date"][:10], a_version=am["tensormass_version"],
        a_commit=am["commit"], s_machine=sm["machine"], s_threads=sm["threads"], s_date=sm["date"][:10],
        s_version=sm["tensormass_version"], s_commit=sm["commit"], s_load=sm["load_average"],
        tolerance=agree["tolerance"], agreement=agreement(agree), track=track[0] if track else float("nan"),
        switching=switched, mixed=mixed_note, sizes=sizes, load_steps=settings["load_steps"], steps=settings["steps"],
        explicit_steps=settings["explicit_steps"], scaling=scaling_rows(scale), speedups=speedups(scale)).rstrip())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
