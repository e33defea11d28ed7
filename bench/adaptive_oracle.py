#!/usr/bin/env python3
"""How few cells must carry the rich law? Chosen with hindsight, per scene.

The targets of `tensormass bench adaptive` ask for adaptive runs within 1 % of
the pure rich law at a fraction of its cost. A run's cost grows with the cells under the rich law, so the
question behind each target is: how small can that set be at 1 %? This script
answers it with hindsight (an oracle no criterion can beat by much):

1. the pure rich run, recording every step's displacement and, per cell, the
   largest value over the run of each indicator;
2. for each indicator and each fraction f: a run with the top f of the cells
   (ranked by that indicator) under the rich law from the first step and
   every other cell under Hooke; its error against the pure rich run (largest
   nodal distance over all steps / the rich run's largest displacement, as in
   `tensormass-bench adaptive`).

Indicators (per cell, the largest value over the rich run; the adaptive
model's criteria, docs/scene.md, read through Simulation.criteria):
  R_NL   |1/2 H^T H|_F, the part of the Green strain Hooke drops
  R_E    |E|_F, the Green strain (rotation-free)
  R_P    |P_rich(F) - P_hooke(F)|_F / E: the stress Hooke gets wrong, in
         units of Young's modulus

Scenes: the indentation and the needle of `tensormass-bench adaptive` (the
24,000-tet block, its probe 1.5 cm or its needle 1 cm down, implicit, rich law
neo-Hookean), its cantilever (8,640 tets, gravity, rich law StVK) and the
thorax deep breath of bench/thorax_deep_breath.py (11,512 mixed cells,
diaphragm 5 cm down). Every run uses the default solver settings. About 5 minutes for all four.

    PYTHONPATH=build/python /usr/bin/python3 bench/adaptive_oracle.py [--only NAME] [--fractions 0.1,0.2,...]
        [--steps N]
"""
import argparse
import itertools
import os
import sys
import tempfile

import numpy as np

import tensormass as tm

HERE = os.path.dirname(os.path.abspath(__file__))
FRACTIONS = "0.1,0.2,0.3,0.5,0.7,0.9"
WORK = tempfile.mkdtemp(prefix="tm-oracle-")  # the runs' final.vtu and summary.json


# --- Scenes ---------------------------------------------------------------------------------------


def tet_block(size, counts):
    """Points and tet4 cells of a box of counts hexahedra, each cut into 6 tets along its diagonal."""
    axes = [np.linspace(0.0, size[a], counts[a] + 1) for a in range(3)]
    grid = np.meshgrid(*axes, indexing="ij")
    points = np.column_stack([g.ravel() for g in grid])
    index = np.arange(len(points)).reshape(np.asarray(counts) + 1)
    i, j, k = (a.ravel() for a in np.meshgrid(*(np.arange(n) for n in counts), indexing="ij"))
    tets = []
    for axes_order in itertools.permutations(range(3)):  # the paths from corner 000 to 111
        path = [np.zeros(3, int)]
        for axis in axes_order:
            corner = path[-1].copy()
            corner[axis] = 1
            path.append(corner)
        tets.append(np.column_stack([index[i + a, j + b, k + c] for a, b, c in path]))
    tets = np.vstack(tets)
    edges = points[tets[:, 1:]] - points[tets[:, :1]]
    flip = np.linalg.det(edges) < 0
    tets[flip, 1], tets[flip, 2] = tets[flip, 2].copy(), tets[flip, 1].copy()
    return points, tets


class Scene:
    """A scene run through Simulation.from_arrays (tet4) or from a YAML file (the thorax)."""

    def __init__(self, name, what, rich, young, poisson):
        self.name, self.what, self.rich = name, what, rich
        self.young, self.poisson = young, poisson

    def simulation(self, law, adaptivity=None):
        raise NotImplementedError


