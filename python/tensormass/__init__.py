"""tensormass: adaptive Tensor-Mass soft-tissue simulation.

The generated kernels on NumPy batches of elements::

    import tensormass as tm
    tm.kernels()                               # every kernel, as dicts
    k = tm.kernel("stvk", "tet4", "whole")
    k.energy(rest, u, young=1e6, poisson=0.3)  # rest, u: (n, nodes, dim) -> (n,)
    k.gradient(rest, u, young=1e6, poisson=0.3)  # -> (n, nodes * dim)
    k.hessian(rest, u, young=1e6, poisson=0.3)   # -> (n, dofs, dofs)

A scene run step by step, its state as NumPy arrays::

    sim = tm.Simulation("scene.yaml", overrides={"solver.steps": 10})
    while sim.step():                          # one step (static: one load step)
        print(sim.time, abs(sim.displacement).max())
    sim.set_law(cells, "neohookean")           # between steps
    sim.set_prescribed("probe", displacement=(0, -0.01, 0))
    sim = tm.Simulation.from_arrays(points, {"tetra": tets}, groups={"base": nodes},
                                    materials=[...], fixed=["base"], solver={...})

Under ``mpirun -n N python script.py`` with ``solver.backend: petsc`` every
rank runs the script and the run is shared among the ranks (each holds the
whole state; rank 0 writes the files; ``tm.mpi_rank()``, ``tm.mpi_size()``).

Bad input raises ValueError; a numerical failure raises tensormass.NumericalError; a failed write, OSError.
See docs/python.md.
"""
import os as _os

# The OpenMP wait policy of the CLI (runtime/include/tensormass/common/
# thread_defaults.hpp): idle threads spin for about 0.1 ms, then sleep,
# where libgomp's default spinning took a core from the serial phases.
# libgomp reads both once, when it is loaded by the import below; values
# set by the user stay.
if "OMP_WAIT_POLICY" not in _os.environ:
    _os.environ["OMP_WAIT_POLICY"] = "passive"
    _os.environ.setdefault("GOMP_SPINCOUNT", "10000")

from ._tensormass import (  # noqa: E402
    Kernel, NumericalError, Simulation, __version__, kernel, kernels, mpi_rank, mpi_size, petsc_available)

__all__ = ["__version__", "Kernel", "NumericalError", "Simulation", "kernel", "kernels", "mpi_rank", "mpi_size", "petsc_available"]
