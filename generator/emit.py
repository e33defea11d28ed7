"""Stage 5 (emit): render `KernelIR`s through the Jinja2 templates.

Input: `KernelIR`s, element specs, the templates directory.
Output: {relative path: C++ text}. Rendering is strict (StrictUndefined): a
template naming a missing field fails the generation.
"""
from __future__ import annotations

from pathlib import Path

import jinja2
import sympy

from .lower import elasticity_assignments, h_expressions
from .model import Block, ElementSpec, KernelIR, LawSpec
from .optimize import eliminate
from .printer import double_literal, print_expr
from .symbolic import element_tables


def _environment(templates: Path) -> jinja2.Environment:
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(templates)),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        autoescape=False,
    )


def _symbol_names(k: KernelIR) -> dict[str, str]:
    """Maps IR symbol names to the C expressions that hold them."""
    n, d = k.element.node_count, k.element.dim
    names = {f"H{i}": f"H[{i}]" for i in range(d * d)}
    names.update({f"u{i}": f"u[{i}]" for i in range(n * d)})
    names.update(k.extra.get("symbol_names", {}))
    return names


def _printed(block: Block, names: dict[str, str]) -> dict:
    return {
        "flops": block.flops,
        "assignments": [{"target": a.target, "declare": a.declare, "code": print_expr(a.expr, names)}
                        for a in block.assignments],
    }


def _tangent_fill(k: KernelIR) -> list[str]:
    d2 = k.element.dim ** 2
    fills = []
    for i in range(d2):
        for j in range(d2):
            own = f"wA[{i * d2 + j}]"
            source = k.law_ir.tangent_map[i][j]
            if source != own:
                fills.append(f"{own} = {source if source else '0.0'};")
    return fills


def prefix(k: KernelIR) -> str:
    return f"tm_{k.law.name}_{k.element.name}_{k.split}"


def kernel_context(k: KernelIR) -> dict:
    names = _symbol_names(k)
    law = k.law
    params = {p: sympy.Symbol(p, real=True) for p in law.parameters}
    context = {
        "prefix": prefix(k),
        "law": law.name,
        "element": k.element.name,
        "split": k.split,
        "dim": k.element.dim,
        "nodes": k.element.node_count,
        "dofs": k.element.dofs,
        "points": len(k.tables.weights),
        "consts": k.consts_size,
        "flops": k.flops,
        "parameters": list(law.parameters),
        "derived": [name for name, _ in law.derived],
        "derived_code": [(name, print_expr(expr.subs(params), names)) for name, expr in law.derived],
        "weights": [double_literal(w) for w in k.tables.weights],
        "reference_gradients": [[[double_literal(x) for x in row] for row in q] for q in k.tables.reference_gradients],
        "law_energy": _printed(k.law_ir.energy, names),
        "law_stress": _printed(k.law_ir.stress, names),
        "law_weighted_stress": _printed(k.law_ir.weighted_stress, names),
        "law_tangent": _printed(k.law_ir.tangent, names),
        "law_tangent_only": _printed(k.law_ir.tangent_only, names),
        "tangent_fill": _tangent_fill(k),
    }
    if k.split == "terms":
        context["terms_h"] = _printed(eliminate(h_expressions(k.element), "h"), names)
        context["parts"] = [{"index": i, "nodes": list(p.nodes), "gradient": _printed(p.gradient, names),
                             "hessian": _printed(p.hessian, names)} for i, p in enumerate(k.extra["parts"])]
    if k.split == "tensor":
        quadratic, layout = k.extra["quadratic"], k.extra["layout"]
        n = k.element.node_count
        pairs = layout["pairs"]
        index = {pair: i for i, pair in enumerate(pairs)}
        context.update({
            "green": quadratic.strain == "E",
            "coefficients": layout["total"],
            "pairs": pairs,
            "pair_of": [[index[(min(j, m), max(j, m))] for m in range(n)] for j in range(n)],
            "elasticity": [(i, print_expr(expr, names)) for i, expr in elasticity_assignments(law, quadratic)],
        })
    return context


def _element_context(e: ElementSpec) -> dict:
    tables = element_tables(e)
    faces = [list(f) for f in e.faces]
    offsets, total = [], 0
    for f in faces:
        offsets.append(total)
        total += len(f)
    edge_sizes = {len(edge) for edge in e.edges}
    if len(edge_sizes) != 1:
        raise ValueError(f"{e.source}: key 'edges': all edges must have the same number of nodes")
    return {
        "name": e.name,
        "cname": e.name.capitalize(),
        "description": e.description,
        "dim": e.dim,
        "order": e.order,
        "nodes": e.node_count,
        "vtk_type": e.vtk.type,
        "gmsh_type": e.gmsh.type,
        "vtk_order": list(e.vtk.node_order),
        "gmsh_order": list(e.gmsh.node_order),
        "edge_count": len(e.edges),
        "edge_size": edge_sizes.pop(),
        "edges": [i for edge in e.edges for i in edge],
        "face_count": len(faces),
        "face_sizes": [len(f) for f in faces],
        "face_offsets": offsets,
        "faces": [i for f in faces for i in f],
        "reference_nodes": [double_literal(float(x)) for node in e.nodes for x in node],
        "points": len(tables.weights),
        "weights": [double_literal(w) for w in tables.weights],
        "shape_values": [double_literal(v) for row in tables.shape_values for v in row],
        "calculix_type": e.calculix.type if e.calculix else "",
        "calculix_order": list(e.calculix.node_order) if e.calculix else [],
    }


def render_all(kernels: list[KernelIR], elements: tuple[ElementSpec, ...], laws: tuple[LawSpec, ...],
               templates: Path) -> dict[str, str]:
    env = _environment(templates)
    files: dict[str, str] = {}
    contexts = []
    for k in kernels:
        context = kernel_context(k)
        contexts.append(context)
        name = f"kernels/{context['prefix'][3:]}.cpp"
        files[name] = env.get_template(f"kernel_{k.split}.cpp.j2").render(k=context)
        if k.split == "terms":
            part_template = env.get_template("kernel_terms_part.cpp.j2")
            for part in context["parts"]:
                files[f"kernels/{context['prefix'][3:]}_part{part['index']}.cpp"] = part_template.render(k=context, p=part)
    files["registry.cpp"] = env.get_template("registry.cpp.j2").render(kernels=contexts, laws=laws)
    files["elements.cpp"] = env.get_template("elements.cpp.j2").render(
        elements=[_element_context(e) for e in elements])
    sources = sorted(files)
    files["sources.cmake"] = env.get_template("sources.cmake.j2").render(files=sources)
    return files
