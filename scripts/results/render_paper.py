#!/usr/bin/python3
"""Renders docs/results/paper.md from docs/results/paper.json (`tensormass bench paper`).

    /usr/bin/python3 scripts/results/render_paper.py docs/results/paper.json > docs/results/paper.md

`tensormass bench paper --out DIR` writes DIR/paper.json and runs this
script to lay DIR/paper.md out from it, so the page has one writer. Every
figure comes from the JSON, the date and commit from its "metadata" (a JSON
of a run without metadata gives MEASURED below), except the origin report's
own times, which are constants here.
"""
import sys

from results_common import load

MEASURED = "2026-11-22, recorded in commit `5f1958c`"

# The origin's Table 1 (ms per step at thresholds 1.5 / 3 / 6 % and 15 / 30 / 60): bench/paper_report.cpp.
ORIGIN = [("hooke", ("0.102", "", ""), ("0.031", "", "")),
          ("R_EL", ("2.690", "0.561", "0.125"), ("1.028", "0.212", "0.048")),
          ("R_V", ("4.093", "1.396", "0.190"), ("2.143", "0.753", "0.110")),
          ("R_S", ("8.668", "8.058", "7.067"), ("-", "-", "-")),
          ("R_NL", ("", "", ""), ("", "", "")),
          ("stvk", ("16.273", "", ""), ("9.011", "", ""))]
HOOKE_600, STVK_600, HOOKE_300, STVK_300 = 0.102, 16.273, 0.031, 9.011
CRITERIA = ["R_EL", "R_V", "R_S", "R_NL"]


def c(pattern, value):
    """C's printf of one value (Python's % operator follows it)."""
    return pattern % value


def figure(value):
    """Three figures, without exponent for the usual ranges (paper_report.cpp's figure())."""
    if value is None or value != value or value in (float("inf"), float("-inf")):
        return "n/a"
    a = abs(value)
    if a != 0 and (a < 1e-3 or a >= 1e5):
        return c("%.2e", value)
    if a >= 100:
        return c("%.0f", value)
    if a >= 10:
        return c("%.1f", value)
    if a >= 1:
        return c("%.2f", value)
    return c("%.3g", value)


def find_row(rows, beam, mode, threshold=None):
    for r in rows:
        if r["beam"] == beam and r["mode"] == mode and (threshold is None or r["threshold"] == threshold):
            return r
    return None


def adaptive_rows(rows, beam, mode):
    return sorted((r for r in rows if r["beam"] == beam and r["mode"] == mode and r["threshold"] is not None),
                  key=lambda r: r["threshold"])


def origin_of(beam):
    """The origin's element count shown beside a beam (600, 300) or 0 (paper_bench.cpp's beam_cases)."""
    return {"quad 60x10": 600, "quad 30x10": 300}.get(beam["beam"], 0)


def markdown_table(rows, beam, origin):
    with_origin = origin in (600, 300)
    out = f"| {beam} | ours: ms per step (threshold; error; upgraded) | | |"
    if with_origin:
        out += f" origin, {origin} el.: ms per step | | |"
    out += "\n|---|---|---|---|"
    if with_origin:
        out += "---|---|---|"
    out += "\n"
    for mode, ms600, ms300 in ORIGIN:
        cells = ["", "", ""]
        if mode in ("hooke", "stvk"):
            r = find_row(rows, beam, mode)
            if r:
                cells[0] = f"**{figure(r['ms_per_step'])}** (-; {figure(r['error'])}; {r['upgraded']})"
        else:
            adaptive = adaptive_rows(rows, beam, mode)
            for i, r in enumerate(adaptive[:3]):
                cells[i] = f"**{figure(r['ms_per_step'])}** ({figure(r['threshold'])}; {figure(r['error'])}; {r['upgraded']})"
            origin_ms = ms600 if origin == 600 else ms300
            if not adaptive and (not with_origin or not origin_ms[0]):
                continue
        label = "Hooke" if mode == "hooke" else "StVK" if mode == "stvk" else mode
        out += f"| {label} | {cells[0]} | {cells[1]} | {cells[2]} |"
        if with_origin:
            ms = ms600 if origin == 600 else ms300
            out += f" {ms[0]} | {ms[1]} | {ms[2]} |"
        out += "\n"
    return out


