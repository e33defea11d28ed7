"""Stage 2 (symbolic): element tables and the law's point-wise derivatives.

Input: `Inputs` (stage 1).
Output: `SymbolicIR`: per element `ElementTables` (weights, shape values and
reference gradients at the quadrature points, as doubles) and, per law and
dimension, `LawDerivatives`: SymPy expressions of psi(H), P = dpsi/dH and
A = d2psi/dH2 in the displacement-gradient symbols H0..H{d*d-1} (row-major)
and the law's derived parameters, and the law as a quadratic in one strain
measure where it is one (for the tensor split).

Laws may use the rotation R of F's polar decomposition F = R S (and the
stretch S = R^T F). R is not a polynomial of H: the kernels compute it at
each point (symbols R0..) together with Y = (tr(S) I - S)^-1 in 3D, 1/tr(S)
in 2D (symbols Y0..), which gives its derivative in closed form:
dR = R [omega]x with omega = Y axial(R^T dF - dF^T R). The energy must depend
on R only through an isotropic function of S, so that P = dpsi/dH holding R
fixed (checked exactly at a rational F = R S). The chain rule
g_ja = sum_q w_q sum_C P_aC G_jC and K_ja,kb = sum_q w_q sum_CD G_jC A_aC,bD G_kD
links them to nodal displacements; the split stage decides how those sums
are written.
"""
from __future__ import annotations

import ast
import functools

import sympy

from .load import REFERENCE_VARIABLES, GeneratorInputError
from .model import FIBRE_CONSTANTS, ElementSpec, ElementTables, Inputs, LawDerivatives, LawSpec, StrainQuadratic, SymbolicIR

# Names a law's energy may use, besides its constants (docs/laws.md). In 2D
# (plane strain, F33 = 1) the invariants are those of the 3D C = diag(C2, 1).
# The fibre invariants I4 .. I8 (model.FIBRE_INVARIANT_FAMILIES) read the unit
# fibre directions a0, g0 of the cell, 3 components in 2D too (a0z enters as
# the out-of-plane stretch 1).
FIBRE_NAMES = ("I4", "I5", "I6", "I7", "I8")
KINEMATIC_NAMES = ("F", "H", "C", "E", "eps", "J", "I1", "I2", "I3", "I1bar", "I2bar", "R", "S", "d", "I") + \
    FIBRE_NAMES + tuple(name + "bar" for name in FIBRE_NAMES)
# The names each part of a split energy may read besides constants and functions.
ISOCHORIC_NAMES = ("I1bar", "I2bar") + tuple(name + "bar" for name in FIBRE_NAMES)
VOLUMETRIC_NAMES = ("J",)
ROTATION_NAMES = ("R", "S")
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
        corner_gradients=corner_gradients(element),
    )


def corner_gradients(element: ElementSpec) -> tuple[tuple[tuple[float, ...], ...], ...]:
    """dN/d(r, s, t) of every node at each corner (#corners by #N by dim), for
    the runtime's inversion check at the corners. Where a shape function is
    singular at a corner (a rational pyramid's apex, 0/0), the value is the
    limit along the line from the corners' centroid to that corner."""
    variables = REFERENCE_VARIABLES[: element.dim]
    gradients = [[sympy.diff(n, v) for v in variables] for n in element.shape_functions]
    corners = [element.nodes[i] for i in range(element.corner_count)]
    centroid = [sum(c[k] for c in corners) / len(corners) for k in range(element.dim)]
    along = sympy.Symbol("along", positive=True)
    result = []
    for corner in corners:
        at = dict(zip(variables, corner))
        towards = {v: m + along * (c - m) for v, m, c in zip(variables, centroid, corner)}
        rows = []
        for row in gradients:
            values = []
            for g in row:
                value = g.subs(at)
                if not value.is_finite:
                    on_line = sympy.cancel(sympy.together(g.subs(towards)))
                    value = on_line.subs(along, 1)
                    if not value.is_finite:
                        value = sympy.limit(on_line, along, 1, "-")
                values.append(_to_double(value))
            rows.append(tuple(values))
        result.append(tuple(rows))
    return tuple(result)


