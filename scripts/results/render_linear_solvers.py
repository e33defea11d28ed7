#!/usr/bin/python3
"""docs/results/linear_solvers.md from bench/linear_solver_choice.py's JSON.

usage: /usr/bin/python3 scripts/results/render_linear_solvers.py linear_solvers.json > docs/results/linear_solvers.md
"""
import sys

from results_common import bold, load, table, thousands

PAGE = """# Which linear solver when: `cholmod`, `cg`, `petsc`

The same implicit runs with each `solver.linear.type` on one process:
beams made by `tensormass beam`, clamped at x = 0, under gravity, implicit
Euler with dt 0.01 s, every other setting at its default (2 threads,
`linear.tolerance` 1e-6, one Newton iteration per step); the solvers
alternate, {rounds} rounds, medians of each run's mean ms per step (the
first step, with CHOLMOD's analysis and factorisation or GAMG's setup,
included). The fastest of each row is in bold.

Measured on {machine} ({threads} threads) on {date}, tensormass {version},
commit `{commit}`, load average {load}:

```sh
/usr/bin/python3 bench/linear_solver_choice.py --json docs/results/linear_solvers.json
/usr/bin/python3 scripts/results/render_linear_solvers.py docs/results/linear_solvers.json > docs/results/linear_solvers.md
```

{rows}

`cholmod` is the default: its factor is reused (as a CG preconditioner)
while the tangent drifts, so a constant matrix (Hooke) costs one
factorisation and then triangular solves. `cg` is Jacobi-preconditioned
conjugate gradients; `petsc` is PETSc's CG with smoothed-aggregation
multigrid (GAMG) on one process, the same solver that shares a run among
MPI ranks ([mpi.md](mpi.md)). The three agree on the largest displacement
to {agreement:.1e} of it (the linear tolerance).
"""


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__)
    data = load(argv[1])
    meta = data["metadata"]
    solvers = ["cholmod", "cg", "petsc"]
    rows, worst = [], 0.0
    for r in data["rows"]:
        times = {s: r[s]["ms_per_step"] for s in solvers if "ms_per_step" in r[s]}
        best = min(times, key=times.get) if times else None
        cells = next((r[s]["cells"] for s in solvers if "cells" in r[s]), 0)
        cell = lambda s: ("failed" if s not in times else
                          bold(f"{times[s]:.2f}") if s == best else f"{times[s]:.2f}")
        rows.append([r["scene"], r["law"], thousands(cells)] + [cell(s) for s in solvers])
        sags = [r[s]["max_displacement"] for s in solvers if "max_displacement" in r[s]]
        if sags:
            worst = max(worst, (max(sags) - min(sags)) / max(abs(x) for x in sags))
    print(PAGE.format(rounds=data["settings"]["rounds"], machine=meta["machine"], threads=meta["threads"],
                      date=meta["date"][:10], version=meta["tensormass_version"], commit=meta["commit"],
                      load=meta["load_average"],
                      rows=table(["scene", "law", "cells"] + [f"`{s}` (ms per step)" for s in solvers], rows,
                                 ["l", "l", "r", "r", "r", "r"]),
                      agreement=worst).rstrip())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
