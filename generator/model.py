"""Typed, immutable outputs of stages 1-3 (load, symbolic, optimise).

The lowered IR of stage 4, which the emitter prints, is in `ir.py`.

Glossary (the same names are used in the C++ runtime):
  reference element   the element in its reference coordinates (r, s, t)
  shape gradient G    dN_j/dX at a quadrature point, in rest (material) coordinates
  H                   displacement gradient, H[a][C] = sum_j u[j][a] G[j][C]; F = I + H
  P                   first Piola-Kirchhoff stress, dpsi/dF (= dpsi/dH)
  A                   tangent, A[aC][bD] = d2 psi / dF[a][C] dF[b][D]
  weight w            quadrature weight times det(dX/dr) at the point
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Optional

import sympy


# --- Stage 1 (load) ----------------------------------------------------------

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
    def corner_count(self) -> int:
        """Nodes 0 .. corner_count-1 are the corners (the element-file rule): the edges' end points."""
        return len({i for edge in self.edges for i in edge[:2]})

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
class ParamLimit:
    """The values one parameter may take, from the law file's `limits`:
    lower < p (lower <= p when lower_inclusive), likewise for upper; None
    where the file states no bound."""
    lower: Optional[sympy.Expr] = None
    upper: Optional[sympy.Expr] = None
    lower_inclusive: bool = False
    upper_inclusive: bool = False


# Fibre families: the parameters a law with fibre invariants takes after its
# own (the runtime fills them per cell from the scene's fibre field), the
# unit directions the energy reads (among its constants), and the invariants
# of each family: I4 = a0.C a0, I5 = a0.C^2 a0, I6 = g0.C g0, I7 = g0.C^2 g0,
# I8 = a0.C g0; the `bar` ones with J^(-2/3) C.
FIBRE_PARAMETERS = (("fibre_x", "fibre_y", "fibre_z"), ("fibre2_x", "fibre2_y", "fibre2_z"))
FIBRE_CONSTANTS = (("a0x", "a0y", "a0z"), ("g0x", "g0y", "g0z"))
FIBRE_INVARIANT_FAMILIES = {"I4": 1, "I5": 1, "I4bar": 1, "I5bar": 1, "I6": 2, "I7": 2, "I6bar": 2, "I7bar": 2,
                            "I8": 2, "I8bar": 2}


def fibre_constants(families: int) -> tuple[tuple[str, sympy.Expr], ...]:
    """(name, expression) of the unit fibre directions: each family's parameters divided by their norm."""
    out = []
    for parameters, constants in zip(FIBRE_PARAMETERS[:families], FIBRE_CONSTANTS[:families]):
        components = [sympy.Symbol(p, real=True) for p in parameters]
        norm = sympy.sqrt(sum(c ** 2 for c in components))
        out.extend((name, c / norm) for name, c in zip(constants, components))
    return tuple(out)


