"""Every law file in laws/, checked through the generator's own symbolic
derivatives (generator/symbolic.py): the reference is energy- and
stress-free, rotations cost nothing where the file claims rotation
invariance (and something where it says they do), laws of (young, poisson)
linearise to Hooke's tangent, and the laws with a closed-form stress below
match it under uniaxial, equibiaxial and simple-shear deformations.

Parameters take values inside each law's limits (conftest.value_inside)."""
from __future__ import annotations

import functools
from pathlib import Path

import numpy
import pytest
import sympy

from conftest import ROOT, value_inside
from generator.load import load_law
from generator.symbolic import (_rational_polar_point, gradient_symbols, law_derivatives, law_energy,
                                rotation_inverse_symbols, rotation_symbols, uses_rotation)

LAW_FILES = sorted((ROOT / "laws").glob("*.toml"))
DIMS = (2, 3)
DIGITS = 30


@functools.lru_cache(maxsize=None)
def _law(path: Path):
    return load_law(path)


def _constant_values(law) -> dict:
    """{symbol: exact value} of the constants the energy reads, at parameters inside the limits."""
    parameters = {sympy.Symbol(p, real=True): sympy.Rational(round(value_inside(law.limit(p), i), 6))
                  for i, p in enumerate(law.parameters)}
    return {sympy.Symbol(name, real=True): sympy.sympify(expr).subs(parameters) for name, expr in law.constants}


def _at(law, dim: int, F: sympy.Matrix, R: sympy.Matrix | None = None) -> dict:
    """Values of H (from F), R and Y (from R, for laws written with the polar rotation) and the constants."""
    values = dict(zip(gradient_symbols(dim), F - sympy.eye(dim)))
    if uses_rotation(law):
        R = sympy.eye(dim) if R is None else R
        S = R.T * F
        Y = [1 / S.trace()] if dim == 2 else list((S.trace() * sympy.eye(3) - S).inv())
        values.update(zip(rotation_symbols(dim), R))
        values.update(zip(rotation_inverse_symbols(dim), Y))
    values.update(_constant_values(law))
    return values


def _number(expr, at: dict) -> float:
    value = sympy.N(expr.subs(at), DIGITS)
    assert value.is_real, f"{expr} is not real at {at}"
    return float(value)


def _rotation(dim: int) -> sympy.Matrix:
    """A rational rotation (Cayley transform of a skew matrix)."""
    if dim == 2:
        skew = sympy.Matrix([[0, -sympy.Rational(3, 5)], [sympy.Rational(3, 5), 0]])
    else:
        skew = sympy.Matrix([[0, -sympy.Rational(1, 2), sympy.Rational(1, 3)],
                             [sympy.Rational(1, 2), 0, -sympy.Rational(2, 7)],
                             [-sympy.Rational(1, 3), sympy.Rational(2, 7), 0]])
    identity = sympy.eye(dim)
    return (identity - skew).inv() * (identity + skew)


def _ids(path: Path) -> str:
    return path.stem


@pytest.mark.parametrize("dim", DIMS)
@pytest.mark.parametrize("path", LAW_FILES, ids=_ids)
def test_reference_is_energy_and_stress_free(path, dim):
    law = _law(path)
    psi, P, _ = law_derivatives(law, dim)
    at = _at(law, dim, sympy.eye(dim))
    assert abs(_number(psi, at)) < 1e-25, f"{law.name}: W(I) != 0"
    assert all(abs(_number(p, at)) < 1e-25 for p in P), f"{law.name}: P(I) != 0"


@pytest.mark.parametrize("dim", DIMS)
@pytest.mark.parametrize("path", LAW_FILES, ids=_ids)
def test_rigid_rotation_costs_nothing_where_the_law_claims_it(path, dim):
    """W(Q F) = W(F) at a deformed F and a rotation Q, or W(Q F) != W(F) where the file says
    rotation_invariant = false (the claim is tested both ways)."""
    law = _law(path)
    values, extra = _rational_polar_point(dim)
    F = sympy.eye(dim) + sympy.Matrix(dim, dim, [values[h] for h in gradient_symbols(dim)])
    R = F * extra["stretch"].inv()
    Q = _rotation(dim)
    psi = law_energy(law, dim)
    before = _number(psi, _at(law, dim, F, R))
    after = _number(psi, _at(law, dim, Q * F, Q * R))
    assert before > 0, f"{law.name}: W = {before} at a deformed F"
    if law.rotation_invariant:
        assert after == pytest.approx(before, rel=1e-20, abs=1e-20), law.name
    else:
        assert abs(after - before) > 1e-6 * abs(before), f"{law.name}: claims rotation_invariant = false"