class BlockScene(Scene):
    def __init__(self, name, what, rich, young, poisson, points, tets, groups, **keys):
        super().__init__(name, what, rich, young, poisson)
        self.points, self.tets, self.groups, self.keys = points, tets, groups, keys

    def simulation(self, law, adaptivity=None):
        keys = dict(self.keys)
        if adaptivity:
            keys["adaptivity"] = adaptivity
        return tm.Simulation.from_arrays(
            self.points, {"tet4": self.tets}, groups=self.groups, name=self.name,
            materials=[{"law": law, "young": self.young, "poisson": self.poisson, "density": keys.pop("density")}],
            output={"directory": os.path.join(WORK, self.name), "every": 0}, **keys)


def pressed_block(name, half_width, depth, steps=50):
    """The 10 x 5 x 10 cm block of `tensormass-bench adaptive` (E 5 kPa, nu 0.45), a square of the top
    face of half-width `half_width` pushed `depth` down over 0.5 s, in implicit steps of 0.01 s: 50 steps
    reach the full depth, fewer stop on the way."""
    size = np.array([0.1, 0.05, 0.1])
    points, tets = tet_block(size, (20, 10, 20))
    base = np.flatnonzero(points[:, 1] < 1e-9)
    top = points[:, 1] > size[1] - 1e-9
    near = np.all(np.abs(points[:, [0, 2]] - 0.05) <= half_width + 1e-9, axis=1)
    tool = np.flatnonzero(top & near)
    what = (f"{len(tets)} tet4, E 5 kPa, nu 0.45, {200 * half_width:g} x {200 * half_width:g} cm tool "
            f"{100 * depth:g} cm into 5 cm, {steps} implicit steps")
    return BlockScene(name, what, "neohookean", 5e3, 0.45, points, tets, {"base": base, "tool": tool},
                      density=1000.0, fixed=["base"],
                      prescribed=[{"region": "tool", "displacement": [0, -depth, 0],
                                   "profile": {"type": "ramp", "duration": 0.5}}],
                      solver={"type": "implicit", "dt": 0.01, "steps": steps})


def cantilever(steps=150):
    """`tensormass-bench adaptive`'s cantilever: 5 x 1 x 1 m, 30 x 6 x 8 hexahedra cut into 6 tets,
    E 20 MPa, nu 0.3, clamped at x = 0, under gravity, `steps` implicit steps of 0.01 s."""
    points, tets = tet_block((5.0, 1.0, 1.0), (30, 6, 8))
    clamp = np.flatnonzero(points[:, 0] < 1e-9)
    return BlockScene("cantilever", f"{len(tets)} tet4, 5 x 1 x 1 m, E 20 MPa, gravity, {steps} implicit steps",
                      "stvk", 2e7, 0.3, points, tets, {"clamp": clamp}, density=1000.0, fixed=["clamp"],
                      loads={"gravity": [0, -9.81, 0]}, solver={"type": "implicit", "dt": 0.01, "steps": steps})


class ThoraxScene(Scene):
    """bench/thorax_deep_breath.py's scene: the example thorax, diaphragm 5 cm down over 40 steps."""

    def __init__(self, steps=40):
        super().__init__("thorax", f"the thorax deep breath, diaphragm 5 cm, {steps} implicit steps of 0.05 s",
                         "neohookean", None, None)
        sys.path.insert(0, HERE)
        import thorax_deep_breath as breath
        self.breath = breath
        self.work = tempfile.mkdtemp(prefix="tm-oracle-thorax-")
        self.scene = breath.make_mesh(os.path.join(os.path.dirname(HERE), "build", "tensormass"), self.work)
        self.args = argparse.Namespace(depth=0.05, steps=steps, explicit=False, every=1)

    def simulation(self, law, adaptivity=None):
        overrides = self.breath.overrides_for("oracle", law, None, self.args, self.work)
        overrides["adaptivity"] = adaptivity
        return tm.Simulation(self.scene, overrides=overrides)


SCENES = {  # name -> the scene, given its steps (None: the benchmark's own)
    "indentation": lambda steps: pressed_block("indentation", 0.01, 0.015, steps or 50),
    "needle": lambda steps: pressed_block("needle", 0.005, 0.01, steps or 50),
    "cantilever": lambda steps: cantilever(steps or 150),
    "thorax": lambda steps: ThoraxScene(steps or 40),
}


