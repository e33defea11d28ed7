"""Validation of the reference-element descriptions ``elements/*.toml``.

Every TOML file found in ``elements/`` is checked on its own, with tomllib and
SymPy only (the project's generator package is deliberately not imported, so
that these tests are an independent check of the data it consumes):

* structure: exactly the allowed keys, name == file stem, consistent counts,
  node_order tables are permutations;
* shape functions: partition of unity, Kronecker property (limit along the
  line towards the element centroid where a rational shape function is 0/0,
  e.g. the pyramid apex), derivatives summing to zero, reference map equal to
  the identity (Jacobian = I), reproduction of linear (and, for quadratic
  elements, quadratic) polynomials;
* quadrature: weights sum to the reference volume, every monomial up to the
  stated degree is integrated exactly (compared to the exact integral over
  the reference domain, relative 1e-13), points strictly inside;
* topology: edges and faces use valid indices, faces are oriented outwards
  (right-hand rule), every edge is shared by two faces with opposite
  directions, the faces' edges are exactly the edges, mid-edge nodes sit at
  the middle of their edges;
* format orderings (Gmsh, VTK, CalculiX): mapping the format's own reference
  node coordinates through node_order must be an orientation-preserving
  affine map onto the tensormass reference nodes.
"""

from __future__ import annotations

import functools
import itertools
import math
import pathlib
import re
import tomllib

import mpmath
import pytest
import sympy as sp

ROOT = pathlib.Path(__file__).resolve().parents[2]
ELEMENT_DIR = ROOT / "elements"
FILES = sorted(ELEMENT_DIR.glob("*.toml"))
IDS = [p.stem for p in FILES]

R, S, T = sp.symbols("r s t", real=True)
ALL_VARS = (R, S, T)
LOCALS = {"r": R, "s": S, "t": T}

TOP_KEYS = {
    "name", "description", "dim", "order", "nodes", "shape_functions",
    "edges", "faces", "reference_volume", "default_quadrature", "quadrature",
    "gmsh", "vtk", "calculix",
}
OPTIONAL_KEYS = {"faces", "calculix"}
RULE_KEYS = {"degree", "points", "weights"}
FORMAT_KEYS = {"type", "node_order"}

EXPECTED_ELEMENTS = {
    "tri3", "tri6", "quad4", "quad8", "tet4", "tet10", "hex8", "hex20",
    "prism6", "pyramid5",
}

REL_TOL = mpmath.mpf("1e-13")
DPS = 40


# --------------------------------------------------------------------------
# Reference coordinates of the external formats, in each format's own node
# order.  Each is a positively oriented element in the format's convention.
# --------------------------------------------------------------------------
def _with_midpoints(corners, *entities):
    """Corners, then one node at the centroid of each listed edge, face or
    cell (lists of corner indices), in the order given."""
    pts = [tuple(sp.Rational(c) for c in p) for p in corners]
    for entity in (e for group in entities for e in group):
        pts.append(tuple(sum(pts[j][i] for j in entity) / len(entity) for i in range(len(pts[0]))))
    return pts


_TRI_C = [(0, 0), (1, 0), (0, 1)]
_TRI_E = [(0, 1), (1, 2), (2, 0)]
_QUAD_C = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
_QUAD_E = [(0, 1), (1, 2), (2, 3), (3, 0)]
_TET_C = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
_HEX_C = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
          (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
# VTK / CalculiX hex20 mid-edge order (vtkQuadraticHexahedron, shape20h.f).
_HEX_E_VTK = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
              (0, 4), (1, 5), (2, 6), (3, 7)]
# VTK / CalculiX tet10 mid-edge order (vtkQuadraticTetra, shape10tet.f).
_TET_E_VTK = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
# Gmsh orders (MElement.h edge lists; Gmsh manual "Node ordering").
_TET_E_GMSH = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]
_HEX_E_GMSH = [(0, 1), (0, 3), (0, 4), (1, 2), (1, 5), (2, 3), (2, 6), (3, 7),
               (4, 5), (4, 7), (5, 6), (6, 7)]
