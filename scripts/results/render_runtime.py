#!/usr/bin/python3
"""docs/results/runtime.md from `tensormass bench runtime --json FILE`.

usage: /usr/bin/python3 scripts/results/render_runtime.py runtime.json > docs/results/runtime.md
"""
import sys

from results_common import bold, load, table, thousands

PAGE = """# Whole-solver timings: `tensormass bench runtime`

Wall-clock timings of complete solves: tensormass against CalculiX on a
static St Venant-Kirchhoff (StVK) cantilever, the default thread count
against one thread, implicit dynamic steps on 10k and 100k tetrahedra, the
origin report's 600-quad beam (Hooke against StVK), batched kernels in the
assembly, and the sparse products and scatter. Why some targets are missed,
in instruction counts: [profiles.md](profiles.md).

Measured on {machine} ({threads} threads) on {date}, tensormass {version},
commit `{commit}`, {build}; BLAS {blas}; one run of {seconds:.0f} s, load
average {load_start} at the start and {load_end} at the end (read 10 %
differences as noise).

## Reproduce

```sh
cmake -S . -B build -G Ninja && cmake --build build   # TENSORMASS_BUILD_BENCH=ON is the default
./build/tensormass bench runtime --json docs/results/runtime.json
/usr/bin/python3 scripts/results/render_runtime.py docs/results/runtime.json > docs/results/runtime.md
./build/tensormass bench runtime --quick              # CI smoke test, a few seconds (ctest -L bench)
./build/tensormass bench runtime --only ccx           # one part: ccx, threads, implicit, quad, batch, spmv or scatter
./build/tensormass bench runtime --only implicit --scaling   # the scaling table, 1k to 1M tets (scaling.md)
```

Options:

- `--threads N`: the thread count of the CalculiX comparison. It applies to
  tensormass and to ccx alike (`OMP_NUM_THREADS=N` for ccx). Default: the
  OpenMP default a user gets (all cores).
- `--scaling`: the implicit table from 1k to a million tets (CG only at a
  million).
- `--ccx PATH`: the CalculiX executable. The default is `$TENSORMASS_CCX`,
  else `ccx` from `PATH`.
- `--keep-ccx`: keeps CalculiX's work directory (deck, `.dat`, `.sta`, log).

The command prints the tables, the targets with PASS/MISS, the BLAS that
CHOLMOD loaded and the load average at the start and the end, and writes
everything to the JSON file, atomically via `FILE.tmp`. Exit codes: 0 when
the run finished (a missed target still exits 0; without ccx the
comparison is skipped with a message); 1 when a solve failed or tensormass
and CalculiX disagree by more than 1e-4; 2 for bad arguments. The ctest
`bench.runtime.quick` (label `bench`) runs the `--quick` variant: the
solvers run and tensormass agrees with CalculiX on a smaller beam; it does
not check the timings.

## Method

Every figure is a median over repetitions run in one process. Runs that are
compared (tensormass against ccx, Hooke against StVK, one thread against
the default) alternate, so that slow drifts of the machine hit both. Each
dynamic run starts with one extra step that is not counted (CHOLMOD's
symbolic analysis and first factorisation, CG's cold start, the first touch
of memory).

1. **Static StVK cantilever against CalculiX** (`--only ccx`): {ccx_tets}
   tet4 and {ccx_nodes} nodes (`make_beam` 3D, 40 x 8 x 8 cubes cut into 6
   tets each), 5 x 1 x 1 m, clamped at x = 0; StVK, E = {ccx_young:g} Pa,
   nu = 0.3, rho = 1000 kg/m^3, gravity {ccx_gravity:g} m/s^2 along -y,
   {ccx_increments} load steps (fixed increments for ccx); the tip deflects
   {ccx_tip:.3f} m. tensormass: its default settings ({ccx_threads} threads,
   CHOLMOD), Newton with line search, relative residual 1e-10, its time
   including building the Model and Assembler. CalculiX:
   `bench/calculix_runner.cpp` writes the deck (C3D4 in our node order,
   `*ELASTIC` + `*STEP, NLGEOM`: the same StVK, total Lagrangian;
   `*STATIC, DIRECT`; `*CONTROLS, PARAMETERS=FIELD` tightened so ccx
   converges each increment to round-off; `*DLOAD GRAV`), run with
   `OMP_NUM_THREADS={ccx_threads}` in a fresh directory, its wall time
   including start-up, deck parsing and output. Agreement: max over nodes
   of |u_tm - u_ccx| over max over nodes of |u_ccx| (ccx prints 7
   significant digits).
2. **Default threads against one** (`--only threads`): an implicit StVK
   beam of {thread_tets} tet4, {thread_steps} steps of 0.01 s, default
   solver settings (CHOLMOD); runs alternate.
3. **Implicit steps** (`--only implicit`): StVK tet6 beams, E = 1e6 Pa,
   gravity, backward Euler with dt = 0.01 s and 1 Newton iteration per
   step, CHOLMOD (its factor reused as a CG preconditioner,
   `linear.reuse_iterations`) or Jacobi-preconditioned CG (tolerance 1e-8,
   warm-started), 1 thread, then the default. The floor: right after each
   run, at its final state and with the same threads, one
   `Assembler::assemble` (gradient and K) plus N_cg times one
   `SparseMatrix::multiply`, N_cg the CG iterations per step.
4. **The origin report's 600-quad beam** (`--only quad`): 60 x 10 quad4,
   6 x 1 m, plane strain, clamped, gravity, E = {quad_young:g} Pa, nu = 0.3,
   rho = 1000 kg/m^3; one core, Hooke and StVK alternating. Implicit:
   backward Euler, dt = 0.01 s, {quad_steps} counted steps, 1 Newton
   iteration, CHOLMOD. Explicit: symplectic Euler at half the estimated
   stable step, {quad_explicit_steps} counted steps (no linear solve: the
   two laws' force evaluations alone). Each law uses its default split.
5. **Batched kernels in the assembly** (`--only batch`): one assembly,
   forces and tangent or forces alone, batched kernels against
   per-element ones.
6. **The tangent product** (`--only spmv`) by node blocks against row by
   row, and the folded Hooke product (`LinearPart::multiply`) in D x D
   sums against one sum per row; **7. the tangent scatter** (`--only
   scatter`) by node blocks against one index per Hessian entry; each the
   default against the plain loop, alternated.

## Targets

{targets}

## 1. Against CalculiX

{ccx}

## 2. Threads

{threads_table}

## 3. Implicit steps

{implicit}

## 4. The 600-quad beam

{quad}

## 5. Batched kernels in the assembly

{batch}

## 6. The tangent product

{spmv}

The rows of a node share one column list made of runs of consecutive
columns, one per neighbour node (`SparseMatrix::node_runs`); the product
reads the values in order with the runs from cache, summing each row into
three partial sums. The values stay in CSR order, so CHOLMOD and PETSc read
the same matrix.

### 6b. The folded Hooke product

{folded}

## 7. The tangent scatter

{scatter}

The scatter map has one index per pair of a cell's nodes (entry (i a, j b)
sits at the pair's position + a times the node's row length + b), where one
per entry of the cell's Hessian would take 144 for a tet4 and 576 for a
hex8; cells with a partly fixed node keep one index per entry. The
additions are the same, in the same order: "same bits" says the tangents
are identical.
"""


