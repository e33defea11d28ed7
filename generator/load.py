"""Stage 1 (load): read and validate element and law files into specs.

Input: the directories holding `elements/*.toml` and `laws/*.toml`.
Output: `Inputs`, immutable `ElementSpec` and `LawSpec` objects. Every error
names the file and the key at fault (`GeneratorInputError`); everything the
later stages rely on about the files' structure is checked here.
"""
from __future__ import annotations

import ast
import re
import tomllib
from pathlib import Path
from typing import Any

import sympy

from .model import (FIBRE_CONSTANTS, FIBRE_INVARIANT_FAMILIES, FIBRE_PARAMETERS, ElementSpec, FormatOrder, Inputs,
                    LawSpec, ParamLimit, QuadratureRule)

REFERENCE_VARIABLES = sympy.symbols("r s t", real=True)
ELEMENT_KEYS = {
    "name", "description", "dim", "order", "nodes", "shape_functions", "edges",
    "faces", "reference_volume", "default_quadrature", "quadrature", "gmsh",
    "vtk", "calculix",
}
ELEMENT_REQUIRED = ELEMENT_KEYS - {"faces", "calculix"}
RULE_KEYS = {"degree", "points", "weights"}
FORMAT_KEYS = {"type", "node_order"}
LAW_KEYS = {"name", "description", "parameters"}
LAW_OPTIONAL_KEYS = {"energy", "isochoric", "volumetric", "bulk", "derived", "invertible", "limits", "rotation_invariant",
                     "viscoelastic"}
VISCOELASTIC_KEYS = {"weights", "times", "volumetric_weights"}
# One limit: `parameter op number`, op one of > >= < <=.
_LIMIT = re.compile(r"^\s*([A-Za-z_]\w*)\s*(>=|<=|>|<)\s*([^<>=\s].*?)\s*$")


class GeneratorInputError(Exception):
    """A description file is malformed; the message names the file and key."""


def _fail(source: str, key: str, message: str) -> GeneratorInputError:
    return GeneratorInputError(f"{source}: key '{key}': {message}")


def _read_toml(path: Path) -> dict:
    try:
        with open(path, "rb") as stream:
            return tomllib.load(stream)
    except tomllib.TOMLDecodeError as error:
        raise GeneratorInputError(f"{path}: not valid TOML: {error}") from None


def _check_keys(data: dict, allowed: set, required: set, source: str, where: str) -> None:
    for key in data:
        if key not in allowed:
            raise _fail(source, f"{where}{key}", f"unknown key (allowed: {', '.join(sorted(allowed))})")
    for key in sorted(required):
        if key not in data:
            raise _fail(source, f"{where}{key}", "missing")


