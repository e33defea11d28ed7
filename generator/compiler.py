"""The kernel compiler: reference elements and laws in, C++ kernels out.

Stages, each timed (`--verbose` prints the times), each taking the previous
stage's typed output and nothing else:
  1. load       elements/, laws/              -> Inputs: ElementSpec, LawSpec (validated)
  2. symbolic   Inputs                        -> SymbolicIR: element tables; per (law, dim)
                                                 psi, P = dpsi/dH, A = d2psi/dH2 and the
                                                 strain quadratic in SymPy
  3. optimise   SymbolicIR                    -> OptimisedIR: per (law, dim) CSE'd
                                                 straight-line law blocks with flop counts
  4. lower      OptimisedIR, tensor limit     -> LoweredIR: per LES triple a KernelIR (split
                                                 IR, flops, constants) or a refusal with its
                                                 reason; per element an ElementIR
  5. emit       LoweredIR, templates/         -> {path: text} through the Jinja2 templates
                                                 (strict); printing only
  6. format     {path: text}, project root    -> normalised whitespace and the input hash;
                                                 `write` stores only files whose bytes changed
                                                 and removes stale ones
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

from . import stale
from .emit import emit
from .format import format_source
from .load import load_all
from .lower import DEFAULT_TENSOR_LIMIT, lower
from .optimize import optimise
from .symbolic import derive


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


def format_all(files: dict[str, str], root: Path) -> dict[str, str]:
    """Stage 6: every file formatted, plus the hash of the inputs they were generated from."""
    formatted = {name: format_source(text) for name, text in files.items()}
    formatted[stale.HASH_FILE] = stale.input_hash(root) + "\n"
    return formatted


def generate(root: Path, tensor_limit: int = DEFAULT_TENSOR_LIMIT) -> tuple[dict[str, str], Report]:
    """Runs stages 1-6 on the project at root; returns {relative path: text} and the report."""
    report = Report()
    with _Timer(report, "load"):
        inputs = load_all(root / "elements", root / "laws")
    with _Timer(report, "symbolic"):
        symbolic = derive(inputs)
    with _Timer(report, "optimise"):
        optimised = optimise(symbolic)
    with _Timer(report, "lower"):
        lowered = lower(optimised, tensor_limit)
    with _Timer(report, "emit"):
        files = emit(lowered, root / "templates")
    with _Timer(report, "format"):
        files = format_all(files, root)
    report.kernels = [(k.law.name, k.element.name, k.split) for k in lowered.kernels]
    report.refused = [(r.law, r.element, r.split, r.reason) for r in lowered.refused]
    return files, report


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