def ms(x):
    return f"{x:,.0f}" if x >= 1000 else f"{x:.1f}" if x >= 100 else f"{x:.2f}" if x >= 1 else f"{x:.3f}"


def targets(data):
    rows = [[t["name"], f"{t['value']:.3g}", f"{t['relation']} {t['goal']:g}", bold("met") if t["pass"] else bold("missed")]
            for t in data["targets"]]
    return table(["target", "measured", "goal", "result"], rows)


def ccx(c):
    if "skipped" in c:
        return f"Skipped: {c['skipped']}."
    rows = [["tensormass", f"{c['tensormass_total_s']:.3f} s", c["tensormass_newton_iterations"],
             f"{c['tensormass_assembly_s']:.3f} s assembly, {c['tensormass_linear_s']:.3f} s linear solves"],
            ["CalculiX", f"{c['ccx_wall_s']:.3f} s", c["ccx_iterations"], f"{c['ccx_reported_s']:.3f} s as ccx reports it"]]
    return (table(["solver", "wall time", "Newton iterations", "of which"], rows, ["l", "r", "r", "l"]) +
            "\n\nccx / tensormass: " + bold(f"{c['ratio_ccx_over_tensormass']:.2f}x") + " "
            f"({c['ratio_ccx_over_tensormass_solve_only']:.2f}x against tensormass's solve alone); "
            f"agreement {c['agreement']:.1e}.")


def threads(t):
    rows = [[t[k]["threads"], f"{t[k]['run_s']:.3f} s", f"{t[k]['assembly_s']:.3f} s", f"{t[k]['solve_s']:.3f} s"]
            for k in ("one_thread", "default_threads")]
    return (table(["threads", "run", "assembly", "solve"], rows, ["r"] * 4) +
            "\n\nDefault / one thread: " + bold(f"{t['ratio_default_over_one']:.2f}") + f" ({thousands(t['tets'])} tets, "
            f"{t['steps']} steps).")


def implicit(rows):
    out = []
    for r in rows:
        floor = r["reference_assembly_ms"] + r["linear_iterations_per_step"] * r["spmv_ms"]
        cg = r["solver"] == "cg"
        out.append([r["mesh"], thousands(r["tets"]), thousands(r["free_dofs"]), r["solver"], r["threads"],
                    ms(r["step_ms"]), ms(r["assembly_ms"]), ms(r["solve_ms"]), ms(r["rest_ms"]),
                    f"{r['linear_iterations_per_step']:.1f}", ms(floor) if cg else "",
                    f"{r['step_ms'] / floor:.2f}" if cg else "", ms(r["first_step_ms"])])
    return table(["mesh", "tets", "free dofs", "solver", "threads", "step (ms)", "assembly", "solve", "rest",
                  "linear its", "floor (ms)", "step / floor", "first step (ms)"], out, ["l", "r", "r", "l"] + ["r"] * 9)


