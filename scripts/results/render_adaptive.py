#!/usr/bin/python3
"""Renders docs/results/adaptive.md from the JSON files of `tensormass bench adaptive`.

    /usr/bin/python3 scripts/results/render_adaptive.py docs/results/adaptive_bench.json \\
        docs/results/adaptive_needle_fine.json > docs/results/adaptive.md

adaptive_bench.json: the eight scenes (`tensormass-bench adaptive --json`);
adaptive_needle_fine.json: the 81,000-tet needle (`--only needle-fine
--json`). The per-scene tables and every figure the prose quotes from those
runs come from the JSON. What the JSON does not hold is written into the
template below and must be changed by hand when it is measured again: the
dates and commits, the thorax deep breath (bench/thorax_deep_breath.py
prints it), the hindsight table (bench/adaptive_oracle.py), the solver's
timers per path and the orderings taken on the 81,000-tet block.
"""
import sys

from results_common import fixed, load, table

MEASURED = "2026-11-29, recorded in commit `230cb43`"
FINE_MEASURED = "2026-11-28, recorded in commit `2ecac2b`"

SCENES = [  # (JSON name, heading)
    ("indentation", "indentation: 24,000 tet4 (a 10 x 5 x 10 cm block, E 5 kPa, nu 0.45), a 2 x 2 cm probe 1.5 cm into 5 cm over 0.5 s, ladder [hooke, neohookean]"),
    ("needle", "needle: the same block, a 1 x 1 cm needle 1 cm into 5 cm, ladder [hooke, neohookean]"),
    ("cantilever", "cantilever: 8,640 tet4, 5 x 1 x 1 m, E 20 MPa, gravity, ladder [hooke, stvk]"),
    ("quad-beam", "quad-beam: 600 quad4, 6 x 1 m, E 10 MPa, gravity, ladder [hooke, stvk]"),
]


def ms(value):
    """ms per step with about three figures."""
    if value == 0:
        return "0"
    if value >= 10:
        return fixed(value, 1)
    if value >= 1:
        return fixed(value, 2)
    if value >= 0.1:
        return fixed(value, 3)
    return fixed(value, 4)


def pct(error):
    """An error (a fraction) in % with three figures."""
    if error == 0:
        return "0"
    value = 100 * error
    return f"{value:.3f} %" if value < 0.1 else f"{value:.2f} %" if value < 10 else f"{value:.1f} %"


def x(value):
    return f"{value:.2f}x"


def laws(run):
    return ", ".join(f"{n} {law}" for law, n in sorted(run["cells_per_law"].items()))


def upgraded(run, cells):
    """The share of the cells not under the first rung (hooke) at the end, in %."""
    return 100 * (cells - run["cells_per_law"].get("hooke", 0)) / cells


def share(value):
    """A share in % with two figures (99.9 above 99.5, so that a few cells left show)."""
    text = f"{value:.1f}" if 99.5 <= value < 100 else f"{value:.0f}" if value >= 10 else f"{value:.2g}"
    return f"{text} %"


class Runs:
    """The runs of the JSON, by scene and label."""

    def __init__(self, data):
        self.scenes = {scene["name"]: scene for scene in data["scenes"]}

    def scene(self, name):
        if name not in self.scenes:
            sys.exit(f"{sys.argv[0]}: no scene '{name}' in the JSON")
        return self.scenes[name]

    def run(self, scene, label):
        for run in self.scene(scene)["runs"]:
            if run["label"] == label:
                return run
        sys.exit(f"{sys.argv[0]}: no run '{label}' in scene '{scene}'")

    def adaptive(self, scene):
        return [run for run in self.scene(scene)["runs"] if run["threshold"] is not None or run["label"].startswith("3 rungs")]


def ratio_cell(run):
    """x rich with its range over the rounds; bold for an adaptive run within 1 %."""
    if run["ratio"] == 1 and run["ratio_low"] == 1 and run["ratio_high"] == 1:
        return "1"
    within = run["label"].startswith(("adaptive", "3 rungs")) and run["error"] <= 0.01 and not run["failed"]
    ratio = f"**{x(run['ratio'])}**" if within else x(run["ratio"])
    return f"{ratio} ({run['ratio_low']:.2f}-{run['ratio_high']:.2f})"


