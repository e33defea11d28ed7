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
  6. format     {path: text}                  -> normalised whitespace; `write` stores only
                                                 files whose bytes changed and removes stale ones

Work is cut into independent tasks run in parallel (one process per core):
one per (law, dim), which derives and optimises the law once in that
dimension and lowers and emits it on each of its elements, and one for the
element tables (elements.cpp). A (law, dim)'s symbolic and optimised results
are cached on disk (`cache`, keyed by the law file and the generator's
sources), so a new element costs its own lowering and emission only. The
registry, sources.cmake and manifest.json are rendered last from the
kernels' manifest rows, so an update that regenerates some pairs renders
them from the others' recorded rows (`update`).
"""
from __future__ import annotations

import concurrent.futures
import dataclasses
import functools
import hashlib
import json
import multiprocessing
import os
import pickle
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from . import stale
from .format import format_source

STAGES = ("load", "symbolic", "optimise", "lower", "emit", "format")
DEFAULT_CACHE = stale.GENERATOR_DIR / "__pycache__" / "laws"


@dataclass
class Report:
    timings: dict[str, float] = field(default_factory=lambda: {stage: 0.0 for stage in STAGES})
    kernels: list[tuple[str, str, str]] = field(default_factory=list)
    refused: list[tuple[str, str, str, str]] = field(default_factory=list)
    written: list[str] = field(default_factory=list)
    removed: list[str] = field(default_factory=list)
    pairs: list[tuple[str, str]] = field(default_factory=list)  # the (law, element) pairs generated
    task_times: list[tuple[str, float]] = field(default_factory=list)  # (task, wall seconds), slowest first
    elements: bool = False  # elements.cpp was generated
    tasks: int = 0
    cached: int = 0  # (law, dim) results read from the cache


class _Timer:
    def __init__(self, timings: dict[str, float], stage: str):
        self.timings, self.stage = timings, stage

    def __enter__(self):
        self.start = time.perf_counter()

    def __exit__(self, *exc):
        self.timings[self.stage] = self.timings.get(self.stage, 0.0) + time.perf_counter() - self.start


@dataclass
class _TaskResult:
    files: dict[str, str] = field(default_factory=dict)
    rows: list[dict] = field(default_factory=list)
    refused: list[dict] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=lambda: {stage: 0.0 for stage in STAGES})
    cached: bool = False
    value: object = None  # a first-phase task's result, handed to the second phase
    name: str = ""  # what the task did, for the report
    seconds: float = 0.0  # its wall time


# The generator modules a cached first-phase result depends on (the stages
# that compute it and the types it is made of); a change elsewhere (a split,
# the emitter, the templates) keeps the cache.
_CACHE_SOURCES = ("load.py", "model.py", "symbolic.py", "optimize.py", "lower_element.py", "ir.py", "printer.py",
                  "emit.py")


def _cache_path(cache: Path, kind: str, path: Path, name: str) -> Path:
    digest = hashlib.sha256(kind.encode() + b"\0" + path.read_bytes())
    for source in _CACHE_SOURCES:
        digest.update(b"\0" + (stale.GENERATOR_DIR / source).read_bytes())
    return cache / f"{name}-{kind}-{digest.hexdigest()[:20]}.pickle"


def _cached(cache: Optional[Path], kind: str, path: Path, name: str, compute, result: _TaskResult, stage: str):
    """compute(), or its value stored under cache by the input file's bytes and the generator's
    sources (the time reading it is counted to stage)."""
    entry = _cache_path(cache, kind, path, name) if cache else None
    if entry and entry.exists():
        try:
            with _Timer(result.timings, stage):
                value = pickle.loads(entry.read_bytes())
            result.cached = True
            return value
        except Exception:  # a damaged or foreign entry is recomputed
            pass
    value = compute()
    if entry:
        entry.parent.mkdir(parents=True, exist_ok=True)
        for old in entry.parent.glob(f"{name}-{kind}-*.pickle"):
            old.unlink(missing_ok=True)
        temporary = entry.with_name(f"{entry.name}.{os.getpid()}.tmp")
        temporary.write_bytes(pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL))
        temporary.replace(entry)
    return value


def _timed(name_of):
    """Records the task's name (name_of(*arguments)) and wall time in its result."""
    def decorate(function):
        @functools.wraps(function)
        def run(*arguments):
            start = time.perf_counter()
            result = function(*arguments)
            result.name, result.seconds = name_of(*arguments), time.perf_counter() - start
            return result
        return run
    return decorate


