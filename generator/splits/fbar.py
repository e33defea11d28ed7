"""The fbar split: the mean-dilatation (F-bar) formulation. Each point's law
block is evaluated at F̄ = (J̄/J)^(1/d) F, J̄ the element's volume ratio (at
H̄ = H + (θ̄ - θ)/d I, the B-bar method, for a small-strain law flagged
linear); the runtime's mean_dilatation.hpp assembles the force and the
tangent from the law's P and A there (its header states the derivatives).

Input: `Triple`. Output: `SplitLowering` with `MeanDilatationIR`, or
`SplitRefused` where the formulation is the whole split's energy (one
quadrature point: J̄ = J) or where it is not offered (quadratic elements,
and prism6, which it does not free).
"""
from __future__ import annotations

from ..ir import Flops, MeanDilatationIR
from ..model import ElementSpec, LawKernelIR
from .common import SplitLowering, SplitRefused, Triple
from .whole import quadrature_flops


# First-order elements the mean dilatation does not free, measured
# (bench/locking_cantilever.py): prism6 fbar sagged 0.114 of the converged
# answer at nu = 0.499, plain prism6 0.024, hex8 fbar 0.968. The anp split
# builds on their mean dilatation and averages J over each node's cells.
NOT_FREED = {
    "prism6": "the mean dilatation does not free prism6: its triangular cross-section has one strain, as tri3 "
              "(docs/results/locking.md)",
}


def formulation_flops(element: ElementSpec, points: int, law_ir: LawKernelIR) -> Flops:
    """The whole split's loops plus, counted from mean_dilatation.hpp's loops:
    per point F^-T and F̄ (about 6 d² flops), the force's extra terms (4 d²),
    the point block's rank updates (10 d⁴) and the two extra gradient
    accumulations; per element the rank-2 update (4 dofs²)."""
    base = quadrature_flops(element, points, law_ir)
    d, n = element.dim, element.node_count
    dofs = d * n
    kinematics = points * 6 * d * d
    force = points * 4 * d * d
    block = points * (10 * d ** 4 + 2 * n * d * 2 * d)
    return Flops(energy=base.energy + kinematics, gradient=base.gradient + kinematics + force,
                 hessian=base.hessian + kinematics + force + block + 4 * dofs * dofs)


def lower(triple: Triple) -> SplitLowering:
    element = triple.element
    points = len(triple.tables.weights)
    if points == 1:
        raise SplitRefused("one quadrature point: the element's volume ratio is the point's, fbar is the whole split")
    if element.order != 1:
        raise SplitRefused("offered on first-order elements only: the quadratic ones lock little "
                           "(docs/results/locking.md)")
    if element.name in NOT_FREED:
        raise SplitRefused(NOT_FREED[element.name])
    return SplitLowering(split_ir=MeanDilatationIR(), flops=formulation_flops(element, points, triple.law_ir),
                         extra_consts=0, symbol_names=())
