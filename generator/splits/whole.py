"""The whole split: one function per entry point; per point H by loops, the
law block, then the gradient and the Hessian as small matrix products
(vectorisable loops of kernel_support.hpp).

Input: `Triple`. Output: `SplitLowering` with `WholeIR` and the flops of the
quadrature loops."""
from __future__ import annotations

import sympy

from ..ir import Flops, WholeIR
from ..model import ElementSpec, LawKernelIR, RationalRoot
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


# Batched entry points (W elements per call, SIMD across the elements) pay
# where the law block vectorises across the lanes and the W lanes' Hessian
# blocks stay in the L1 cache (docs/results/kernels.md has the figures):
# - at most BATCH_BLOCK_LIMIT doubles of component-pair blocks per lane. Above
#   it (hex8, tet10, hex20) the batched kernel was 1.8 to 8x slower than the
#   per-element one, which is already vectorised along its 8 or more nodes.
# - no library calls but `log` and `exp` (fractional powers x^(p/q) other
#   than sqrt reach the block as one root exp(+-log(x)/q) per base,
#   optimize.eliminate). With scalar calls per lane neo-Hookean and
#   corotational ran batched at 0.8 to 1.0x alone and 1.07 to 1.13x in the
#   assembly, where packing the batch costs more than the kernel saves. `log`
#   and `exp` are declared with glibc's vector variants (kernel_support.hpp:
#   libmvec's, as -ffast-math would), so their lanes run in one SIMD call.
# - auxiliaries: only the polar rotation and its inverse term. The batch
#   computes the lanes' rotations together before the SIMD loop
#   (polar_rotation_batch, one Newton-Schulz iteration over all lanes), and the
#   inverse term is straight-line code.
BATCH_BLOCK_LIMIT = 256
BATCHED_AUXILIARIES = frozenset({"rotation", "rotation_inverse"})


def batch_pays(element: ElementSpec, law_ir: LawKernelIR) -> bool:
    """True when the (law, element)'s whole kernels get batched entry points."""
    d, n = element.dim, element.node_count
    if d * (d + 1) // 2 * n * n > BATCH_BLOCK_LIMIT:
        return False
    block = law_ir.tangent
    calls = any(any(not _vector_call(f) for f in a.expr.atoms(sympy.Function)) or
                any(not p.exp.is_Integer for p in a.expr.atoms(sympy.Pow)) for a in block.assignments)
    return not calls and set(block.auxiliaries) <= BATCHED_AUXILIARIES


def _vector_call(function: sympy.Expr) -> bool:
    """A call that runs on all lanes at once through libmvec: log, exp, a root printed as exp(e*log(x))."""
    if isinstance(function, RationalRoot):
        return function.args[1].q != 2
    return isinstance(function, (sympy.log, sympy.exp))


def lower(triple: Triple) -> SplitLowering:
    flops = quadrature_flops(triple.element, len(triple.tables.weights), triple.law_ir)
    return SplitLowering(split_ir=WholeIR(batched=batch_pays(triple.element, triple.law_ir)), flops=flops, extra_consts=0,
                         symbol_names=())