def markdown_ratios(rows, beam):
    hooke, stvk = find_row(rows, beam, "hooke"), find_row(rows, beam, "stvk")
    if not hooke or not stvk:
        return ""
    out = (f"| {beam} | threshold | ms per step | / StVK | position (0 = Hooke, 1 = StVK) | error | "
           "error / Hooke's | upgraded | criteria ms per step | assembly ms per step | factorisation + solve ms per step |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|\n")
    span = stvk["ms_per_step"] - hooke["ms_per_step"]

    def line(r, label):
        threshold = figure(r["threshold"]) if r["threshold"] is not None else "-"
        position = c("%.2f", (r["ms_per_step"] - hooke["ms_per_step"]) / span) if span != 0 else "nan"
        to_hooke = c("%.2f", r["error"] / hooke["error"]) if hooke["error"] > 0 else "-"
        return (f"| {label} | {threshold} | {figure(r['ms_per_step'])} | {c('%.2f', r['ms_per_step'] / stvk['ms_per_step'])} | "
                f"{position} | {figure(r['error'])} | {to_hooke} | {r['upgraded']} / {r['elements']} | "
                f"{figure(r['criteria_ms'])} | {figure(r['assembly_ms'])} | {figure(r['solve_ms'])} |\n")

    out += line(hooke, "Hooke")
    for mode in CRITERIA:
        for r in adaptive_rows(rows, beam, mode):
            out += line(r, mode)
    out += line(stvk, "StVK")
    out += (f"\nStVK / Hooke (ms per step): **{c('%.2f', stvk['ms_per_step'] / hooke['ms_per_step'])}** "
            f"(origin: {c('%.0f', STVK_600 / HOOKE_600)} on 600 elements, {c('%.0f', STVK_300 / HOOKE_300)} on 300).\n")
    return out


def measured(data):
    """The date and commit of the run: its metadata's, else MEASURED."""
    meta = data.get("metadata")
    if not meta:
        return MEASURED
    return f"{meta['date'][:10]}, commit `{meta['commit']}`"


def header(data):
    s = data["settings"]
    dt, steps = s["dt"], s["steps"]
    return f"""\
# The origin report's experiment: `tensormass bench paper`

Table 1 and Figure 12 of the origin report (Caillaud, LIRIS; `docs/architecture.md`) on our code: 2D cantilever beams of 60 x 10 and 30 x 10 square quads under gravity, pure Hooke, pure StVK, and adaptive runs (every element starts under Hooke and is upgraded to StVK when its criterion exceeds the threshold), then the same on 3D tet, hex and mixed beams.

Measured on `{data['machine']}` (one thread) on {measured(data)} (run: {data['run']}). `tensormass bench paper` writes `docs/results/paper.json` and lays this page out from it with `scripts/results/render_paper.py`.

## Reproduce

```sh
cmake -S . -B build -G Ninja && cmake --build build
./build/tensormass bench paper            # full run: writes docs/results/paper.{{md,json}} and the plots
./build/tensormass bench paper --quick --out /tmp/paper   # about 2 minutes
./build/tensormass bench paper --smoke    # CI smoke test, seconds
/usr/bin/python3 bench/plot_paper.py docs/results/paper.json docs/results   # the plots again
/usr/bin/python3 scripts/results/render_paper.py docs/results/paper.json > docs/results/paper.md   # the page from the JSON
```

## Machine and method

- CPU: `{data['machine']}`, one thread (OpenMP and BLAS); load average at the end of the run: {data['load_average']} (the machine is shared: expect a few percent of noise).
- Build: {data['build']}.
- Every run: implicit (backward) Euler, dt = {c('%g', dt)} s, {steps} steps ({c('%.2g', dt * steps)} s), one Newton iteration per step (the linearised step), CHOLMOD; gravity (9.81 m/s^2 along -y) ramped in over the first second, Rayleigh mass damping 4 /s (the 6 m beam's first mode is critically damped at about 5.6 /s), so the beam bends down to near its static sag without a violent swing; plane strain in 2D (unit thickness); nu = 0.3, rho = 1000 kg/m^3; clamped at x = 0 (every node of the clamp face).
- Material: the origin gives none. E = 1e7 Pa on the 6 m beams (H = 1 m): the static tip sag is about 1.7 m, 28 % of L; the 3 m x 1 m beam has E = 1.25e6 Pa, so that rho g L^3 / (E H^2), hence the sag over L, is the same (the thicker short beam then has about twice the strain at the clamp). 3D beams: 6 x 1 x 1 m, E = 1e7 Pa.
- Time per step: the wall time from the end of one step to the end of the next step's adaptivity update (solve, criteria, switches), the first step (CHOLMOD's symbolic analysis) not counted. Each run gives its mean (and median) over the steps; the figure quoted is the median over {s['repetitions_2d']} repetitions (2D) or {s['repetitions_3d']} (3D); one repetition runs every configuration once, in turn.
- Error (Figure 12): the largest distance between a node in the run and the same node in the pure StVK run, over all nodes and all steps, divided by the beam's length L.
- Upgraded: elements under StVK at the end (no downgrade, no blending: the origin switches at once).
- R_S thresholds: each element's largest R_S over a pure Hooke run (R_S evaluated, nothing switching); the thresholds leave 1/2, 1/5 and 1/20 of the elements above. In an adaptive run the upgrades change the forces, so the counts differ somewhat.
"""