@_timed(lambda law_path, dim, cache: f"derive {law_path.stem} {dim}D")
def _law_phase(law_path: Path, dim: int, cache: Optional[Path]) -> _TaskResult:
    """Stages 1-3 of one law in one dimension: (LawDerivatives, LawKernelIR)."""
    from .emit import printed_law_blocks
    from .load import load_law
    from .optimize import build_law_ir
    from .symbolic import derive_law

    result = _TaskResult()

    def compute():
        with _Timer(result.timings, "load"):
            law = load_law(law_path)
        with _Timer(result.timings, "symbolic"):
            derivatives = derive_law(law, dim)
            derivatives.linear  # noqa: B018 (computed once, kept with the results)
        with _Timer(result.timings, "optimise"):
            law_ir = build_law_ir(derivatives)
        with _Timer(result.timings, "emit"):
            return derivatives, law_ir, printed_law_blocks(law_ir)

    derivatives, law_ir, printed = _cached(cache, f"law{dim}", law_path, law_path.stem, compute, result, "symbolic")
    # A cached law names the file it was first read from; this run's path names errors.
    law = dataclasses.replace(derivatives.law, source=str(law_path))
    result.value = (dataclasses.replace(derivatives, law=law), law_ir, printed)
    return result


@_timed(lambda element_path, cache, full: f"element {element_path.stem}")
def _element_phase(element_path: Path, cache: Optional[Path], full: bool = True) -> _TaskResult:
    """Stages 1-2 and the element lowering of one element: (ElementSpec, ElementTables, ElementIR),
    or (None, None, ElementIR) when not full (elements.cpp needs nothing else; it reads faster)."""
    from .load import load_element
    from .lower_element import lower_element
    from .symbolic import element_tables

    result = _TaskResult()

    def compute():
        with _Timer(result.timings, "load"):
            element = load_element(element_path)
        with _Timer(result.timings, "symbolic"):
            tables = element_tables(element)
        with _Timer(result.timings, "lower"):
            return element, tables, lower_element(element, tables)

    if not full:
        element_ir = _cached(cache, "elementir", element_path, element_path.stem, lambda: compute()[2], result,
                             "symbolic")
        result.value = (None, None, element_ir)
        return result
    element, tables, element_ir = _cached(cache, "element", element_path, element_path.stem, compute, result,
                                          "symbolic")
    _cached(cache, "elementir", element_path, element_path.stem, lambda: element_ir, _TaskResult(), "symbolic")
    result.value = (dataclasses.replace(element, source=str(element_path)), tables, element_ir)
    return result


@_timed(lambda root, law_results, elements, limit, splits: f"kernels {law_results[0].law.name} {law_results[0].dim}D "
        f"({len(elements)} elements)")
def _kernels_phase(root: Path, law_results: tuple, elements: list[tuple], tensor_limit: int,
                   splits: tuple[str, ...]) -> _TaskResult:
    """Stages 4-6 of one law in one dimension on its elements: the files, rows and refusals of `splits`."""
    from .emit import emit_kernel, environment, refusal_row, reuse_printed_law_blocks
    from .ir import Refusal
    from .lower import SplitRefused, build_kernel_ir
    from .model import Inputs, OptimisedIR, SymbolicIR

    result = _TaskResult()
    derivatives, law_ir, printed = law_results
    reuse_printed_law_blocks(law_ir, printed)
    law = derivatives.law
    specs = tuple(spec for spec, _, _ in elements)
    symbolic = SymbolicIR(inputs=Inputs(elements=specs, laws=(law,)), tables=tuple(t for _, t, _ in elements),
                          derivatives=(derivatives,))
    optimised = OptimisedIR(symbolic=symbolic, laws=(law_ir,))
    env = environment(root / "templates")
    for element in specs:
        for split in splits:
            with _Timer(result.timings, "lower"):
                try:
                    kernel = build_kernel_ir(optimised, law, element, split, tensor_limit)
                except SplitRefused as why:
                    result.refused.append(refusal_row(Refusal(law=law.name, element=element.name, split=split,
                                                              reason=str(why))))
                    continue
            with _Timer(result.timings, "emit"):
                kernel_files, row = emit_kernel(kernel, env)
            with _Timer(result.timings, "format"):
                result.files.update({name: format_source(text) for name, text in kernel_files.items()})
            result.rows.append(row)
    return result


