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

from .ir import ElementIR, KernelIR, LoweredIR, NodalPressureIR, ProductBlock, SumOfProducts, TensorIR, TermsIR, WholeIR
from .model import Block, LawKernelIR, LawSpec, ParamLimit
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


# Printed law blocks by (id(block), dim): the law's blocks are shared by every
# kernel of a (law, dim) and read only H, R, Y, the constants and their own
# temporaries, so each is printed once (the block is kept to pin its id).
_PRINTED: dict[tuple[int, int], tuple[Block, dict]] = {}


def _printed_law_block(block: Block, names: dict[str, str], dim: int) -> dict:
    key = (id(block), dim)
    if key not in _PRINTED:
        _PRINTED[key] = (block, _printed(block, names, dim))
    return _PRINTED[key][1]


LAW_BLOCKS = ("energy", "stress", "weighted_stress", "tangent", "tangent_only")


def printed_law_blocks(law_ir: LawKernelIR) -> dict[str, dict]:
    """The law's blocks printed (they read no element-specific names), to keep with the law IR."""
    d = law_ir.dim
    names = {f"{prefix}{i}": f"{prefix}[{i}]" for prefix, count in (("H", d * d), ("R", d * d), ("Y", 9 if d == 3 else 1))
             for i in range(count)}  # lower._base_symbol_names without the element's u
    return {name: _printed_law_block(getattr(law_ir, name), names, d) for name in LAW_BLOCKS}


def reuse_printed_law_blocks(law_ir: LawKernelIR, printed: dict[str, dict]) -> None:
    """Lets the kernels of law_ir print its blocks as `printed_law_blocks` gave them."""
    for name in LAW_BLOCKS:
        block = getattr(law_ir, name)
        _PRINTED[(id(block), law_ir.dim)] = (block, printed[name])


def _printed(block: Block, names: dict[str, str], dim: int = 0) -> dict:
    sizes = {"d": dim, "dd": dim * dim, "y": 9 if dim == 3 else 1}
    return {
        "flops": block.flops,
        "prelude": [line.format(**sizes) for aux in block.auxiliaries for line in _AUXILIARY_CODE[aux]],
        "assignments": [{"target": a.target, "declare": a.declare, "code": print_expr(a.expr, names)}
                        for a in block.assignments],
    }


def _sum_of_products(assignment: SumOfProducts) -> str:
    return " + ".join(("" if c == 1 else double_literal(c) + "*") + "*".join(factors)
                      for c, factors in assignment.terms)


def _printed_products(block: ProductBlock) -> dict:
    """A ProductBlock in the shape of `_printed` (no prelude)."""
    return {
        "flops": block.flops,
        "prelude": [],
        "assignments": [{"target": a.target, "declare": a.declare, "code": _sum_of_products(a)}
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
        "prony_weights": [law.parameters.index(p) for p in law.prony_weights],
        "prony_times": [law.parameters.index(p) for p in law.prony_times],
        "prony_volumetric_weights": [law.parameters.index(p) for p in law.prony_volumetric_weights],
    }


def _tangent_fill(k: KernelIR) -> list[str]:
    return [f"wA[{index}] = {source if source else '0.0'};" for index, source in k.law_ir.tangent_fill]


def _terms_context(terms: TermsIR, names: dict[str, str]) -> dict:
    return {
        "terms_h": _printed_products(terms.h_block),
        "parts": [{"index": i, "nodes": list(p.nodes), "gradient": _printed_products(p.gradient),
                   "hessian": _printed_products(p.hessian)} for i, p in enumerate(terms.parts)],
    }


def _tensor_context(tensor: TensorIR, names: dict[str, str]) -> dict:
    return {
        "green": tensor.green,
        "coefficients": tensor.layout.total,
        "elasticity": [(index, print_expr(expr, names)) for index, expr in tensor.elasticity],
    }


def _batched(k: KernelIR) -> bool:
    """Whether the kernel has batched entry points (the whole split's, which anp shares)."""
    return isinstance(k.split_ir, (WholeIR, NodalPressureIR)) and k.split_ir.batched


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
        "batched": _batched(k),
        "rotation": "rotation" in k.law_ir.tangent.auxiliaries,
        "parameters": list(law.parameters),
        "limits": [_limit_context(law.limit(p)) for p in law.parameters],
        "derived": [name for name, _ in law.constants],
        "derived_code": [(name, print_expr(expr, names)) for name, expr in law.constants],
        "weights": _literals(k.tables.weights),
        "reference_gradients": [[_literals(row) for row in q] for q in k.tables.reference_gradients],
        "law_energy": _printed_law_block(k.law_ir.energy, names, k.element.dim),
        "law_stress": _printed_law_block(k.law_ir.stress, names, k.element.dim),
        "law_weighted_stress": _printed_law_block(k.law_ir.weighted_stress, names, k.element.dim),
        "law_tangent": _printed_law_block(k.law_ir.tangent, names, k.element.dim),
        "law_tangent_only": _printed_law_block(k.law_ir.tangent_only, names, k.element.dim),
        "tangent_fill": _tangent_fill(k),
        "bulk": [],
        "prony_parameters": list(law.prony_parameters),
    }
    if isinstance(k.split_ir, TermsIR):
        context.update(_terms_context(k.split_ir, names))
    if isinstance(k.split_ir, TensorIR):
        context.update(_tensor_context(k.split_ir, names))
    if isinstance(k.split_ir, NodalPressureIR):
        context.update(bulk=[print_expr(expr) for expr in k.split_ir.bulk], bulk_text=law.bulk,
                       anp_base=k.split_ir.base)
    elif k.viscous_bulk:
        context.update(bulk=[print_expr(expr) for expr in k.viscous_bulk], bulk_text=law.bulk)
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
        "corner_count": e.corner_count,
        "reference_volume": _literals((e.reference_volume,))[0],
        "shape_gradients": _literals(e.shape_gradients),
        "corner_gradients": _literals(e.corner_gradients),
    }


