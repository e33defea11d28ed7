"""Stage 5 (emit): print the lowered IR through the Jinja2 templates.

Input: `LoweredIR` (stage 4) and the templates directory.
Output: {relative path: C++ text} for every kernel (and terms part),
registry.cpp, elements.cpp, sources.cmake and manifest.json. Printing only:
expressions through the C printer, numbers as round-tripping literals, IR
fields into template contexts. Rendering is strict (StrictUndefined): a
template naming a missing field fails the generation.
"""
from __future__ import annotations

import json
from pathlib import Path

import jinja2

from .ir import ElementIR, KernelIR, LoweredIR, TensorIR, TermsIR, WholeIR
from .model import Block, LawSpec, ParamLimit
from .printer import double_literal, print_expr


def _environment(templates: Path) -> jinja2.Environment:
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(templates)),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        autoescape=False,
    )


# C statements computing a block's auxiliary quantities from H (polar_decomposition.hpp).
_AUXILIARY_CODE = {
    "rotation": ("double R[{dd}];", "tensormass::kernel::polar_rotation<{d}>(H, R);"),
    "rotation_inverse": ("double Y[{y}];", "tensormass::kernel::rotation_inverse<{d}>(H, R, Y);"),
}


def _printed(block: Block, names: dict[str, str], dim: int = 0) -> dict:
    sizes = {"d": dim, "dd": dim * dim, "y": 9 if dim == 3 else 1}
    return {
        "flops": block.flops,
        "prelude": [line.format(**sizes) for aux in block.auxiliaries for line in _AUXILIARY_CODE[aux]],
        "assignments": [{"target": a.target, "declare": a.declare, "code": print_expr(a.expr, names)}
                        for a in block.assignments],
    }


def _literals(values) -> list[str]:
    return [double_literal(v) for v in values]


def _limit_context(limit: ParamLimit) -> dict:
    """One tm_param_limit initialiser's fields as C text."""
    return {
        "lower": "-HUGE_VAL" if limit.lower is None else double_literal(float(limit.lower)),
        "upper": "HUGE_VAL" if limit.upper is None else double_literal(float(limit.upper)),
        "lower_inclusive": int(limit.lower_inclusive),
        "upper_inclusive": int(limit.upper_inclusive),
    }


def law_context(law: LawSpec) -> dict:
    """The template context of one law (an item of registry.cpp.j2's `laws`)."""
    return {
        "name": law.name,
        "parameters": list(law.parameters),
        "limits": [_limit_context(law.limit(p)) for p in law.parameters],
    }


def _tangent_fill(k: KernelIR) -> list[str]:
    return [f"wA[{index}] = {source if source else '0.0'};" for index, source in k.law_ir.tangent_fill]


def _terms_context(terms: TermsIR, names: dict[str, str]) -> dict:
    return {
        "terms_h": _printed(terms.h_block, names),
        "parts": [{"index": i, "nodes": list(p.nodes), "gradient": _printed(p.gradient, names),
                   "hessian": _printed(p.hessian, names)} for i, p in enumerate(terms.parts)],
    }


def _tensor_context(tensor: TensorIR, names: dict[str, str]) -> dict:
    return {
        "green": tensor.green,
        "coefficients": tensor.layout.total,
        "elasticity": [(index, print_expr(expr, names)) for index, expr in tensor.elasticity],
    }


