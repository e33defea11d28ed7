"""Stage 2 (symbolic): element tables and the law's point-wise derivatives.

Input: `Inputs` (stage 1).
Output: `SymbolicIR`: per element `ElementTables` (weights, shape values and
reference gradients at the quadrature points, as doubles) and, per law and
dimension, `LawDerivatives`: SymPy expressions of psi(H), P = dpsi/dH and
A = d2psi/dH2 in the displacement-gradient symbols H0..H{d*d-1} (row-major)
and the law's derived parameters, and the law as a quadratic in one strain
measure where it is one (for the tensor split). The chain rule
g_ja = sum_q w_q sum_C P_aC G_jC and K_ja,kb = sum_q w_q sum_CD G_jC A_aC,bD G_kD
links them to nodal displacements; the split stage decides how those sums
are written.
"""
from __future__ import annotations

import ast
import functools

import sympy

from .load import REFERENCE_VARIABLES, GeneratorInputError
from .model import ElementSpec, ElementTables, Inputs, LawDerivatives, LawSpec, StrainQuadratic, SymbolicIR

# Names a law's energy may use, besides its derived parameters.
KINEMATIC_NAMES = ("F", "H", "C", "E", "eps", "J", "I1", "I2", "I3", "d", "I")
FUNCTION_NAMES = ("tr", "det", "inv", "log", "exp", "sqrt", "transpose")
_DIGITS = 40  # evaluation precision before rounding to double


def _to_double(expr: sympy.Expr) -> float:
    return float(sympy.N(expr, _DIGITS))


def element_tables(element: ElementSpec, rule_name: str | None = None) -> ElementTables:
    rule = element.rule(rule_name)
    variables = REFERENCE_VARIABLES[: element.dim]
    gradients = [[sympy.diff(n, v) for v in variables] for n in element.shape_functions]
    values, reference_gradients = [], []
    for point in rule.points:
        at = dict(zip(variables, point))
        values.append(tuple(_to_double(n.subs(at)) for n in element.shape_functions))
        reference_gradients.append(tuple(tuple(_to_double(g.subs(at)) for g in row) for row in gradients))
    return ElementTables(
        rule=rule,
        weights=tuple(_to_double(w) for w in rule.weights),
        shape_values=tuple(values),
        reference_gradients=tuple(reference_gradients),
    )


def gradient_symbols(dim: int) -> tuple[sympy.Symbol, ...]:
    """H0..H{d*d-1}: the displacement gradient, row-major (H[a][C] = du_a/dX_C)."""
    return sympy.symbols(f"H0:{dim * dim}", real=True)


def parameter_symbols(law: LawSpec) -> dict[str, sympy.Symbol]:
    return {name: sympy.Symbol(name, real=True) for name, _ in law.derived}


def _energy_names(law: LawSpec) -> set[str]:
    try:
        tree = ast.parse(law.energy.replace("^", "**"), mode="eval")
    except SyntaxError as error:
        raise GeneratorInputError(f"{law.source}: key 'energy': cannot parse: {error}") from None
    return {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)}


def _check_energy_names(law: LawSpec) -> None:
    allowed = set(KINEMATIC_NAMES) | set(FUNCTION_NAMES) | {name for name, _ in law.derived}
    unknown = _energy_names(law) - allowed
    if unknown:
        raise GeneratorInputError(
            f"{law.source}: key 'energy': unknown names {sorted(unknown)}; available: "
            f"kinematics {', '.join(KINEMATIC_NAMES)}, functions {', '.join(FUNCTION_NAMES)}, "
            f"derived parameters {', '.join(n for n, _ in law.derived)}")


def _functions() -> dict:
    return {
        "tr": lambda m: m.trace(),
        "det": lambda m: m.det(),
        "inv": lambda m: m.inv(),
        "transpose": lambda m: m.T,
        "log": sympy.log,
        "exp": sympy.exp,
        "sqrt": sympy.sqrt,
    }


def _evaluate(law: LawSpec, names: dict) -> sympy.Expr:
    local = {**_functions(), **parameter_symbols(law), **names}
    try:
        value = sympy.sympify(law.energy.replace("^", "**"), locals=local, rational=True)
    except Exception as error:  # SymPy raises many types for malformed input
        raise GeneratorInputError(f"{law.source}: key 'energy': cannot evaluate: {error}") from None
    if isinstance(value, sympy.MatrixBase):
        raise GeneratorInputError(f"{law.source}: key 'energy': evaluates to a matrix, expected a scalar")
    return sympy.sympify(value)


