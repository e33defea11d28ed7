"""The tensor split: Tensor-Mass form. The element energy is a polynomial of
degree 2 (linear strain) or 4 (Green strain) in the nodal displacements whose
coefficient tensors K, V, D are precomputed per element; the C++ loops are in
runtime/include/tensormass/tensor_split.hpp. Offered for first-order
elements, laws quadratic in one strain measure and coefficient counts under a
limit.

Input: `Triple`. Output: `SplitLowering` with `TensorIR` (strain, coefficient
layout, non-zero elasticity entries) and the flops of the polynomial form;
`SplitRefused` otherwise."""
from __future__ import annotations

import sympy

from ..ir import Flops, TensorIR, TensorLayout
from ..model import ElementSpec, StrainQuadratic
from .common import SplitLowering, SplitRefused, Triple

DEFAULT_LIMIT = 3000


def tensor_layout(element: ElementSpec, strain: str) -> TensorLayout:
    n, d = element.node_count, element.dim
    pairs = tuple((j, k) for j in range(n) for k in range(j, n))
    green = strain == "E"
    return TensorLayout(pairs=pairs, k_size=(n * d) ** 2,
                        v_size=n * len(pairs) * d if green else 0,
                        d_size=len(pairs) ** 2 if green else 0)


def tensor_flops(element: ElementSpec, strain: str) -> Flops:
    n, d = element.node_count, element.dim
    dofs = n * d
    ku = dofs * 2 * dofs
    if strain == "eps":
        return Flops(energy=ku + 2 * dofs, gradient=ku, hessian=0)
    p = n * (n + 1) // 2
    s = p * (2 * d - 1)
    t = p * n * 2 * d
    r = p * 2 * p
    return Flops(
        energy=ku + 2 * dofs + s + t + r + p * 4,
        gradient=ku + s + t + r + n * p * d * 3 + n * n * d * 2 * 2,
        hessian=s + t + r + n * n * (d * d * (1 + 4 * n) + 2 * d) + n ** 3 * (2 * n * d + 2 * d * d),
    )


def elasticity_assignments(quadratic: StrainQuadratic) -> tuple[tuple[int, sympy.Expr], ...]:
    """Non-zero entries of the flattened elasticity tensor CC[a][b][c][d]."""
    dim = len(quadratic.elasticity)
    flat = []
    for a in range(dim):
        for b in range(dim):
            for c in range(dim):
                for e in range(dim):
                    value = quadratic.elasticity[a][b][c][e]
                    if value != 0:
                        flat.append((((a * dim + b) * dim + c) * dim + e, value))
    return tuple(flat)


def _quadratic(triple: Triple) -> StrainQuadratic:
    """The law's strain quadratic, or SplitRefused saying why the tensor form is not offered."""
    law, element = triple.law, triple.element
    if element.order != 1:
        raise SplitRefused(f"tensor split: {element.name} is of order {element.order}; "
                           "the tensor form is offered for first-order elements only")
    quadratic = triple.derivatives.quadratic
    if quadratic is None:
        raise SplitRefused(f"tensor split: {triple.derivatives.not_quadratic}")
    return quadratic


def lower(triple: Triple) -> SplitLowering:
    quadratic = _quadratic(triple)
    layout = tensor_layout(triple.element, quadratic.strain)
    if layout.total > triple.tensor_limit:
        raise SplitRefused(f"tensor split: {triple.element.name} with {triple.law.name} needs {layout.total} "
                           f"coefficients per element, over the limit {triple.tensor_limit} (--tensor-limit)")
    split_ir = TensorIR(strain=quadratic.strain, layout=layout, elasticity=elasticity_assignments(quadratic))
    return SplitLowering(split_ir=split_ir, flops=tensor_flops(triple.element, quadratic.strain),
                         extra_consts=layout.total, symbol_names=())
