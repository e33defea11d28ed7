"""Stage 3 (optimise): flop counting, CSE'd law blocks and their tangent map."""
from __future__ import annotations

import sympy

from conftest import ROOT
from generator.load import load_element, load_law
from generator.model import Inputs, LawKernelIR, OptimisedIR
from generator.optimize import build_law_ir, count_flops, eliminate, optimise
from generator.symbolic import derive, derive_law


def test_flop_count():
    x, y, z = sympy.symbols("x y z", real=True)
    assert count_flops(x + y + z) == 2
    assert count_flops(x * y * z) == 2
    assert count_flops(x**3) == 2
    assert count_flops(1 / x) == 1
    assert count_flops(sympy.log(x * y)) == 2
    assert count_flops(-x) == 1


def test_eliminate_shares_subexpressions_and_counts_their_flops():
    x, y = sympy.symbols("x y", real=True)
    block = eliminate([("a", (x + y) ** 2), ("b", (x + y) * x)], "t")
    assert [a.target for a in block.assignments] == ["t0", "a", "b"]
    assert block.assignments[0].declare and not block.assignments[1].declare
    assert block.flops == 1 + 1 + 1  # x + y once, then one product each


def test_law_ir_tangent_map_is_symmetric_and_fill_completes_it():
    law_ir = build_law_ir(derive_law(load_law(ROOT / "laws" / "stvk.toml"), 2))
    d2 = 4
    assigned = {a.target for a in law_ir.tangent.assignments if a.target.startswith("wA[")}
    for i in range(d2):
        for j in range(d2):
            assert law_ir.tangent_map[i][j] == law_ir.tangent_map[j][i]
    filled = {index for index, _ in law_ir.tangent_fill}
    for flat in range(d2 * d2):
        assert (f"wA[{flat}]" in assigned) != (flat in filled), flat
    for index, source in law_ir.tangent_fill:
        assert source is None or source in assigned


def test_optimise_gives_one_law_ir_per_law_and_dimension():
    inputs = Inputs(elements=(load_element(ROOT / "elements" / "tri3.toml"),),
                    laws=(load_law(ROOT / "laws" / "hooke.toml"),))
    optimised = optimise(derive(inputs))
    assert isinstance(optimised, OptimisedIR)
    law_ir = optimised.law_ir(inputs.laws[0], 2)
    assert isinstance(law_ir, LawKernelIR) and law_ir.law == "hooke" and law_ir.dim == 2
    assert len(optimised.laws) == 1


def test_fractional_powers_share_one_root_per_base():
    """x^(-2/3), x^(-5/3) and x^(1/3) read one root r = x^(-1/3) (the sign of the first power met)."""
    from generator.model import RationalRoot
    from generator.printer import print_expr
    x, y = sympy.symbols("x y", real=True)
    block = eliminate([("a", (x + y) ** sympy.Rational(-2, 3) * y), ("b", (x + y) ** sympy.Rational(-5, 3)),
                       ("c", (x + y) ** sympy.Rational(1, 3))], "t")
    roots = [a for a in block.assignments if isinstance(a.expr, RationalRoot)]
    assert len(roots) == 1 and roots[0].declare and roots[0].expr.args[1] == sympy.Rational(-1, 3)
    code = " ".join(print_expr(a.expr) for a in block.assignments)
    assert "pow(" not in code and code.count("std::log(") == 1 and code.count("std::exp(") == 1
    r = sympy.Symbol(roots[0].target, real=True)
    outputs = {a.target: a.expr for a in block.assignments if not a.declare}
    assert outputs["b"] == r ** 5 and outputs["c"] == 1 / r
    assert count_flops(roots[0].expr) == 3  # exp, multiply, log of the temporary t0 = x + y


def test_batched_kernels_allow_log_exp_and_roots_but_not_sqrt():
    from generator.model import RationalRoot
    from generator.splits.whole import _vector_call
    x = sympy.Symbol("x", real=True)
    assert _vector_call(sympy.log(x)) and _vector_call(sympy.exp(x))
    assert _vector_call(RationalRoot(x, sympy.Rational(-1, 3)))
    assert not _vector_call(RationalRoot(x, sympy.Rational(1, 2)))
    assert not _vector_call(sympy.sin(x))
