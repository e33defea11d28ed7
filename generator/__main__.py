"""Command line: python3 -m generator [--law L] [--element E] [--force | --check] [--splits LIST] [--verbose].

Brings generated/ up to date with elements/, laws/, templates/ and the
generator: only the (law, element) pairs whose inputs changed are
regenerated (recorded in generated/INPUTS.sha256), only files whose bytes
change are written, and files of pairs that no longer exist are removed. An
up-to-date tree is recognised without importing SymPy."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from . import stale

ROOT = Path(__file__).resolve().parent.parent


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m generator", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--root", type=Path, default=ROOT, help="project root holding elements/, laws/, templates/")
    parser.add_argument("--output", type=Path, default=None, help="output directory (default ROOT/generated)")
    parser.add_argument("--law", action="append", default=[], metavar="NAME",
                        help="generate this law's pairs (repeatable; with --element, their pairs only), stale or not")
    parser.add_argument("--element", action="append", default=[], metavar="NAME",
                        help="generate this element's pairs (repeatable; with --law, their pairs only), stale or not")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--if-stale", action="store_true",
                      help="the default: regenerate what changed, nothing (and no SymPy) when nothing did")
    mode.add_argument("--force", action="store_true", help="regenerate every pair")
    mode.add_argument("--check", action="store_true",
                      help="regenerate everything in memory and fail, listing the files, if the output differs")
    parser.add_argument("--jobs", "-j", type=int, default=None, help="worker processes (default: one per core)")
    parser.add_argument("--no-cache", action="store_true",
                        help="derive every law afresh instead of reading generator/__pycache__/laws")
    parser.add_argument("--tensor-limit", type=int, default=None,
                        help="largest coefficient count per element the tensor split accepts")
    parser.add_argument("--splits", default=",".join(stale.DEFAULT_SPLITS), metavar="LIST",
                        help="the splits to emit, comma-separated (default %(default)s; all: "
                             + ",".join(stale.SPLITS) + ")")
    parser.add_argument("--verbose", "-v", action="store_true", help="print stage times and refused splits")
    args = parser.parse_args(argv)
    try:
        splits = stale.split_selection([name for name in args.splits.split(",") if name])
    except ValueError as error:
        parser.error(f"--splits: {error}")
    root = args.root.resolve()
    output = (args.output or root / "generated").resolve()

    from . import compiler  # standard library only until work is found
    started = time.perf_counter()
    cache = None if args.no_cache else compiler.DEFAULT_CACHE
    try:
        if args.check:
            _require_sympy()
            files, report = compiler.generate(root, args.tensor_limit, args.jobs, cache, splits)
        else:
            if args.law or args.element or args.force:
                _require_sympy()
            report = compiler.update(root, output, args.tensor_limit, args.law, args.element, args.force,
                                     args.jobs, cache, splits)
    except ImportError as error:
        print(f"generator: {error.name} is missing; install python3-sympy and python3-jinja2 "
              f"and run the generator with /usr/bin/python3 (now {sys.executable})", file=sys.stderr)
        return 2
    except Exception as error:
        from .load import GeneratorInputError
        if isinstance(error, GeneratorInputError):
            print(f"generator: error: {error}", file=sys.stderr)
            return 2
        raise
    elapsed = time.perf_counter() - started
    if args.check:
        wrong = compiler.differences(files, output)
        if wrong:
            print("generator: generated/ differs from its inputs in:\n  " + "\n  ".join(wrong), file=sys.stderr)
            return 1
        print(f"generator: {len(files)} files match ({elapsed:.1f} s)")
        return 0
    if not report.pairs and not report.elements and not report.written and not report.removed:
        if args.verbose:
            print(f"generator: {output} is up to date with its inputs ({elapsed:.2f} s)")
        return 0
    print(f"generator: {len(report.pairs)} pairs regenerated ({len(report.kernels)} kernels in the registry, "
          f"{len(report.refused)} splits refused), {len(report.written)} files written, "
          f"{len(report.removed)} removed, {elapsed:.1f} s")
    if args.verbose:
        print(f"  {report.tasks} tasks, {report.cached} laws from the cache; stage times summed over the workers:")
        for stage, seconds in report.timings.items():
            print(f"  stage {stage:<18} {seconds:7.2f} s")
        for name, seconds in report.task_times[:8]:
            print(f"  task {name:<40} {seconds:6.2f} s")
        for law, element, split, why in report.refused:
            print(f"  refused {law}/{element}/{split}: {why}")
    return 0


def _require_sympy() -> None:
    import jinja2  # noqa: F401
    import sympy  # noqa: F401


if __name__ == "__main__":
    sys.exit(main())