def kernel_context(k: KernelIR) -> dict:
    """The template context of one kernel (the `k` of kernel_*.cpp.j2 and registry.cpp.j2)."""
    names = dict(k.symbol_names)
    law = k.law
    context = {
        "prefix": k.prefix,
        "law": law.name,
        "element": k.element.name,
        "split": k.split,
        "dim": k.element.dim,
        "nodes": k.element.node_count,
        "dofs": k.element.dofs,
        "points": len(k.tables.weights),
        "consts": k.consts_size,
        "flops": k.flops,
        "linear": k.linear,
        "invertible": k.invertible,
        "batched": isinstance(k.split_ir, WholeIR) and k.split_ir.batched,
        "rotation": "rotation" in k.law_ir.tangent.auxiliaries,
        "parameters": list(law.parameters),
        "limits": [_limit_context(law.limit(p)) for p in law.parameters],
        "derived": [name for name, _ in law.constants],
        "derived_code": [(name, print_expr(expr, names)) for name, expr in law.constants],
        "weights": _literals(k.tables.weights),
        "reference_gradients": [[_literals(row) for row in q] for q in k.tables.reference_gradients],
        "law_energy": _printed(k.law_ir.energy, names, k.element.dim),
        "law_stress": _printed(k.law_ir.stress, names, k.element.dim),
        "law_weighted_stress": _printed(k.law_ir.weighted_stress, names, k.element.dim),
        "law_tangent": _printed(k.law_ir.tangent, names, k.element.dim),
        "law_tangent_only": _printed(k.law_ir.tangent_only, names, k.element.dim),
        "tangent_fill": _tangent_fill(k),
    }
    if isinstance(k.split_ir, TermsIR):
        context.update(_terms_context(k.split_ir, names))
    if isinstance(k.split_ir, TensorIR):
        context.update(_tensor_context(k.split_ir, names))
    return context


def element_context(e: ElementIR) -> dict:
    """The template context of one element (an item of elements.cpp.j2's `elements`)."""
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
        "edge_size": e.edge_size,
        "edges": [i for edge in e.edges for i in edge],
        "face_count": len(e.faces),
        "face_sizes": [len(f) for f in e.faces],
        "face_offsets": list(e.face_offsets),
        "faces": [i for f in e.faces for i in f],
        "reference_nodes": _literals(e.reference_nodes),
        "points": len(e.weights),
        "weights": _literals(e.weights),
        "shape_values": _literals(e.shape_values),
        "calculix_type": e.calculix.type if e.calculix else "",
        "calculix_order": list(e.calculix.node_order) if e.calculix else [],
    }


def manifest(lowered: LoweredIR) -> str:
    """manifest.json: every kernel with its sizes and flops, every refusal with its reason."""
    rows = [{"law": k.law.name, "element": k.element.name, "split": k.split, "nodes": k.element.node_count,
             "dim": k.element.dim, "consts": k.consts_size, "flops_energy": k.flops.energy,
             "flops_gradient": k.flops.gradient, "flops_hessian": k.flops.hessian, "linear": k.linear,
             "invertible": k.invertible, "batched": isinstance(k.split_ir, WholeIR) and k.split_ir.batched}
            for k in lowered.kernels]
    refused = [{"law": r.law, "element": r.element, "split": r.split, "reason": r.reason} for r in lowered.refused]
    return json.dumps({"kernels": rows, "refused": refused}, indent=1, sort_keys=True) + "\n"


def emit(lowered: LoweredIR, templates: Path) -> dict[str, str]:
    """Stage 5: every generated file's text, by its path relative to generated/."""
    env = _environment(templates)
    files: dict[str, str] = {}
    contexts = []
    for k in lowered.kernels:
        context = kernel_context(k)
        contexts.append(context)
        name = f"kernels/{context['prefix'][3:]}.cpp"
        files[name] = env.get_template(f"kernel_{k.split}.cpp.j2").render(k=context)
        if isinstance(k.split_ir, TermsIR):
            part_template = env.get_template("kernel_terms_part.cpp.j2")
            for part in context["parts"]:
                files[f"kernels/{context['prefix'][3:]}_part{part['index']}.cpp"] = part_template.render(k=context, p=part)
    files["registry.cpp"] = env.get_template("registry.cpp.j2").render(
        kernels=contexts, laws=[law_context(law) for law in lowered.laws])
    files["elements.cpp"] = env.get_template("elements.cpp.j2").render(
        elements=[element_context(e) for e in lowered.elements])
    files["sources.cmake"] = env.get_template("sources.cmake.j2").render(files=sorted(files))
    files["manifest.json"] = manifest(lowered)
    return files
