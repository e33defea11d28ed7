"""Stage 3 (optimise): common subexpression elimination and flop counting.

Input: `SymbolicIR` (stage 2).
Output: `OptimisedIR`: per law and dimension a `LawKernelIR`, the law at one
quadrature point as CSE'd straight-line `Block`s (energy, stress, weighted
stress, tangent) with their flop counts.

`eliminate` turns named SymPy outputs (target lvalue -> expression) into a
`Block` (temporaries first); the lower stage uses it for the split-specific
entries too. Fractional powers x^(p/q) (other than sqrt) become integer
powers of one root x^(1/q) or x^(-1/q) per base (`RationalRoot`), so J^(-2/3),
J^(-5/3), J^(-8/3) cost one exp and one log together. Flops: each +, -, *, /
counts 1; an integer power x^n counts n-1 multiplications (emitted as
products, never pow()); a negative power adds one division; each
transcendental call (log, exp, sqrt) counts 1, a root through exp and log 3.
"""
from __future__ import annotations

from typing import Optional

import sympy

from .model import Assignment, Block, LawDerivatives, LawKernelIR, OptimisedIR, RationalRoot, SymbolicIR

WEIGHT = sympy.Symbol("w", real=True)

# Auxiliary per-point quantities: the symbol prefix that marks their use, and
# the flops their support code executes (polar_decomposition.hpp): in 3D the
# rotation is counted at 6 scaled Newton iterations of 80 flops, typical for
# strains up to about 50 %; in 2D it is a closed form.
AUXILIARIES = (("rotation", "R"), ("rotation_inverse", "Y"))
AUXILIARY_FLOPS = {("rotation", 2): 12, ("rotation", 3): 6 * 80 + 9,
                   ("rotation_inverse", 2): 8, ("rotation_inverse", 3): 100}


def count_flops(expr: sympy.Expr) -> int:
    if expr.is_Atom:
        return 0
    if isinstance(expr, RationalRoot):
        base, exponent = expr.args
        cost = (1 + (1 if exponent < 0 else 0)) if exponent.q == 2 else 3
        return cost + count_flops(base)
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


def _auxiliaries(exprs: list[sympy.Expr], dim: int) -> tuple[tuple[str, ...], int]:
    """The auxiliary quantities the expressions read, and their flops."""
    names = {s.name for e in exprs for s in e.free_symbols}
    used = tuple(aux for aux, prefix in AUXILIARIES
                 if any(n.startswith(prefix) and n[len(prefix):].isdigit() for n in names))
    if "rotation_inverse" in used and "rotation" not in used:
        used = ("rotation",) + used  # Y is computed from R
    return used, sum(AUXILIARY_FLOPS[(aux, dim)] for aux in used)


def _fractional(exponent: sympy.Expr) -> bool:
    """A rational, non-integer exponent other than +-1/2 (which print as sqrt)."""
    return exponent.is_Rational and not exponent.is_Integer and abs(exponent) != sympy.Rational(1, 2)


def _rational_roots(assignments: list[Assignment], prefix: str) -> list[Assignment]:
    """x^(p/q) -> r^n with one temporary r = x^(+-1/q) per (x, q), declared
    before the first assignment that reads it (its sign that of the first power met)."""
    roots: dict[tuple[sympy.Expr, int], tuple[sympy.Symbol, int]] = {}
    result: list[Assignment] = []

    def rewrite(expr: sympy.Expr) -> sympy.Expr:
        if expr.is_Atom:
            return expr
        args = tuple(rewrite(a) for a in expr.args)
        if isinstance(expr, sympy.Pow) and _fractional(expr.exp):
            base, exponent = args[0], expr.exp
            key = (base, exponent.q)
            if key not in roots:
                sign = 1 if exponent > 0 else -1
                root = sympy.Symbol(f"{prefix}r{len(roots)}", real=True)
                roots[key] = (root, sign)
                result.append(Assignment(root.name, RationalRoot(base, sympy.Rational(sign, exponent.q)), declare=True))
            root, sign = roots[key]
            return root ** (exponent.p * sign)
        return expr.func(*args) if args != expr.args else expr

    for a in assignments:
        expr = rewrite(a.expr) if any(_fractional(p.exp) for p in a.expr.atoms(sympy.Pow)) else a.expr
        result.append(Assignment(a.target, expr, a.declare))
    return result


def eliminate(outputs: list[tuple[str, sympy.Expr]], prefix: str, dim: int = 0) -> Block:
    """CSE over all outputs; temporaries are named prefix0, prefix1, ..., roots prefixr0, ...

    dim: the space dimension, needed when the outputs read auxiliaries (R.., Y..)."""
    exprs = [expr for _, expr in outputs]
    replacements, reduced = sympy.cse(exprs, symbols=sympy.numbered_symbols(prefix, real=True), order="canonical")
    assignments = [Assignment(str(symbol), value, declare=True) for symbol, value in replacements]
    assignments += [Assignment(target, expr) for (target, _), expr in zip(outputs, reduced)]
    assignments = _rational_roots(assignments, prefix)
    auxiliaries, auxiliary_flops = _auxiliaries(exprs, dim) if dim else ((), 0)
    return Block(tuple(assignments), sum(count_flops(a.expr) for a in assignments) + auxiliary_flops, auxiliaries)


