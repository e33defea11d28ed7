"""tensormass: adaptive Tensor-Mass soft-tissue simulation.

The generated kernels on NumPy batches of elements::

    import tensormass as tm
    tm.kernels()                               # every kernel, as dicts
    k = tm.kernel("stvk", "tet4", "whole")
    k.energy(rest, u, young=1e6, poisson=0.3)  # rest, u: (n, nodes, dim) -> (n,)
    k.gradient(rest, u, young=1e6, poisson=0.3)  # -> (n, nodes * dim)
    k.hessian(rest, u, young=1e6, poisson=0.3)   # -> (n, dofs, dofs)

Bad input raises ValueError; a numerical failure raises tensormass.NumericalError.
"""
from ._tensormass import Kernel, NumericalError, kernel, kernels

__all__ = ["Kernel", "NumericalError", "kernel", "kernels"]