def gradient_symbols(dim: int) -> tuple[sympy.Symbol, ...]:
    """H0..H{d*d-1}: the displacement gradient, row-major (H[a][C] = du_a/dX_C)."""
    return sympy.symbols(f"H0:{dim * dim}", real=True)


def rotation_symbols(dim: int) -> tuple[sympy.Symbol, ...]:
    """R0..R{d*d-1}: the rotation of F's polar decomposition, row-major."""
    return sympy.symbols(f"R0:{dim * dim}", real=True)


def rotation_inverse_symbols(dim: int) -> tuple[sympy.Symbol, ...]:
    """Y0..: (tr(S) I - S)^-1 row-major in 3D; Y0 = 1/tr(S) in 2D."""
    return sympy.symbols(f"Y0:{9 if dim == 3 else 1}", real=True)


def uses_rotation(law: LawSpec) -> bool:
    return bool(_energy_names(law) & set(ROTATION_NAMES))


def rotation_derivatives(dim: int) -> tuple[sympy.Matrix, ...]:
    """dR/dH_J (a d by d matrix) for each J = a*d + C, in the symbols R.. and Y..

    3D: R^T dF - dF^T R = [(tr(S) I - S) omega]x for dR = R [omega]x; with
    dF = e_a e_C^T the left side is [e_C x r]x, r = R^T e_a. 2D: omega =
    (R_a1 delta_C0 - R_a0 delta_C1) / tr(S) and dR = R omega [[0, -1], [1, 0]]."""
    R = sympy.Matrix(dim, dim, rotation_symbols(dim))
    Y = rotation_inverse_symbols(dim)
    derivatives = []
    for a in range(dim):
        for c in range(dim):
            if dim == 2:
                omega = Y[0] * (R[a, 1] * int(c == 0) - R[a, 0] * int(c == 1))
                derivatives.append(R * sympy.Matrix([[0, -omega], [omega, 0]]))
                continue
            r = R[a, :].T
            axis = sympy.Matrix([int(c == i) for i in range(3)]).cross(r)
            w = sympy.Matrix(3, 3, Y) * axis
            skew = sympy.Matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
            derivatives.append(R * skew)
    return tuple(derivatives)


def parameter_symbols(law: LawSpec) -> dict[str, sympy.Symbol]:
    """The symbols of the constants the energy reads (derived parameters, or the parameters)."""
    return {name: sympy.Symbol(name, real=True) for name, _ in law.constants}


def _names(law: LawSpec, key: str, text: str) -> set[str]:
    try:
        tree = ast.parse(text.replace("^", "**"), mode="eval")
    except SyntaxError as error:
        raise GeneratorInputError(f"{law.source}: key '{key}': cannot parse: {error}") from None
    return {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)}


def _energy_names(law: LawSpec) -> set[str]:
    if law.split_volumetric:
        return _names(law, "isochoric", law.isochoric) | _names(law, "volumetric", law.volumetric)
    return _names(law, "energy", law.energy)


def _check_energy_names(law: LawSpec) -> None:
    constants = [name for name, _ in law.constants]
    reserved = sorted(set(constants) & (set(KINEMATIC_NAMES) | set(FUNCTION_NAMES)))
    if reserved:
        key = "derived" if law.derived else "parameters"
        raise GeneratorInputError(f"{law.source}: key '{key}': {reserved} are names of kinematic quantities "
                                  f"or functions; rename them")
    parts = ([("isochoric", law.isochoric, ISOCHORIC_NAMES), ("volumetric", law.volumetric, VOLUMETRIC_NAMES)]
             if law.split_volumetric else [("energy", law.energy, KINEMATIC_NAMES)])
    for key, text, kinematics in parts:
        unknown = _names(law, key, text) - set(kinematics) - set(FUNCTION_NAMES) - set(constants)
        if unknown & set(law.parameters):
            raise GeneratorInputError(
                f"{law.source}: key '{key}': reads the parameters {sorted(unknown & set(law.parameters))}; "
                "with a [derived] table the energy reads the derived parameters only (add name = \"name\" to it)")
        if unknown:
            what = "derived parameters" if law.derived else "parameters"
            raise GeneratorInputError(
                f"{law.source}: key '{key}': unknown names {sorted(unknown)}; available: "
                f"kinematics {', '.join(kinematics)}, functions {', '.join(FUNCTION_NAMES)}, "
                f"{what} {', '.join(constants)}")


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