@dataclass(frozen=True)
class LawSpec:
    """A law file. The energy reads `constants`: the derived parameters when
    the file has a [derived] table, else the parameters themselves; they are
    the leading doubles of every kernel's consts, in this order.

    energy is the whole energy density; a file that gives `isochoric` and
    `volumetric` instead has energy = (isochoric) + (volumetric), the
    isochoric part a function of I1bar and I2bar, the volumetric one of J."""
    name: str
    description: str
    source: str
    energy: str  # SymPy text in the kinematic symbols
    parameters: tuple[str, ...]  # user-facing parameters, in kernel order
    derived: tuple[tuple[str, sympy.Expr], ...]  # (name, expression of parameters); () without [derived]
    invertible: bool = False  # defined and finite for det F <= 0 (checked by the symbolic stage)
    limits: tuple[ParamLimit, ...] = ()  # one per parameter (unbounded when the file gives none)
    isochoric: str = ""  # the isochoric part of the energy, when the file splits it
    volumetric: str = ""  # the volumetric part U(J), when the file splits it
    # The part of the energy that is a function of J alone and carries the
    # bulk stiffness (lam or kappa): `volumetric`, or the file's `bulk` beside
    # its `energy`; "" when it has none. The anp split integrates it at the nodes.
    bulk: str = ""
    rotation_invariant: bool = True  # W(QF) = W(F) for every rotation Q (the file's claim, checked by tests)
    # Fibre families the energy reads (0, 1 or 2): their FIBRE_PARAMETERS end
    # `parameters` and their FIBRE_CONSTANTS end `constants`.
    fibre_families: int = 0
    # The Prony series of a viscoelastic law (the file's [viscoelastic] table):
    # the parameters holding the weights g_i and the relaxation times tau_i,
    # term by term. The kernels never read them; the runtime's viscous part
    # does (docs/viscoelasticity.md).
    prony_weights: tuple[str, ...] = ()
    prony_times: tuple[str, ...] = ()
    # The weights of the same terms on the bulk part's stress; () when it does not relax.
    prony_volumetric_weights: tuple[str, ...] = ()

    @property
    def viscoelastic(self) -> bool:
        return bool(self.prony_weights)

    @property
    def prony_parameters(self) -> tuple[str, ...]:
        """Every parameter of the Prony series (the kernels never read them)."""
        return self.prony_weights + self.prony_times + self.prony_volumetric_weights

    @property
    def constants(self) -> tuple[tuple[str, sympy.Expr], ...]:
        """(name, expression of the parameters) of each symbol the energy reads besides the kinematics."""
        fibres = fibre_constants(self.fibre_families)
        if self.derived:
            return self.derived + fibres
        prony = set(self.prony_parameters)
        return tuple((name, sympy.Symbol(name, real=True)) for name in self.own_parameters
                     if name not in prony) + fibres

    @property
    def own_parameters(self) -> tuple[str, ...]:
        """The parameters the law file lists (`parameters` without the fibre components)."""
        return self.parameters[: len(self.parameters) - 3 * self.fibre_families]

    @property
    def split_volumetric(self) -> bool:
        """True when the file gives the energy as isochoric + volumetric(J)."""
        return bool(self.volumetric)

    def limit(self, parameter: str) -> ParamLimit:
        """The limits of one parameter (unbounded when none are stated)."""
        index = self.parameters.index(parameter)
        return self.limits[index] if self.limits else ParamLimit()


@dataclass(frozen=True)
class Inputs:
    """Stage 1 (load) output: the validated element and law descriptions, sorted by file name."""
    elements: tuple[ElementSpec, ...]
    laws: tuple[LawSpec, ...]

    @property
    def dims(self) -> tuple[int, ...]:
        """The dimensions of the elements, ascending (laws are derived once per dimension)."""
        return tuple(sorted({e.dim for e in self.elements}))


# --- Stage 2 (symbolic) ------------------------------------------------------

@dataclass(frozen=True)
class ElementTables:
    """Numbers the kernels need from the reference element at one quadrature rule."""
    rule: QuadratureRule
    weights: tuple[float, ...]  # #Q
    shape_values: tuple[tuple[float, ...], ...]  # #Q by #N
    reference_gradients: tuple[tuple[tuple[float, ...], ...], ...]  # #Q by #N by dim
    corner_gradients: tuple[tuple[tuple[float, ...], ...], ...]  # #corners by #N by dim (symbolic.corner_gradients)


@dataclass(frozen=True)
class StrainQuadratic:
    """A law that is a homogeneous quadratic in one strain measure: psi = 1/2 S:CC:S."""
    strain: str  # "eps" (linear) or "E" (Green-Lagrange)
    elasticity: tuple[tuple[tuple[tuple[sympy.Expr, ...], ...], ...], ...]  # CC[a][b][c][d], in derived parameters