SPLIT_ORDER = ("whole", "terms", "tensor", "fbar", "anp")  # lower.SPLITS, the registry's order within a (law, element)


def kernel_row(k: KernelIR, sources: list[str]) -> dict:
    """The kernel's manifest.json row: what registry.cpp and sources.cmake need, so that
    an update regenerating some kernels renders the tables without the others' IR."""
    return {"law": k.law.name, "element": k.element.name, "split": k.split, "nodes": k.element.node_count,
            "dim": k.element.dim, "points": len(k.tables.weights), "params": len(k.law.parameters),
            "derived_params": len(k.law.constants), "consts": k.consts_size, "flops_energy": k.flops.energy,
            "flops_gradient": k.flops.gradient, "flops_hessian": k.flops.hessian, "linear": k.linear,
            "invertible": k.invertible, "batched": _batched(k), "bulk": isinstance(k.split_ir, NodalPressureIR) or bool(k.viscous_bulk),
            "prony_terms": len(k.law.prony_weights), "prony_volumetric": bool(k.law.prony_volumetric_weights),
            "sources": sources}


def row_order(row: dict) -> tuple:
    """Kernels and refusals sort by law, element, then split in lower.SPLITS order."""
    return row["law"], row["element"], SPLIT_ORDER.index(row["split"])


def _registry_context(row: dict) -> dict:
    """A manifest row as registry.cpp.j2's `k`."""
    return dict(row, prefix=f"tm_{row['law']}_{row['element']}_{row['split']}", dofs=row["nodes"] * row["dim"])


def emit_kernel(k: KernelIR, env: jinja2.Environment) -> tuple[dict[str, str], dict]:
    """One kernel's files (the terms split's parts included) and its manifest row."""
    context = kernel_context(k)
    stem = f"kernels/{context['prefix'][3:]}"
    files = {f"{stem}.cpp": env.get_template(f"kernel_{k.split}.cpp.j2").render(k=context)}
    if isinstance(k.split_ir, TermsIR):
        part_template = env.get_template("kernel_terms_part.cpp.j2")
        for part in context["parts"]:
            files[f"{stem}_part{part['index']}.cpp"] = part_template.render(k=context, p=part)
    return files, kernel_row(k, sorted(files))


def emit_tables(rows: list[dict], refused: list[dict], laws: list[LawSpec], env: jinja2.Environment,
                elements: list[ElementIR] | None = None) -> dict[str, str]:
    """registry.cpp, sources.cmake and manifest.json from the kernels' rows (and elements.cpp when given)."""
    rows = sorted(rows, key=row_order)
    refused = sorted(refused, key=row_order)
    files = {"registry.cpp": env.get_template("registry.cpp.j2").render(
        kernels=[_registry_context(row) for row in rows], laws=[law_context(law) for law in laws])}
    if elements is not None:
        files["elements.cpp"] = env.get_template("elements.cpp.j2").render(
            elements=[element_context(e) for e in elements])
    sources = sorted({source for row in rows for source in row["sources"]} | {"registry.cpp", "elements.cpp"})
    files["sources.cmake"] = env.get_template("sources.cmake.j2").render(files=sources)
    files["manifest.json"] = json.dumps({"kernels": rows, "refused": refused}, indent=1, sort_keys=True) + "\n"
    return files


def refusal_row(r) -> dict:
    return {"law": r.law, "element": r.element, "split": r.split, "reason": r.reason}


def environment(templates: Path) -> jinja2.Environment:
    """The strict Jinja2 environment of the templates directory."""
    return _environment(templates)


def emit(lowered: LoweredIR, templates: Path) -> dict[str, str]:
    """Stage 5: every generated file's text, by its path relative to generated/."""
    env = _environment(templates)
    files: dict[str, str] = {}
    rows = []
    for k in lowered.kernels:
        kernel_files, row = emit_kernel(k, env)
        files.update(kernel_files)
        rows.append(row)
    files.update(emit_tables(rows, [refusal_row(r) for r in lowered.refused], list(lowered.laws), env,
                             list(lowered.elements)))
    return files