@_timed(lambda root, element_irs: "elements.cpp")
def _elements_file(root: Path, element_irs: list) -> _TaskResult:
    """elements.cpp from every element's ElementIR."""
    from .emit import element_context, environment

    result = _TaskResult()
    with _Timer(result.timings, "emit"):
        text = environment(root / "templates").get_template("elements.cpp.j2").render(
            elements=[element_context(e) for e in element_irs])
    with _Timer(result.timings, "format"):
        result.files["elements.cpp"] = format_source(text)
    return result


def _check_names(root: Path) -> None:
    """The project has law and element files."""
    from .load import GeneratorInputError
    if not stale.element_files(root):
        raise GeneratorInputError(f"{root / 'elements'}: no element files (*.toml)")
    if not stale.law_files(root):
        raise GeneratorInputError(f"{root / 'laws'}: no law files (*.toml)")


class _Inline:
    """The executor interface, run in this process (one job)."""

    def submit(self, function, *arguments):
        future = concurrent.futures.Future()
        try:
            future.set_result(function(*arguments))
        except BaseException as error:  # noqa: B902 (handed to the caller through the future)
            future.set_exception(error)
        return future

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def _dimension(path: Path) -> int:
    import tomllib
    try:
        with open(path, "rb") as stream:
            dim = tomllib.load(stream).get("dim")
    except tomllib.TOMLDecodeError:
        return 0  # the element's load reports the file
    return dim if isinstance(dim, int) else 0


def _run(root: Path, pairs: list[tuple[str, str]], with_elements: bool, tensor_limit: int,
         jobs: Optional[int], cache: Optional[Path], report: Report,
         splits: tuple[str, ...] = stale.DEFAULT_SPLITS) -> list[_TaskResult]:
    """The tasks of the given pairs and of elements.cpp, in parallel.

    First phase: each needed (law, dim) derived and optimised, each needed
    element loaded with its tables. Second phase, as soon as a (law, dim) and
    its elements are ready: its kernels lowered and emitted; and elements.cpp."""
    from . import emit, load, lower, optimize, symbolic  # noqa: F401 (imported once, before the workers fork)

    laws, elements = stale.law_files(root), stale.element_files(root)
    element_names = sorted({e for _, e in pairs} | (set(elements) if with_elements else set()))
    dims = {name: _dimension(elements[name]) for name in element_names}
    groups: dict[tuple[str, int], list[str]] = {}
    for law, element in sorted(pairs):
        groups.setdefault((law, dims[element]), []).append(element)
    order = sorted(groups, key=lambda group: (-group[1], group[0]))  # 3D laws, the costliest, first
    workers = max(1, min(jobs or os.cpu_count() or 1, len(groups) + len(element_names)))
    report.tasks = len(groups) + len(element_names)
    results: list[_TaskResult] = []
    if workers == 1:
        executor = _Inline()
    else:
        executor = concurrent.futures.ProcessPoolExecutor(max_workers=workers,
                                                          mp_context=multiprocessing.get_context("fork"))
    with executor as pool:
        first = {pool.submit(_law_phase, laws[law], dim, cache): ("law", (law, dim)) for law, dim in order}
        needed = {e for _, e in pairs}
        first.update({pool.submit(_element_phase, elements[name], cache, name in needed): ("element", name)
                      for name in element_names})
        ready_laws, ready_elements, second = {}, {}, []
        started: set = set()
        for future in concurrent.futures.as_completed(list(first)):
            kind, key = first[future]
            result = future.result()
            results.append(result)
            (ready_laws if kind == "law" else ready_elements)[key] = result.value
            for group in order:
                if group in started or group not in ready_laws:
                    continue
                if all(name in ready_elements for name in groups[group]):
                    started.add(group)
                    second.append(pool.submit(_kernels_phase, root, ready_laws[group],
                                              [ready_elements[name] for name in groups[group]], tensor_limit, splits))
            if with_elements and "elements.cpp" not in started and len(ready_elements) == len(element_names):
                started.add("elements.cpp")
                second.append(pool.submit(_elements_file, root, [ready_elements[name][2] for name in element_names]))
        results += [future.result() for future in second]
    return results


