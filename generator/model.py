"""Typed, immutable intermediate representations shared by the generator stages.

Glossary (the same names are used in the C++ runtime):
  reference element   the element in its reference coordinates (r, s, t)
  shape gradient G    dN_j/dX at a quadrature point, in rest (material) coordinates
  H                   displacement gradient, H[a][C] = sum_j u[j][a] G[j][C]; F = I + H
  P                   first Piola-Kirchhoff stress, dpsi/dF (= dpsi/dH)
  A                   tangent, A[aC][bD] = d2 psi / dF[a][C] dF[b][D]
  weight w            quadrature weight times det(dX/dr) at the point
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import sympy


@dataclass(frozen=True)
class QuadratureRule:
    name: str
    degree: int
    points: tuple[tuple[sympy.Expr, ...], ...]
    weights: tuple[sympy.Expr, ...]


@dataclass(frozen=True)
class FormatOrder:
    """An external format's element type id and node order.

    node_order[k] is the tensormass index of the k-th node the format lists."""
    type: object
    node_order: tuple[int, ...]


@dataclass(frozen=True)
class ElementSpec:
    name: str
    description: str
    source: str  # file the element was read from (for messages)
    dim: int
    order: int
    nodes: tuple[tuple[sympy.Expr, ...], ...]
    shape_functions: tuple[sympy.Expr, ...]
    edges: tuple[tuple[int, ...], ...]
    faces: tuple[tuple[int, ...], ...]
    reference_volume: sympy.Expr
    default_quadrature: str
    quadrature: tuple[QuadratureRule, ...]
    gmsh: FormatOrder
    vtk: FormatOrder
    calculix: Optional[FormatOrder]

    @property
    def node_count(self) -> int:
        return len(self.nodes)

    @property
    def dofs(self) -> int:
        return self.node_count * self.dim

    def rule(self, name: Optional[str] = None) -> QuadratureRule:
        wanted = name or self.default_quadrature
        for rule in self.quadrature:
            if rule.name == wanted:
                return rule
        raise KeyError(wanted)


@dataclass(frozen=True)
class LawSpec:
    name: str
    description: str
    source: str
    energy: str  # SymPy text in the kinematic symbols
    parameters: tuple[str, ...]  # user-facing parameters, in kernel order
    derived: tuple[tuple[str, sympy.Expr], ...]  # (name, expression of parameters)


@dataclass(frozen=True)
class ElementTables:
    """Numbers the kernels need from the reference element at one quadrature rule."""
    rule: QuadratureRule
    weights: tuple[float, ...]  # #Q
    shape_values: tuple[tuple[float, ...], ...]  # #Q by #N
    reference_gradients: tuple[tuple[tuple[float, ...], ...], ...]  # #Q by #N by dim


@dataclass(frozen=True)
class Assignment:
    """`target = expr;` in emitted straight-line code.

    declare: the target is a new `const double` temporary (else an lvalue the
    template declared, such as `wP[3]`)."""
    target: str
    expr: sympy.Expr
    declare: bool = False


@dataclass(frozen=True)
class Block:
    """Straight-line code: temporaries then outputs, with its flop count."""
    assignments: tuple[Assignment, ...]
    flops: int


@dataclass(frozen=True)
class LawKernelIR:
    """The law at one point, in terms of H (symbols H0..), w and the derived parameters.

    energy: defines `psi` (weighted by w); stress: defines P0.. (unweighted);
    weighted_stress: defines wP0..; tangent: defines wP0.. and wA0.. (unique
    entries of the weighted tangent, row-major upper triangle of the d^2 x d^2
    matrix); tangent_only: the same wA without wP; tangent_map[I][J] names the symbol holding A[I][J], or None when
    that entry is identically zero."""
    dim: int
    energy: Block
    stress: Block
    weighted_stress: Block
    tangent: Block
    tangent_only: Block  # wA entries alone (for code that needs no stress)
    tangent_map: tuple[tuple[Optional[str], ...], ...]


@dataclass(frozen=True)
class StrainQuadratic:
    """A law that is a homogeneous quadratic in one strain measure: psi = 1/2 S:CC:S."""
    strain: str  # "eps" (linear) or "E" (Green-Lagrange)
    elasticity: tuple  # CC[a][b][c][d] as SymPy expressions of the derived parameters


@dataclass(frozen=True)
class KernelIR:
    """Everything a template needs to emit one LES triple."""
    law: LawSpec
    element: ElementSpec
    split: str  # whole | terms | tensor
    tables: ElementTables
    law_ir: LawKernelIR
    consts_size: int
    flops: dict = field(hash=False, compare=False)  # energy/gradient/hessian -> int
    extra: dict = field(hash=False, compare=False)  # split-specific data for templates
