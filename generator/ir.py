"""Typed, immutable output of stage 4 (lower): what the emitter prints.

`LoweredIR` holds one `KernelIR` per offered LES triple (law, element,
split), the refused triples with their reasons, one `ElementIR` per element
(for elements.cpp) and the law specs (for the registry). Every number and
table a template prints is here; the emitter only formats it.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Union

import sympy

from .model import Block, ElementSpec, ElementTables, FormatOrder, LawKernelIR, LawSpec


@dataclass(frozen=True)
class Flops:
    """Floating-point operations per element of a kernel's entry points, counted
    on the code the kernel executes (see optimize.count_flops)."""
    energy: int
    gradient: int
    hessian: int


# --- Split-specific IR -------------------------------------------------------

@dataclass(frozen=True)
class WholeIR:
    """The whole split needs the law block and the element tables, and says
    whether it also gets batched entry points (several elements per call)."""
    batched: bool


@dataclass(frozen=True)
class SumOfProducts:
    """`target = sum of coefficient * product of factors;` in emitted code: the
    terms split's straight-line entries, built directly (no SymPy).

    terms: (integer coefficient, C names of the factors) per term; declare:
    the target is a new `const double` temporary (else an lvalue the template
    declared, such as `K[5]`, assigned with the template's operator)."""
    target: str
    terms: tuple[tuple[int, tuple[str, ...]], ...]
    declare: bool = False


@dataclass(frozen=True)
class ProductBlock:
    """Straight-line sums of products, temporaries before their uses, with their flop count."""
    assignments: tuple[SumOfProducts, ...]
    flops: int


@dataclass(frozen=True)
class TermsPart:
    """One translation unit of the terms split."""
    nodes: tuple[int, ...]  # the node rows this part computes
    gradient: ProductBlock  # defines g[...] entries (accumulated with +=)
    hessian: ProductBlock  # defines K[...] upper-triangle entries (accumulated with +=)


@dataclass(frozen=True)
class TermsIR:
    """The gradient and Hessian written out entry by entry, cut into parts.

    h_block: H[...] from u and GT at one point (straight-line)."""
    parts: tuple[TermsPart, ...]
    h_block: ProductBlock


@dataclass(frozen=True)
class TensorLayout:
    """The per-element coefficient tensors after the point data in the constants.

    pairs: the node pairs (j, k), j <= k, row-major (the order of
    tensormass::kernel::tensor::NodePairs); K is dofs by dofs, V nodes by
    pairs by dim and D pairs by pairs (V and D only for the Green strain)."""
    pairs: tuple[tuple[int, int], ...]
    k_size: int
    v_size: int
    d_size: int

    @property
    def total(self) -> int:
        return self.k_size + self.v_size + self.d_size


@dataclass(frozen=True)
class TensorIR:
    """The Tensor-Mass form of a law quadratic in one strain measure.

    elasticity: the non-zero entries of CC[a][b][c][e], as (flat row-major
    index, expression of the derived parameters)."""
    strain: str  # "eps" (linear: a quadratic energy) or "E" (Green-Lagrange: a quartic one)
    layout: TensorLayout
    elasticity: tuple[tuple[int, sympy.Expr], ...]

    @property
    def green(self) -> bool:
        return self.strain == "E"


@dataclass(frozen=True)
class MeanDilatationIR:
    """The fbar split (the mean-dilatation formulation, mean_dilatation.hpp):
    the law block at F̄ = (J̄/J)^(1/d) F and the element tables; nothing of its
    own beyond the formulation's runtime loops."""


@dataclass(frozen=True)
class NodalPressureIR:
    """The anp split (averaged nodal pressure, assembly/nodal_pressure.hpp):
    the base split's kernel of the full energy (whole on one-point elements,
    fbar where the element's points need tying into one J), and the law's
    bulk part U(J) with its first two derivatives in J, which the runtime
    moves from the element to the nodes."""
    batched: bool  # the whole split's rule (splits/whole.batch_pays); False on fbar
    bulk: tuple[sympy.Expr, sympy.Expr, sympy.Expr]  # U, dU/dJ, d2U/dJ2 in J and the law's constants
    base: str = "whole"  # whole | fbar: whose entry points the kernel has


SplitIR = Union[WholeIR, TermsIR, TensorIR, MeanDilatationIR, NodalPressureIR]


# --- Kernels and elements ----------------------------------------------------

@dataclass(frozen=True)
class KernelIR:
    """Everything a template needs to emit one LES triple.

    symbol_names maps the IR's symbols (H0, u3, G1_2, ...) to the C
    expressions that hold them (H[0], u[3], GT[...], ...)."""
    law: LawSpec
    element: ElementSpec
    split: str  # whole | terms | tensor | fbar | anp
    tables: ElementTables
    law_ir: LawKernelIR
    consts_size: int
    flops: Flops
    symbol_names: tuple[tuple[str, str], ...]
    split_ir: SplitIR
    linear: bool  # force = K u with K constant (LawDerivatives.linear)
    invertible: bool = False  # the law is defined for det F <= 0 (LawSpec.invertible)
    # (U, dU/dJ, d2U/dJ2) of the law's bulk part for a `whole` kernel of a
    # viscoelastic law: the runtime's viscous part relaxes the rest of the
    # stress. () otherwise (the anp split's NodalPressureIR has its own).
    viscous_bulk: tuple[sympy.Expr, ...] = ()

    @property
    def prefix(self) -> str:
        """The C name prefix of the kernel's functions."""
        return f"tm_{self.law.name}_{self.element.name}_{self.split}"


@dataclass(frozen=True)
class ElementIR:
    """Reference-element facts for elements.cpp (meshes, criteria, outputs).

    reference_nodes, shape_values, shape_gradients and corner_gradients are flattened row-major
    (nodes by dim, points by nodes, points by nodes by dim, corners by nodes by dim); face_offsets[f] is where face f starts in the
    concatenated face lists."""
    name: str
    description: str
    dim: int
    order: int
    node_count: int
    vtk: FormatOrder
    gmsh: FormatOrder
    calculix: Optional[FormatOrder]
    edges: tuple[tuple[int, ...], ...]
    edge_size: int
    faces: tuple[tuple[int, ...], ...]
    face_offsets: tuple[int, ...]
    reference_nodes: tuple[float, ...]
    weights: tuple[float, ...]
    shape_values: tuple[float, ...]
    corner_count: int
    reference_volume: float
    shape_gradients: tuple[float, ...]  # points by nodes by dim
    corner_gradients: tuple[float, ...]  # corners by nodes by dim (symbolic.corner_gradients)


@dataclass(frozen=True)
class Refusal:
    """A split not offered for a (law, element), and why."""
    law: str
    element: str
    split: str
    reason: str


@dataclass(frozen=True)
class LoweredIR:
    """Stage 4 (lower) output: kernels in (law, element, split) order, refusals,
    elements in file order and the laws (for the registry's parameter names)."""
    kernels: tuple[KernelIR, ...]
    refused: tuple[Refusal, ...]
    elements: tuple[ElementIR, ...]
    laws: tuple[LawSpec, ...]
