"""Stage 2 (symbolic): element tables and law derivatives, checked against
independent formulas; the stage output is typed."""
from __future__ import annotations

import pytest
import sympy

from conftest import ROOT
from generator.load import GeneratorInputError, load_element, load_law
from generator.model import Inputs, LawDerivatives, SymbolicIR
from generator.load import REFERENCE_VARIABLES
from generator.symbolic import (corner_gradients, derive, derive_law, gradient_symbols, law_bulk, law_derivatives,
                                law_energy, strain_quadratic)

LAM, MU = sympy.Symbol("lam", real=True), sympy.Symbol("mu", real=True)
H_VALUES = [0.03, -0.02, 0.05, 0.01, 0.04, -0.03, 0.02, 0.06, -0.01]


def _law(name: str):
    return load_law(ROOT / "laws" / f"{name}.toml")


def test_stvk_stress_is_F_times_S():
    _, P, _ = law_derivatives(_law("stvk"), 3)
    H = gradient_symbols(3)
    lam, mu = 2.0, 3.0
    F = sympy.eye(3) + sympy.Matrix(3, 3, H_VALUES)
    E = (F.T * F - sympy.eye(3)) / 2
    S = lam * E.trace() * sympy.eye(3) + 2 * mu * E
    expected = F * S
    at = dict(zip(H, H_VALUES)) | {LAM: lam, MU: mu}
    for i in range(9):
        assert float(P[i].subs(at)) == pytest.approx(float(expected[i // 3, i % 3]), rel=1e-13)


def test_neohookean_stress_reference():
    _, P, _ = law_derivatives(_law("neohookean"), 3)
    lam, mu = 2.0, 3.0
    F = sympy.eye(3) + sympy.Matrix(3, 3, H_VALUES)
    J = F.det()
    expected = mu * (F - F.inv().T) + lam * sympy.log(J) * F.inv().T
    at = dict(zip(gradient_symbols(3), H_VALUES)) | {LAM: lam, MU: mu}
    for i in range(9):
        assert float(P[i].subs(at)) == pytest.approx(float(expected[i // 3, i % 3]), rel=1e-12)


def test_law_energy_with_unknown_names_is_refused(tmp_path):
    path = tmp_path / "stvk.toml"
    path.write_text((ROOT / "laws" / "stvk.toml").read_text().replace("tr(E*E)", "tr(Q*E)"))
    law = load_law(path)
    with pytest.raises(GeneratorInputError, match=r"energy.*unknown names \['Q'\]"):
        law_derivatives(law, 3)


def test_only_laws_quadratic_in_one_strain_have_a_strain_quadratic():
    with pytest.raises(GeneratorInputError, match="one strain measure"):
        strain_quadratic(_law("neohookean"), 3)
    assert strain_quadratic(_law("stvk"), 3).strain == "E"
    assert strain_quadratic(_law("hooke"), 2).strain == "eps"


@pytest.mark.parametrize("dim", [2, 3])
def test_only_hooke_is_linear(dim):
    assert derive_law(_law("hooke"), dim).linear
    assert not derive_law(_law("stvk"), dim).linear
    assert not derive_law(_law("neohookean"), dim).linear
    assert not derive_law(_law("corotational"), dim).linear  # constant-looking in H, but R moves


def test_elasticity_tensor_of_hooke_is_isotropic():
    quadratic = strain_quadratic(_law("hooke"), 3)
    delta = lambda i, j: 1 if i == j else 0  # noqa: E731
    for a in range(3):
        for b in range(3):
            for c in range(3):
                for d in range(3):
                    expected = LAM * delta(a, b) * delta(c, d) + MU * (delta(a, c) * delta(b, d) + delta(a, d) * delta(b, c))
                    assert sympy.simplify(quadratic.elasticity[a][b][c][d] - expected) == 0


def test_derive_gives_tables_per_element_and_derivatives_per_law_and_dimension():
    tet4, tri3 = (load_element(ROOT / "elements" / f"{n}.toml") for n in ("tet4", "tri3"))
    stvk, neo = _law("stvk"), _law("neohookean")
    symbolic = derive(Inputs(elements=(tet4, tri3), laws=(stvk, neo)))
    assert isinstance(symbolic, SymbolicIR)
    assert symbolic.tables_of(tet4).weights == (1 / 6,)
    assert symbolic.tables_of(tri3).reference_gradients == (((-1.0, -1.0), (1.0, 0.0), (0.0, 1.0)),)
    assert [(d.law.name, d.dim) for d in symbolic.derivatives] == [("stvk", 2), ("stvk", 3),
                                                                    ("neohookean", 2), ("neohookean", 3)]
    assert all(isinstance(d, LawDerivatives) for d in symbolic.derivatives)
    assert symbolic.derivatives_of(stvk, 3).quadratic.strain == "E"
    neo3 = symbolic.derivatives_of(neo, 3)
    assert neo3.quadratic is None and "one strain measure" in neo3.not_quadratic
    assert len(neo3.stress) == 9 and len(neo3.tangent) == 9


def _at_rational_polar_point(law, dim):
    """Values at F = R0 S0 (symbolic.py's rational test point) and lam = 2, mu = 3."""
    from generator.symbolic import _rational_polar_point
    at, extra = _rational_polar_point(dim)
    at.update({LAM: 2, MU: 3})
    return at, extra["stretch"]


@pytest.mark.parametrize("dim", [2, 3])
def test_corotational_stress_is_2mu_F_minus_R_plus_lam_trace_R(dim):
    _, P, _ = law_derivatives(_law("corotational"), dim)
    at, stretch = _at_rational_polar_point(_law("corotational"), dim)
    F = sympy.eye(dim) + sympy.Matrix(dim, dim, [at[h] for h in gradient_symbols(dim)])
    R = F * stretch.inv()
    expected = 2 * 3 * (F - R) + 2 * (stretch.trace() - dim) * R
    assert [sympy.simplify(p.subs(at) - e) for p, e in zip(P, expected)] == [0] * dim ** 2


@pytest.mark.parametrize("dim", [2, 3])
def test_corotational_tangent_is_the_derivative_of_its_stress_along_the_polar_rotation(dim):
    """A = dP/dH with R = R(H): compare with a central difference of P, R taken
    from the exact polar decomposition of F +- h E_J (SymPy, high precision)."""
    import mpmath
    from generator.symbolic import rotation_inverse_symbols, rotation_symbols
    mpmath.mp.dps = 50
    _, P, A = law_derivatives(_law("corotational"), dim)
    at, _ = _at_rational_polar_point(_law("corotational"), dim)
    H = gradient_symbols(dim)
    F0 = sympy.eye(dim) + sympy.Matrix(dim, dim, [at[h] for h in H])

    def values(F):
        Fm = mpmath.matrix([[mpmath.mpf(sympy.Rational(F[i, j]).p) / sympy.Rational(F[i, j]).q
                             for j in range(dim)] for i in range(dim)])
        eigenvalues, V = mpmath.eigsy(Fm.T * Fm)
        root = V * mpmath.diag([mpmath.sqrt(x) for x in eigenvalues]) * V.T
        Rm = Fm * mpmath.inverse(root)
        R = sympy.Matrix(dim, dim, [sympy.Float(Rm[i, j], 50) for i in range(dim) for j in range(dim)])
        S = R.T * F
        Y = [1 / S.trace()] if dim == 2 else list((S.trace() * sympy.eye(3) - S).inv())
        v = dict(zip(H, F - sympy.eye(dim)))
        v.update(zip(rotation_symbols(dim), R))
        v.update(zip(rotation_inverse_symbols(dim), Y))
        v.update({LAM: 2, MU: 3})
        return v

    step = sympy.Rational(1, 10 ** 12)
    for j in range(dim * dim):
        E = sympy.zeros(dim, dim)
        E[j // dim, j % dim] = step
        plus, minus = values(F0 + E), values(F0 - E)
        for i in range(dim * dim):
            difference = (P[i].subs(plus) - P[i].subs(minus)) / (2 * step)
            assert float(A[i][j].subs(values(F0))) == pytest.approx(float(difference), rel=1e-9, abs=1e-9)


def test_rotation_outside_an_isotropic_function_of_the_stretch_is_refused(tmp_path):
    text = (ROOT / "laws" / "corotational.toml").read_text().replace(
        'energy = "mu * tr(transpose(F - R)*(F - R)) + lam/2 * tr(S - I)**2"', 'energy = "mu * tr(R*F)"')
    path = tmp_path / "twisted.toml"
    path.write_text(text.replace('name = "corotational"', 'name = "twisted"'))
    with pytest.raises(GeneratorInputError, match="isotropic function of S"):
        law_derivatives(load_law(path), 3)


@pytest.mark.parametrize("name", ["neohookean", "corotational"])
def test_invertible_is_refused_for_laws_undefined_or_reflected_at_inversion(tmp_path, name):
    text = (ROOT / "laws" / f"{name}.toml").read_text().replace('parameters = ["young", "poisson"]',
                                                                'parameters = ["young", "poisson"]\ninvertible = true')
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    with pytest.raises(GeneratorInputError, match="invertible"):
        derive_law(load_law(path), 3)


@pytest.mark.parametrize("dim", [2, 3])
def test_stable_neohookean_is_invertible_and_stress_free_at_rest(dim):
    law = _law("stable_neohookean")
    assert law.invertible
    derivatives = derive_law(law, dim)
    at_rest = {h: 0 for h in gradient_symbols(dim)}
    assert all(sympy.simplify(p.subs(at_rest)) == 0 for p in derivatives.stress)
    assert sympy.simplify(derivatives.energy.subs(at_rest)) == 0
    assert not derivatives.linear


def _split_law(tmp_path, body: str, parameters: str = '["c10", "kappa"]'):
    path = tmp_path / "split.toml"
    path.write_text(f'name = "split"\ndescription = "test law"\nparameters = {parameters}\n{body}')
    return load_law(path)


@pytest.mark.parametrize("body, message", [
    ('isochoric = "c10*(I1bar - 3) + c10*J"\nvolumetric = "kappa*(J - 1)**2"\n', r"'isochoric'.*\['J'\]"),
    ('isochoric = "c10*(I1bar - 3)"\nvolumetric = "kappa*(J - 1)**2 + I1"\n', r"'volumetric'.*\['I1'\]"),
    ('energy = "c10*(I1 - 3)"\n[derived]\nmu = "c10/2"\n', r"'energy'.*reads the parameters \['c10'\]"),
])
def test_energy_parts_read_only_their_own_names(tmp_path, body, message):
    with pytest.raises(GeneratorInputError, match=message):
        law_energy(_split_law(tmp_path, body), 3)


def test_constants_may_not_shadow_kinematic_names(tmp_path):
    with pytest.raises(GeneratorInputError, match=r"'parameters'.*\['J'\]"):
        law_energy(_split_law(tmp_path, 'energy = "J*(I1 - 3)"\n', '["J"]'), 3)


@pytest.mark.parametrize("dim", [2, 3])
def test_invariants_are_the_3d_ones_in_plane_strain(tmp_path, dim):
    """I1, I2, I3, J, I1bar, I2bar of F (2D: F33 = 1) against their definitions on the 3D F."""
    H = gradient_symbols(dim)
    values = dict(zip(H, H_VALUES))
    F3 = sympy.eye(3)
    F3[:dim, :dim] += sympy.Matrix(dim, dim, H_VALUES[:dim * dim])
    C3 = F3.T * F3
    J = F3.det()
    I1, I2 = C3.trace(), (C3.trace() ** 2 - (C3 * C3).trace()) / 2
    expected = {"I1": I1, "I2": I2, "I3": C3.det(), "J": J, "I1bar": J ** sympy.Rational(-2, 3) * I1,
                "I2bar": J ** sympy.Rational(-4, 3) * I2}
    for name, value in expected.items():
        law = _split_law(tmp_path, f'energy = "c10*{name}"\n')
        got = law_energy(law, dim).subs(values).subs(sympy.Symbol("c10", real=True), 1)
        assert float(got) == pytest.approx(float(value), rel=1e-14), name


@pytest.mark.parametrize("name", ["quad4", "hex8", "tet10", "prism15", "pyramid5", "pyramid13"])
def test_corner_gradients_are_the_gradients_at_the_corners_or_their_limit_from_the_centroid(name):
    """At a regular corner the value; at a pyramid's apex (0/0) the gradient
    a step of 1e-8 short of it on the line from the centroid, to 1e-6."""
    element = load_element(ROOT / "elements" / f"{name}.toml")
    variables = REFERENCE_VARIABLES[: element.dim]
    corners = [element.nodes[i] for i in range(element.corner_count)]
    centroid = [sum(c[k] for c in corners) / len(corners) for k in range(element.dim)]
    table = corner_gradients(element)
    assert len(table) == element.corner_count
    for corner, rows in zip(corners, table):
        near = [float(c) + 1e-8 * float(m - c) for c, m in zip(corner, centroid)]
        for n, row in zip(element.shape_functions, rows):
            for v, value in zip(variables, row):
                expected = float(sympy.diff(n, v).subs(dict(zip(variables, near))))
                assert value == pytest.approx(expected, abs=1e-6)


def _bulk_law(tmp_path, bulk: str):
    path = tmp_path / "bulky.toml"
    path.write_text('name = "bulky"\ndescription = "test"\nparameters = ["c10", "kappa"]\n'
                    f'energy = "c10*(I1 - 3) + kappa/2*(J - 1)**2"\nbulk = "{bulk}"\n')
    return load_law(path)


@pytest.mark.parametrize("bulk, message", [
    ("kappa/2*(J - 1)**2 + c10*I1", "unknown names ['I1']"),
    ("kappa*(J - 1)", "must vanish"),
    ("kappa/2*J**2", "must vanish"),
])
def test_bulk_part_errors_name_file_and_key(tmp_path, bulk, message):
    with pytest.raises(GeneratorInputError) as error:
        law_bulk(_bulk_law(tmp_path, bulk))
    assert "bulky.toml" in str(error.value) and "'bulk'" in str(error.value) and message in str(error.value)


def test_neohookean_bulk_part_and_its_derivatives():
    U, dU, d2U = law_bulk(_law("neohookean"))
    J, lam = sympy.Symbol("J", positive=True), sympy.Symbol("lam", real=True)
    assert sympy.simplify(U - lam / 2 * sympy.log(J) ** 2) == 0
    assert sympy.simplify(dU - lam * sympy.log(J) / J) == 0
    assert sympy.simplify(d2U - lam * (1 - sympy.log(J)) / J ** 2) == 0


def _remainder_bulk_modulus(law, values: dict) -> float:
    """K of psi - U(J) under a pure dilatation F = s I (3D): d2/ds2 at s = 1, over 9."""
    s = sympy.Symbol("s", positive=True)
    psi = law_energy(law, 3).subs({h: 0 for h in gradient_symbols(3)[1:4] + gradient_symbols(3)[5:8]})
    H = gradient_symbols(3)
    psi = psi.subs({H[0]: s - 1, H[4]: s - 1, H[8]: s - 1})
    J = 3 * s - 2 if derive_law(law, 3).linear else s ** 3  # a linear law's J is 1 + tr(eps)
    U = law_bulk(law)[0].subs(sympy.Symbol("J", positive=True), J)
    constants = {sympy.Symbol(name, real=True): expr for name, expr in law.constants}
    curvature = sympy.diff(psi - U, s, 2).subs(s, 1).subs(constants)
    return float(curvature.subs({sympy.Symbol(k, real=True): v for k, v in values.items()})) / 9


@pytest.mark.parametrize("name", ["hooke", "neohookean", "stable_neohookean"])
def test_what_the_bulk_part_leaves_does_not_stiffen_near_incompressibility(name):
    """The bulk part carries lam: the rest of the energy keeps a bulk modulus
    of order mu, which falls as nu nears 1/2 where the whole law's grows 100-fold."""
    law = _law(name)
    loose = _remainder_bulk_modulus(law, {"young": 1.0, "poisson": 0.3})
    tight = _remainder_bulk_modulus(law, {"young": 1.0, "poisson": 0.499})
    assert abs(tight) <= 1.0 and abs(tight) <= abs(loose) + 1e-12


@pytest.mark.parametrize("name", ["mooney_rivlin", "yeoh", "gent", "arruda_boyce", "veronda_westmann"])
def test_a_split_laws_bulk_part_is_its_whole_volume_response(name):
    law = _law(name)
    values = {p: 1.0 for p in law.parameters}
    assert abs(_remainder_bulk_modulus(law, values)) < 1e-12