def upgraded_cell(run, cells):
    """The share of the cells above the first rung at the end, and the middle rung's count on three rungs."""
    if run["failed"] or not run["label"].startswith(("adaptive", "3 rungs")):
        return ""
    text = share(upgraded(run, cells))
    if "corotational" in run["cells_per_law"]:
        text += f" ({run['cells_per_law']['corotational']} corot.)"
    return text


def error_cell(run):
    return "inverts: failed" if run["failed"] else pct(run["error"])


def scene_table(implicit, explicit=None):
    """One table per scene: each run implicit and, when given, explicit, side by side."""
    header = ["run", "implicit ms/step", "x rich (range)", "solve", "criteria", "upgraded", "error"]
    align = ["l", "r", "l", "r", "r", "r", "r"]
    if explicit:
        header += ["explicit ms/step", "x rich (range)", "assembly", "criteria", "upgraded", "error"]
        align += ["r", "l", "r", "r", "r", "r"]
        other = {run["label"]: run for run in explicit["runs"]}
    rows = []
    for run in implicit["runs"]:
        row = [run["label"], ms(run["ms_per_step"]), ratio_cell(run), ms(run["solve_ms"]), ms(run["criteria_ms"]),
               upgraded_cell(run, implicit["cells"]), error_cell(run)]
        if explicit:
            e = other.get(run["label"])
            row += ([ms(e["ms_per_step"]), ratio_cell(e), ms(e["assembly_ms"]), ms(e["criteria_ms"]),
                     upgraded_cell(e, explicit["cells"]), error_cell(e)] if e else [""] * 6)
        rows.append(row)
    return table(header, rows, align)


def criteria_share(runs, scene, prefix):
    """criteria ms over the pure Hooke step, in %, over the scene's runs whose label starts with prefix."""
    hooke = runs.run(scene, "hooke")["ms_per_step"]
    shares = [100 * r["criteria_ms"] / hooke for r in runs.scene(scene)["runs"] if r["label"].startswith(prefix)]
    low, high = f"{min(shares):.1f}", f"{max(shares):.1f}"
    return (low if low == high else f"{low} to {high}") + " %"


def short(label):
    """A run's label, short: 'adaptive R_P 0.03' -> 'R_P 0.03', '3 rungs, ...' -> '3 rungs'."""
    if label.startswith("3 rungs"):
        return "3 rungs"
    return label.replace("adaptive ", "").replace(", every cell evaluated", ", every cell")


def worst(runs, scene):
    """The slowest adaptive run of a scene: 'ratio (label)'."""
    run = max(runs.adaptive(scene), key=lambda r: r["ratio"])
    return f"{x(run['ratio'])} ({short(run['label'])})"


