"""Stage 4 (lower): one `KernelIR` per LES triple (law, element, split).

Input: specs, element tables, law derivatives (symbolic stage).
Output: `KernelIR` holding the optimised law blocks (CSE'd straight-line code
at one quadrature point), the split's extra data for its template (the
straight-line entries of `terms`, the coefficient layout of `tensor`) and the
flop count of each kernel, counted on what the emitted code executes.

Splits:
  whole   one function per kernel; per point: H by loops, the law block, then
          the gradient and the Hessian as small matrix products (vectorisable)
  terms   the gradient and Hessian written out entry by entry as explicit sums
          (the origin report's long equations), cut by node rows into parts,
          one function and one translation unit per part
  tensor  Tensor-Mass form: the force as a polynomial of degree 1 (linear
          strain) or 3 (Green strain) in nodal displacements with coefficient
          tensors precomputed per element; first-order elements, laws quadratic
          in one strain measure, coefficient count under a limit
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import sympy

from .load import GeneratorInputError
from .model import Block, ElementSpec, KernelIR, LawKernelIR, LawSpec
from .optimize import eliminate
from .symbolic import element_tables, law_derivatives, strain_quadratic

SPLITS = ("whole", "terms", "tensor")
DEFAULT_TENSOR_LIMIT = 3000
TERMS_ENTRIES_PER_PART = 400
WEIGHT = sympy.Symbol("w", real=True)


class SplitRefused(Exception):
    """This split is not offered for this (law, element); the message says why."""


def build_law_ir(law: LawSpec, dim: int) -> LawKernelIR:
    psi, P, A = law_derivatives(law, dim)
    d2 = dim * dim
    energy = eliminate([("psi", WEIGHT * psi)], "e")
    stress = eliminate([(f"P[{i}]", p) for i, p in enumerate(P)], "s")
    weighted = [(f"wP[{i}]", WEIGHT * p) for i, p in enumerate(P)]
    weighted_stress = eliminate(weighted, "s")
    outputs, canonical, tangent_map = list(weighted), {}, [[None] * d2 for _ in range(d2)]
    for i in range(d2):
        for j in range(i, d2):
            entry = WEIGHT * A[i][j]
            key = sympy.expand(entry) if A[i][j].is_polynomial() else entry
            if key == 0:
                continue
            if key not in canonical:
                canonical[key] = f"wA[{i * d2 + j}]"
                outputs.append((canonical[key], entry))
            tangent_map[i][j] = tangent_map[j][i] = canonical[key]
    tangent = eliminate(outputs, "a")
    tangent_only = eliminate(outputs[len(weighted):], "a")
    return LawKernelIR(dim=dim, energy=energy, stress=stress, weighted_stress=weighted_stress,
                       tangent=tangent, tangent_only=tangent_only, tangent_map=tuple(tuple(row) for row in tangent_map))


def point_stride(element: ElementSpec) -> int:
    """Doubles per quadrature point in the constants: w, then G^T (dim by nodes)."""
    return 1 + element.dim * element.node_count


def _quadrature_flops(element: ElementSpec, q: int, law_ir: LawKernelIR) -> dict:
    n, d = element.node_count, element.dim
    h = d * d * (2 * n - 1)
    gradient_accumulate = n * d * 2 * d
    pairs = d * (d + 1) // 2
    hessian_products = pairs * (d * n * (2 * d - 1) + n * n * 2 * d)
    return {
        "energy": q * (h + law_ir.energy.flops + 1),
        "gradient": q * (h + law_ir.weighted_stress.flops + gradient_accumulate),
        "hessian": q * (h + law_ir.tangent.flops + hessian_products),
    }


@dataclass(frozen=True)
class TermsPart:
    nodes: tuple[int, ...]  # the node rows this part computes
    gradient: Block  # defines g[...] entries (accumulated with +=)
    hessian: Block  # defines K[...] upper-triangle entries (accumulated with +=)


def _terms_parts(element: ElementSpec, law_ir: LawKernelIR) -> tuple[TermsPart, ...]:
    n, d = element.node_count, element.dim
    dofs = n * d
    G = [[sympy.Symbol(f"G{c}_{j}", real=True) for c in range(d)] for j in range(n)]
    A = [[sympy.Symbol(name.replace("[", "").replace("]", ""), real=True) if name else sympy.S.Zero
          for name in row] for row in law_ir.tangent_map]
    wP = [sympy.Symbol(f"wP{i}", real=True) for i in range(d * d)]
    rows_of = [sum(dofs - (j * d + a) for a in range(d)) for j in range(n)]
    parts_wanted = max(2, math.ceil(sum(rows_of) / TERMS_ENTRIES_PER_PART))
    parts_wanted = min(parts_wanted, n)
    target = sum(rows_of) / parts_wanted
    groups, current, load = [], [], 0.0
    for j in range(n):
        current.append(j)
        load += rows_of[j]
        if load >= target * (len(groups) + 1) and len(groups) < parts_wanted - 1:
            groups.append(tuple(current))
            current = []
    if current:
        groups.append(tuple(current))
    parts = []
    for group in groups:
        g_out, k_out = [], []
        for j in group:
            for a in range(d):
                row = j * d + a
                g_out.append((f"g[{row}]", sum(wP[a * d + c] * G[j][c] for c in range(d))))
                for k in range(n):
                    for b in range(d):
                        col = k * d + b
                        if col < row:
                            continue
                        entry = sum(G[j][c] * A[a * d + c][b * d + e] * G[k][e]
                                    for c in range(d) for e in range(d))
                        k_out.append((f"K[{row * dofs + col}]", entry))
        parts.append(TermsPart(nodes=group, gradient=eliminate(g_out, "x"), hessian=eliminate(k_out, "y")))
    return tuple(parts)


def terms_symbol_names(element: ElementSpec, law_ir: LawKernelIR) -> dict[str, str]:
    n, d = element.node_count, element.dim
    names = {f"G{c}_{j}": f"GT[{c * n + j}]" for c in range(d) for j in range(n)}
    names.update({f"wP{i}": f"wP[{i}]" for i in range(d * d)})
    for row in law_ir.tangent_map:
        for name in row:
            if name:
                names[name.replace("[", "").replace("]", "")] = name
    return names


def tensor_layout(element: ElementSpec, strain: str) -> dict:
    n, d = element.node_count, element.dim
    pairs = [(j, k) for j in range(n) for k in range(j, n)]
    count = {"K": (n * d) ** 2, "V": 0, "D": 0}
    if strain == "E":
        count["V"] = n * len(pairs) * d
        count["D"] = len(pairs) ** 2
    return {"pairs": pairs, "count": count, "total": sum(count.values())}


def _tensor_flops(element: ElementSpec, strain: str) -> dict:
    n, d = element.node_count, element.dim
    dofs = n * d
    ku = dofs * 2 * dofs
    if strain == "eps":
        return {"energy": ku + 2 * dofs, "gradient": ku, "hessian": 0}
    p = n * (n + 1) // 2
    s = p * (2 * d - 1)
    t = p * n * 2 * d
    r = p * 2 * p
    energy = ku + 2 * dofs + s + t + r + p * 4
    gradient = ku + s + t + r + n * p * d * 3 + n * n * d * 2 * 2
    hessian = s + t + r + n * n * (d * d * (1 + 4 * n) + 2 * d) + n ** 3 * (2 * n * d + 2 * d * d)
    return {"energy": energy, "gradient": gradient, "hessian": hessian}


def build_kernel_ir(law: LawSpec, element: ElementSpec, split: str, law_ir: LawKernelIR,
                    tensor_limit: int = DEFAULT_TENSOR_LIMIT) -> KernelIR:
    tables = element_tables(element)
    q = len(tables.weights)
    base_consts = len(law.derived) + q * point_stride(element)
    extra: dict = {}
    if split == "whole":
        flops = _quadrature_flops(element, q, law_ir)
        consts = base_consts
    elif split == "terms":
        parts = _terms_parts(element, law_ir)
        h = element.dim ** 2 * (2 * element.node_count - 1)
        flops = {
            "energy": _quadrature_flops(element, q, law_ir)["energy"],
            "gradient": q * sum(h + law_ir.weighted_stress.flops + p.gradient.flops + len(p.nodes) * element.dim
                                for p in parts),
            "hessian": q * sum(h + law_ir.tangent_only.flops + p.hessian.flops
                               + sum(1 for a in p.hessian.assignments if not a.declare) for p in parts),
        }
        extra = {"parts": parts, "symbol_names": terms_symbol_names(element, law_ir)}
        consts = base_consts
    elif split == "tensor":
        if element.order != 1:
            raise SplitRefused(f"tensor split: {element.name} is of order {element.order}; "
                               "the tensor form is offered for first-order elements only")
        try:
            quadratic = strain_quadratic(law, element.dim)
        except GeneratorInputError as error:
            raise SplitRefused(f"tensor split: {error}") from None
        layout = tensor_layout(element, quadratic.strain)
        if layout["total"] > tensor_limit:
            raise SplitRefused(f"tensor split: {element.name} with {law.name} needs {layout['total']} "
                               f"coefficients per element, over the limit {tensor_limit} (--tensor-limit)")
        flops = _tensor_flops(element, quadratic.strain)
        extra = {"quadratic": quadratic, "layout": layout}
        consts = base_consts + layout["total"]
    else:
        raise ValueError(f"unknown split {split}")
    return KernelIR(law=law, element=element, split=split, tables=tables, law_ir=law_ir,
                    consts_size=consts, flops=flops, extra=extra)


def elasticity_assignments(law: LawSpec, quadratic) -> list[tuple[int, sympy.Expr]]:
    """Non-zero entries of the flattened elasticity tensor CC[a][b][c][d]."""
    flat = []
    dim = len(quadratic.elasticity)
    for a in range(dim):
        for b in range(dim):
            for c in range(dim):
                for e in range(dim):
                    value = quadratic.elasticity[a][b][c][e]
                    if value != 0:
                        flat.append((((a * dim + b) * dim + c) * dim + e, value))
    return flat


def h_expressions(element: ElementSpec) -> list[tuple[str, sympy.Expr]]:
    """H[a*d+C] = sum_j u[j*d+a] GT[C*n+j], as symbols for the terms split."""
    n, d = element.node_count, element.dim
    u = [sympy.Symbol(f"u{i}", real=True) for i in range(n * d)]
    G = [[sympy.Symbol(f"G{c}_{j}", real=True) for c in range(d)] for j in range(n)]
    return [(f"H[{a * d + c}]", sum(u[j * d + a] * G[j][c] for j in range(n)))
            for a in range(d) for c in range(d)]