def _collect(results: list[_TaskResult], report: Report) -> tuple[dict[str, str], list[dict], list[dict]]:
    files, rows, refused = {}, [], []
    for result in results:
        files.update(result.files)
        rows += result.rows
        refused += result.refused
        report.cached += result.cached
        report.task_times.append((result.name, result.seconds))
        for stage, seconds in result.timings.items():
            report.timings[stage] += seconds
    report.task_times.sort(key=lambda item: -item[1])
    return files, rows, refused


def _tables(root: Path, rows: list[dict], refused: list[dict], report: Report) -> dict[str, str]:
    from .emit import emit_tables, environment
    from .load import load_law
    timings = report.timings
    with _Timer(timings, "load"):
        laws = [load_law(path) for path in stale.law_files(root).values()]
    with _Timer(timings, "emit"):
        files = emit_tables(rows, refused, laws, environment(root / "templates"))
    with _Timer(timings, "format"):
        files = {name: format_source(text) for name, text in files.items()}
    from .emit import row_order
    report.kernels = [(r["law"], r["element"], r["split"]) for r in sorted(rows, key=row_order)]
    report.refused = [(r["law"], r["element"], r["split"], r["reason"]) for r in sorted(refused, key=row_order)]
    return files


def _previous_manifest(output: Path) -> dict:
    path = output / "manifest.json"
    try:
        return json.loads(path.read_text()) if path.exists() else {}
    except json.JSONDecodeError:
        return {}


def _incomplete_pairs(manifest: dict, output: Path) -> set[str]:
    """Keys of the pairs whose manifest rows name a file output lacks (or that have no row)."""
    missing = {stale.pair_key(r["law"], r["element"]) for r in manifest.get("kernels", [])
               if any(not (output / source).exists() for source in r.get("sources", [""]))}
    if not (output / "elements.cpp").exists():
        missing.add(stale.ELEMENTS_KEY)
    return missing


def _all_pairs(root: Path) -> list[tuple[str, str]]:
    return [(law, element) for law in stale.law_files(root) for element in stale.element_files(root)]


def generate(root: Path, tensor_limit: Optional[int] = None, jobs: Optional[int] = None,
             cache: Optional[Path] = DEFAULT_CACHE,
             splits: tuple[str, ...] = stale.DEFAULT_SPLITS) -> tuple[dict[str, str], Report]:
    """Every file of the project at root, in memory: all pairs with `splits`, the tables and the input hashes."""
    from .lower import DEFAULT_TENSOR_LIMIT
    _check_names(root)
    report = Report()
    pairs = _all_pairs(root)
    results = _run(root, pairs, True, tensor_limit or DEFAULT_TENSOR_LIMIT, jobs, cache, report, splits)
    files, rows, refused = _collect(results, report)
    files.update(_tables(root, rows, refused, report))
    files[stale.HASH_FILE] = stale.format_hashes(stale.expected_hashes(root, splits))
    report.pairs, report.elements = pairs, True
    return files, report