def quad(q):
    parts = []
    for name in ("implicit", "explicit"):
        part = q[name]
        rows = [[l["law"], f"{l['step_ms_median']:.4f}", f"{l['assembly_ms']:.4f}", f"{l['solve_ms']:.4f}",
                 f"{l['tip_deflection']:.4f}"] for l in part["laws"]]
        parts.append(f"{name.capitalize()} ({part['steps']} counted steps, dt {part['dt']:.3g} s):\n\n" +
                     table(["law", "step (ms, median)", "assembly", "solve", "tip deflection (m)"], rows,
                           ["l", "r", "r", "r", "r"]) +
                     "\n\nStVK / Hooke: " + bold(f"{part['ratio_stvk_over_hooke']:.2f}") + " (assembly alone "
                     f"{part['ratio_assembly']:.2f}).")
    return "\n\n".join(parts)


def batch(rows):
    out = [[r["case"], thousands(r["cells"]), r["threads"], ms(r["tangent_per_element_ms"]), ms(r["tangent_batched_ms"]),
            f"{r['tangent_batched_ms'] / r['tangent_per_element_ms']:.2f}", ms(r["forces_per_element_ms"]),
            ms(r["forces_batched_ms"]), f"{r['forces_batched_ms'] / r['forces_per_element_ms']:.2f}"] for r in rows]
    return table(["case", "cells", "threads", "tangent, per element (ms)", "batched", "ratio", "forces, per element",
                  "batched", "ratio"], out, ["l"] + ["r"] * 8)


def spmv(rows):
    out = [[thousands(r["tets"]), thousands(r["rows"]), thousands(r["nonzeros"]), r["threads"], ms(r["by_rows_ms"]),
            ms(r["by_blocks_ms"]), bold(f"{r['by_blocks_ms'] / r['by_rows_ms']:.2f}"), f"{r['relative_difference']:.1e}"]
           for r in rows]
    return table(["tets", "rows", "non-zeros", "threads", "by rows (ms)", "by blocks (ms)", "ratio",
                  "relative difference"], out, ["r"] * 8)


def folded(rows):
    out = [[thousands(r["tets"]), thousands(r["nodes"]), r["threads"], ms(r["one_sum_per_row_ms"]),
            ms(r["d_by_d_sums_ms"]), bold(f"{r['d_by_d_sums_ms'] / r['one_sum_per_row_ms']:.2f}"),
            f"{r['relative_difference']:.1e}"] for r in rows]
    return table(["tets", "nodes", "threads", "one sum per row (ms)", "D x D sums (ms)", "ratio", "relative difference"],
                 out, ["r"] * 7)


def scatter(rows):
    out = [[r["case"], thousands(r["cells"]), r["threads"], ms(r["by_entries_ms"]), ms(r["by_blocks_ms"]),
            f"{r['by_blocks_ms'] / r['by_entries_ms']:.2f}", "yes" if r["identical"] else bold("no"),
            f"{r['map_mib_blocks']:.2f} / {r['map_mib_entries']:.2f}"] for r in rows]
    return table(["case", "cells", "threads", "by entries (ms)", "by blocks (ms)", "ratio", "same bits",
                  "map MiB (blocks / entries)"], out, ["l", "r", "r", "r", "r", "r", "l", "r"])


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__)
    data = load(argv[1])
    meta, c, q = data["metadata"], data["ccx"], data["quad_beam"]
    print(PAGE.format(
        machine=meta["machine"], threads=meta["threads"], date=meta["date"][:10], version=meta["tensormass_version"],
        commit=meta["commit"], build=data["build"], blas=data["blas"], seconds=data["seconds"],
        load_start=data["load_average_start"], load_end=data["load_average_end"],
        ccx_tets=thousands(c["tets"]), ccx_nodes=thousands(c["nodes"]), ccx_young=c["young"], ccx_gravity=c["gravity"],
        ccx_increments=c["increments"], ccx_tip=c.get("tip_deflection", 0.0), ccx_threads=c["threads"],
        thread_tets=thousands(data["threads"]["tets"]), thread_steps=data["threads"]["steps"],
        quad_young=q["young"], quad_steps=q["implicit"]["steps"], quad_explicit_steps=q["explicit"]["steps"],
        targets=targets(data), ccx=ccx(c), threads_table=threads(data["threads"]), implicit=implicit(data["implicit"]),
        quad=quad(q), batch=batch(data["batched_assembly"]), spmv=spmv(data["block_products"]),
        folded=folded(data["folded_products"]), scatter=scatter(data["scatter"])).rstrip())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