@functools.lru_cache(maxsize=None)
def law_energy(law: LawSpec, dim: int) -> sympy.Expr:
    """psi as an expression of H0.. and the derived parameters."""
    _check_energy_names(law)
    identity = sympy.eye(dim)
    H = sympy.Matrix(dim, dim, gradient_symbols(dim))
    F = identity + H
    C = F.T * F
    names = {
        "F": F, "H": H, "C": C, "E": (C - identity) / 2, "eps": (H + H.T) / 2,
        "J": F.det(), "I1": C.trace(), "I2": (C.trace() ** 2 - (C * C).trace()) / 2,
        "I3": C.det(), "d": sympy.Integer(dim), "I": identity,
    }
    psi = _evaluate(law, names)
    allowed = set(gradient_symbols(dim)) | set(parameter_symbols(law).values())
    if psi.free_symbols - allowed:
        raise GeneratorInputError(f"{law.source}: key 'energy': unexpected symbols {psi.free_symbols - allowed}")
    return psi


@functools.lru_cache(maxsize=None)
def law_derivatives(law: LawSpec, dim: int) -> tuple[sympy.Expr, tuple, tuple]:
    """(psi, P, A): P[I] = dpsi/dH_I, A[I][J] = d2psi/dH_I dH_J (full, symmetric)."""
    psi = law_energy(law, dim)
    H = gradient_symbols(dim)
    P = tuple(sympy.diff(psi, h) for h in H)
    A = [[None] * len(H) for _ in H]
    for i in range(len(H)):
        for j in range(i, len(H)):
            A[i][j] = A[j][i] = sympy.diff(P[i], H[j])
    return psi, P, tuple(tuple(row) for row in A)


def strain_quadratic(law: LawSpec, dim: int) -> StrainQuadratic:
    """The law as psi = 1/2 S:CC:S in one strain measure, for the tensor split.

    Raises GeneratorInputError (with the reason) when the law is not a
    homogeneous quadratic polynomial of eps alone or of E alone."""
    _check_energy_names(law)
    used = _energy_names(law) & set(KINEMATIC_NAMES)
    used.discard("d")
    if used not in ({"E"}, {"eps"}):
        raise GeneratorInputError(
            f"law {law.name} is not written in one strain measure alone (uses {', '.join(sorted(used))}); "
            "the tensor split needs a quadratic polynomial of E or of eps")
    strain = used.pop()
    S = sympy.Matrix(dim, dim, sympy.symbols(f"S0:{dim * dim}", real=True))
    psi = sympy.expand(_evaluate(law, {strain: S, "d": sympy.Integer(dim), "I": sympy.eye(dim)}))
    variables = list(S)
    try:
        poly = sympy.Poly(psi, *variables)
    except sympy.PolynomialError:
        raise GeneratorInputError(f"law {law.name} is not a polynomial in {strain}") from None
    if not poly.is_homogeneous or poly.total_degree() != 2:
        raise GeneratorInputError(
            f"law {law.name} is not a homogeneous quadratic in {strain} (degree {poly.total_degree()})")
    # Second derivatives, symmetrised over the minor index pairs (S is symmetric).
    raw = [[[[sympy.diff(psi, S[a, b], S[c, e]) for e in range(dim)] for c in range(dim)]
            for b in range(dim)] for a in range(dim)]
    cc = tuple(tuple(tuple(tuple(
        sympy.simplify((raw[a][b][c][e] + raw[b][a][c][e] + raw[a][b][e][c] + raw[b][a][e][c]) / 4)
        for e in range(dim)) for c in range(dim)) for b in range(dim)) for a in range(dim))
    return StrainQuadratic(strain=strain, elasticity=cc)


def derive_law(law: LawSpec, dim: int) -> LawDerivatives:
    """psi, P and A of the law in dimension dim, and its strain quadratic or why it has none."""
    psi, P, A = law_derivatives(law, dim)
    try:
        quadratic, why = strain_quadratic(law, dim), ""
    except GeneratorInputError as error:
        quadratic, why = None, str(error)
    return LawDerivatives(law=law, dim=dim, energy=psi, stress=P, tangent=A, quadratic=quadratic, not_quadratic=why)


def derive(inputs: Inputs) -> SymbolicIR:
    """Stage 2: the tables of every element and the derivatives of every law in every element dimension."""
    return SymbolicIR(
        inputs=inputs,
        tables=tuple(element_tables(e) for e in inputs.elements),
        derivatives=tuple(derive_law(law, dim) for law in inputs.laws for dim in inputs.dims),
    )