def _tangent_fill(tangent_map: tuple[tuple[Optional[str], ...], ...]) -> tuple[tuple[int, Optional[str]], ...]:
    """Entries of the full wA array that the tangent block leaves unassigned."""
    d2 = len(tangent_map)
    fills = []
    for i in range(d2):
        for j in range(d2):
            flat = i * d2 + j
            source = tangent_map[i][j]
            if source != f"wA[{flat}]":
                fills.append((flat, source))
    return tuple(fills)


def _test_point(exprs: list[sympy.Expr]) -> dict:
    """Values of the expressions' symbols at which equal polynomials agree and distinct ones almost surely differ."""
    symbols = sorted({s for e in exprs for s in e.free_symbols} | {WEIGHT}, key=lambda s: s.name)
    return {s: sympy.Float(sympy.Rational(7 * k + 3, 11 * k + 13) + sympy.Rational(1, 997), 40)
            for k, s in enumerate(symbols)}


def _fingerprint(expr: sympy.Expr, point: dict) -> sympy.Float:
    return sympy.Float(expr.xreplace(point), 30)


def _equal(a: sympy.Expr, b: sympy.Expr, fa, fb, polynomial: bool) -> bool:
    """a == b as expressions: structurally, or for polynomials expanded (tried only where their values
    at the test point agree, so that distinct entries cost no expansion)."""
    if a == b:
        return True
    if not polynomial or fb is None or abs(fa - fb) > 1e-20 * (1 + abs(fa)):
        return False
    return sympy.expand(a - b) == 0


def _pruned(block: Block, keep, dim: int) -> Block:
    """The block's outputs whose target keep() accepts, with only the temporaries they read."""
    needed: set[str] = set()
    kept = []
    for a in reversed(block.assignments):
        if (a.declare and a.target in needed) or (not a.declare and keep(a.target)):
            kept.append(a)
            needed.update(s.name for s in a.expr.free_symbols)
    kept.reverse()
    auxiliaries, auxiliary_flops = _auxiliaries([a.expr for a in kept], dim)
    return Block(tuple(kept), sum(count_flops(a.expr) for a in kept) + auxiliary_flops, auxiliaries)


def build_law_ir(derivatives: LawDerivatives) -> LawKernelIR:
    """The law's blocks at one point; symmetric or repeated tangent entries are computed once."""
    psi, P, A = derivatives.energy, derivatives.stress, derivatives.tangent
    d2 = derivatives.dim ** 2
    dim = derivatives.dim
    energy = eliminate([("psi", WEIGHT * psi)], "e", dim)
    stress = eliminate([(f"P[{i}]", p) for i, p in enumerate(P)], "s", dim)
    weighted = [(f"wP[{i}]", WEIGHT * p) for i, p in enumerate(P)]
    weighted_stress = eliminate(weighted, "s", dim)
    outputs, canonical, tangent_map = list(weighted), [], [[None] * d2 for _ in range(d2)]
    point = _test_point([A[i][j] for i in range(d2) for j in range(i, d2)])
    for i in range(d2):
        for j in range(i, d2):
            entry = WEIGHT * A[i][j]
            polynomial = A[i][j].is_polynomial()
            if A[i][j] == 0 or (polynomial and _fingerprint(entry, point) == 0 and sympy.expand(entry) == 0):
                continue
            fingerprint = _fingerprint(entry, point) if polynomial else None
            name = next((n for e, f, n in canonical if _equal(entry, e, fingerprint, f, polynomial)), None)
            if name is None:
                name = f"wA[{i * d2 + j}]"
                canonical.append((entry, fingerprint, name))
                outputs.append((name, entry))
            tangent_map[i][j] = tangent_map[j][i] = name
    tangent = eliminate(outputs, "a", dim)
    tangent_only = _pruned(tangent, lambda target: target.startswith("wA["), dim)
    tangent_map = tuple(tuple(row) for row in tangent_map)
    return LawKernelIR(law=derivatives.law.name, dim=derivatives.dim, energy=energy, stress=stress,
                       weighted_stress=weighted_stress, tangent=tangent, tangent_only=tangent_only,
                       tangent_map=tangent_map, tangent_fill=_tangent_fill(tangent_map))


def optimise(symbolic: SymbolicIR) -> OptimisedIR:
    """Stage 3: the optimised law blocks of every law in every element dimension."""
    return OptimisedIR(symbolic=symbolic, laws=tuple(build_law_ir(d) for d in symbolic.derivatives))
