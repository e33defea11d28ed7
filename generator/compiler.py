"""The kernel compiler: reference elements and laws in, C++ kernels out.

Stages, each timed (`--verbose` prints the times):
  1. load       elements/*.toml, laws/*.toml  -> ElementSpec, LawSpec (validated)
  2. symbolic   specs -> element tables (weights, dN/dr at points) and, per
                (law, dim), psi, P = dpsi/dH and A = d2psi/dH2 in SymPy
  3. optimise   per (law, dim): CSE'd straight-line law blocks with flop counts
  4. lower      per LES triple: KernelIR (split-specific entries, layouts, flops);
                refused splits are reported with their reason
  5. emit       KernelIR -> C++ text through the Jinja2 templates (strict)
  6. format     normalise whitespace; write only files whose bytes changed,
                remove stale ones; record the input hash
"""
from __future__ import annotations

import json
import time
from dataclasses import dataclass, field
from pathlib import Path

from . import stale
from .emit import render_all
from .format import format_source
from .load import load_all
from .lower import DEFAULT_TENSOR_LIMIT, SPLITS, SplitRefused, build_kernel_ir, build_law_ir


@dataclass
class Report:
    timings: dict[str, float] = field(default_factory=dict)
    kernels: list[tuple[str, str, str]] = field(default_factory=list)
    refused: list[tuple[str, str, str, str]] = field(default_factory=list)
    written: list[str] = field(default_factory=list)
    removed: list[str] = field(default_factory=list)


class _Timer:
    def __init__(self, report: Report, stage: str):
        self.report, self.stage = report, stage

    def __enter__(self):
        self.start = time.perf_counter()

    def __exit__(self, *exc):
        self.report.timings[self.stage] = self.report.timings.get(self.stage, 0.0) + time.perf_counter() - self.start


def generate(root: Path, tensor_limit: int = DEFAULT_TENSOR_LIMIT) -> tuple[dict[str, str], Report]:
    """Runs stages 1-5 and 6's formatting; returns {relative path: text}."""
    report = Report()
    with _Timer(report, "load"):
        elements, laws = load_all(root / "elements", root / "laws")
    with _Timer(report, "symbolic+optimise"):
        law_irs = {(law.name, dim): build_law_ir(law, dim) for law in laws for dim in sorted({e.dim for e in elements})}
    kernels = []
    with _Timer(report, "lower"):
        for law in laws:
            for element in elements:
                for split in SPLITS:
                    try:
                        kernels.append(build_kernel_ir(law, element, split, law_irs[(law.name, element.dim)],
                                                       tensor_limit))
                        report.kernels.append((law.name, element.name, split))
                    except SplitRefused as why:
                        report.refused.append((law.name, element.name, split, str(why)))
    with _Timer(report, "emit"):
        files = render_all(kernels, elements, laws, root / "templates")
        files["manifest.json"] = _manifest(kernels, report)
    with _Timer(report, "format"):
        files = {name: format_source(text) for name, text in files.items()}
        files[stale.HASH_FILE] = stale.input_hash(root) + "\n"
    return files, report


def _manifest(kernels, report: Report) -> str:
    rows = [{"law": k.law.name, "element": k.element.name, "split": k.split, "nodes": k.element.node_count,
             "dim": k.element.dim, "consts": k.consts_size, "flops_energy": k.flops["energy"],
             "flops_gradient": k.flops["gradient"], "flops_hessian": k.flops["hessian"]} for k in kernels]
    refused = [{"law": law, "element": element, "split": split, "reason": why}
               for law, element, split, why in report.refused]
    return json.dumps({"kernels": rows, "refused": refused}, indent=1, sort_keys=True) + "\n"


def write(files: dict[str, str], output: Path, report: Report) -> None:
    """Writes changed files (atomically) and removes generated files no longer produced."""
    output.mkdir(parents=True, exist_ok=True)
    for name, text in sorted(files.items()):
        path = output / name
        if path.exists() and path.read_text() == text:
            continue
        path.parent.mkdir(parents=True, exist_ok=True)
        temporary = path.with_name(path.name + ".tmp")
        temporary.write_text(text)
        temporary.replace(path)
        report.written.append(name)
    for path in sorted(output.rglob("*")):
        if path.is_file() and path.relative_to(output).as_posix() not in files:
            path.unlink()
            report.removed.append(path.relative_to(output).as_posix())


def differences(files: dict[str, str], output: Path) -> list[str]:
    """Names of files that differ from (or are missing in, or extra in) output."""
    wrong = [name for name, text in sorted(files.items())
             if not (output / name).exists() or (output / name).read_text() != text]
    extra = [p.relative_to(output).as_posix() for p in sorted(output.rglob("*"))
             if p.is_file() and p.relative_to(output).as_posix() not in files]
    return wrong + extra