FOOTER = """
## Plots

Error against threshold per criterion (the origin's Figure 12; thresholds of R_S scaled by the smallest one so all fit one axis):

![error against threshold](paper_threshold.png)

Error against time per step for every run (which criterion buys the most accuracy per millisecond):

![error against time per step](paper_error_time.png)

## What the criteria see

- R_EL (edge lengths) and R_V (area or volume) are invariant under rotation: an element that rotates without stretching passes them. Under Hooke, a rigid rotation is not strain-free (the linear strain of a rotation by theta is about 1 - cos theta on the diagonal): such elements inflate and stiffen the beam, yet R_EL and R_V never upgrade them. In large-rotation bending (the tip of a sagging cantilever) this leaves Hooke elements exactly where the linear law errs most.
- R_NL (the quadratic part of the Green-Lagrange strain, 1/2 H^T H) grows with rotation as well as strain, so it upgrades the rotated elements.
- R_S averages the assembled nodal forces over the element: (1/v) integral of sum_j N_j f_j is a force (N), not a force per volume as criteria.hpp says. Under gravity every interior node carries about the same weight, so R_S is nearly uniform over the interior and large only at the clamp (the reaction) and along the boundary: its upgrade count falls off a cliff around the interior value (see the calibrated thresholds: the bisection cannot always reach 1/5 and 1/20), and it does not see rotation either. Upgrading an element changes the forces of its neighbours, which can cascade.
- R_S also costs one extra assembly of the internal forces per step (Adaptivity::evaluate calls Assembler::assemble at the new state, which the next implicit step assembles again): this is most of its overhead in the table above.

## Why the times look like this

- Pure Hooke with one Newton iteration per step assembles the same stiffness matrix at every step, and the CHOLMOD solver keeps its factor when the matrix is unchanged: a Hooke step is an assembly and two triangular solves. A StVK element changes the matrix at every step, so a StVK step also refactorises. StVK / Hooke therefore compares a factorisation with none, not the two laws' kernels: compare the assembly columns for the kernels' cost.
- For the same reason, as soon as ONE element is upgraded every later step refactorises: an adaptive step then costs about a StVK step, whatever the number of upgraded elements. An adaptive run's mean time sits between Hooke and StVK according to how many steps ran before the first switch (the median per step tells on which side of the first switch most steps fell). The origin's Table 1, where the time follows the share of upgraded elements, reflects a solver whose cost is per element.
- The criteria run on every element at every step (`every: 1`); their cost (tens of ns per element) is small against a refactorising step but not against a Hooke step that reuses its factor, hence the overhead table. Evaluating them every few steps (`adaptivity.every`) divides it accordingly.
"""


