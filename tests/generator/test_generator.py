"""Generator tests: golden output, input validation, printer and flop counts."""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import sympy

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from generator import stale  # noqa: E402
from generator.compiler import differences, generate  # noqa: E402
from generator.load import GeneratorInputError, load_element, load_law  # noqa: E402
from generator.lower import SplitRefused, build_kernel_ir  # noqa: E402
from generator.model import Inputs  # noqa: E402
from generator.optimize import count_flops, optimise  # noqa: E402
from generator.printer import print_expr  # noqa: E402
from generator.symbolic import derive, gradient_symbols, law_derivatives, strain_quadratic  # noqa: E402


@pytest.fixture(scope="module")
def regenerated():
    return generate(ROOT)


def test_generated_matches_inputs_byte_for_byte(regenerated):
    files, _ = regenerated
    wrong = differences(files, ROOT / "generated")
    assert not wrong, "generated/ is stale or edited by hand; run `cmake --build build --target generate`:\n" + \
        "\n".join(wrong)


def test_generated_files_carry_banner_and_no_timestamp(regenerated):
    files, _ = regenerated
    for name, text in files.items():
        if name.endswith(".cpp"):
            assert "do not edit" in text.splitlines()[0], name
            assert "templates/" in text.splitlines()[0], name
        assert not re.search(r"\b\d{4}-\d{2}-\d{2}\b|\d{2}:\d{2}:\d{2}", text), name  # no dates or times
        assert "pow(" not in text, name


def test_registry_covers_every_pair_and_refuses_with_reasons(regenerated):
    _, report = regenerated
    kernels = set(report.kernels)
    laws = {p.stem for p in (ROOT / "laws").glob("*.toml")}
    elements = {p.stem for p in (ROOT / "elements").glob("*.toml")}
    for law in laws:
        for element in elements:
            assert (law, element, "whole") in kernels
            assert (law, element, "terms") in kernels
    for law, element, split, why in report.refused:
        assert split == "tensor" and why
    for element in ("tri3", "quad4", "tet4", "hex8", "prism6", "pyramid5"):
        assert ("stvk", element, "tensor") in kernels
        assert ("hooke", element, "tensor") in kernels


def test_if_stale_needs_no_sympy(tmp_path):
    """An up-to-date tree is detected with the standard library alone."""
    code = ("import sys; sys.modules['sympy'] = None; sys.modules['jinja2'] = None; "
            "from generator.__main__ import main; sys.exit(main(['--if-stale']))")
    result = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert stale.is_current(ROOT, ROOT / "generated")


# --- input validation ------------------------------------------------------

def _copy_element(tmp_path: Path, name: str = "tet4") -> Path:
    target = tmp_path / f"{name}.toml"
    shutil.copy(ROOT / "elements" / f"{name}.toml", target)
    return target


@pytest.mark.parametrize("edit, key", [
    (lambda t: "surprise = 1\n" + t, "surprise"),
    (lambda t: t.replace('"1 - r - s - t"', '"1 - r - s - q"'), "shape_functions[0]"),
    (lambda t: t.replace('name = "tet4"', 'name = "tet5"'), "name"),
    (lambda t: t.replace('default_quadrature = "gauss1"', 'default_quadrature = "nope"'), "default_quadrature"),
    (lambda t: t.replace('weights = ["1/6"]', 'weights = [0.1666]'), "quadrature.gauss1.weights[0]"),
    (lambda t: t.replace("node_order = [0, 1, 2, 3]\n\n[vtk]", "node_order = [0, 1, 1, 3]\n\n[vtk]"), "gmsh.node_order"),
    (lambda t: t.replace("[1, 2, 3], [2, 0, 3]]", "[1, 2, 3], [2, 0, 7]]"), "faces[3]"),
])
def test_element_errors_name_file_and_key(tmp_path, edit, key):
    path = _copy_element(tmp_path)
    path.write_text(edit(path.read_text()))
    with pytest.raises(GeneratorInputError) as error:
        load_element(path)
    assert str(path) in str(error.value)
    assert f"'{key}'" in str(error.value)


def test_invalid_toml_names_file(tmp_path):
    path = tmp_path / "tet4.toml"
    path.write_text("name = \n")
    with pytest.raises(GeneratorInputError, match=str(path)):
        load_element(path)


def test_law_errors(tmp_path):
    path = tmp_path / "stvk.toml"
    text = (ROOT / "laws" / "stvk.toml").read_text()
    path.write_text(text.replace("tr(E*E)", "tr(Q*E)"))
    law = load_law(path)
    with pytest.raises(GeneratorInputError, match=r"energy.*unknown names \['Q'\]"):
        law_derivatives(law, 3)
    path.write_text(text.replace('mu = "young/(2*(1 + poisson))"', 'mu = "young/(2*(1 + nu))"'))
    with pytest.raises(GeneratorInputError, match="derived.mu"):
        load_law(path)