# Gmsh / CalculiX prism: triangle 0,1,2 has its normal towards 3,4,5.
_PRISM_C_GMSH = [(0, 0, -1), (1, 0, -1), (0, 1, -1), (0, 0, 1), (1, 0, 1), (0, 1, 1)]
# VTK wedge: triangle 0,1,2 has its normal pointing away from 3,4,5
# (vtkWedge.h); ParaView gives such a cell a positive volume.
_WEDGE_C_VTK = [(0, 0, 0), (0, 1, 0), (1, 0, 0), (0, 0, 1), (0, 1, 1), (1, 0, 1)]
_PYR_C = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0), (0, 0, 1)]
_PYR_C_VTK = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), ("1/2", "1/2", 1)]
_QUAD_CENTRE = [(0, 1, 2, 3)]
_HEX_CENTRE = [tuple(range(8))]
# VTK biquadratic / triquadratic face-centre order (vtkTriQuadraticHexahedron).
_HEX_F_VTK = [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)]
# Gmsh hexahedron faces (MHexahedron::getFace), the order of its face nodes.
_HEX_F_GMSH = [(0, 3, 2, 1), (0, 1, 5, 4), (0, 4, 7, 3), (1, 2, 6, 5), (2, 3, 7, 6), (4, 5, 6, 7)]
# Wedge / prism mid-edge orders: VTK (vtkQuadraticWedge) and CalculiX
# (shape15w.f) list the edges of the two triangles, then the vertical ones;
# Gmsh (MPrism) lists them by first corner.
_WEDGE_E_VTK = [(0, 1), (1, 2), (2, 0), (3, 4), (4, 5), (5, 3), (0, 3), (1, 4), (2, 5)]
_PRISM_E_GMSH = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 4), (2, 5), (3, 4), (3, 5), (4, 5)]
# Pyramid mid-edge orders: VTK (vtkQuadraticPyramid) and Gmsh (MPyramid).
_PYR_E_VTK = [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (1, 4), (2, 4), (3, 4)]
_PYR_E_GMSH = [(0, 1), (0, 3), (0, 4), (1, 2), (1, 4), (2, 3), (2, 4), (3, 4)]

GMSH_REF = {
    2: _with_midpoints(_TRI_C, []),
    9: _with_midpoints(_TRI_C, _TRI_E),
    3: _with_midpoints(_QUAD_C, []),
    16: _with_midpoints(_QUAD_C, _QUAD_E),
    4: _with_midpoints(_TET_C, []),
    11: _with_midpoints(_TET_C, _TET_E_GMSH),
    5: _with_midpoints(_HEX_C, []),
    17: _with_midpoints(_HEX_C, _HEX_E_GMSH),
    6: _with_midpoints(_PRISM_C_GMSH, []),
    7: _with_midpoints(_PYR_C, []),
    10: _with_midpoints(_QUAD_C, _QUAD_E, _QUAD_CENTRE),
    12: _with_midpoints(_HEX_C, _HEX_E_GMSH, _HEX_F_GMSH, _HEX_CENTRE),
    18: _with_midpoints(_PRISM_C_GMSH, _PRISM_E_GMSH),
    19: _with_midpoints(_PYR_C, _PYR_E_GMSH),
}
VTK_REF = {
    5: _with_midpoints(_TRI_C, []),
    22: _with_midpoints(_TRI_C, _TRI_E),
    9: _with_midpoints([(0, 0), (1, 0), (1, 1), (0, 1)], []),
    23: _with_midpoints([(0, 0), (1, 0), (1, 1), (0, 1)], _QUAD_E),
    10: _with_midpoints(_TET_C, []),
    24: _with_midpoints(_TET_C, _TET_E_VTK),
    12: _with_midpoints(_HEX_C, []),
    25: _with_midpoints(_HEX_C, _HEX_E_VTK),
    13: _with_midpoints(_WEDGE_C_VTK, []),
    14: _with_midpoints(_PYR_C_VTK, []),
    28: _with_midpoints([(0, 0), (1, 0), (1, 1), (0, 1)], _QUAD_E, _QUAD_CENTRE),
    29: _with_midpoints(_HEX_C, _HEX_E_VTK, _HEX_F_VTK, _HEX_CENTRE),
    26: _with_midpoints(_WEDGE_C_VTK, _WEDGE_E_VTK),
    27: _with_midpoints(_PYR_C_VTK, _PYR_E_VTK),
}
CALCULIX_REF = {
    "CPE3": _with_midpoints(_TRI_C, []),
    "CPE6": _with_midpoints(_TRI_C, _TRI_E),
    "CPE4": _with_midpoints(_QUAD_C, []),
    "CPE8": _with_midpoints(_QUAD_C, _QUAD_E),
    "C3D4": _with_midpoints(_TET_C, []),
    "C3D10": _with_midpoints(_TET_C, _TET_E_VTK),
    "C3D8": _with_midpoints(_HEX_C, []),
    "C3D20": _with_midpoints(_HEX_C, _HEX_E_VTK),
    "C3D6": _with_midpoints(_PRISM_C_GMSH, []),
    "C3D15": _with_midpoints(_PRISM_C_GMSH, _WEDGE_E_VTK),
}
FORMAT_REF = {"gmsh": GMSH_REF, "vtk": VTK_REF, "calculix": CALCULIX_REF}
# Format element types whose node order must differ from tensormass (= VTK).
NON_IDENTITY = {("gmsh", 11), ("gmsh", 17), ("gmsh", 6), ("gmsh", 12), ("gmsh", 18), ("gmsh", 19),
                ("calculix", "C3D6"), ("calculix", "C3D15")}


