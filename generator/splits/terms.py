"""The terms split: the gradient and Hessian written out entry by entry as
explicit sums (the origin report's long equations), cut by node rows into
parts, one function and one translation unit per part.

Built directly as sums of products of C names (no SymPy): per node pair
(j, k) the products G_jc G_ke once, then each Hessian entry
K[ja][kb] = sum_ce wA[ac][be] G_jc G_ke over the non-zero tangent entries;
for j = k the symmetric terms (c, e) and (e, c) are merged (their tangent
entries summed once per part), for j != k the
sum over c = e, shared by K[ja][kb] and K[jb][ka], is one temporary, and
terms sharing one tangent entry (laws whose tangent repeats entries, such
as Hooke's constant one) are factored: wA[i] (G.. + G..), the inner sums
shared across the part.

Input: `Triple`. Output: `SplitLowering` with `TermsIR` (the parts and the
H block), the flops of the parts and the C names of G, wP and wA."""
from __future__ import annotations

import math

from ..ir import Flops, ProductBlock, SumOfProducts, TermsIR, TermsPart
from ..model import ElementSpec, LawKernelIR
from .common import SplitLowering, Triple
from .whole import displacement_gradient_flops, quadrature_flops

ENTRIES_PER_PART = 400


def _flops(assignment: SumOfProducts) -> int:
    """One multiplication per factor after the first and per coefficient other than 1, one addition between terms."""
    return sum(len(factors) - 1 + (coefficient != 1) for coefficient, factors in assignment.terms) + \
        len(assignment.terms) - 1


def product_block(assignments: list[SumOfProducts]) -> ProductBlock:
    return ProductBlock(assignments=tuple(assignments), flops=sum(_flops(a) for a in assignments))


def _gt(element: ElementSpec, c: int, j: int) -> str:
    """G_jc = dN_j/dX_c at GT[c*n+j]."""
    return f"GT[{c * element.node_count + j}]"


def h_block(element: ElementSpec) -> ProductBlock:
    """H[a*d+C] = sum_j GT[C*n+j] u[j*d+a]."""
    n, d = element.node_count, element.dim
    return product_block([SumOfProducts(f"H[{a * d + c}]", tuple((1, (_gt(element, c, j), f"u[{j * d + a}]"))
                                                                  for j in range(n)))
                          for a in range(d) for c in range(d)])


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


def _gradient(group: tuple[int, ...], element: ElementSpec) -> ProductBlock:
    d = element.dim
    return product_block([SumOfProducts(f"g[{j * d + a}]", tuple((1, (_gt(element, c, j), f"wP[{a * d + c}]"))
                                                                  for c in range(d)))
                          for j in group for a in range(d)])


def _hessian(group: tuple[int, ...], element: ElementSpec, law_ir: LawKernelIR) -> ProductBlock:
    n, d = element.node_count, element.dim
    dofs = n * d
    A = law_ir.tangent_map
    out: list[SumOfProducts] = []
    count = [0]

    def temporary(terms: tuple) -> str:
        name = f"y{count[0]}"
        count[0] += 1
        out.append(SumOfProducts(name, terms, declare=True))
        return name

    inner_sums: dict[tuple, str] = {}
    tangent_sums: dict[tuple[str, str], str] = {}

    def factored(terms: list) -> tuple:
        """Terms wA[i] * p grouped by wA[i]: one wA[i] * (sum of their p) per repeated entry."""
        groups: dict[str, list] = {}
        for coefficient, factors in terms:
            groups.setdefault(factors[0] if len(factors) == 2 else "", []).append((coefficient, factors))
        result = []
        for name, members in groups.items():
            if not name or len(members) == 1:
                result += members
                continue
            key = tuple(sorted((c, f[1]) for c, f in members))
            if key not in inner_sums:
                inner_sums[key] = temporary(tuple((c, (p,)) for c, p in key))
            result.append((1, (name, inner_sums[key])))
        return tuple(result)

    for j in group:
        for k in range(j, n):
            products: dict[tuple[int, int], str] = {}
            diagonal_sums: dict[tuple[int, int], str] = {}

            def product(c: int, e: int) -> str:
                key = (min(c, e), max(c, e)) if j == k else (c, e)
                if key not in products:
                    products[key] = temporary(((1, (_gt(element, key[0], j), _gt(element, key[1], k))),))
                return products[key]

            for a in range(d):
                for b in range(a if j == k else 0, d):
                    terms: list[tuple[int, tuple[str, ...]]] = []
                    if j == k:
                        for c in range(d):
                            for e in range(c, d):
                                first, second = A[a * d + c][b * d + e], A[a * d + e][b * d + c]
                                if c == e or (first and first == second):
                                    if first:
                                        terms.append((1 if c == e else 2, (first, product(c, e))))
                                    continue
                                if first and second:  # wA[ac][ae] + wA[ae][ac], once per part
                                    key = (first, second)
                                    if key not in tangent_sums:
                                        tangent_sums[key] = temporary(((1, (first,)), (1, (second,))))
                                    terms.append((1, (tangent_sums[key], product(c, e))))
                                    continue
                                terms += [(1, (name, product(c, e))) for name in (first, second) if name]
                    else:
                        diagonal = tuple((1, (A[a * d + c][b * d + c], product(c, c)))
                                         for c in range(d) if A[a * d + c][b * d + c])
                        if len(diagonal) > 1 and a != b:
                            key = (min(a, b), max(a, b))
                            if key not in diagonal_sums:
                                diagonal_sums[key] = temporary(factored(list(diagonal)))
                            terms.append((1, (diagonal_sums[key],)))
                        else:
                            terms += diagonal
                        terms += [(1, (A[a * d + c][b * d + e], product(c, e)))
                                  for c in range(d) for e in range(d) if c != e and A[a * d + c][b * d + e]]
                    if terms:
                        out.append(SumOfProducts(f"K[{(j * d + a) * dofs + k * d + b}]", factored(terms)))
    return product_block(out)


def terms_parts(element: ElementSpec, law_ir: LawKernelIR) -> tuple[TermsPart, ...]:
    return tuple(TermsPart(nodes=group, gradient=_gradient(group, element), hessian=_hessian(group, element, law_ir))
                 for group in _node_groups(element))


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


def _kernel_flops(triple: Triple, parts: tuple[TermsPart, ...]) -> Flops:
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
                         flops=_kernel_flops(triple, parts), extra_consts=0,
                         symbol_names=symbol_names(triple.element, triple.law_ir))