# --- laws: independent references -------------------------------------------

def test_stvk_stress_is_F_times_S():
    law = load_law(ROOT / "laws" / "stvk.toml")
    _, P, _ = law_derivatives(law, 3)
    H = gradient_symbols(3)
    values = [0.03, -0.02, 0.05, 0.01, 0.04, -0.03, 0.02, 0.06, -0.01]
    lam, mu = 2.0, 3.0
    F = sympy.eye(3) + sympy.Matrix(3, 3, values)
    E = (F.T * F - sympy.eye(3)) / 2
    S = lam * E.trace() * sympy.eye(3) + 2 * mu * E
    expected = F * S
    at = dict(zip(H, values)) | {sympy.Symbol("lam", real=True): lam, sympy.Symbol("mu", real=True): mu}
    for i in range(9):
        assert float(P[i].subs(at)) == pytest.approx(float(expected[i // 3, i % 3]), rel=1e-13)


def test_neohookean_stress_reference():
    law = load_law(ROOT / "laws" / "neohookean.toml")
    _, P, _ = law_derivatives(law, 3)
    values = [0.03, -0.02, 0.05, 0.01, 0.04, -0.03, 0.02, 0.06, -0.01]
    lam, mu = 2.0, 3.0
    F = sympy.eye(3) + sympy.Matrix(3, 3, values)
    J = F.det()
    expected = mu * (F - F.inv().T) + lam * sympy.log(J) * F.inv().T
    at = dict(zip(gradient_symbols(3), values)) | {sympy.Symbol("lam", real=True): lam,
                                                   sympy.Symbol("mu", real=True): mu}
    for i in range(9):
        assert float(P[i].subs(at)) == pytest.approx(float(expected[i // 3, i % 3]), rel=1e-12)


def test_tensor_split_refusals():
    neo = load_law(ROOT / "laws" / "neohookean.toml")
    with pytest.raises(GeneratorInputError, match="one strain measure"):
        strain_quadratic(neo, 3)
    stvk = load_law(ROOT / "laws" / "stvk.toml")
    hex8 = load_element(ROOT / "elements" / "hex8.toml")
    tet10 = load_element(ROOT / "elements" / "tet10.toml")
    optimised = optimise(derive(Inputs(elements=(hex8, tet10), laws=(stvk,))))
    with pytest.raises(SplitRefused, match="first-order"):
        build_kernel_ir(optimised, stvk, tet10, "tensor")
    with pytest.raises(SplitRefused, match="over the limit 100"):
        build_kernel_ir(optimised, stvk, hex8, "tensor", tensor_limit=100)
    assert build_kernel_ir(optimised, stvk, hex8, "tensor").consts_size > 2000


def test_elasticity_tensor_of_hooke_is_isotropic():
    hooke = load_law(ROOT / "laws" / "hooke.toml")
    quadratic = strain_quadratic(hooke, 3)
    lam, mu = sympy.Symbol("lam", real=True), sympy.Symbol("mu", real=True)
    delta = lambda i, j: 1 if i == j else 0  # noqa: E731
    for a in range(3):
        for b in range(3):
            for c in range(3):
                for d in range(3):
                    expected = lam * delta(a, b) * delta(c, d) + mu * (delta(a, c) * delta(b, d) + delta(a, d) * delta(b, c))
                    assert sympy.simplify(quadratic.elasticity[a][b][c][d] - expected) == 0


# --- printer and flops --------------------------------------------------------

def test_printer_never_uses_pow_for_integer_powers():
    x, y = sympy.symbols("x y", real=True)
    assert print_expr(x**3) == "(x*x*x)"
    assert print_expr(x**-2) == "(1.0/(x*x))"
    assert print_expr((x + y)**2) == "((x + y)*(x + y))"
    assert print_expr(sympy.Rational(1, 3) * x) == "(0.3333333333333333)*x"
    assert print_expr(sympy.Symbol("H3"), {"H3": "H[3]"}) == "H[3]"


def test_flop_count():
    x, y, z = sympy.symbols("x y z", real=True)
    assert count_flops(x + y + z) == 2
    assert count_flops(x * y * z) == 2
    assert count_flops(x**3) == 2
    assert count_flops(1 / x) == 1
    assert count_flops(sympy.log(x * y)) == 2
    assert count_flops(-x) == 1