# --------------------------------------------------------------------------
# Loading
# --------------------------------------------------------------------------
def parse(value):
    """Exact SymPy value of a TOML number or string."""
    if isinstance(value, bool):
        raise TypeError("boolean where a number was expected")
    if isinstance(value, int):
        return sp.Integer(value)
    if isinstance(value, float):
        raise TypeError("write %r as an exact string (TOML floats lose digits)" % value)
    return sp.sympify(value, locals=LOCALS, rational=True)


class Element:
    def __init__(self, path: pathlib.Path):
        self.path = path
        with open(path, "rb") as fh:
            self.data = tomllib.load(fh)
        d = self.data
        self.dim = d["dim"]
        self.vars = ALL_VARS[: self.dim]
        self.nodes = [tuple(parse(c) for c in p) for p in d["nodes"]]
        self.n = len(self.nodes)
        self.N = [parse(f) for f in d["shape_functions"]]
        self.order = d["order"]
        self.edges = [list(e) for e in d["edges"]]
        self.faces = [list(f) for f in d.get("faces", [])]
        if self.order == 1:
            self.corner_ids = list(range(self.n))
        else:
            self.corner_ids = sorted({i for e in self.edges for i in e[:2]})
        self.corners = [self.nodes[i] for i in self.corner_ids]
        self.centroid = tuple(sum(c[k] for c in self.corners) / len(self.corners)
                              for k in range(self.dim))
        self.volume = parse(d["reference_volume"])
        self.domain = classify_domain(self.dim, self.corners)


@functools.lru_cache(maxsize=None)
def load(path: pathlib.Path) -> Element:
    return Element(path)


@functools.lru_cache(maxsize=None)
def raw(path: pathlib.Path) -> dict:
    with open(path, "rb") as fh:
        return tomllib.load(fh)


# --------------------------------------------------------------------------
# Reference domains and exact integration
# --------------------------------------------------------------------------
def classify_domain(dim, corners):
    nc = len(corners)
    if nc == dim + 1:
        return ("simplex", corners)
    if (dim, nc) in ((2, 4), (3, 8)):
        lo = [min(c[k] for c in corners) for k in range(dim)]
        hi = [max(c[k] for c in corners) for k in range(dim)]
        assert set(corners) == set(itertools.product(*zip(lo, hi))), \
            "quadrilateral/hexahedron reference corners must be an axis-aligned box"
        return ("box", lo, hi)
    if (dim, nc) == (3, 6):
        t0 = min(c[2] for c in corners)
        t1 = max(c[2] for c in corners)
        bottom = [c[:2] for c in corners if c[2] == t0]
        top = [c[:2] for c in corners if c[2] == t1]
        assert len(bottom) == 3 and sorted(bottom) == sorted(top), \
            "prism reference element must be a right prism along t"
        return ("prism", bottom, t0, t1)
    if (dim, nc) == (3, 5):
        t0 = min(c[2] for c in corners)
        base = [c for c in corners if c[2] == t0]
        apex = [c for c in corners if c[2] != t0]
        assert len(base) == 4 and len(apex) == 1
        apex = apex[0]
        xs = sorted({c[0] for c in base})
        ys = sorted({c[1] for c in base})
        assert len(xs) == 2 and len(ys) == 2 and xs[1] - xs[0] == ys[1] - ys[0]
        h = (xs[1] - xs[0]) / 2
        cx, cy = (xs[0] + xs[1]) / 2, (ys[0] + ys[1]) / 2
        assert (apex[0], apex[1]) == (cx, cy) and apex[2] > t0, \
            "pyramid apex must lie above the centre of its square base"
        return ("pyramid", cx, cy, h, t0, apex[2] - t0)
    raise AssertionError("unknown reference shape: dim %d with %d corners" % (dim, nc))