def figures(runs, fine):
    r = runs.run
    f = {}

    def put(key, scene, label, what):
        run = r(scene, label)
        f[key] = {"ratio": x(run["ratio"]), "error": pct(run["error"]), "ms": ms(run["ms_per_step"]),
                  "share": share(upgraded(run, runs.scene(scene)['cells']))}[what]

    for key, scene, label in [
            ("ne_p05", "needle-explicit", "adaptive R_P 0.05"), ("ne_nl01", "needle-explicit", "adaptive R_NL 0.01"),
            ("ne_nl003", "needle-explicit", "adaptive R_NL 0.003"),
            ("ie_nl01", "indentation-explicit", "adaptive R_NL 0.01"), ("ie_p05", "indentation-explicit", "adaptive R_P 0.05"),
            ("i_nl01", "indentation", "adaptive R_NL 0.01"), ("i_p01", "indentation", "adaptive R_P 0.1"),
            ("i_p005", "indentation", "adaptive R_P 0.05"), ("i_nl03", "indentation", "adaptive R_NL 0.03"),
            ("n_nl01", "needle", "adaptive R_NL 0.01"), ("n_p05", "needle", "adaptive R_P 0.05"),
            ("n_nl03", "needle", "adaptive R_NL 0.03"),
            ("c_nl003", "cantilever", "adaptive R_NL 0.003"), ("c_p003", "cantilever", "adaptive R_P 0.003"),
            ("ce_nl003", "cantilever-explicit", "adaptive R_NL 0.003"),
            ("q_nl005", "quad-beam", "adaptive R_NL 0.005"), ("q_nl03", "quad-beam", "adaptive R_NL 0.03")]:
        for what in ("ratio", "error", "share"):
            put(f"{key}_{what}", scene, label, what)
    f["ce_corot"] = x(r("cantilever-explicit", "corotational")["ratio"])
    f["c_corot"] = x(r("cantilever", "corotational")["ratio"])
    f["c_corot_error"] = pct(r("cantilever", "corotational")["error"])
    f["q_corot_error"] = pct(r("quad-beam", "corotational")["error"])
    f["ie_corot"] = x(r("indentation-explicit", "corotational")["ratio"])
    f["c_3r_error"] = pct(r("cantilever", "3 rungs, R_NL 0.001 -> corot., R_E 0.003 -> stvk")["error"])
    f["ce_3r_worst"] = x(max(run["ratio"] for run in runs.adaptive("cantilever-explicit") if run["label"].startswith("3 rungs")))
    f["ie_3r_worst"] = x(max(run["ratio"] for run in runs.adaptive("indentation-explicit") if run["label"].startswith("3 rungs")))
    f["i_3r_worst"] = x(max(run["ratio"] for run in runs.adaptive("indentation") if run["label"].startswith("3 rungs")))
    f["ce_hooke"] = x(r("cantilever-explicit", "hooke")["ratio"])
    f["stvk_inverts"] = "pure StVK and pure corotational"
    for scene in ("needle", "needle-explicit", "indentation", "indentation-explicit", "cantilever", "cantilever-explicit",
                  "quad-beam", "quad-beam-explicit"):
        f["worst_" + scene.replace("-", "_")] = worst(runs, scene)
    f["q_hooke_ms"] = ms(r("quad-beam", "hooke")["ms_per_step"])
    f["c_p03"] = x(r("cantilever", "adaptive R_P 0.03")["ratio"])
    for scene in ("needle", "indentation", "cantilever", "quad-beam"):
        key = scene.replace("-", "_")
        f["crit_nl_" + key] = criteria_share(runs, scene, "adaptive R_NL")
        if any(run["label"].startswith("adaptive R_P") for run in runs.scene(scene)["runs"]):
            f["crit_p_" + key] = criteria_share(runs, scene, "adaptive R_P")
        f["crit_3r_" + key] = criteria_share(runs, scene, "3 rungs") if any(
            run["label"].startswith("3 rungs") for run in runs.scene(scene)["runs"]) else ""
    solve_shares = [100 * r(s, "neohookean")["solve_ms"] / r(s, "neohookean")["ms_per_step"] for s in ("indentation", "needle")]
    f["solve_share"] = f"{min(solve_shares):.0f} to {max(solve_shares):.0f} %"
    f["ie_crit_ms"] = fixed(r("indentation-explicit", "adaptive R_P 0.05")["criteria_ms"], 3)
    f["ie_crit_nl_ms"] = fixed(r("indentation-explicit", "adaptive R_NL 0.01")["criteria_ms"], 3)
    # The 81,000-tet needle.
    fine_scene = fine["scenes"][0]
    fine_runs = {run["label"]: run for run in fine_scene["runs"]}
    fine01 = fine_runs["adaptive R_NL 0.01"]
    f["fine_machine"] = fine["machine"]
    f["fine_nl01_ratio"] = x(fine01["ratio"])
    f["fine_nl01_error"] = pct(fine01["error"])
    f["fine_nl01_share"] = share(upgraded(fine01, fine_scene["cells"]))
    f["fine_table"] = scene_table(fine_scene)
    f["fine_cells"] = f"{fine_scene['cells']:,}"
    return f


