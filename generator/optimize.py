"""Stage 3 (optimise): common subexpression elimination and flop counting.

Input: named SymPy outputs (target lvalue -> expression).
Output: a `Block` of straight-line assignments (temporaries first) and its
flop count: each +, -, *, / counts 1; an integer power x^n counts n-1
multiplications (emitted as products, never pow()); a negative power adds one
division; each transcendental call (log, exp, sqrt) counts 1.
"""
from __future__ import annotations

import sympy

from .model import Assignment, Block


def count_flops(expr: sympy.Expr) -> int:
    if expr.is_Atom:
        return 0
    if isinstance(expr, sympy.Add):
        return len(expr.args) - 1 + sum(count_flops(a) for a in expr.args)
    if isinstance(expr, sympy.Mul):
        factors = [a for a in expr.args if a not in (sympy.S.NegativeOne,)]
        numeric_sign_only = len(factors) < len(expr.args)
        ops = max(len(factors) - 1, 0)
        if numeric_sign_only and len(factors) == 1:
            ops = 1  # a negation
        return ops + sum(count_flops(a) for a in factors)
    if isinstance(expr, sympy.Pow):
        base, exponent = expr.args
        inner = count_flops(base)
        if exponent.is_Integer:
            n = abs(int(exponent))
            return inner + max(n - 1, 0) + (1 if exponent < 0 else 0)
        if exponent == sympy.Rational(1, 2) or exponent == -sympy.Rational(1, 2):
            return inner + 1 + (1 if exponent < 0 else 0)
        return inner + 1 + count_flops(exponent)
    # functions: one flop for the call plus the arguments
    return 1 + sum(count_flops(a) for a in expr.args)


def eliminate(outputs: list[tuple[str, sympy.Expr]], prefix: str) -> Block:
    """CSE over all outputs; temporaries are named prefix0, prefix1, ..."""
    exprs = [expr for _, expr in outputs]
    replacements, reduced = sympy.cse(exprs, symbols=sympy.numbered_symbols(prefix, real=True), order="canonical")
    assignments = [Assignment(str(symbol), value, declare=True) for symbol, value in replacements]
    assignments += [Assignment(target, expr) for (target, _), expr in zip(outputs, reduced)]
    return Block(tuple(assignments), sum(count_flops(a.expr) for a in assignments))
