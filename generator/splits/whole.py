"""The whole split: one function per entry point; per point H by loops, the
law block, then the gradient and the Hessian as small matrix products
(vectorisable loops of kernel_support.hpp).

Input: `Triple`. Output: `SplitLowering` with `WholeIR` and the flops of the
quadrature loops."""
from __future__ import annotations

from ..ir import Flops, WholeIR
from ..model import ElementSpec, LawKernelIR
from .common import SplitLowering, Triple


def displacement_gradient_flops(element: ElementSpec) -> int:
    """H = sum_j u_j G_j^T at one point."""
    return element.dim ** 2 * (2 * element.node_count - 1)


def quadrature_flops(element: ElementSpec, points: int, law_ir: LawKernelIR) -> Flops:
    n, d = element.node_count, element.dim
    h = displacement_gradient_flops(element)
    gradient_accumulate = n * d * 2 * d
    pairs = d * (d + 1) // 2
    hessian_products = pairs * (d * n * (2 * d - 1) + n * n * 2 * d)
    return Flops(
        energy=points * (h + law_ir.energy.flops + 1),
        gradient=points * (h + law_ir.weighted_stress.flops + gradient_accumulate),
        hessian=points * (h + law_ir.tangent.flops + hessian_products),
    )


def lower(triple: Triple) -> SplitLowering:
    flops = quadrature_flops(triple.element, len(triple.tables.weights), triple.law_ir)
    return SplitLowering(split_ir=WholeIR(), flops=flops, extra_consts=0, symbol_names=())