TEMPLATE = """\
# The adaptive model: does it pay? (`tensormass bench adaptive`)

Local-deformation scenes, each run with the pure linear law, the pure rich
law and adaptive runs (cells start under Hooke and climb the ladder where a
criterion asks) at three thresholds of R_NL and, on the 3D scenes, of R_P, the same middle
threshold with every cell evaluated (the criteria screen off), the pure
`corotational` law and two runs on the three-rung ladder `[linear,
corotational, rich]` (R_NL lifts a cell to corotational, R_E, the
rotation-free Green strain, to the rich law); the indentation also runs
pure StVK and pure `stable_neohookean`. Implicit Euler with the default
settings (2 OpenMP threads, CHOLMOD with factor reuse, one Newton iteration
per step, `solver.linear.tolerance` 1e-6). Each scene also runs explicitly
(`NAME-explicit`: symplectic Euler over the same time, dt half the stable
step estimated at rest, the criteria every 10 steps). Error: the largest
nodal distance to the pure rich run over all steps, over the rich run's
largest displacement. Every run is made 3 times, round after round: the
tables give the median ms per step and, as `x rich`, the median of each
round's ratio to the pure rich run of the same round, with its range.

Measured on a 2-core `{machine}` with AVX-512 ({threads} threads) on
{measured}; the 81,000-tet needle on the 2-core `{fine_machine}` on
{fine_measured}. The commands that remake the figures:

```sh
./build/tensormass bench adaptive --json docs/results/adaptive_bench.json        # the eight scenes, 4 to 7 minutes
./build/tensormass bench adaptive --only needle-fine --json docs/results/adaptive_needle_fine.json   # 6 minutes
/usr/bin/python3 bench/plot_adaptive.py docs/results/adaptive_bench.json docs/results/adaptive_error_cost.png
PYTHONPATH=build/python /usr/bin/python3 bench/thorax_deep_breath.py [--criterion R_P] [--explicit]   # the thorax, about 45 s
PYTHONPATH=build/python /usr/bin/python3 bench/adaptive_oracle.py [--only SCENE]                      # with hindsight, 2.5 minutes
/usr/bin/python3 scripts/results/render_adaptive.py docs/results/adaptive_bench.json \\
    docs/results/adaptive_needle_fine.json > docs/results/adaptive.md                                # this page
```

`--only NAME` runs one scene, `--rounds N` changes the rounds, `--quick` is
the smoke run of ctest `bench.adaptive.quick`.

![error against cost, every scene](adaptive_error_cost.png)

Each point is a run: the median of its step over the pure rich law's (the
grey bar: the range over the rounds) against its error (the rich run
itself is drawn at 1e-3 %). Circles: R_NL runs; diamonds: R_P runs. Dashed:
the targets (1 % error; 0.5x on the indentation and needle, 0.7x on the
beams). No adaptive point is inside both on this machine: the explicit
needle comes nearest (R_P 0.05: {ne_p05_ratio} at {ne_p05_error}; R_NL 0.01:
{ne_nl01_ratio} at {ne_nl01_error}).

## Which settings, when

- **Explicit integration with a local non-linear region** (a needle or a
  probe in a larger body): the adaptive model pays. `[hooke, neohookean]`
  with `every: 10`: the needle at {ne_nl003_ratio} the pure neo-Hookean
  step with R_NL 0.003 ({ne_nl003_error}), {ne_p05_ratio} with R_P 0.05
  ({ne_p05_error}); the probe at {ie_nl01_ratio} with R_NL 0.01
  ({ie_nl01_error}). A step costs Hooke's folded product, the non-linear
  cells' kernels and the criteria, so it follows the non-linear set.
- **Implicit integration**: the linear solve is {solve_share} of the pure
  neo-Hookean step on the 24k-tet scenes, whatever the laws. CG runs on the
  rows that changed since the reused factor, over the part of the factor
  they reach, and each whole factorisation orders a small non-linear
  region last (below), so an adaptive run pays where the region is local:
  the needle at {n_nl01_ratio} ({n_nl01_error}, R_NL 0.01), the probe at
  {i_nl01_ratio} ({i_nl01_error}), on this machine. The ratios depend on
  the machine: here a whole factorisation costs about 75 CG iterations,
  and the three a run needs are half its solve (below).
- **R_P** (the stress the linear law gets wrong) ranks the cells better
  than R_NL where tissue is compressed, but buys accuracy, not time (below).
  Use R_P 0.05 to 0.1 for about 1 %, R_P 0.02 for 0.5 % on the thorax.
- **Global deformation** (a bending beam, a 5 cm breath): 90 to 99 % of the
  cells climb at 1 % accuracy, and the adaptive run costs what the rich
  law costs, implicit or explicit. Chosen with hindsight, no mix with fewer
  than 70 % (cantilever) or 90 % (thorax) of the cells under the rich law
  is within 1 %. Run the rich law (or `stable_neohookean`) directly.
- **A high threshold** (R_NL 0.015 to 0.03) on a body where most cells end
  up climbing can cost more than the rich law: each cell switches when its
  tangent is already far from Hooke's, so the reused factor stops
  converging and the solver corrects it on the rows that jumped, with
  dearer iterations (quad beam R_NL 0.03: {q_nl03_ratio}).
- **The corotational rung** is accurate ({c_corot_error} of StVK on the
  cantilever, {q_corot_error} on the quad beam) but its polar rotation, even
  batched, makes an explicit corotational step {ce_corot} StVK's on the
  cantilever: the three-rung ladder buys accuracy ({c_3r_error} on the
  cantilever), not time.
- **Tissue under compression**: `neohookean` or `stable_neohookean` as the
  top rung; {stvk_inverts} invert under the probe (`inverts: failed`
  below).

## Against the targets

| target | measured | result |
|---|---|---|
| indentation: adaptive within 1 % of pure neo-Hookean at <= 0.5x its step (goal 0.3x) | implicit R_NL 0.01 {i_nl01_error} at {i_nl01_ratio}, R_P 0.1 {i_p01_error} at {i_p01_ratio}; explicit R_NL 0.01 {ie_nl01_error} at {ie_nl01_ratio}. With hindsight at least 20 % of the cells must be neo-Hookean | **missed** |
| cantilever: within 1 % of pure StVK at <= 0.7x | R_NL 0.003 {c_nl003_error} at {c_nl003_ratio} (explicit {ce_nl003_error} at {ce_nl003_ratio}). With hindsight 70 to 90 % of the cells must carry StVK | **missed**: not reachable |
| no adaptive run slower than the rich law x 1.05 | worst run: needle {worst_needle}, needle-explicit {worst_needle_explicit}, indentation {worst_indentation}, indentation-explicit {worst_indentation_explicit}, cantilever {worst_cantilever}, cantilever-explicit {worst_cantilever_explicit}, quad beam {worst_quad_beam}, quad-beam-explicit {worst_quad_beam_explicit}; thorax R_NL 1.01x, R_P 1.03x | met on the needles and the thorax, at the line on the implicit probe, **missed** on the explicit probe and the beams |
| criteria <= 5 % of a Hooke step (`every: 1`, implicit) | R_NL: needle {crit_nl_needle}, probe {crit_nl_indentation}, cantilever {crit_nl_cantilever}, quad beam {crit_nl_quad_beam}; R_P (unscreened, two stress kernels a cell): needle {crit_p_needle}, probe {crit_p_indentation}, cantilever {crit_p_cantilever} | **met** with R_NL on the 3D scenes, missed on the quad beam (a Hooke step of {q_hooke_ms} ms) and with R_P on the probe and the cantilever |
| thorax deep breath: within 1 % of pure neo-Hookean at <= 0.5x | R_NL 0.005 1.05 % at 0.96x, R_P 0.02 0.52 % at 0.98x, each with more than 99 % of the cells neo-Hookean. With hindsight no mix with fewer than 90 % neo-Hookean cells is within 1 % | **missed**: not reachable by a model that mixes the laws cell by cell |
| needle (not a target: a local non-linear region) | implicit R_NL 0.01 {n_nl01_error} at {n_nl01_ratio}, R_P 0.05 {n_p05_error} at {n_p05_ratio}; explicit R_P 0.05 {ne_p05_error} at {ne_p05_ratio}, R_NL 0.01 {ne_nl01_error} at {ne_nl01_ratio}; the 81,000-tet needle (AMD EPYC) R_NL 0.01 {fine_nl01_error} at {fine_nl01_ratio} | nearest the 0.5x line explicitly |
| corotational rung | built (law, R_E, per-criterion rungs); accurate (pure corotational {c_corot_error} of StVK on the cantilever) but no cheaper: pure corotational {c_corot} StVK's implicit step and {ce_corot} its explicit one on the cantilever; 3-rung runs up to {ce_3r_worst} (explicit cantilever) | built, **no gain** |

## The scenes

Each table gives a scene's runs implicit and explicit (`NAME-explicit`)
side by side: ms per step, the median ratio to the pure rich run and its
range over the rounds (bold: adaptive runs within 1 %), the solve's,
assembly's and criteria's ms per step, the share of the cells upgraded at
the end (on three rungs, with the cells left on corotational) and the
error. "inverts": the pure law inverts a cell under the probe and the run
stops.

{scene_tables}

## The needle in an 81,000-tet block

`--only needle-fine`: the same block cut 1.5x finer along each side,
{fine_cells} tets and 43,218 free rows, run only when named (the JSON is
`adaptive_needle_fine.json`; the 2-core `{fine_machine}`, {fine_measured}):

{fine_table}

R_NL 0.01 upgrades {fine_nl01_share} of the cells. Three region-last
orderings are taken, at 1.03x, 1.08x and 1.33x the flops of CHOLMOD's own
(METIS on both parts: 124 to 137 ms each, plus a 16 to 36 ms analysis).

## How few cells must climb, with hindsight

`bench/adaptive_oracle.py`: the pure rich run gives each cell its largest
value of an indicator over the run; then the top share of the cells by that
indicator carries the rich law from the first step, every other cell
Hooke, and the run's error against the pure rich run is measured. No
criterion deciding step by step can do much better than this ranking.
Errors (% of the largest displacement):

| scene | pure Hooke | indicator | top 10 % | top 20 % | top 30 % | top 50 % | top 70 % | top 90 % | least within 1 % |
|---|---:|---|---:|---:|---:|---:|---:|---:|---:|
| indentation (probe) | 13.7 % | R_NL | 3.31 | 1.36 | 0.71 | 0.32 | 0.17 | 0.08 | 30 % |
| | | R_E | 6.69 | 6.57 | 5.47 | 1.60 | 0.85 | 0.48 | 70 % |
| | | R_P | 2.57 | **0.99** | 0.50 | 0.20 | 0.10 | 0.03 | **20 %** |
| needle | 10.4 % | R_NL | 0.67 | 0.24 | 0.13 | 0.06 | 0.03 | 0.01 | 10 % (5 %: 1.44) |
| | | R_P | 0.43 | 0.16 | 0.08 | 0.04 | 0.02 | 0.00 | 10 % (5 %: 1.03) |
| cantilever (StVK) | 9.3 % | R_NL | 17.4 | 10.5 | 9.28 | 6.68 | 1.66 | 0.35 | 90 % |
| | | R_P | 17.5 | 10.4 | 9.11 | 6.08 | 1.59 | 0.50 | 90 % |
| thorax deep breath | 4.5 % | R_NL | 6.96 | 6.98 | 6.78 | 5.78 | 4.34 | 2.20 | none |
| | | R_E | 6.87 | 6.76 | 6.29 | 5.41 | 3.85 | 1.92 | none |
| | | R_P | 6.28 | 5.80 | 5.41 | 4.56 | 3.06 | 1.17 | none |

- **The thorax**: no mix of Hooke and neo-Hookean is within 1 % with
  fewer than 90 % of the cells neo-Hookean; mixes of 10 to 50 % err more
  than pure Hooke (the linear cells fight the non-linear ones). The breath
  strains the whole lung (R_NL above 0.024 on 90 % of the cells).
- **The cantilever**: 70 to 90 % of the cells must carry StVK. At 0.7x the
  pure law's step, about half of the cells could at best (explicit: a Hooke
  step is {ce_hooke} StVK's, and the criteria cost more).
- **The probe**: at least 20 % (ranked by R_P) or 30 % (by R_NL); the
  adaptive R_NL 0.01 run ends with {i_nl01_share} at {i_nl01_error}. **The
  needle**: 5 to 10 %.
- A static set costs as much as a growing one in implicit runs: the probe
  with its top 5 % by R_P fixed from the start (no switch in the run) runs
  at 0.88 and 0.93x the pure neo-Hookean step, 20 % at 0.94 and 0.98x, 30 %
  at 1.02x (two rounds). What costs is the solve, whichever cells are
  non-linear.

## R_P, the stress the first rung gets wrong

`runtime/src/adaptivity/criteria.cpp`: max over quadrature points of
|P_target(F) - P_first(F)|_F / E, from both laws' generated stress kernels
(batched, `stress_batch`, on the elements that have batched kernels). It
weighs each strain component by what it does to the stress: for tissue
with nu 0.45, volume change counts about ten times shear. The tests hold
it to closed forms of StVK and neo-Hookean on every element.

R_P ranks cells better than R_NL on the probe and the needle (the scene
tables: the implicit probe within 1 % with {i_p01_share} of the cells
upgraded at R_P 0.1, against {i_nl01_share} at R_NL 0.01; the needle at
{n_p05_error} against {n_nl01_error} with as many cells); on the bending
cantilever, where rotation dominates, the two rank alike ({c_p003_share}
of the cells at R_P 0.003 for {c_p003_error}, {c_nl003_share} at R_NL
0.003 for {c_nl003_error}). It buys
no time: implicit steps cost the same with fewer cells upgraded (the solve
sets the cost), and in explicit runs the probe's set shrinks less (waves
carry strain further) while R_P costs {ie_crit_ms} ms a step at `every:
10` against R_NL's {ie_crit_nl_ms} (two stress kernels per cell; R_NL is
also screened).

## The thorax deep breath

`bench/thorax_deep_breath.py` runs the thorax example on
`tensormass.Simulation`: it builds the example's surfaces and mesh (11,512
cells, about 15 s of the 45), then breathes in, the diaphragm 5 cm down over 40
implicit steps of 0.05 s, on the ladder [hooke, neohookean], every run 3
times round after round (`--rounds N`), with the default settings
(`--criterion R_P` for R_P runs, thresholds 0.05, 0.1, 0.2 unless
`--thresholds` says otherwise; `--explicit` for 5,000 explicit steps of
0.4 ms). Measured with the eight scenes above:

- R_NL 0.005: 1.05 % at 0.96x the pure neo-Hookean step, 99.3 % of the
  cells neo-Hookean; R_P 0.02: 0.52 % at 0.98x, 99.2 %; worst adaptive
  runs R_NL 1.01x, R_P 1.03x; pure Hooke 4.5 %.
- Error against threshold (R_NL, one round): 0.001: 0.21 %, 28 cells left
  on Hooke; 0.002: 0.43 %, 47 cells; 0.003: 0.65 %, 61 cells; 0.005:
  1.05 %, 79 cells. Every run within 1 % ends with more than 99.3 % of the
  cells under neo-Hookean, so its cost is the rich law's.
- Explicitly (the 2-core AMD EPYC, 2026-11-27, recorded in commit
  `0fc1e44`, one round): R_NL 0.005 1.12 % at 0.84x, 0.01 at 1.18x, 0.03
  at 0.88x; the pure neo-Hookean step 0.49 ms, Hooke's 0.08 ms.

## Where an implicit adaptive step's solve goes

Timers per path in `CholmodSolver` (one run each, taken out again), the
implicit needle, 50 steps, this machine:

| path | pure neo-Hookean | adaptive R_NL 0.01 |
|---|---|---|
| whole factorisations | 3, 835 ms (278 ms each) | 3, 954 ms (70 ms of it ordering the region last) |
| CG with the old factor | 280 iterations, 3.7 ms each | - |
| CG on the changed rows | - | 298 iterations at a reach of 0.35, 2.4 ms each |

A whole factorisation costs about 75 CG iterations here; the reuse policy
counts 35 (measured on beams on the AMD machine), so the three
factorisations are half the solve, and the cheaper restricted iterations
save only a third of the other half. What would pay here: fewer or cheaper
factorisations where only the region's rows changed, i.e. refactorising
the trailing block alone (0.2 to 1.0 of a whole factorisation's flops).

## How the adaptive model runs

- **Linear cells are folded into a constant matrix** (`assembly/linear_part`):
  Hooke cells cost one block sparse product per step (D x D sums per node,
  [runtime.md](runtime.md)), run over the nodes that folded cells hold when
  they are fewer than 90 % of all.
- **The criteria** run in one parallel pass over the cells
  (`Criterion::evaluate_block`, `Adaptivity::assess`), R_NL and R_E on
  tet4 four cells at a time. The criteria screen
  (`runtime/src/adaptivity/criteria_screen.cpp`, on by default;
  `AdaptivitySettings::screen = false` turns it off) skips the chunks of
  64 cells whose nodes have not moved far enough for a value to reach a
  threshold (R_NL and R_E are functions of the displacement gradients, and
  their change is bounded from their value): every decision is the one a
  full evaluation takes, and the outputs are the same bits. The "every
  cell evaluated" rows are the same runs with the screen off.
- **The reused factor.** CHOLMOD's factor preconditions CG while CG
  converges within `linear.reuse_iterations` (12). While the non-linear
  cells' rows reach at most 90 % of the factor's entries, CG runs on those
  rows only (`restricted_cg`, `linear_solvers/factor_reach.hpp`). When the reused
  factor stops converging, `CholmodSolver` corrects it with an exact factor
  of the block of rows that jumped (an entry moved by more than 5 % of the
  row's diagonal; at most 60 % of the rows and 10 % of a whole
  factorisation's flops); only when that fails too is the whole matrix
  factorised.
- **The region ordered last** (`runtime/src/linear_solvers/region_last_ordering.cpp`):
  at a whole factorisation, the changing rows and two rings of their
  neighbours are ordered after all the other rows, each part by METIS, so
  that the changed rows reach only the trailing block. It is kept while the
  region holds at most half the rows and its factorisation costs at most
  2x the flops of CHOLMOD's own ordering; otherwise the solver goes back to
  CHOLMOD's ordering. The probe's region grows to {i_nl01_share} of the
  cells: ordered last it would cost 3x a factorisation, so it keeps
  CHOLMOD's ordering, where it reaches up to 92 % of the factor.
  Checkpoints save the rows, the ordering and the jumped-row block, so a
  resumed run repeats bit for bit.
- **The linear tolerance** defaults to 1e-6: a linearised step
  (`newton_iterations: 1`) has no use for ten digits of its linear solve
  (the thorax's trajectory moves by 4e-6 % against 1e-10), and every
  implicit run costs about 0.7x what it costs at 1e-10, the rich law's as
  much as the adaptive ones.
- **Blending** (`adaptivity.blend_steps`) stays off by default: it changes
  the trajectory, and blended cells run two kernels unbatched.
"""


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: render_adaptive.py adaptive_bench.json adaptive_needle_fine.json > adaptive.md")
    data, fine = load(sys.argv[1]), load(sys.argv[2])
    runs = Runs(data)
    tables = []
    for name, heading in SCENES:
        scene, explicit = runs.scene(name), runs.scene(name + "-explicit")
        tables.append(f"### {heading}\n\n{scene['steps']} implicit steps, {explicit['steps']} explicit ones.\n\n"
                      + scene_table(scene, explicit))
    values = {"machine": data["machine"], "threads": data["threads"], "measured": MEASURED,
              "fine_measured": FINE_MEASURED, "scene_tables": "\n\n".join(tables)}
    values.update(figures(runs, fine))
    sys.stdout.write(TEMPLATE.format(**values))


if __name__ == "__main__":
    main()