def _number(value: Any, source: str, key: str) -> sympy.Expr:
    """An exact number: an int, or a string SymPy parses without free symbols."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise _fail(source, key, f"expected a number or a numeric string, got {value!r}")
    if isinstance(value, float):
        raise _fail(source, key, f"write {value!r} as an exact string (floats lose digits)")
    try:
        expr = sympy.sympify(value, rational=True)
    except (sympy.SympifyError, SyntaxError, TypeError) as error:
        raise _fail(source, key, f"cannot parse {value!r}: {error}") from None
    if expr.free_symbols or not expr.is_finite or not expr.is_real:
        raise _fail(source, key, f"{value!r} is not a finite real number")
    return expr


def _int_list(value: Any, source: str, key: str, bound: int) -> tuple[int, ...]:
    if not isinstance(value, list) or not all(isinstance(v, int) and not isinstance(v, bool) for v in value):
        raise _fail(source, key, "expected a list of integers")
    for v in value:
        if not 0 <= v < bound:
            raise _fail(source, key, f"node index {v} out of range 0..{bound - 1}")
    return tuple(value)


def _format_order(data: Any, source: str, key: str, nodes: int) -> FormatOrder:
    if not isinstance(data, dict):
        raise _fail(source, key, "expected a table")
    _check_keys(data, FORMAT_KEYS, FORMAT_KEYS, source, f"{key}.")
    order = _int_list(data["node_order"], source, f"{key}.node_order", nodes)
    if sorted(order) != list(range(nodes)):
        raise _fail(source, f"{key}.node_order", f"must be a permutation of 0..{nodes - 1}")
    return FormatOrder(type=data["type"], node_order=order)


def _rule(name: str, data: Any, source: str, dim: int) -> QuadratureRule:
    key = f"quadrature.{name}"
    if not isinstance(data, dict):
        raise _fail(source, key, "expected a table")
    _check_keys(data, RULE_KEYS, RULE_KEYS, source, f"{key}.")
    points = data["points"]
    weights = data["weights"]
    if not isinstance(points, list) or not isinstance(weights, list) or len(points) != len(weights) or not points:
        raise _fail(source, key, "points and weights must be non-empty lists of equal length")
    parsed_points = []
    for q, point in enumerate(points):
        if not isinstance(point, list) or len(point) != dim:
            raise _fail(source, f"{key}.points[{q}]", f"expected {dim} coordinates")
        parsed_points.append(tuple(_number(x, source, f"{key}.points[{q}]") for x in point))
    parsed_weights = tuple(_number(w, source, f"{key}.weights[{q}]") for q, w in enumerate(weights))
    degree = data["degree"]
    if not isinstance(degree, int) or degree < 0:
        raise _fail(source, f"{key}.degree", "expected a non-negative integer")
    return QuadratureRule(name=name, degree=degree, points=tuple(parsed_points), weights=parsed_weights)


def _shape_functions(data: Any, source: str, dim: int, nodes: int) -> tuple[sympy.Expr, ...]:
    if not isinstance(data, list) or len(data) != nodes:
        raise _fail(source, "shape_functions", f"expected {nodes} strings, one per node")
    variables = REFERENCE_VARIABLES[:dim]
    names = {str(v): v for v in variables}
    result = []
    for i, text in enumerate(data):
        if not isinstance(text, str):
            raise _fail(source, f"shape_functions[{i}]", "expected a string")
        try:
            expr = sympy.sympify(text, locals=names, rational=True)
        except (sympy.SympifyError, SyntaxError, TypeError) as error:
            raise _fail(source, f"shape_functions[{i}]", f"cannot parse {text!r}: {error}") from None
        extra = expr.free_symbols - set(variables)
        if extra:
            raise _fail(source, f"shape_functions[{i}]",
                        f"unknown symbols {sorted(map(str, extra))} (use {', '.join(names)})")
        result.append(expr)
    return tuple(result)


def _edges(data: Any, source: str, nodes: int) -> tuple[tuple[int, ...], ...]:
    """Node lists of the edges, all of one size (the runtime's edge table has a fixed stride)."""
    if not isinstance(data, list) or not data:
        raise _fail(source, "edges", "expected a non-empty list of node lists")
    edges = tuple(_int_list(e, source, f"edges[{i}]", nodes) for i, e in enumerate(data))
    if len({len(edge) for edge in edges}) != 1:
        raise _fail(source, "edges", "all edges must have the same number of nodes")
    return edges


def load_element(path: Path) -> ElementSpec:
    source = str(path)
    data = _read_toml(path)
    _check_keys(data, ELEMENT_KEYS, ELEMENT_REQUIRED, source, "")
    if data["name"] != path.stem:
        raise _fail(source, "name", f"'{data['name']}' must equal the file name '{path.stem}'")
    dim = data["dim"]
    if dim not in (2, 3):
        raise _fail(source, "dim", "must be 2 or 3")
    if data["order"] not in (1, 2):
        raise _fail(source, "order", "must be 1 or 2")
    raw_nodes = data["nodes"]
    if not isinstance(raw_nodes, list) or len(raw_nodes) < dim + 1:
        raise _fail(source, "nodes", f"expected at least {dim + 1} nodes")
    nodes = []
    for i, node in enumerate(raw_nodes):
        if not isinstance(node, list) or len(node) != dim:
            raise _fail(source, f"nodes[{i}]", f"expected {dim} coordinates")
        nodes.append(tuple(_number(x, source, f"nodes[{i}]") for x in node))
    count = len(nodes)
    edges = _edges(data["edges"], source, count)
    faces = tuple(_int_list(f, source, f"faces[{i}]", count) for i, f in enumerate(data.get("faces", [])))
    if dim == 3 and not faces:
        raise _fail(source, "faces", "3D elements must list their faces")
    quadrature = data["quadrature"]
    if not isinstance(quadrature, dict) or not quadrature:
        raise _fail(source, "quadrature", "expected at least one [quadrature.NAME] table")
    rules = tuple(_rule(name, rule, source, dim) for name, rule in quadrature.items())
    if data["default_quadrature"] not in quadrature:
        raise _fail(source, "default_quadrature", f"no rule named '{data['default_quadrature']}'")
    calculix = data.get("calculix")
    return ElementSpec(
        name=data["name"],
        description=str(data["description"]),
        source=source,
        dim=dim,
        order=data["order"],
        nodes=tuple(nodes),
        shape_functions=_shape_functions(data["shape_functions"], source, dim, count),
        edges=edges,
        faces=faces,
        reference_volume=_number(data["reference_volume"], source, "reference_volume"),
        default_quadrature=data["default_quadrature"],
        quadrature=rules,
        gmsh=_format_order(data["gmsh"], source, "gmsh", count),
        vtk=_format_order(data["vtk"], source, "vtk", count),
        calculix=None if calculix is None else _format_order(calculix, source, "calculix", count),
    )


def _limits(data: Any, parameters: list[str], source: str) -> tuple[ParamLimit, ...]:
    """One ParamLimit per parameter from the `limits` list ("young > 0", "poisson < 1/2", ...)."""
    if not isinstance(data, list):
        raise _fail(source, "limits", 'expected a list of inequalities such as "young > 0"')
    bounds: dict[str, dict] = {p: {} for p in parameters}
    for i, text in enumerate(data):
        key = f"limits[{i}]"
        match = _LIMIT.match(text) if isinstance(text, str) else None
        if not match:
            raise _fail(source, key, f"expected \"parameter op number\" with op one of > >= < <=, got {text!r}")
        name, op, number = match.groups()
        if name not in bounds:
            raise _fail(source, key, f"'{name}' is not a parameter; parameters are {parameters}")
        value = _number(number, source, key)
        side = "lower" if op.startswith(">") else "upper"
        if side in bounds[name]:
            raise _fail(source, key, f"a second {side} bound for '{name}'")
        bounds[name][side] = (value, op.endswith("="))
    limits = []
    for name in parameters:
        lower, upper = bounds[name].get("lower"), bounds[name].get("upper")
        limit = ParamLimit(lower=lower[0] if lower else None, upper=upper[0] if upper else None,
                           lower_inclusive=bool(lower and lower[1]), upper_inclusive=bool(upper and upper[1]))
        if lower and upper and (lower[0] > upper[0] or (lower[0] == upper[0] and not (lower[1] and upper[1]))):
            raise _fail(source, "limits", f"no value of '{name}' satisfies its limits")
        limits.append(limit)
    return tuple(limits)


def _energy_text(data: dict, source: str) -> tuple[str, str, str]:
    """(energy, isochoric, volumetric): `energy`, or the pair `isochoric` + `volumetric`."""
    split = [key for key in ("isochoric", "volumetric") if key in data]
    if "energy" in data and split:
        raise _fail(source, split[0], "give either `energy` or `isochoric` and `volumetric`, not both")
    if "energy" not in data and len(split) != 2:
        missing = "energy" if not split else ({"isochoric", "volumetric"} - set(split)).pop()
        raise _fail(source, missing, "missing (give `energy`, or `isochoric` and `volumetric`)")
    for key in ("energy", "isochoric", "volumetric"):
        if key in data and not isinstance(data[key], str):
            raise _fail(source, key, "expected a string")
    if "energy" in data:
        return data["energy"], "", ""
    return f"({data['isochoric']}) + ({data['volumetric']})", data["isochoric"], data["volumetric"]


def _bulk_text(data: dict, volumetric: str, source: str) -> str:
    """The bulk part U(J) of the energy: `bulk`, or the `volumetric` part of a split energy."""
    if "bulk" not in data:
        return volumetric
    if volumetric:
        raise _fail(source, "bulk", "a split energy's bulk part is its `volumetric` part; drop `bulk`")
    if not isinstance(data["bulk"], str):
        raise _fail(source, "bulk", "expected a string")
    return data["bulk"]


def _names_read(text: str) -> set[str]:
    """The identifiers an expression reads (none when it does not parse: the symbolic stage reports that)."""
    try:
        tree = ast.parse(text.replace("^", "**"), mode="eval")
    except SyntaxError:
        return set()
    return {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)}


