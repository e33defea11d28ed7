"""Stage 4 (lower): one `KernelIR` per LES triple (law, element, split).

Input: `OptimisedIR` (stage 3) and the tensor split's coefficient limit.
Output: `LoweredIR`: per offered triple a `KernelIR` holding the optimised
law block, the split's own IR (`splits/`), the size of the constants, the
C names of the symbols and the flop count of each entry point, counted on
what the emitted code executes; the refused triples with their reasons; one
`ElementIR` per element (`lower_element.py`).

Splits (one module each in `splits/`):
  whole   one function per kernel; per point: H by loops, the law block, then
          the gradient and the Hessian as small matrix products (vectorisable)
  terms   the gradient and Hessian written out entry by entry as explicit sums
          (the origin report's long equations), cut by node rows into parts,
          one function and one translation unit per part
  tensor  Tensor-Mass form: the force as a polynomial of degree 1 (linear
          strain) or 3 (Green strain) in nodal displacements with coefficient
          tensors precomputed per element; first-order elements, laws quadratic
          in one strain measure, coefficient count under a limit
  fbar    the mean-dilatation (F-bar) formulation: the law at F̄ = (J̄/J)^(1/d) F
          with J̄ the element's volume ratio (a different energy from the three
          above, free of volumetric locking); first-order elements with more
          than one quadrature point but prism6
  anp     averaged nodal pressure: the whole (or, on prism6, fbar) split's
          kernel of the full energy and the law's bulk part U(J), which the
          runtime integrates at the nodes instead of the element (free of
          volumetric locking); tet4, tri3 and prism6, laws with a bulk part
"""
from __future__ import annotations

from .ir import KernelIR, LoweredIR, Refusal
from .lower_element import lower_element
from .model import ElementSpec, LawSpec, OptimisedIR
from .splits import anp, fbar, tensor, terms, whole
from .symbolic import law_bulk
from .splits.common import SplitRefused, Triple, point_stride

from .stale import SPLITS
_LOWERINGS = {"whole": whole.lower, "terms": terms.lower, "tensor": tensor.lower, "fbar": fbar.lower, "anp": anp.lower}
DEFAULT_TENSOR_LIMIT = tensor.DEFAULT_LIMIT

__all__ = ["SPLITS", "DEFAULT_TENSOR_LIMIT", "SplitRefused", "build_kernel_ir", "lower"]


def _base_symbol_names(element: ElementSpec) -> dict[str, str]:
    """H{i} -> H[i], u{i} -> u[i], R{i} -> R[i], Y{i} -> Y[i]: the displacement
    gradient, the nodal displacements, the polar rotation and its inverse term."""
    n, d = element.node_count, element.dim
    names = {f"H{i}": f"H[{i}]" for i in range(d * d)}
    names.update({f"R{i}": f"R[{i}]" for i in range(d * d)})
    names.update({f"Y{i}": f"Y[{i}]" for i in range(9 if d == 3 else 1)})
    names.update({f"u{i}": f"u[{i}]" for i in range(n * d)})
    return names


def build_kernel_ir(optimised: OptimisedIR, law: LawSpec, element: ElementSpec, split: str,
                    tensor_limit: int = DEFAULT_TENSOR_LIMIT) -> KernelIR:
    """The KernelIR of one triple; SplitRefused when the split is not offered for it."""
    if split not in _LOWERINGS:
        raise ValueError(f"unknown split {split}")
    symbolic = optimised.symbolic
    tables = symbolic.tables_of(element)
    law_ir = optimised.law_ir(law, element.dim)
    derivatives = symbolic.derivatives_of(law, element.dim)
    triple = Triple(law=law, element=element, tables=tables, law_ir=law_ir,
                    derivatives=derivatives, tensor_limit=tensor_limit)
    lowering = _LOWERINGS[split](triple)
    names = _base_symbol_names(element)
    names.update(lowering.symbol_names)
    consts = len(law.constants) + len(tables.weights) * point_stride(element) + lowering.extra_consts
    return KernelIR(law=law, element=element, split=split, tables=tables, law_ir=law_ir, consts_size=consts,
                    flops=lowering.flops, symbol_names=tuple(names.items()), split_ir=lowering.split_ir,
                    linear=derivatives.linear, invertible=law.invertible and split != "fbar" and not (
                        split == "anp" and lowering.split_ir.base == "fbar"),
                    viscous_bulk=law_bulk(law) if law.viscoelastic and law.bulk and split == "whole" else ())


def lower(optimised: OptimisedIR, tensor_limit: int = DEFAULT_TENSOR_LIMIT) -> LoweredIR:
    """Stage 4: every (law, element, split) in that order, offered or refused, and the elements."""
    inputs = optimised.symbolic.inputs
    kernels, refused = [], []
    for law in inputs.laws:
        for element in inputs.elements:
            for split in SPLITS:
                try:
                    kernels.append(build_kernel_ir(optimised, law, element, split, tensor_limit))
                except SplitRefused as why:
                    refused.append(Refusal(law=law.name, element=element.name, split=split, reason=str(why)))
    elements = tuple(lower_element(e, optimised.symbolic.tables_of(e)) for e in inputs.elements)
    return LoweredIR(kernels=tuple(kernels), refused=tuple(refused), elements=elements, laws=inputs.laws)
