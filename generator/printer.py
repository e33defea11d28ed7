"""C++ expression printer: SymPy's C99 printer with the project's conventions.

- integer powers become products (x*x*x), negative ones a division; never pow()
- rationals and floats print as the shortest decimal that round-trips a
  double (byte-stable across machines; never integer division)
- symbols print through a name map (H3 -> H[3]) so templates own the storage
- a RationalRoot x^(+-1/q) prints as std::sqrt for q = 2, else as
  std::exp(e*std::log(x)) (vectorised in batched kernels, kernel_support.hpp)
"""
from __future__ import annotations

import sympy
from sympy.printing.c import C99CodePrinter


def double_literal(value: float) -> str:
    text = repr(float(value))
    if text in ("inf", "-inf", "nan"):
        raise ValueError(f"non-finite constant {text} in generated code")
    return text if any(c in text for c in ".e") else text + ".0"


class KernelPrinter(C99CodePrinter):
    def __init__(self, symbol_names: dict[str, str] | None = None):
        super().__init__()
        self._symbol_names = symbol_names or {}

    def _print_Symbol(self, expr):
        return self._symbol_names.get(expr.name, expr.name)

    def _print_Rational(self, expr):
        if expr.q == 1:
            return double_literal(expr.p)
        return double_literal(expr.p / expr.q)

    def _print_Integer(self, expr):
        return double_literal(int(expr))

    def _print_Float(self, expr):
        return double_literal(float(expr))

    def _print_Pow(self, expr):
        base, exponent = expr.args
        if exponent.is_Integer and exponent != 0:
            n = abs(int(exponent))
            factor = self.parenthesize(base, sympy.printing.precedence.PRECEDENCE["Mul"] + 1)
            product = "*".join([factor] * n)
            if exponent > 0:
                return product if n == 1 else f"({product})"
            return f"(1.0/({product}))"
        if exponent == sympy.Rational(1, 2):
            return f"std::sqrt({self._print(base)})"
        if exponent == -sympy.Rational(1, 2):
            return f"(1.0/std::sqrt({self._print(base)}))"
        return f"std::pow({self._print(base)}, {self._print(exponent)})"

    def _print_RationalRoot(self, expr):
        base, exponent = expr.args
        if exponent == sympy.Rational(1, 2):
            return f"std::sqrt({self._print(base)})"
        if exponent == -sympy.Rational(1, 2):
            return f"(1.0/std::sqrt({self._print(base)}))"
        return f"std::exp({self._print(exponent)}*std::log({self._print(base)}))"

    def _print_log(self, expr):
        return f"std::log({self._print(expr.args[0])})"

    def _print_exp(self, expr):
        return f"std::exp({self._print(expr.args[0])})"


def print_expr(expr: sympy.Expr, symbol_names: dict[str, str] | None = None) -> str:
    return KernelPrinter(symbol_names).doprint(expr)