def _hooke_tangent(dim: int, young: float, poisson: float) -> numpy.ndarray:
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    mu = young / (2 * (1 + poisson))
    delta = numpy.eye(dim)
    A = numpy.zeros((dim, dim, dim, dim))
    for a in range(dim):
        for c in range(dim):
            for b in range(dim):
                for e in range(dim):
                    A[a, c, b, e] = (lam * delta[a, c] * delta[b, e]
                                     + mu * (delta[a, b] * delta[c, e] + delta[a, e] * delta[c, b]))
    return A.reshape(dim * dim, dim * dim)


@pytest.mark.parametrize("dim", DIMS)
@pytest.mark.parametrize("path", [p for p in LAW_FILES if _law(p).parameters == ("young", "poisson")], ids=_ids)
def test_laws_of_young_and_poisson_linearise_to_hooke(path, dim):
    """A(F = I) = lam d_aC d_bD + mu (d_ab d_CD + d_aD d_bC), lam and mu from (young, poisson);
    in 2D the plane-strain Lame constants are the 3D ones."""
    law = _law(path)
    _, _, A = law_derivatives(law, dim)
    at = _at(law, dim, sympy.eye(dim))
    young, poisson = (float(v) for v in (sympy.Rational(round(value_inside(law.limit(p), i), 6))
                                         for i, p in enumerate(law.parameters)))
    expected = _hooke_tangent(dim, young, poisson)
    actual = numpy.array([[_number(entry, at) for entry in row] for row in A])
    numpy.testing.assert_allclose(actual, expected, rtol=1e-12, atol=1e-12 * abs(expected).max())


# --- Closed forms ---------------------------------------------------------------
# Per law (by file name) the derivatives of W(I1bar, I2bar, J) = W_iso(I1bar, I2bar) + U(J):
# (dW/dI1bar, dW/dI2bar, dU/dJ) as functions of the parameters p (a dict) and the invariants.
# The Cauchy stress of such a law is (Holzapfel, Nonlinear Solid Mechanics, 6.6)
#   sigma = 2/J [(W1 + I1bar W2) Bbar - W2 Bbar^2 - (W1 I1bar + 2 W2 I2bar)/3 I] + U'(J) I
# with Bbar = J^(-2/3) F F^T, and P = J sigma F^-T.
_ARRUDA_BOYCE = (1 / 2, 1 / 20, 11 / 1050, 19 / 7000, 519 / 673750)
CLOSED_FORMS = {
    "mooney_rivlin": lambda p, I1, I2, J: (p["c10"], p["c01"], p["kappa"] * (J - 1)),
    "yeoh": lambda p, I1, I2, J: (p["c10"] + 2 * p["c20"] * (I1 - 3) + 3 * p["c30"] * (I1 - 3) ** 2, 0.0,
                                  p["kappa"] * (J - 1)),
    "gent": lambda p, I1, I2, J: (p["mu"] / 2 / (1 - (I1 - 3) / p["Jm"]), 0.0, p["kappa"] * (J - 1)),
    "veronda_westmann": lambda p, I1, I2, J: (p["c1"] * p["c2"] * numpy.exp(p["c2"] * (I1 - 3)),
                                              -p["c1"] * p["c2"] / 2, p["kappa"] * (J - 1)),
    "arruda_boyce": lambda p, I1, I2, J: (p["mu"] * sum(i * c * I1 ** (i - 1) / p["lambda_m"] ** (2 * i - 2)
                                                        for i, c in enumerate(_ARRUDA_BOYCE, start=1)),
                                          0.0, p["kappa"] * (J - 1)),
}


