"""The terms split: the gradient and Hessian written out entry by entry as
explicit sums (the origin report's long equations), cut by node rows into
parts, one function and one translation unit per part.

Input: `Triple`. Output: `SplitLowering` with `TermsIR` (the CSE'd parts and
the H block), the flops of the parts and the C names of G, wP and wA."""
from __future__ import annotations

import math

import sympy

from ..ir import Flops, TermsIR, TermsPart
from ..model import Block, ElementSpec, LawKernelIR
from ..optimize import eliminate
from .common import SplitLowering, Triple
from .whole import displacement_gradient_flops, quadrature_flops

ENTRIES_PER_PART = 400


def shape_gradient_symbols(element: ElementSpec) -> list[list[sympy.Symbol]]:
    """G{c}_{j} = dN_j/dX_c at one point, indexed [j][c]."""
    return [[sympy.Symbol(f"G{c}_{j}", real=True) for c in range(element.dim)] for j in range(element.node_count)]


def h_block(element: ElementSpec) -> Block:
    """H[a*d+C] = sum_j u[j*d+a] GT[C*n+j], CSE'd."""
    n, d = element.node_count, element.dim
    u = [sympy.Symbol(f"u{i}", real=True) for i in range(n * d)]
    G = shape_gradient_symbols(element)
    return eliminate([(f"H[{a * d + c}]", sum(u[j * d + a] * G[j][c] for j in range(n)))
                      for a in range(d) for c in range(d)], "h")


def _node_groups(element: ElementSpec) -> list[tuple[int, ...]]:
    """Consecutive node rows with about ENTRIES_PER_PART upper-triangle Hessian entries each."""
    n, d = element.node_count, element.dim
    dofs = n * d
    rows_of = [sum(dofs - (j * d + a) for a in range(d)) for j in range(n)]
    parts_wanted = min(max(2, math.ceil(sum(rows_of) / ENTRIES_PER_PART)), n)
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
    return groups


def _part(group: tuple[int, ...], element: ElementSpec, law_ir: LawKernelIR) -> TermsPart:
    n, d = element.node_count, element.dim
    dofs = n * d
    G = shape_gradient_symbols(element)
    A = [[sympy.Symbol(name.replace("[", "").replace("]", ""), real=True) if name else sympy.S.Zero
          for name in row] for row in law_ir.tangent_map]
    wP = [sympy.Symbol(f"wP{i}", real=True) for i in range(d * d)]
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
                    entry = sum(G[j][c] * A[a * d + c][b * d + e] * G[k][e] for c in range(d) for e in range(d))
                    k_out.append((f"K[{row * dofs + col}]", entry))
    return TermsPart(nodes=group, gradient=eliminate(g_out, "x"), hessian=eliminate(k_out, "y"))


def terms_parts(element: ElementSpec, law_ir: LawKernelIR) -> tuple[TermsPart, ...]:
    return tuple(_part(group, element, law_ir) for group in _node_groups(element))


def symbol_names(element: ElementSpec, law_ir: LawKernelIR) -> tuple[tuple[str, str], ...]:
    """G{c}_{j} -> GT[c*n+j], wP{i} -> wP[i], wA{i} -> wA[i]."""
    n, d = element.node_count, element.dim
    names = {f"G{c}_{j}": f"GT[{c * n + j}]" for c in range(d) for j in range(n)}
    names.update({f"wP{i}": f"wP[{i}]" for i in range(d * d)})
    for row in law_ir.tangent_map:
        for name in row:
            if name:
                names[name.replace("[", "").replace("]", "")] = name
    return tuple(names.items())


def _flops(triple: Triple, parts: tuple[TermsPart, ...]) -> Flops:
    element, law_ir = triple.element, triple.law_ir
    q = len(triple.tables.weights)
    h = displacement_gradient_flops(element)
    return Flops(
        energy=quadrature_flops(element, q, law_ir).energy,
        gradient=q * sum(h + law_ir.weighted_stress.flops + p.gradient.flops + len(p.nodes) * element.dim
                         for p in parts),
        hessian=q * sum(h + law_ir.tangent_only.flops + p.hessian.flops
                        + sum(1 for a in p.hessian.assignments if not a.declare) for p in parts),
    )


def lower(triple: Triple) -> SplitLowering:
    parts = terms_parts(triple.element, triple.law_ir)
    return SplitLowering(split_ir=TermsIR(parts=parts, h_block=h_block(triple.element)),
                         flops=_flops(triple, parts), extra_consts=0,
                         symbol_names=symbol_names(triple.element, triple.law_ir))
