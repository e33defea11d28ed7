#!/usr/bin/python3
"""docs/results/soak.md from scripts/soak_steps.py's and scripts/soak_thorax.py's JSON.

usage: /usr/bin/python3 scripts/results/render_soak.py soak_steps.json soak_thorax.json > docs/results/soak.md
"""
import sys

from results_common import load, table, thousands

PAGE = """# Soak: long runs in one process

## {long_steps} explicit steps

Measured on {steps_machine} ({steps_threads} threads) on {steps_date},
tensormass {steps_version}, commit `{steps_commit}`, beside {baseline}, side
by side in one run:

```sh
/usr/bin/python3 scripts/soak_steps.py --steps {long_steps_plain} --baseline OTHER_BINARY --baseline-label TEXT --json docs/results/soak_steps.json
```

A 2D beam of {cells} quads, StVK, explicit, dt {dt:g} s, no frames, the
body's centroid tracked (`output.track`), the adaptive model's criteria
evaluated at every step, a checkpoint every 100,000 steps. Each run is its
own process; its peak resident memory comes from `wait4`. The run keeps its
per-step records in bounded memory and writes its track rows and adaptivity
records to their files as it goes:

{steps_table}

## The breathing thorax for {cycles} cycles

Measured on {thorax_machine} ({thorax_threads} threads) on {thorax_date},
tensormass {thorax_version}, commit `{thorax_commit}`:

```sh
/usr/bin/python3 scripts/soak_thorax.py --cycles {cycles} --json docs/results/soak_thorax.json
/usr/bin/python3 scripts/results/render_soak.py docs/results/soak_steps.json docs/results/soak_thorax.json > docs/results/soak.md
```

It builds the thorax example's mesh (as `examples/thorax/run.sh` does: 2 cm
hexahedra, 1 cm in the region of interest, a 1 cm prism layer), runs
`examples/thorax/thorax.yaml` (the adaptive model, Hooke upgraded to StVK
where R_NL > 0.005, implicit, dt {thorax_dt:g} s) for {cycles} breathing cycles of {cycle:g} s
({thorax_steps} steps) in one process, samples its resident memory (VmRSS) twice a
second and reads the tumour's track.

{thorax_table}

The tumour comes back within {rest_um:.0f} micrometres of its rest position
at every end-exhale, and the inspiration peak of cycle {cycles} is within
{drift_um:.1f} micrometres of the first one's.
"""


def steps_rows(data):
    rows = []
    for i, r in enumerate(data["rows"]):
        target = ("within 1 %: " + ("met" if abs(r["growth_percent"]) <= 1 else "missed")) if i == 0 else ""
        rows.append([r["label"], f"{r['short_mib']:.1f} MiB", f"{r['long_mib']:.1f} MiB", f"{r['growth_percent']:+.2f} %",
                     f"{r['long_seconds']:.1f} s", target])
    long_steps = thousands(data["settings"]["long_steps"])
    return table(["build", "1,000 steps", f"{long_steps} steps", "growth", f"{long_steps} steps' wall time", "target"],
                 rows, ["l", "r", "r", "r", "r", "l"])


def thorax_rows(data):
    growth = 100 * (data["largest_after_mib"] - data["first_cycle_mib"]) / data["first_cycle_mib"]
    rest, peaks = data["end_exhale_mm"], data["inspiration_mm"]
    cycles = data["settings"]["cycles"]
    rows = [
        ["resident memory after the first cycle", f"{data['first_cycle_mib']:.1f} MiB", ""],
        [f"largest resident memory after it ({data['samples']} samples over {data['seconds']:.0f} s)",
         f"{data['largest_after_mib']:.1f} MiB: growth {growth:.2f} %", "under 1 %"],
        [f"tumour displacement at every end-exhale (t = 4k s, diaphragm at rest)",
         f"at most {max(rest):.4f} mm over the {cycles} cycles", "no drift"],
        [f"tumour displacement at inspiration (t = 4k + 2 s), cycle 1 and cycle {cycles}",
         f"{peaks[0]:.4f} mm and {peaks[-1]:.4f} mm ({abs(peaks[-1] - peaks[0]):.1e} mm apart)", "periodic"],
    ]
    return table(["quantity", "measured", "target"], rows)


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    steps, thorax = load(argv[1]), load(argv[2])
    sm, tm = steps["metadata"], thorax["metadata"]
    baselines = [r["label"] for r in steps["rows"][1:]]
    ts = thorax["settings"]
    print(PAGE.format(
        long_steps=thousands(steps["settings"]["long_steps"]), long_steps_plain=steps["settings"]["long_steps"],
        steps_machine=sm["machine"], steps_threads=sm["threads"], steps_date=sm["date"][:10],
        steps_version=sm["tensormass_version"], steps_commit=sm["commit"],
        baseline=" and ".join(baselines) if baselines else "no baseline",
        cells=steps["settings"]["cells"], dt=steps["settings"]["dt"], steps_table=steps_rows(steps),
        cycles=ts["cycles"], thorax_machine=tm["machine"], thorax_threads=tm["threads"], thorax_date=tm["date"][:10],
        thorax_version=tm["tensormass_version"], thorax_commit=tm["commit"], thorax_dt=ts["dt"], cycle=ts["cycle_seconds"],
        thorax_steps=thousands(round(ts["cycles"] * ts["cycle_seconds"] / ts["dt"])), thorax_table=thorax_rows(thorax),
        rest_um=1e3 * max(thorax["end_exhale_mm"]),
        drift_um=1e3 * abs(thorax["inspiration_mm"][-1] - thorax["inspiration_mm"][0])).rstrip())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