def update(root: Path, output: Path, tensor_limit: Optional[int] = None, laws: Optional[list[str]] = None,
           elements: Optional[list[str]] = None, force: bool = False, jobs: Optional[int] = None,
           cache: Optional[Path] = DEFAULT_CACHE, splits: tuple[str, ...] = stale.DEFAULT_SPLITS) -> Report:
    """Brings output up to date with the project at root, regenerating only what changed.

    laws / elements: generate just the pairs of these laws and elements (all of
    one kind when its list is empty or None), stale or not; otherwise the stale
    pairs (every pair with force). The tables always list exactly the kernels
    whose files are in output; the pairs get the kernels of `splits`. Returns
    without importing SymPy when nothing changed."""
    report = Report()
    expected = stale.expected_hashes(root, splits)
    recorded = {} if force else stale.recorded_hashes(output)
    previous = _previous_manifest(output)
    for key in _incomplete_pairs(previous, output) | (set() if previous else set(recorded)):
        recorded.pop(key, None)  # a pair whose files are gone is stale
    current = _all_pairs(root)
    if laws or elements:
        known_laws, known_elements = stale.law_files(root), stale.element_files(root)
        from .load import GeneratorInputError
        for name in laws or []:
            if name not in known_laws:
                raise GeneratorInputError(f"--law {name}: no file {root / 'laws' / name}.toml")
        for name in elements or []:
            if name not in known_elements:
                raise GeneratorInputError(f"--element {name}: no file {root / 'elements' / name}.toml")
        pairs = [(law, element) for law, element in current
                 if (not laws or law in laws) and (not elements or element in elements)]
    else:
        pairs = [pair for pair in current if recorded.get(stale.pair_key(*pair)) != expected[stale.pair_key(*pair)]]
    with_elements = (recorded.get(stale.ELEMENTS_KEY) != expected[stale.ELEMENTS_KEY]
                     or not (output / "elements.cpp").exists())
    gone = [key for key in recorded if key != stale.ELEMENTS_KEY and key not in expected]
    if not pairs and not with_elements and not gone:
        return report
    _check_names(root)
    from .lower import DEFAULT_TENSOR_LIMIT
    results = _run(root, pairs, with_elements, tensor_limit or DEFAULT_TENSOR_LIMIT, jobs, cache, report, splits)
    files, rows, refused = _collect(results, report)
    rebuilt = {stale.pair_key(*pair) for pair in pairs}
    kept = {key for key in recorded if key in expected and key not in rebuilt and key != stale.ELEMENTS_KEY}
    rows += [r for r in previous.get("kernels", []) if stale.pair_key(r["law"], r["element"]) in kept]
    refused += [r for r in previous.get("refused", []) if stale.pair_key(r["law"], r["element"]) in kept]
    files.update(_tables(root, rows, refused, report))
    hashes = {key: recorded[key] for key in kept}
    hashes.update({key: expected[key] for key in rebuilt})
    elements_hash = expected[stale.ELEMENTS_KEY] if with_elements else recorded.get(stale.ELEMENTS_KEY)
    if elements_hash:
        hashes[stale.ELEMENTS_KEY] = elements_hash
    files[stale.HASH_FILE] = stale.format_hashes(hashes)
    keep = {source for row in rows for source in row["sources"]} | set(files) | {"elements.cpp"}
    write(files, output, report, keep)
    report.pairs, report.elements = pairs, with_elements
    return report


def write(files: dict[str, str], output: Path, report: Report, keep: Optional[set[str]] = None) -> None:
    """Writes changed files (atomically) and removes files of output that are neither written nor in keep."""
    keep = set(files) if keep is None else keep | set(files)
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
        if path.is_file() and path.relative_to(output).as_posix() not in keep:
            path.unlink()
            report.removed.append(path.relative_to(output).as_posix())


def differences(files: dict[str, str], output: Path) -> list[str]:
    """Names of files that differ from (or are missing in, or extra in) output."""
    wrong = [name for name, text in sorted(files.items())
             if not (output / name).exists() or (output / name).read_text() != text]
    extra = [p.relative_to(output).as_posix() for p in sorted(output.rglob("*"))
             if p.is_file() and p.relative_to(output).as_posix() not in files]
    return wrong + extra