# J^(-1/3) while differentiating: the isochoric invariants are polynomials in
# H and this symbol, whose derivative dJr/dH = -Jr^4 dJ/dH / 3 the chain rule
# applies (`law_derivatives`); the results then read J^(-k/3) again.
ROOT_J = sympy.Symbol("Jr", positive=True)


def _determinant(dim: int) -> sympy.Expr:
    return (sympy.eye(dim) + sympy.Matrix(dim, dim, gradient_symbols(dim))).det()


def _fibre_invariants(C: sympy.Matrix, dim: int) -> dict:
    """Builders of I4 .. I8 and their isochoric forms (J^(-2/3) C) from the
    fibre constants; in 2D C = diag(C2, 1), so a direction's z component adds
    its square (I4, I5) or the product (I8)."""
    a, g = ([sympy.Symbol(n, real=True) for n in names] for names in FIBRE_CONSTANTS)

    def pair(u, v, power):
        inner, outer = sympy.Matrix(u[:dim]), sympy.Matrix(v[:dim])
        value = (inner.T * C ** power * outer)[0]
        return value + (u[2] * v[2] if dim == 2 else 0)

    plain = {"I4": lambda: pair(a, a, 1), "I5": lambda: pair(a, a, 2), "I6": lambda: pair(g, g, 1),
             "I7": lambda: pair(g, g, 2), "I8": lambda: pair(a, g, 1)}
    powers = {"I4": 2, "I5": 4, "I6": 2, "I7": 4, "I8": 2}  # J^(-1/3) to the power: J^(-2/3) C, its square
    bars = {name + "bar": (lambda n=name: ROOT_J ** powers[n] * plain[n]()) for name in plain}
    return {**plain, **bars}


@functools.lru_cache(maxsize=None)
def _law_energy(law: LawSpec, dim: int) -> sympy.Expr:
    """psi as an expression of H0.., the law's constants and ROOT_J (standing for J^(-1/3))."""
    _check_energy_names(law)
    identity = sympy.eye(dim)
    H = sympy.Matrix(dim, dim, gradient_symbols(dim))
    F = identity + H
    C = F.T * F
    R = sympy.Matrix(dim, dim, rotation_symbols(dim))
    out_of_plane = 3 - dim  # C33 = 1 in plane strain
    I1 = lambda: C.trace() + out_of_plane  # noqa: E731
    I2 = lambda: (I1() ** 2 - ((C * C).trace() + out_of_plane)) / 2  # noqa: E731
    names = {  # built only when the energy reads them
        "F": lambda: F, "H": lambda: H, "C": lambda: C, "E": lambda: (C - identity) / 2,
        "eps": lambda: (H + H.T) / 2, "J": F.det, "I1": I1, "I2": I2, "I3": lambda: F.det() ** 2,
        "I1bar": lambda: ROOT_J ** 2 * I1(), "I2bar": lambda: ROOT_J ** 4 * I2(),
        "R": lambda: R, "S": lambda: R.T * F, "d": lambda: sympy.Integer(dim), "I": lambda: identity,
    }
    names.update(_fibre_invariants(C, dim))
    used = _energy_names(law)
    psi = _evaluate(law, {name: value() for name, value in names.items() if name in used})
    allowed = set(gradient_symbols(dim)) | set(parameter_symbols(law).values()) | set(rotation_symbols(dim))
    if psi.free_symbols - allowed - {ROOT_J}:
        raise GeneratorInputError(f"{law.source}: key 'energy': unexpected symbols "
                                  f"{psi.free_symbols - allowed - {ROOT_J}}")
    return psi


def _without_root(expr: sympy.Expr, dim: int) -> sympy.Expr:
    """ROOT_J replaced by J^(-1/3)."""
    if ROOT_J not in expr.free_symbols:
        return expr
    return expr.xreplace({ROOT_J: _determinant(dim) ** sympy.Rational(-1, 3)})


@functools.lru_cache(maxsize=None)
def law_energy(law: LawSpec, dim: int) -> sympy.Expr:
    """psi as an expression of H0.. and the law's constants.

    The invariants are those of the 3D right Cauchy-Green tensor; in 2D
    (plane strain) C33 = 1 adds 1 to tr(C) and to tr(C^2); I1bar = J^(-2/3) I1,
    I2bar = J^(-4/3) I2."""
    return _without_root(_law_energy(law, dim), dim)