def _integrate_simplex_poly(expr, lam):
    """Integral over the unit simplex in the variables lam of a polynomial."""
    d = len(lam)
    total = sp.Integer(0)
    for monom, coeff in sp.Poly(sp.expand(expr), *lam).terms():
        num = math.prod(math.factorial(a) for a in monom)
        total += coeff * sp.Rational(num, math.factorial(sum(monom) + d))
    return total


def _integrate_box_poly(expr, variables, bounds):
    total = sp.Integer(0)
    for monom, coeff in sp.Poly(sp.expand(expr), *variables).terms():
        term = coeff
        for a, (lo, hi) in zip(monom, bounds):
            term *= (sp.Integer(hi) ** (a + 1) - sp.Integer(lo) ** (a + 1)) / (a + 1)
        total += term
    return total


def exact_integral(el: Element, expr):
    """Exact integral of a polynomial in r, s(, t) over the reference domain."""
    kind = el.domain[0]
    x = el.vars
    if kind == "simplex":
        v = el.domain[1]
        lam = sp.symbols("l0:%d" % el.dim)
        A = sp.Matrix([[v[j + 1][i] - v[0][i] for j in range(el.dim)] for i in range(el.dim)])
        sub = {x[i]: v[0][i] + sum(A[i, j] * lam[j] for j in range(el.dim)) for i in range(el.dim)}
        return abs(A.det()) * _integrate_simplex_poly(expr.subs(sub, simultaneous=True), lam)
    if kind == "box":
        _, lo, hi = el.domain
        return _integrate_box_poly(expr, x, list(zip(lo, hi)))
    if kind == "prism":
        _, tri, t0, t1 = el.domain
        l0, l1, tau = sp.symbols("l0 l1 tau")
        A = sp.Matrix([[tri[1][0] - tri[0][0], tri[2][0] - tri[0][0]],
                       [tri[1][1] - tri[0][1], tri[2][1] - tri[0][1]]])
        sub = {R: tri[0][0] + A[0, 0] * l0 + A[0, 1] * l1,
               S: tri[0][1] + A[1, 0] * l0 + A[1, 1] * l1,
               T: t0 + (t1 - t0) * tau}
        g = sp.expand(expr.subs(sub, simultaneous=True))
        total = sp.Integer(0)
        for (a, b, c), coeff in sp.Poly(g, l0, l1, tau).terms():
            total += coeff * sp.Rational(math.factorial(a) * math.factorial(b),
                                         math.factorial(a + b + 2)) / (c + 1)
        return abs(A.det()) * (t1 - t0) * total
    if kind == "pyramid":
        _, cx, cy, h, t0, H = el.domain
        a, b, tau = sp.symbols("a b tau")
        sub = {R: cx + h * a * (1 - tau), S: cy + h * b * (1 - tau), T: t0 + H * tau}
        jac = h ** 2 * H * (1 - tau) ** 2
        return _integrate_box_poly(expr.subs(sub, simultaneous=True) * jac,
                                   (a, b, tau), [(-1, 1), (-1, 1), (0, 1)])
    raise AssertionError(kind)


