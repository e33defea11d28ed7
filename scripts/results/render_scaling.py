#!/usr/bin/python3
"""docs/results/scaling.md from `tensormass bench runtime --only implicit --scaling --json FILE`.

usage: /usr/bin/python3 scripts/results/render_scaling.py scaling.json > docs/results/scaling.md
"""
import sys

from results_common import bold, load, table, thousands

PAGE = """# Scaling: implicit StVK steps from a thousand to a million tets

One implicit (backward Euler) StVK step per row, 1 Newton iteration, on
tet6-cut beams (`tensormass beam --type tet6`), with CHOLMOD and with
Jacobi CG, on one thread and on the default thread count, beside the floor
measured in the same process: one assembly (gradient + Hessian) plus the CG
iterations' sparse products. Measured on {machine} ({threads} threads) on
{date}, tensormass {version}, commit `{commit}`, {build}, BLAS {blas};
load average {load_start} at the start and {load_end} at the end ({seconds:.0f} s):

```sh
./build/tensormass bench runtime --only implicit --scaling --json docs/results/scaling.json
/usr/bin/python3 scripts/results/render_scaling.py docs/results/scaling.json > docs/results/scaling.md
```

Settings: E = 1 MPa, nu = 0.3, rho = 1000, gravity, dt = 0.01 s, linear
tolerance 1e-8, one uncounted warm-up step per run; `OMP_WAIT_POLICY=passive`
(the default tensormass programs set, [performance.md](../performance.md#threads)).

{rows}

Columns: step = mean of the counted steps; assembly, solve, rest = their
split (rest: forces, residual, vector updates); linear its = CG iterations
per step (CHOLMOD: CG iterations preconditioned by the last factor, 1 when
it factorises); floor = one assembly + linear its x one SpMV, both timed
right after the run at its final state; SpMV GB/s = the bytes one
`K.multiply` must move (12 per non-zero, 20 per row) over its time; peak RSS
= the process's peak so far (rows run in increasing size, so each is an
upper bound for its own row). The first step of a CHOLMOD run (analysis and
first factorisation) is excluded from the mean: {first_steps}. CHOLMOD is
not run at a million tets: its factorisation flops grow about as n^2 on
these meshes.

## Targets

{targets}

## What the table says

- **Threads.** CHOLMOD's BLAS runs on one thread, so a second thread
  changes only its assembly: the two-thread step is {cholmod_threads} the
  one-thread step. CG on two threads: {cg_speedups} the one-thread step's
  speed.
- **The floor.** CG steps sit at {floor_low:.2f} to {floor_high:.2f} times
  the floor.
- **Memory**: {rss_100k} MB at 100k tets with the CHOLMOD factor,
  {rss_1m} MB for a million tets with CG.
"""


def row_cells(r):
    floor = r.get("reference_assembly_ms", 0) + r["linear_iterations_per_step"] * r.get("spmv_ms", 0)
    cg = r["solver"] == "cg"
    ms = (lambda x: f"{x:,.0f}") if r["step_ms"] >= 1000 else (lambda x: f"{x:.1f}" if x >= 100 else f"{x:.2f}")
    return [r["mesh"], thousands(r["tets"]), thousands(r["free_dofs"]), r["solver"], r["threads"], ms(r["step_ms"]),
            ms(r["assembly_ms"]), ms(r["solve_ms"]), ms(r["rest_ms"]), f"{r['linear_iterations_per_step']:.1f}",
            ms(floor) if cg else "", f"{r['step_ms'] / floor:.2f}" if cg else "", f"{r['spmv_gb_per_s']:.1f}",
            thousands(round(r["peak_rss_mb"]))]


def find(rows, mesh, solver, threads):
    for r in rows:
        if (r["mesh"], r["solver"], r["threads"]) == (mesh, solver, threads):
            return r
    return None


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__)
    data = load(argv[1])
    rows, meta = data["implicit"], data["metadata"]
    most = max(r["threads"] for r in rows)
    header = ["mesh", "tets", "free dofs", "solver", "threads", "step (ms)", "assembly", "solve", "rest", "linear its",
              "floor (ms)", "step / floor", "SpMV GB/s", "peak RSS (MB)"]
    body = table(header, [row_cells(r) for r in rows], ["l", "r", "r", "l"] + ["r"] * 10)
    cholmod = [r for r in rows if r["solver"] == "cholmod"]
    first_steps = ", ".join(f"{r['first_step_ms']:,.0f} ms at {r['mesh']}" for r in cholmod if r["threads"] == 1)
    cholmod_threads = ", ".join(
        f"{find(rows, m, 'cholmod', most)['step_ms'] / find(rows, m, 'cholmod', 1)['step_ms']:.2f}x at {m}"
        for m in ("10k", "100k") if find(rows, m, "cholmod", 1) and find(rows, m, "cholmod", most))
    cg_speedups = ", ".join(
        f"{find(rows, m, 'cg', 1)['step_ms'] / find(rows, m, 'cg', most)['step_ms']:.2f}x at {m}"
        for m in ("10k", "100k", "1M") if find(rows, m, "cg", 1) and find(rows, m, "cg", most))
    ratios = [r["step_ms"] / (r["reference_assembly_ms"] + r["linear_iterations_per_step"] * r["spmv_ms"])
              for r in rows if r["solver"] == "cg"]
    targets = table(["target", "measured", "goal", "result"],
                    [[t["name"], f"{t['value']:.2f}" if t["value"] < 10 else f"{t['value']:.0f}",
                      f"{t['relation']} {t['goal']:g}", bold("met") if t["pass"] else bold("missed")]
                     for t in data["targets"]])
    rss = lambda mesh, solver: thousands(round(find(rows, mesh, solver, most)["peak_rss_mb"])) \
        if find(rows, mesh, solver, most) else "-"
    print(PAGE.format(
        machine=meta["machine"], threads=meta["threads"], date=meta["date"][:10], version=meta["tensormass_version"],
        commit=meta["commit"], build=data["build"], blas=data["blas"], load_start=data["load_average_start"],
        load_end=data["load_average_end"], seconds=data["seconds"], rows=body, first_steps=first_steps,
        targets=targets, cholmod_threads=cholmod_threads, cg_speedups=cg_speedups, floor_low=min(ratios),
        floor_high=max(ratios), rss_100k=rss("100k", "cholmod"), rss_1m=rss("1M", "cg")).rstrip())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