# --- Indicators ---------------------------------------------------------------------------------------


def watching_criteria(scene):
    """An adaptivity that evaluates R_NL, R_E and R_P on every cell at every step and moves none: the
    cells are on its ladder's top rung, and R_P (which no screen bounds) keeps the criteria screen off."""
    return {"criteria": [{"name": name, "threshold": 1e9} for name in ("R_NL", "R_E", "R_P")],
            "ladder": ["hooke", scene.rich]}


def rich_run(scene):
    """The pure rich run: its displacements per step and each indicator's largest value per cell."""
    sim = scene.simulation(scene.rich, watching_criteria(scene))
    history, peaks = [], {}
    while sim.step():
        u = sim.displacement
        history.append(u)
        for name, value in sim.criteria().items():
            peaks[name] = np.maximum(peaks.get(name, value), value)
    return np.array(history), peaks


def mixed_run(scene, rich_cells):
    """Hooke everywhere but `rich_cells`, which carry the rich law from the first step."""
    sim = scene.simulation("hooke")
    if len(rich_cells):
        sim.set_law([int(c) for c in rich_cells], scene.rich)
    history = []
    try:
        while sim.step():
            history.append(sim.displacement)
    except tm.NumericalError as failure:
        return None, str(failure).split(";")[0]
    return np.array(history), None


def error(history, reference):
    steps = min(len(history), len(reference))
    distance = np.linalg.norm(history[:steps] - reference[:steps], axis=2).max()
    return distance / np.linalg.norm(reference, axis=2).max()


# --- Report ---------------------------------------------------------------------------------------


def report(scene, fractions):
    print(f"## {scene.name}: {scene.what}, rich law {scene.rich}\n", flush=True)
    reference, peaks = rich_run(scene)
    hooke, _ = mixed_run(scene, [])
    cells = len(next(iter(peaks.values())))
    print(f"pure hooke: {100 * error(hooke, reference):.3f} %\n")
    print("| indicator | " + " | ".join(f"top {100 * f:g} %" for f in fractions) + " | least within 1 % |")
    print("|---|" + "---:|" * (len(fractions) + 1))
    for name in ("R_NL", "R_E", "R_P"):
        order = np.argsort(-peaks[name], kind="stable")
        row, least = [], "none"
        for f in fractions:
            history, failure = mixed_run(scene, order[: int(round(f * cells))])
            if failure:
                row.append("failed")
                continue
            e = error(history, reference)
            row.append(f"{100 * e:.2f} %")
            if e <= 0.01 and least == "none":
                least = f"{100 * f:g} %"
        print(f"| {name} | " + " | ".join(row) + f" | {least} |", flush=True)
    print()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=sorted(SCENES), action="append", help="one scene (repeatable)")
    parser.add_argument("--fractions", default=FRACTIONS, help="shares of the cells under the rich law")
    parser.add_argument("--steps", type=int, default=None,
                        help="run only this many steps of every scene (a shallower push, a shorter sag or "
                             "breath; default each benchmark's own)")
    args = parser.parse_args()
    try:
        fractions = [float(f) for f in args.fractions.split(",")]
    except ValueError:
        parser.error(f"--fractions: a comma-separated list of numbers, not {args.fractions!r}")
    if not fractions or any(not 0.0 < f <= 1.0 for f in fractions):
        parser.error("--fractions: each share must lie in (0, 1]")
    if args.steps is not None and args.steps < 1:
        parser.error(f"--steps must be at least 1, not {args.steps}")
    print("# the least non-linear set, chosen with hindsight (bench/adaptive_oracle.py)\n")
    print("error against the pure rich run with the top share of the cells (ranked by each indicator's largest")
    print("value over that run) under the rich law from the first step, every other cell under Hooke\n")
    for name in args.only or list(SCENES):
        report(SCENES[name](args.steps), sorted(fractions))
    return 0


if __name__ == "__main__":
    sys.exit(main())