def strictly_inside(el: Element, p, eps=mpmath.mpf("1e-14")):
    kind = el.domain[0]
    if kind == "simplex":
        v = [[mpmath.mpf(sp.Float(c, DPS)) for c in q] for q in el.domain[1]]
        A = mpmath.matrix([[v[j + 1][i] - v[0][i] for j in range(el.dim)] for i in range(el.dim)])
        lam = mpmath.lu_solve(A, mpmath.matrix([p[i] - v[0][i] for i in range(el.dim)]))
        bary = [1 - sum(lam)] + [lam[i] for i in range(el.dim)]
        return all(x > eps for x in bary)
    if kind == "box":
        _, lo, hi = el.domain
        return all(lo[i] + eps < p[i] < hi[i] - eps for i in range(el.dim))
    if kind == "prism":
        _, tri, t0, t1 = el.domain
        v = [[mpmath.mpf(sp.Float(c, DPS)) for c in q] for q in tri]
        A = mpmath.matrix([[v[1][0] - v[0][0], v[2][0] - v[0][0]],
                           [v[1][1] - v[0][1], v[2][1] - v[0][1]]])
        lam = mpmath.lu_solve(A, mpmath.matrix([p[0] - v[0][0], p[1] - v[0][1]]))
        bary = [1 - lam[0] - lam[1], lam[0], lam[1]]
        return all(x > eps for x in bary) and t0 + eps < p[2] < t1 - eps
    if kind == "pyramid":
        _, cx, cy, h, t0, H = el.domain
        tau = (p[2] - t0) / H
        half = h * (1 - tau)
        return (eps < tau < 1 - eps and abs(p[0] - cx) < half - eps
                and abs(p[1] - cy) < half - eps)
    raise AssertionError(kind)


def monomials(variables, degree):
    for exps in itertools.product(range(degree + 1), repeat=len(variables)):
        if sum(exps) <= degree:
            yield exps, sp.Mul(*[v ** e for v, e in zip(variables, exps)])


def is_zero(expr) -> bool:
    return sp.cancel(sp.together(sp.expand(expr))) == 0


def value_at_node(expr, el: Element, j: int):
    """expr at node j; where it is a 0/0 form, its limit along the line from
    the node towards the element centroid."""
    sub = dict(zip(el.vars, el.nodes[j]))
    val = expr.subs(sub, simultaneous=True)
    if val.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        h = sp.symbols("h", positive=True)
        path = {x: el.nodes[j][i] + h * (el.centroid[i] - el.nodes[j][i])
                for i, x in enumerate(el.vars)}
        val = sp.limit(sp.cancel(expr.subs(path, simultaneous=True)), h, 0, "+")
    return sp.nsimplify(val)


# --------------------------------------------------------------------------
# Tests
# --------------------------------------------------------------------------
def test_elements_found():
    assert FILES, "no elements/*.toml found"
    assert EXPECTED_ELEMENTS <= set(IDS), "missing: %s" % (EXPECTED_ELEMENTS - set(IDS))


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_keys_and_counts(path):
    d = raw(path)
    keys = set(d)
    assert keys <= TOP_KEYS, "unknown keys %s" % (keys - TOP_KEYS)
    missing = (TOP_KEYS - OPTIONAL_KEYS) - keys
    assert not missing, "missing keys %s" % missing
    assert d["name"] == path.stem
    assert isinstance(d["description"], str) and d["description"].strip()
    assert d["dim"] in (2, 3)
    assert d["order"] in (1, 2)
    if d["dim"] == 3:
        assert "faces" in d, "3D elements need faces"
    else:
        assert "faces" not in d, "2D elements have no faces"

    n = len(d["nodes"])
    assert n >= d["dim"] + 1
    for p in d["nodes"]:
        assert len(p) == d["dim"]
        for c in p:
            assert isinstance(c, (int, str)) and not isinstance(c, bool)
    assert len(set(tuple(parse(c) for c in p) for p in d["nodes"])) == n, "duplicate nodes"
    assert len(d["shape_functions"]) == n
    assert all(isinstance(f, str) for f in d["shape_functions"])
    assert isinstance(d["reference_volume"], str)

    q = d["quadrature"]
    assert isinstance(q, dict) and q
    assert d["default_quadrature"] in q
    assert next(iter(q)) == d["default_quadrature"], "the default rule must come first"
    for name, rule in q.items():
        assert set(rule) == RULE_KEYS, "rule %s: keys %s" % (name, set(rule))
        assert isinstance(rule["degree"], int) and rule["degree"] >= 1
        assert len(rule["points"]) == len(rule["weights"]) >= 1
        for p in rule["points"]:
            assert len(p) == d["dim"]
            assert all(isinstance(c, (int, str)) and not isinstance(c, bool) for c in p), \
                "rule %s: coordinates must be integers or exact strings" % name
        assert all(isinstance(w, (int, str)) and not isinstance(w, bool) for w in rule["weights"]), \
            "rule %s: weights must be integers or exact strings" % name

    for fmt in ("gmsh", "vtk", "calculix"):
        if fmt not in d:
            continue
        tab = d[fmt]
        assert set(tab) == FORMAT_KEYS, "[%s] keys %s" % (fmt, set(tab))
        if fmt == "calculix":
            assert isinstance(tab["type"], str)
        else:
            assert isinstance(tab["type"], int) and not isinstance(tab["type"], bool)
        assert sorted(tab["node_order"]) == list(range(n)), \
            "[%s] node_order is not a permutation of range(%d)" % (fmt, n)
    # tensormass node order is the VTK node order
    assert d["vtk"]["node_order"] == list(range(n))