@dataclass(frozen=True)
class LawDerivatives:
    """A law at one point in dimension dim, in H0.. and the derived parameters.

    quadratic: the law as 1/2 S:CC:S in one strain measure (for the tensor
    split), or None, with not_quadratic saying why."""
    law: LawSpec
    dim: int
    energy: sympy.Expr  # psi
    stress: tuple[sympy.Expr, ...]  # P[I] = dpsi/dH_I
    tangent: tuple[tuple[sympy.Expr, ...], ...]  # A[I][J] = d2psi/dH_I dH_J (full, symmetric)
    quadratic: Optional[StrainQuadratic]
    not_quadratic: str = ""

    @functools.cached_property
    def linear(self) -> bool:
        """True when psi is quadratic in H with a stress-free reference: the
        tangent A is constant and P(0) = 0, so an element's force is K u with
        K independent of u (the runtime folds such cells into one constant matrix).
        A tangent with any symbol besides the parameters (H.., or the rotation's R.., Y..) is not constant."""
        parameters = {sympy.Symbol(name, real=True) for name, _ in self.law.constants}
        if any(entry.free_symbols - parameters for row in self.tangent for entry in row):
            return False
        at_rest = {sympy.Symbol(f"H{i}", real=True): 0 for i in range(self.dim * self.dim)}
        return all(sympy.simplify(p.subs(at_rest)) == 0 for p in self.stress)


@dataclass(frozen=True)
class SymbolicIR:
    """Stage 2 (symbolic) output: the inputs, one ElementTables per element
    (same order) and one LawDerivatives per law and element dimension."""
    inputs: Inputs
    tables: tuple[ElementTables, ...]
    derivatives: tuple[LawDerivatives, ...]

    def tables_of(self, element: ElementSpec) -> ElementTables:
        return self.tables[self.inputs.elements.index(element)]

    def derivatives_of(self, law: LawSpec, dim: int) -> LawDerivatives:
        return next(d for d in self.derivatives if d.law == law and d.dim == dim)


# --- Stage 3 (optimise) ------------------------------------------------------

class RationalRoot(sympy.Function):
    """root(x, e) = x^e for e = 1/q or -1/q (q >= 2): the one root a block
    computes per base, whose integer powers give every x^(p/q) it reads
    (optimize.eliminate). Printed as std::sqrt for q = 2, else as
    std::exp(e*std::log(x)), which batched kernels vectorise (libmvec)."""
    nargs = 2

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
    """Straight-line code: temporaries then outputs, with its flop count.

    auxiliaries: per-point quantities the code reads that are not polynomial
    in H, computed before it by support code, in this order: "rotation"
    (R0.., F's polar rotation) and "rotation_inverse" (Y.., for dR/dH).
    Their flops are counted in `flops` (AUXILIARY_FLOPS)."""
    assignments: tuple[Assignment, ...]
    flops: int
    auxiliaries: tuple[str, ...] = ()


@dataclass(frozen=True)
class LawKernelIR:
    """The law at one point, in terms of H (symbols H0..), w and the derived parameters.

    energy: defines `psi` (weighted by w); stress: defines P0.. (unweighted);
    weighted_stress: defines wP0..; tangent: defines wP0.. and wA0.. (unique
    entries of the weighted tangent, row-major upper triangle of the d^2 x d^2
    matrix); tangent_only: the same wA without wP; tangent_map[I][J] names the
    symbol holding A[I][J], or None when that entry is identically zero;
    tangent_fill lists the entries of the full wA array the tangent block does
    not assign: (flat index, symbol to copy, or None for zero)."""
    law: str  # the law's name
    dim: int
    energy: Block
    stress: Block
    weighted_stress: Block
    tangent: Block
    tangent_only: Block  # wA entries alone (for code that needs no stress)
    tangent_map: tuple[tuple[Optional[str], ...], ...]
    tangent_fill: tuple[tuple[int, Optional[str]], ...]


@dataclass(frozen=True)
class OptimisedIR:
    """Stage 3 (optimise) output: the symbolic IR and one LawKernelIR per law and dimension."""
    symbolic: SymbolicIR
    laws: tuple[LawKernelIR, ...]

    def law_ir(self, law: LawSpec, dim: int) -> LawKernelIR:
        return next(ir for ir in self.laws if ir.law == law.name and ir.dim == dim)