def _closed_form_stress(name: str, p: dict, F: numpy.ndarray) -> numpy.ndarray:
    J = numpy.linalg.det(F)
    Bbar = J ** (-2 / 3) * F @ F.T
    I1 = numpy.trace(Bbar)
    I2 = (I1 ** 2 - numpy.trace(Bbar @ Bbar)) / 2
    W1, W2, dU = CLOSED_FORMS[name](p, I1, I2, J)
    sigma = 2 / J * ((W1 + I1 * W2) * Bbar - W2 * Bbar @ Bbar - (W1 * I1 + 2 * W2 * I2) / 3 * numpy.eye(3))
    sigma += dU * numpy.eye(3)
    return J * sigma @ numpy.linalg.inv(F).T


DEFORMATIONS = {
    "uniaxial": numpy.diag([1.3, 0.9, 0.9]),
    "equibiaxial": numpy.diag([1.2, 1.2, 0.8]),
    "simple_shear": numpy.array([[1.0, 0.4, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
}
# Plane strain: the same deformations with the out-of-plane stretch 1.
DEFORMATIONS_2D = {
    "uniaxial": numpy.diag([1.3, 0.9, 1.0]),
    "equibiaxial": numpy.diag([1.2, 1.2, 1.0]),
    "simple_shear": DEFORMATIONS["simple_shear"],
}
CLOSED_FORM_FILES = [p for p in LAW_FILES if p.stem in CLOSED_FORMS]


def _generator_stress(law, dim: int, F: numpy.ndarray) -> numpy.ndarray:
    _, P, _ = law_derivatives(law, dim)
    Fd = sympy.Matrix(dim, dim, [sympy.Rational(str(x)) for x in F[:dim, :dim].flatten()])
    at = _at(law, dim, Fd)
    return numpy.array([_number(p, at) for p in P]).reshape(dim, dim)


@pytest.mark.parametrize("deformation", sorted(DEFORMATIONS))
@pytest.mark.parametrize("dim", DIMS)
@pytest.mark.parametrize("path", CLOSED_FORM_FILES, ids=_ids)
def test_first_piola_stress_matches_the_closed_form(path, dim, deformation):
    law = _law(path)
    F = (DEFORMATIONS if dim == 3 else DEFORMATIONS_2D)[deformation]
    p = {name: float(value) for name, value in
         ((p, sympy.Rational(round(value_inside(law.limit(p), i), 6))) for i, p in enumerate(law.parameters))}
    expected = _closed_form_stress(law.name, p, F)[:dim, :dim]
    actual = _generator_stress(law, dim, F)
    numpy.testing.assert_allclose(actual, expected, rtol=1e-11, atol=1e-11 * abs(expected).max())


@pytest.mark.parametrize("path", [p for p in CLOSED_FORM_FILES if p.stem == "mooney_rivlin"], ids=_ids)
def test_mooney_rivlin_shear_stress_is_linear_in_the_shear(path):
    """Simple shear of Mooney-Rivlin (J = 1): sigma_12 = 2 (c10 + c01) gamma exactly, and P_12 = sigma_12."""
    law = _law(path)
    gamma = 0.4
    p = {name: float(sympy.Rational(round(value_inside(law.limit(name), i), 6)))
         for i, name in enumerate(law.parameters)}
    F = DEFORMATIONS["simple_shear"]
    assert F[0, 1] == gamma
    actual = _generator_stress(law, 3, F)
    assert actual[0, 1] == pytest.approx(2 * (p["c10"] + p["c01"]) * gamma, rel=1e-12)


# --- Fibre laws -------------------------------------------------------------------
# Per law the fibre terms' derivatives (dW/dI4bar, dW/dI6bar) and the matrix's
# (dW/dI1bar, dW/dI2bar, dU/dJ). A fibre family a0 adds to the Cauchy stress
# (Holzapfel, Nonlinear Solid Mechanics, 6.7)
#   2/J W4 (abar abar^T - I4bar/3 I),  abar = J^(-1/3) F a0,  I4bar = |abar|^2.
FIBRE_FORMS = {
    "transversely_isotropic_mooney_rivlin": lambda p, I1, I2, I4, I6, J: (
        (p["c10"], p["c01"], p["kappa"] * (J - 1)), (p["eta"] * (I4 - 1), 0.0)),
    "holzapfel_gasser_ogden": lambda p, I1, I2, I4, I6, J: (
        (p["c10"], 0.0, p["kappa"] / 2 * (J - 1 / J)),
        tuple(p["k1"] * (I - 1) * numpy.exp(p["k2"] * (I - 1) ** 2) for I in (I4, I6))),
}
FIBRE_FILES = [p for p in LAW_FILES if p.stem in FIBRE_FORMS]
# Fibre directions (first family; the second is the first turned 90 degrees
# about z) along, across and at 45 degrees to the stretch of DEFORMATIONS.
FIBRE_DIRECTIONS = {"along": (1.0, 0.0, 0.0), "across": (0.0, 1.0, 0.0), "at_45": (0.6, 0.6, 0.0)}


def _fibre_parameters(law, direction) -> dict:
    second = (-direction[1], direction[0], direction[2])
    values = {p: sympy.Rational(round(value_inside(law.limit(p), i), 6)) for i, p in enumerate(law.own_parameters)}
    for name, component in zip(("fibre_x", "fibre_y", "fibre_z", "fibre2_x", "fibre2_y", "fibre2_z"),
                               direction + second):
        values[name] = sympy.Rational(str(component))
    return {name: value for name, value in values.items() if name in law.parameters}


def _fibre_closed_form_stress(law, p: dict, F: numpy.ndarray) -> numpy.ndarray:
    J = numpy.linalg.det(F)
    Bbar = J ** (-2 / 3) * F @ F.T
    I1 = numpy.trace(Bbar)
    I2 = (I1 ** 2 - numpy.trace(Bbar @ Bbar)) / 2
    fibres = []
    for family in ("fibre", "fibre2"):
        a0 = numpy.array([p.get(f"{family}_{c}", 0.0) for c in "xyz"])
        fibres.append(J ** (-1 / 3) * F @ (a0 / numpy.linalg.norm(a0)) if a0.any() else numpy.zeros(3))
    I4, I6 = (a @ a for a in fibres)
    (W1, W2, dU), (W4, W6) = FIBRE_FORMS[law.name](p, I1, I2, I4, I6, J)
    sigma = 2 / J * ((W1 + I1 * W2) * Bbar - W2 * Bbar @ Bbar - (W1 * I1 + 2 * W2 * I2) / 3 * numpy.eye(3))
    for W, a in ((W4, fibres[0]), (W6, fibres[1])):
        sigma += 2 / J * W * (numpy.outer(a, a) - a @ a / 3 * numpy.eye(3))
    sigma += dU * numpy.eye(3)
    return J * sigma @ numpy.linalg.inv(F).T


@pytest.mark.parametrize("direction", sorted(FIBRE_DIRECTIONS))
@pytest.mark.parametrize("deformation", sorted(DEFORMATIONS))
@pytest.mark.parametrize("dim", DIMS)
@pytest.mark.parametrize("path", FIBRE_FILES, ids=_ids)
def test_fibre_law_stress_matches_the_closed_form(path, dim, deformation, direction):
    law = _law(path)
    F = (DEFORMATIONS if dim == 3 else DEFORMATIONS_2D)[deformation]
    parameters = _fibre_parameters(law, FIBRE_DIRECTIONS[direction])
    _, P, _ = law_derivatives(law, dim)
    Fd = sympy.Matrix(dim, dim, [sympy.Rational(str(x)) for x in F[:dim, :dim].flatten()])
    at = dict(zip(gradient_symbols(dim), Fd - sympy.eye(dim)))
    symbols = {sympy.Symbol(name, real=True): value for name, value in parameters.items()}
    at.update({sympy.Symbol(name, real=True): sympy.sympify(expr).subs(symbols) for name, expr in law.constants})
    actual = numpy.array([_number(p, at) for p in P]).reshape(dim, dim)
    expected = _fibre_closed_form_stress(law, {n: float(v) for n, v in parameters.items()}, F)[:dim, :dim]
    numpy.testing.assert_allclose(actual, expected, rtol=1e-11, atol=1e-11 * abs(expected).max())