_DECIMAL = re.compile(r"(?<![\w.])(\d*\.\d+(?:[eE][-+]?\d+)?|\d+\.\d*(?:[eE][-+]?\d+)?)")


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_decimal_literals_are_precise(path):
    """Decimal (non-exact) numbers must carry at least 20 significant digits."""
    d = raw(path)
    strings = [c for p in d["nodes"] for c in p if isinstance(c, str)]
    strings += list(d["shape_functions"]) + [d["reference_volume"]]
    for rule in d["quadrature"].values():
        strings += [c for p in rule["points"] for c in p if isinstance(c, str)]
        strings += [w for w in rule["weights"] if isinstance(w, str)]
    for s in strings:
        for lit in _DECIMAL.findall(s):
            mant = re.split(r"[eE]", lit)[0].replace(".", "").lstrip("0")
            assert len(mant) >= 20 or set(mant) <= {"0"}, \
                "decimal literal %r has fewer than 20 significant digits" % lit


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_shape_function_symbols(path):
    el = load(path)
    for f in el.N:
        assert f.free_symbols <= set(el.vars), "unexpected symbols in %s" % f


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_partition_of_unity(path):
    el = load(path)
    assert is_zero(sum(el.N) - 1)


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_derivatives_sum_to_zero(path):
    el = load(path)
    for x in el.vars:
        assert is_zero(sum(sp.diff(f, x) for f in el.N)), "sum of dN/d%s != 0" % x


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_kronecker_property(path):
    el = load(path)
    for i, f in enumerate(el.N):
        for j in range(el.n):
            v = value_at_node(f, el, j)
            assert v == (1 if i == j else 0), "N_%d(node %d) = %s" % (i, j, v)


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_reference_map_is_identity(path):
    """x(xi) = sum_i N_i(xi) X_i with the reference nodes themselves is the
    identity, so its Jacobian is the (positive) identity matrix."""
    el = load(path)
    x_of_xi = [sum(f * p[k] for f, p in zip(el.N, el.nodes)) for k in range(el.dim)]
    for k in range(el.dim):
        assert is_zero(x_of_xi[k] - el.vars[k])
    J = sp.Matrix([[sp.cancel(sp.together(sp.diff(x_of_xi[i], v))) for v in el.vars]
                   for i in range(el.dim)])
    assert J == sp.eye(el.dim)
    assert J.det() > 0


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_polynomial_reproduction(path):
    """Linear elements reproduce linear functions, quadratic ones every
    quadratic monomial (Lagrange and serendipity spaces alike)."""
    el = load(path)
    for _, m in monomials(el.vars, el.order):
        interp = sum(f * m.subs(dict(zip(el.vars, p)), simultaneous=True)
                     for f, p in zip(el.N, el.nodes))
        assert is_zero(interp - m), "monomial %s not reproduced" % m


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_reference_volume(path):
    el = load(path)
    assert el.volume > 0
    assert sp.simplify(exact_integral(el, sp.Integer(1)) - el.volume) == 0


def _rules(path):
    d = raw(path)
    return [(path, name) for name in d["quadrature"]]


