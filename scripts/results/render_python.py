#!/usr/bin/python3
"""docs/results/python.md from bench/python_stepping.py's JSON.

usage: /usr/bin/python3 scripts/results/render_python.py python_stepping.json > docs/results/python.md
"""
import sys

from results_common import bold, load, table, thousands

PAGE = """# Stepping from Python against the CLI

Measured on {machine} ({threads} threads) on {date}, tensormass {version},
commit `{commit}`, load average {load}. The commands that remake this page
(after the README's build):

```sh
PYTHONPATH=build/python /usr/bin/python3 bench/python_stepping.py --json docs/results/python_stepping.json
/usr/bin/python3 scripts/results/render_python.py docs/results/python_stepping.json > docs/results/python.md
```

The scene: a 3D StVK cantilever, `tensormass beam --dim 3 --cells 20,6,14
--size 2,0.6,1.4 --type tet6` ({tets} tets, {nodes} nodes), E = 1 MPa,
nu = 0.3, gravity, implicit Euler, dt 0.01 s, {steps} steps, every other
setting at its default (threads, linear solver, one Newton iteration per
step). Two ways, alternated in one process, {repeats} runs each (medians):

- **cli**: `tensormass run SCENE --quiet` as a subprocess (wall time from
  the start of the process to its exit);
- **python**: `tm.Simulation(SCENE)` and `while sim.step(): sim.displacement`
  (wall time from the construction to the end, reading the state as NumPy
  after every step).

"loop" is each run's own `time_loop_seconds` (summary.json: the steps alone).

{medians}

{verdict} Single runs vary from {low:.3f} to {high:.3f} s (cli wall), so
only the medians of alternated runs mean anything. The CLI pays its
process start and the loading of its libraries on every run (it loads
them twice, re-executing itself for the OpenMP wait policy), which Python
pays once at import.

The package sets `OMP_WAIT_POLICY=passive` at import (what the CLI does by
re-executing itself): libgomp's default spinning wait would take the second
core from CHOLMOD and make the Python loop slower than the CLI's.
"""


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__)
    data = load(argv[1])
    meta, settings = data["metadata"], data["settings"]
    wall, loop = data["median_wall_s"], data["median_loop_s"]
    wall_ratio, loop_ratio = wall["python"] / wall["cli"], loop["python"] / loop["cli"]
    medians = table(["cli wall", "python wall", "python / cli (wall)", "cli loop", "python loop", "python / cli (loop)"],
                    [[f"{wall['cli']:.3f} s", f"{wall['python']:.3f} s", f"{wall_ratio:.2f}", f"{loop['cli']:.3f} s",
                      f"{loop['python']:.3f} s", f"{loop_ratio:.2f}"]], ["r"] * 6)
    met = wall_ratio <= 1.05 and loop_ratio <= 1.05
    verdict = bold(f"Target (at most 5 % more than the CLI, wall and loop): {'met' if met else 'missed'}.")
    print(PAGE.format(machine=meta["machine"], threads=meta["threads"], date=meta["date"][:10],
                      version=meta["tensormass_version"], commit=meta["commit"], load=meta["load_average"],
                      tets=thousands(settings["tets"]), nodes=thousands(settings["nodes"]), steps=settings["steps"],
                      repeats=settings["repeats"], medians=medians, verdict=verdict, low=min(data["wall_s"]["cli"]),
                      high=max(data["wall_s"]["cli"])).rstrip())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