def _fibre_families(energy: str, source: str) -> int:
    """How many fibre families the energy's invariants read (0, 1 or 2)."""
    return max((FIBRE_INVARIANT_FAMILIES.get(name, 0) for name in _names_read(energy)), default=0)


def _prony_series(data: Any, parameters: list[str], read: set[str], source: str) -> tuple[tuple[str, ...], ...]:
    """(weights, times, volumetric weights): the [viscoelastic] table's parameter names, term by term
    (the volumetric weights () when the bulk part does not relax); ((), (), ()) without one.
    The runtime alone reads them, so the energy and the derived parameters must not."""
    if data is None:
        return (), (), ()
    if not isinstance(data, dict):
        raise _fail(source, "viscoelastic", "expected a table with `weights` and `times`")
    _check_keys(data, VISCOELASTIC_KEYS, {"weights", "times"}, source, "viscoelastic.")
    lists = []
    for key in [k for k in ("weights", "times", "volumetric_weights") if k in data]:
        names = data[key]
        if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
            raise _fail(source, f"viscoelastic.{key}", "expected a non-empty list of parameter names")
        for name in names:
            if name not in parameters:
                raise _fail(source, f"viscoelastic.{key}", f"'{name}' is not a parameter; parameters are {parameters}")
            if name in read:
                raise _fail(source, f"viscoelastic.{key}", f"'{name}' is read by the energy or a derived parameter; "
                            "a Prony parameter is read by the runtime only")
        lists.append(tuple(names))
    weights, times, volumetric = lists[0], lists[1], lists[2] if len(lists) > 2 else ()
    if len(weights) != len(times):
        raise _fail(source, "viscoelastic.times", f"{len(times)} times for {len(weights)} weights")
    if volumetric and len(volumetric) != len(weights):
        raise _fail(source, "viscoelastic.volumetric_weights",
                    f"{len(volumetric)} volumetric weights for {len(weights)} terms")
    if len(set(weights + times + volumetric)) != len(weights + times + volumetric):
        raise _fail(source, "viscoelastic", "a parameter is named twice")
    return weights, times, volumetric