RULES = [r for p in FILES for r in _rules(p)]
RULE_IDS = ["%s-%s" % (p.stem, name) for p, name in RULES]


@pytest.mark.parametrize("path,rule", RULES, ids=RULE_IDS)
def test_quadrature_rule(path, rule):
    el = load(path)
    d = raw(path)["quadrature"][rule]
    with mpmath.workdps(DPS):
        pts = [[mpmath.mpf(sp.N(parse(c), DPS)) for c in p] for p in d["points"]]
        wts = [mpmath.mpf(sp.N(parse(w), DPS)) for w in d["weights"]]
        vol = mpmath.mpf(sp.N(el.volume, DPS))

        assert abs(sum(wts) - vol) <= REL_TOL * vol, "weights do not sum to the volume"
        for k, p in enumerate(pts):
            assert strictly_inside(el, p), "point %d %s is not strictly inside" % (k, d["points"][k])

        for exps, m in monomials(el.vars, d["degree"]):
            exact = mpmath.mpf(sp.N(exact_integral(el, m), DPS))
            approx = mpmath.fsum(w * mpmath.fprod(x ** e for x, e in zip(p, exps))
                                 for p, w in zip(pts, wts))
            scale = max(abs(exact), vol)
            assert abs(approx - exact) <= REL_TOL * scale, \
                "rule %s does not integrate %s exactly: %s vs %s" % (rule, m, approx, exact)


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_edges(path):
    el = load(path)
    assert el.edges
    seen = set()
    for e in el.edges:
        assert len(e) == (2 if el.order == 1 else 3)
        assert all(0 <= i < el.n for i in e), "edge %s: invalid node index" % e
        assert len(set(e)) == len(e)
        key = frozenset(e[:2])
        assert key not in seen, "duplicate edge %s" % e
        seen.add(key)
        if el.order == 2:
            a, b, m = (el.nodes[i] for i in e)
            assert all(m[k] == (a[k] + b[k]) / 2 for k in range(el.dim)), \
                "node %d is not the midpoint of edge %s" % (e[2], e)
    if el.order == 2:
        mids = [e[2] for e in el.edges]
        assert len(set(mids)) == len(mids)
        assert not set(mids) & set(el.corner_ids)

    if el.dim == 2:
        # counter-clockwise: the outward normal (dy, -dx) of every edge
        # points away from the centroid
        for e in el.edges:
            a, b = el.nodes[e[0]], el.nodes[e[1]]
            normal = (b[1] - a[1], -(b[0] - a[0]))
            mid = ((a[0] + b[0]) / 2 - el.centroid[0], (a[1] + b[1]) / 2 - el.centroid[1])
            assert normal[0] * mid[0] + normal[1] * mid[1] > 0, \
                "edge %s is not counter-clockwise" % e


def _node_kinds(el):
    """Each node's kind: 0 corner, 1 mid-edge, 2 face (3D), 3 interior."""
    kinds = [3] * el.n
    for f in el.faces:
        for i in f:
            kinds[i] = 2
    for e in el.edges:
        for k, i in enumerate(e):
            kinds[i] = 0 if k < 2 else 1
    return kinds


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_node_kinds(path):
    """The element-file rule on node order: corners first, then mid-edge
    nodes, then face nodes (3D), then interior nodes; a node on no edge and
    no face lies strictly inside the element, a face node at the centroid of
    its face's corners, an interior node at the element's centroid."""
    el = load(path)
    kinds = _node_kinds(el)
    assert kinds == sorted(kinds), "nodes are not ordered corners, mid-edge, face, interior: %s" % kinds
    with mpmath.workdps(DPS):
        for i in (i for i in range(el.n) if kinds[i] == 3):
            point = [mpmath.mpf(sp.N(c, DPS)) for c in el.nodes[i]]
            assert strictly_inside(el, point), "interior node %d is on the boundary" % i
            assert tuple(el.nodes[i]) == tuple(el.centroid), "interior node %d is not at the centroid" % i
    for f in el.faces:
        for i in (i for i in f if kinds[i] == 2):
            assert f[-1] == i, "face %s: its face node %d is not its last node" % (f, i)
            corners = [el.nodes[j] for j in f if kinds[j] == 0]
            centre = tuple(sum(c[k] for c in corners) / len(corners) for k in range(el.dim))
            assert tuple(el.nodes[i]) == centre, "face node %d is not the centroid of %s" % (i, f)