BULK_J = sympy.Symbol("J", positive=True)


@functools.lru_cache(maxsize=None)
def law_bulk(law: LawSpec) -> tuple[sympy.Expr, sympy.Expr, sympy.Expr]:
    """(U, dU/dJ, d2U/dJ2) of the law's bulk part U(J) (LawSpec.bulk), in
    BULK_J and the law's constants; GeneratorInputError when it reads other
    names or does not vanish with its derivative at J = 1."""
    constants = parameter_symbols(law)
    unknown = _names(law, "bulk", law.bulk) - set(VOLUMETRIC_NAMES) - set(FUNCTION_NAMES) - set(constants)
    if unknown:
        raise GeneratorInputError(f"{law.source}: key 'bulk': unknown names {sorted(unknown)}; available: J, "
                                  f"functions {', '.join(FUNCTION_NAMES)}, constants {', '.join(constants)}")
    try:
        U = sympy.sympify(law.bulk.replace("^", "**"), locals={**_functions(), **constants, "J": BULK_J},
                          rational=True)
    except Exception as error:  # SymPy raises many types for malformed input
        raise GeneratorInputError(f"{law.source}: key 'bulk': cannot evaluate: {error}") from None
    if isinstance(U, sympy.MatrixBase):
        raise GeneratorInputError(f"{law.source}: key 'bulk': evaluates to a matrix, expected a scalar")
    dU = sympy.diff(U, BULK_J)
    # A bulk part that stores energy or stress at rest would move them to the nodes.
    if sympy.simplify(U.subs(BULK_J, 1)) != 0 or sympy.simplify(dU.subs(BULK_J, 1)) != 0:
        raise GeneratorInputError(f"{law.source}: key 'bulk': U(1) and U'(1) must vanish (no energy or "
                                  "pressure at rest)")
    return U, dU, sympy.diff(dU, BULK_J)


def _rational_polar_point(dim: int) -> tuple[dict, dict]:
    """A rational F = R0 S0 (R0 a Cayley rotation, S0 symmetric positive
    definite): values of H.., R.. and Y.. where R = R0 and S = S0 exactly."""
    half, third = sympy.Rational(1, 2), sympy.Rational(1, 3)
    if dim == 2:
        skew = sympy.Matrix([[0, -third], [third, 0]])
        stretch = sympy.Matrix([[sympy.Rational(6, 5), sympy.Rational(1, 7)], [sympy.Rational(1, 7), sympy.Rational(9, 10)]])
    else:
        skew = sympy.Matrix([[0, -third, half], [third, 0, -sympy.Rational(1, 4)], [-half, sympy.Rational(1, 4), 0]])
        stretch = sympy.Matrix([[sympy.Rational(6, 5), sympy.Rational(1, 7), sympy.Rational(-1, 9)],
                                [sympy.Rational(1, 7), sympy.Rational(9, 10), sympy.Rational(1, 8)],
                                [sympy.Rational(-1, 9), sympy.Rational(1, 8), sympy.Rational(11, 10)]])
    identity = sympy.eye(dim)
    rotation = (identity - skew).inv() * (identity + skew)
    F = rotation * stretch
    inverse = [1 / stretch.trace()] if dim == 2 else list((stretch.trace() * identity - stretch).inv())
    values = dict(zip(gradient_symbols(dim), F - identity))
    values.update(zip(rotation_symbols(dim), rotation))
    values.update(zip(rotation_inverse_symbols(dim), inverse))
    return values, {"stretch": stretch}