def load_law(path: Path) -> LawSpec:
    source = str(path)
    data = _read_toml(path)
    _check_keys(data, LAW_KEYS | LAW_OPTIONAL_KEYS, LAW_KEYS, source, "")
    for key in ("invertible", "rotation_invariant"):
        if not isinstance(data.get(key, False), bool):
            raise _fail(source, key, "expected true or false")
    if data["name"] != path.stem:
        raise _fail(source, "name", f"'{data['name']}' must equal the file name '{path.stem}'")
    parameters = data["parameters"]
    if not isinstance(parameters, list) or not parameters or not all(isinstance(p, str) and p.isidentifier() for p in parameters):
        raise _fail(source, "parameters", "expected a non-empty list of identifiers")
    if len(set(parameters)) != len(parameters):
        raise _fail(source, "parameters", "a parameter is listed twice")
    reserved = sorted(set(parameters) & {n for family in FIBRE_PARAMETERS + FIBRE_CONSTANTS for n in family})
    if reserved:
        raise _fail(source, "parameters", f"{reserved} are the fibre directions' names (set per cell by the "
                    "scene); rename them")
    energy, isochoric, volumetric = _energy_text(data, source)
    bulk = _bulk_text(data, volumetric, source)
    families = _fibre_families(energy, source)
    symbols = {p: sympy.Symbol(p, real=True) for p in parameters}
    derived = []
    if not isinstance(data.get("derived", {}), dict):
        raise _fail(source, "derived", "expected a table name = expression")
    for name, text in data.get("derived", {}).items():
        key = f"derived.{name}"
        if not name.isidentifier() or not isinstance(text, str):
            raise _fail(source, key, "expected identifier = \"expression\"")
        try:
            expr = sympy.sympify(text, locals=symbols, rational=True)
        except (sympy.SympifyError, SyntaxError, TypeError) as error:
            raise _fail(source, key, f"cannot parse {text!r}: {error}") from None
        unknown = expr.free_symbols - set(symbols.values())
        if unknown:
            raise _fail(source, key, f"unknown symbols {sorted(map(str, unknown))}; parameters are {parameters}")
        derived.append((name, expr))
    limits = _limits(data.get("limits", []), parameters, source)
    read = _names_read(energy) | {str(symbol) for _, expr in derived for symbol in expr.free_symbols}
    prony_weights, prony_times, prony_volumetric = _prony_series(data.get("viscoelastic"), parameters, read, source)
    if prony_volumetric and not bulk:
        raise _fail(source, "viscoelastic.volumetric_weights", "the law has no bulk part to relax (`bulk`, or "
                    "`isochoric` + `volumetric`)")
    fibres = tuple(name for family in FIBRE_PARAMETERS[:families] for name in family)
    return LawSpec(
        name=data["name"],
        description=str(data["description"]),
        source=source,
        energy=energy,
        parameters=tuple(parameters) + fibres,
        derived=tuple(derived),
        invertible=data.get("invertible", False),
        limits=limits + (ParamLimit(),) * len(fibres) if limits else (),
        isochoric=isochoric,
        volumetric=volumetric,
        bulk=bulk,
        rotation_invariant=data.get("rotation_invariant", True),
        fibre_families=families,
        prony_weights=prony_weights,
        prony_times=prony_times,
        prony_volumetric_weights=prony_volumetric,
    )


def load_all(elements_dir: Path, laws_dir: Path) -> Inputs:
    """Stage 1: every element and law file of the two directories, sorted by name."""
    element_paths = sorted(elements_dir.glob("*.toml"))
    law_paths = sorted(laws_dir.glob("*.toml"))
    if not element_paths:
        raise GeneratorInputError(f"{elements_dir}: no element files (*.toml)")
    if not law_paths:
        raise GeneratorInputError(f"{laws_dir}: no law files (*.toml)")
    return Inputs(elements=tuple(load_element(p) for p in element_paths),
                  laws=tuple(load_law(p) for p in law_paths))