@pytest.mark.parametrize("path", [p for p in FILES if raw(p)["dim"] == 3],
                         ids=[p.stem for p in FILES if raw(p)["dim"] == 3])
def test_faces(path):
    el = load(path)
    assert el.faces
    edge_mid = {frozenset(e[:2]): (e[2] if el.order == 2 else None) for e in el.edges}
    directed = {}
    for f in el.faces:
        assert all(0 <= i < el.n for i in f), "face %s: invalid node index" % f
        assert len(set(f)) == len(f)
        nc = len(f) if el.order == 1 else len(f) // 2
        assert nc in (3, 4) and len(f) in ((nc,) if el.order == 1 else (2 * nc, 2 * nc + 1)), \
            "face %s has a wrong number of nodes" % f
        corners = f[:nc]
        assert set(corners) <= set(el.corner_ids)
        p = [sp.Matrix(el.nodes[i]) for i in corners]
        normal = (p[1] - p[0]).cross(p[2] - p[0])
        assert normal.norm() != 0
        for q in p[3:]:
            assert normal.dot(q - p[0]) == 0, "face %s is not planar" % f
        fc = sum(p, sp.zeros(3, 1)) / nc
        assert normal.dot(fc - sp.Matrix(el.centroid)) > 0, \
            "face %s: right-hand normal points into the element" % f
        for k in range(nc):
            a, b = corners[k], corners[(k + 1) % nc]
            key = frozenset((a, b))
            assert key in edge_mid, "face %s uses %s, which is not an edge" % (f, (a, b))
            if el.order == 2:
                assert f[nc + k] == edge_mid[key], \
                    "face %s: mid-edge node of %s should be %d" % (f, (a, b), edge_mid[key])
            assert (a, b) not in directed, "edge %s traversed twice in the same direction" % ((a, b),)
            directed[(a, b)] = f
    # closed, consistently oriented surface: each edge used once each way
    face_edges = {frozenset(k) for k in directed}
    assert face_edges == set(edge_mid), "the faces' edges differ from the edges"
    for a, b in directed:
        assert (b, a) in directed, "edge %s belongs to one face only" % ((a, b),)
    # Euler characteristic of the boundary of a polyhedron
    assert len(el.corner_ids) - len(el.edges) + len(el.faces) == 2


FORMAT_CASES = [(p, fmt) for p in FILES for fmt in ("gmsh", "vtk", "calculix") if fmt in raw(p)]
FORMAT_IDS = ["%s-%s" % (p.stem, fmt) for p, fmt in FORMAT_CASES]


@pytest.mark.parametrize("path,fmt", FORMAT_CASES, ids=FORMAT_IDS)
def test_format_node_order(path, fmt):
    """The format's own reference element, node k moved to tensormass node
    node_order[k], must be an orientation-preserving affine image of the
    tensormass reference element: this checks both the permutation and the
    orientation convention (e.g. VTK wedge vs Gmsh/CalculiX prism)."""
    el = load(path)
    tab = raw(path)[fmt]
    ref = FORMAT_REF[fmt].get(tab["type"])
    if ref is None:
        pytest.skip("no reference coordinates known for %s type %r" % (fmt, tab["type"]))
    order = tab["node_order"]
    assert len(ref) == el.n, "%s type %r has %d nodes" % (fmt, tab["type"], len(ref))
    assert len(ref[0]) == el.dim
    # least squares (exact) affine fit  X_tm[order[k]] = A ref[k] + b
    M = sp.Matrix([list(q) + [1] for q in ref])
    Y = sp.Matrix([list(el.nodes[order[k]]) for k in range(el.n)])
    coeff = (M.T * M).LUsolve(M.T * Y)
    assert M * coeff == Y, "%s node_order is not an affine relabelling" % fmt
    A = coeff[: el.dim, :].T
    assert A.det() > 0, "%s node_order reverses the orientation" % fmt

    identity = order == list(range(el.n))
    if (fmt, tab["type"]) in NON_IDENTITY:
        assert not identity, "%s type %r must not use the identity order" % (fmt, tab["type"])
    if fmt == "vtk":
        assert identity