def render(data):
    rows = data["rows"]
    out = header(data)
    out += ("\n## Beams\n\n| beam | elements | L (m) | E (Pa) | final tip deflection, StVK (m) | Hooke (m) | R_S thresholds "
            "(1/2, 1/5, 1/20 of the elements) |\n|---|---|---|---|---|---|---|\n")
    for b in data["beams"]:
        thresholds = ", ".join(c("%.4g", t["threshold"]) for t in b["r_s_thresholds"])
        out += (f"| {b['beam']} | {b['elements']} | {c('%g', b['length'])} | {c('%g', b['young'])} | "
                f"{c('%.3f', b['tip_deflection_stvk'])} | {c('%.3f', b['tip_deflection_hooke'])} | {thresholds} |\n")
    out += ("\n## Table 1, ours beside the origin's\n\n"
            "Cells: **mean ms per step** (threshold; error = largest nodal distance to the pure StVK run over all "
            "steps / L; elements upgraded at the end). The origin's thresholds are 1.5, 3, 6 % for R_EL and R_V "
            "(ours: 0.015, 0.03, 0.06, the same) and 15, 30, 60 for R_S (units not given; ours are calibrated, see "
            "Beams). The origin's machine is unknown: compare ratios, not milliseconds.\n\n")
    for b in data["beams"]:
        out += f"### {b['beam']}\n\n" + markdown_table(rows, b["beam"], origin_of(b)) + "\n"
        out += markdown_ratios(rows, b["beam"]) + "\n"
    main_beam = data["beams"][0]["beam"]
    out += f"## Targets ({main_beam})\n\n| | target | measured | |\n|---|---|---|---|\n"
    for t in data["targets"]:
        out += (f"| {t['what']} | {t['op']} {c('%g', t['limit'])} | {c('%.3f', t['value'])} | "
                f"{'PASS' if t['pass'] else '**MISS**'} |\n")
    if data["overhead"]:
        elements = next(b["elements"] for b in data["beams"] if b["beam"] == main_beam)
        out += (f"\n## Criteria overhead ({main_beam})\n\n"
                "Adaptive runs whose threshold no element reaches (nothing switches, the criterion runs on every "
                "element every step) against pure Hooke, same repetitions.\n\n"
                "The criteria's own time (Adaptivity::criteria_seconds, per step) over pure Hooke's mean step is the "
                "figure of the target; the whole-step differences (mean and median per step) are also given, but on "
                "this shared machine they carry several percent of noise.\n\n"
                "| criterion | criteria ms per step | / Hooke's mean step | mean ms per step | pure Hooke | difference | "
                "median ms per step | pure Hooke | difference | criteria ns per element |\n"
                "|---|---|---|---|---|---|---|---|---|---|\n")
        for o in data["overhead"]:
            added = o["criteria_ms"] / o["hooke_ms_per_step"]
            out += (f"| {o['criterion']} | {c('%.4f', o['criteria_ms'])} | {c('%.1f %%', 100 * added)} | "
                    f"{c('%.4f', o['ms_per_step'])} | {c('%.4f', o['hooke_ms_per_step'])} | "
                    f"{c('%+.1f %%', 100 * (o['ms_per_step'] / o['hooke_ms_per_step'] - 1))} | "
                    f"{c('%.4f', o['ms_per_step_median'])} | {c('%.4f', o['hooke_ms_per_step_median'])} | "
                    f"{c('%+.1f %%', 100 * (o['ms_per_step_median'] / o['hooke_ms_per_step_median'] - 1))} | "
                    f"{c('%.0f', 1e6 * o['criteria_ms'] / elements)} |\n")
    return out + FOOTER


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: render_paper.py docs/results/paper.json > docs/results/paper.md")
    sys.stdout.write(render(load(sys.argv[1])))


if __name__ == "__main__":
    main()
