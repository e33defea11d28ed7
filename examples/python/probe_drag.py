#!/usr/bin/env python3
"""A probe pressed into a soft block and dragged across it, scripted from Python.

The block (10 x 5 x 10 cm, E = 5 kPa, nu = 0.45, stable neo-Hookean, bottom
fixed) is built from NumPy arrays; a 2 x 2 cm square of its top face is the
probe. Each static load step moves the probe (Simulation.set_prescribed):
first down to `--depth`, then along x by `--drag` at that depth. The force
on the probe is minus the tissue's internal force at the probe's nodes
(Simulation.internal_force), checked against the same sum computed in
Python from the generated kernel (tensormass.kernel). Writes
the frames (series.pvd, for ParaView), force.csv and force.png (force
against depth while pressing, drag force against travel while dragging).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/probe_drag.py -o probe-out
"""
import argparse
import os
import sys

import numpy as np

import tensormass as tm

YOUNG, POISSON, DENSITY = 5.0e3, 0.45, 1000.0
SIZE = np.array([0.10, 0.05, 0.10])  # x, y (up), z in metres
LAW = "stable_neohookean"


def block(cells_per_cm):
    """Points, hex8 cells (VTK order) and the bottom and probe point groups."""
    counts = np.maximum(1, np.round(SIZE * 100 * cells_per_cm).astype(int))
    axes = [np.linspace(0.0, SIZE[a], counts[a] + 1) for a in range(3)]
    x, y, z = np.meshgrid(*axes, indexing="ij")
    points = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    index = np.arange(points.shape[0]).reshape(counts + 1)
    i, j, k = (a.ravel() for a in np.meshgrid(*(np.arange(n) for n in counts), indexing="ij"))
    corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    hexes = np.column_stack([index[i + a, j + b, k + c] for a, b, c in corners])
    bottom = np.flatnonzero(points[:, 1] == 0.0)
    on_top = np.isclose(points[:, 1], SIZE[1])
    centre = SIZE[[0, 2]] / 2 - np.array([0.02, 0.0])  # starts 2 cm left of the centre
    near = np.all(np.abs(points[:, [0, 2]] - centre) <= 0.01 + 1e-9, axis=1)
    probe = np.flatnonzero(on_top & near)
    return points, hexes, bottom, probe


def probe_force(sim, probe):
    """The force of the tissue on the probe (N): minus the internal force at its nodes."""
    return -sim.internal_force()[probe].sum(axis=0)


def probe_force_from_kernels(sim, kernel, rest_cells, hexes, probe):
    """The same force computed in Python from the generated kernel, cell by cell (a cross-check)."""
    gradient = kernel.gradient(rest_cells, sim.displacement[hexes], young=YOUNG, poisson=POISSON)
    internal = np.zeros_like(sim.displacement)
    np.add.at(internal, hexes.ravel(), gradient.reshape(-1, 3))
    return -internal[probe].sum(axis=0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", default="probe-out", help="output directory")
    parser.add_argument("--depth", type=float, default=0.008, help="pressing depth (m)")
    parser.add_argument("--drag", type=float, default=0.01, help="drag distance along x (m)")
    parser.add_argument("--steps", type=int, default=8, help="load steps for each of pressing and dragging")
    parser.add_argument("--cells-per-cm", type=float, default=2.0, help="mesh resolution")
    parser.add_argument("--progress", action="store_true", help="a progress bar on stderr")
    args = parser.parse_args()

    points, hexes, bottom, probe = block(args.cells_per_cm)
    sim = tm.Simulation.from_arrays(
        points, {"hexahedron": hexes}, groups={"bottom": bottom, "probe": probe}, name="probe_drag",
        progress=args.progress,
        materials=[{"law": LAW, "young": YOUNG, "poisson": POISSON, "density": DENSITY}],
        fixed=["bottom"],
        prescribed=[{"region": "probe", "displacement": [0, 0, 0]}],
        solver={"type": "static", "load_steps": 2 * args.steps, "tolerance": 1e-8},
        output={"directory": args.output, "every": 1})
    kernel = tm.kernel(LAW, "hex8")
    rest_cells = sim.rest_positions[hexes]
    print(f"block: {len(points)} points, {len(hexes)} hex8 cells; probe: {len(probe)} nodes")

    rows = []  # step, probe x and y displacement, force x, y, z
    for step in range(1, 2 * args.steps + 1):
        pressing = step <= args.steps
        depth = args.depth * min(step / args.steps, 1.0)
        travel = 0.0 if pressing else args.drag * (step - args.steps) / args.steps
        sim.set_prescribed("probe", displacement=(travel, -depth, 0.0))
        sim.step()
        force = probe_force(sim, probe)
        check = probe_force_from_kernels(sim, kernel, rest_cells, hexes, probe)
        if not np.allclose(force, check, rtol=1e-9, atol=1e-12):
            raise SystemExit(f"step {step}: internal_force {force} and the kernels' {check} disagree")
        rows.append((step, travel, -depth, *force))
        print(f"step {step:2d}: depth {depth * 1e3:5.2f} mm, travel {travel * 1e3:5.2f} mm, "
              f"force on the probe ({force[0]:+.4f}, {force[1]:+.4f}, {force[2]:+.4f}) N")
    rows = np.array(rows)
    np.savetxt(os.path.join(args.output, "force.csv"), rows, delimiter=",",
               header="step,travel_m,probe_uy_m,force_x_N,force_y_N,force_z_N", comments="")
    plot(rows, args, os.path.join(args.output, "force.png"))
    print(f"wrote {args.output}/series.pvd, force.csv and force.png")
    return 0


def plot(rows, args, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pressing, dragging = rows[: args.steps], rows[args.steps:]
    figure, (left, right) = plt.subplots(1, 2, figsize=(9, 3.5))
    left.plot(-pressing[:, 2] * 1e3, pressing[:, 4], "o-")
    left.set(xlabel="depth (mm)", ylabel="vertical force on the probe (N)", title="pressing")
    right.plot(dragging[:, 1] * 1e3, -dragging[:, 3], "o-", label="drag (-x)")
    right.plot(dragging[:, 1] * 1e3, dragging[:, 4], "s-", label="vertical")
    right.set(xlabel="travel (mm)", ylabel="force on the probe (N)", title=f"dragging at {args.depth * 1e3:g} mm")
    right.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=120)


if __name__ == "__main__":
    sys.exit(main())