def _check_rotation_enters_through_stretch(law: LawSpec, psi: sympy.Expr, dim: int) -> None:
    """The term dpsi/dR : dR/dH that P = dpsi/dH|R leaves out must vanish; it
    does when psi is an isotropic function of S (checked exactly at a rational point)."""
    R = rotation_symbols(dim)
    at, _ = _rational_polar_point(dim)
    at.update({p: sympy.Rational(3 + i, 2) for i, p in enumerate(parameter_symbols(law).values())})
    dpsi_dR = [sympy.diff(psi, r).subs(at) for r in R]
    for J, dR in enumerate(rotation_derivatives(dim)):
        left_out = sympy.nsimplify(sum(g * dr.subs(at) for g, dr in zip(dpsi_dR, dR)))
        if sympy.simplify(left_out) != 0:
            raise GeneratorInputError(
                f"{law.source}: key 'energy': depends on R other than through an isotropic function "
                f"of S = R^T F (dpsi/dR : dR/dH{J} = {left_out} at a test point); the generator "
                "differentiates such energies holding R fixed")


@functools.lru_cache(maxsize=None)
def law_derivatives(law: LawSpec, dim: int) -> tuple[sympy.Expr, tuple, tuple]:
    """(psi, P, A): P[I] = dpsi/dH_I, A[I][J] = d2psi/dH_I dH_J (full, symmetric).

    With R: P holds R fixed (see the module docstring) and A adds dP/dR : dR/dH_J.
    With the isochoric invariants: psi is differentiated as a polynomial in H
    and Jr = J^(-1/3), with dJr/dH = -Jr^4 dJ/dH / 3."""
    psi = _law_energy(law, dim)
    H = gradient_symbols(dim)
    root = ROOT_J in psi.free_symbols
    if root:
        J = _determinant(dim)
        droot = [-ROOT_J ** 4 * sympy.diff(J, h) / 3 for h in H]

    def derivative(expr, i):
        value = sympy.diff(expr, H[i])
        return value + sympy.diff(expr, ROOT_J) * droot[i] if root else value

    P = tuple(derivative(psi, i) for i in range(len(H)))
    rotation = uses_rotation(law)
    if rotation:
        _check_rotation_enters_through_stretch(law, _without_root(psi, dim), dim)
        R, dR = rotation_symbols(dim), rotation_derivatives(dim)
    A = [[None] * len(H) for _ in H]
    for i in range(len(H)):
        for j in range(i, len(H)):
            entry = derivative(P[i], j)
            if rotation:
                entry += sum(sympy.diff(P[i], r) * dr for r, dr in zip(R, dR[j]))
            A[i][j] = A[j][i] = _without_root(entry, dim)
    return (_without_root(psi, dim), tuple(_without_root(p, dim) for p in P), tuple(tuple(row) for row in A))


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


def _inverted_point(dim: int) -> dict:
    """H at a rational F with det F < 0 (an inverted element)."""
    if dim == 2:
        F = sympy.Matrix([[sympy.Rational(-1, 2), sympy.Rational(1, 5)], [sympy.Rational(1, 7), 1]])
    else:
        F = sympy.Matrix([[sympy.Rational(-1, 2), sympy.Rational(1, 5), 0],
                          [sympy.Rational(1, 7), 1, sympy.Rational(1, 9)],
                          [0, sympy.Rational(1, 4), sympy.Rational(6, 5)]])
    assert F.det() < 0
    return dict(zip(gradient_symbols(dim), F - sympy.eye(dim)))


def _check_invertible(law: LawSpec, psi: sympy.Expr, P: tuple, dim: int) -> None:
    """A law declared invertible has a finite, real energy and stress at an inverted F."""
    if uses_rotation(law):
        raise GeneratorInputError(f"{law.source}: key 'invertible': a law written with R cannot be invertible "
                                  "(at det F < 0 the polar factor is a reflection)")
    at = _inverted_point(dim)
    at.update({p: sympy.Rational(3 + i, 2) for i, p in enumerate(parameter_symbols(law).values())})
    for name, expr in [("energy", psi)] + [(f"stress P{i}", p) for i, p in enumerate(P)]:
        value = sympy.N(expr.subs(at), 30)  # numeric: simplify would factor the logs' large rationals
        if not (value.is_real and value.is_finite):
            raise GeneratorInputError(f"{law.source}: key 'invertible': the {name} is {value} at an inverted F "
                                      "(det F < 0); an invertible law must be defined there")


def derive_law(law: LawSpec, dim: int) -> LawDerivatives:
    """psi, P and A of the law in dimension dim, and its strain quadratic or why it has none."""
    psi, P, A = law_derivatives(law, dim)
    if law.invertible:
        _check_invertible(law, psi, P, dim)
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
