"""A cantilever solved by tensormass and by FEniCS DOLFINx (Debian's
python3-dolfinx), same mesh, same law written in UFL: the nodal
displacements must agree to 1e-6 of the largest one.

The beam is 5 x 1 x 1 m of tet4 (tensormass beam --type tet6), clamped at
x = 0 and sagging under its weight. On linear tetrahedra the deformation
gradient is constant per cell, so any quadrature rule integrates both
energies exactly: the two solvers minimise the same discrete energy, and
the comparison tests the laws, the kernels and the solver, not the rules.

usage: cantilever.py --binary TENSORMASS [--law neohookean|mooney_rivlin] [--keep DIR]
"""
import argparse
import logging
import pathlib
import subprocess
import sys
import tempfile

import meshio
import numpy as np
import ufl
from dolfinx import fem, mesh as dmesh, nls
from dolfinx.fem import petsc as fem_petsc
from dolfinx.nls import petsc as nls_petsc
from mpi4py import MPI
from petsc4py import PETSc

logging.getLogger().setLevel(logging.WARNING)  # FFCx's JIT compiler logs every build at INFO
DENSITY, GRAVITY = 1000.0, 9.81
# Small-strain moduli of E = 1 MPa, nu = 0.3 for both laws (Mooney-Rivlin:
# c10 + c01 = mu/2, kappa the bulk modulus): the tip sags about 4 m of the
# 5 m beam, far into the non-linear range (measured: the two solvers agree
# to 6e-14 and 8e-13 of the largest displacement).
YOUNG, POISSON = 1.0e6, 0.3
MU = YOUNG / (2 * (1 + POISSON))
LAM = YOUNG * POISSON / ((1 + POISSON) * (1 - 2 * POISSON))
KAPPA = LAM + 2 * MU / 3
MATERIALS = {
    "neohookean": f"{{region: all, law: neohookean, young: {YOUNG}, poisson: {POISSON}, density: {DENSITY}}}",
    "mooney_rivlin": (f"{{region: all, law: mooney_rivlin, c10: {0.3 * MU}, c01: {0.2 * MU}, kappa: {KAPPA}, "
                      f"density: {DENSITY}}}"),
}
TOLERANCE = 1e-6


def energy_density(law, u):
    """The law file's W (laws/LAW.toml) in UFL."""
    F = ufl.Identity(3) + ufl.grad(u)
    C = F.T * F
    J = ufl.det(F)
    I1 = ufl.tr(C)
    if law == "neohookean":
        return MU / 2 * (I1 - 3) - MU * ufl.ln(J) + LAM / 2 * ufl.ln(J) ** 2
    I2 = (I1 ** 2 - ufl.tr(C * C)) / 2
    I1bar, I2bar = J ** (-2.0 / 3) * I1, J ** (-4.0 / 3) * I2
    return 0.3 * MU * (I1bar - 3) + 0.2 * MU * (I2bar - 3) + KAPPA / 2 * (J - 1) ** 2


def run_tensormass(binary, work, law):
    subprocess.run([binary, "beam", "--dim", "3", "--type", "tet6", "--cells", "10,2,2", "--size", "5,1,1",
                    "-o", str(work / "beam.msh")], check=True, stdout=subprocess.DEVNULL)
    (work / "scene.yaml").write_text(f"""mesh: beam.msh
materials:
  - {MATERIALS[law]}
fixed: [clamp]
loads:
  gravity: [0, -{GRAVITY}, 0]
solver:
  type: static
  load_steps: 4
  tolerance: 1.0e-12
output: {{directory: out, every: 0}}
""")
    subprocess.run([binary, "run", str(work / "scene.yaml"), "--quiet"], check=True)
    result = meshio.read(work / "out" / "final.vtu")
    return result.points, result.point_data["displacement"]


def run_dolfinx(work, law):
    source = meshio.read(work / "beam.msh")
    points, cells = source.points, source.cells_dict["tetra"]
    domain = dmesh.create_mesh(MPI.COMM_SELF, cells.astype(np.int64), points,
                               ufl.Mesh(ufl.VectorElement("Lagrange", "tetrahedron", 1)))
    V = fem.VectorFunctionSpace(domain, ("Lagrange", 1))
    clamped = dmesh.locate_entities_boundary(domain, 0, lambda x: np.isclose(x[0], 0.0))
    zero = np.zeros(3, dtype=PETSc.ScalarType)
    bc = fem.dirichletbc(zero, fem.locate_dofs_topological(V, 0, clamped), V)
    u, v = fem.Function(V), ufl.TestFunction(V)
    weight = fem.Constant(domain, PETSc.ScalarType((0.0, 0.0, 0.0)))
    energy = energy_density(law, u) * ufl.dx - ufl.dot(weight, u) * ufl.dx
    residual = ufl.derivative(energy, u, v)
    problem = fem_petsc.NonlinearProblem(residual, u, [bc], ufl.derivative(residual, u))
    solver = nls_petsc.NewtonSolver(MPI.COMM_SELF, problem)
    solver.rtol, solver.atol, solver.max_it = 1e-14, 1e-11, 50
    solver.convergence_criterion = "incremental"
    for step in range(1, 5):  # the same four load steps
        weight.value = (0.0, -DENSITY * GRAVITY * step / 4, 0.0)
        solver.solve(u)
    coordinates = V.tabulate_dof_coordinates()
    return coordinates, u.x.array.reshape(-1, 3)


def by_position(points, values):
    keys = [tuple(np.round(p, 9)) for p in points]
    return dict(zip(keys, values))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", required=True)
    parser.add_argument("--law", default="neohookean", choices=sorted(MATERIALS))
    parser.add_argument("--keep")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        work = pathlib.Path(args.keep or scratch)
        work.mkdir(parents=True, exist_ok=True)
        ours = by_position(*run_tensormass(args.binary, work, args.law))
        theirs = by_position(*run_dolfinx(work, args.law))
    if set(ours) != set(theirs):
        sys.exit(f"the two meshes' nodes differ ({len(ours)} and {len(theirs)} positions)")
    scale = max(np.linalg.norm(d) for d in ours.values())
    error = max(np.linalg.norm(ours[p] - theirs[p]) for p in ours)
    print(f"{args.law}: largest displacement {scale:.6f} m, largest difference from DOLFINx "
          f"{error:.3e} m ({error / scale:.2e} of it; tolerance {TOLERANCE:g})")
    if not error <= TOLERANCE * scale:
        sys.exit("tensormass and DOLFINx disagree")


if __name__ == "__main__":
    main()
