"""Command line: python3 -m generator [--output DIR] [--if-stale | --check] [--verbose]."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from . import stale

ROOT = Path(__file__).resolve().parent.parent


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m generator", description=__doc__)
    parser.add_argument("--root", type=Path, default=ROOT, help="project root holding elements/, laws/, templates/")
    parser.add_argument("--output", type=Path, default=None, help="output directory (default ROOT/generated)")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--if-stale", action="store_true",
                      help="do nothing (and import no SymPy) when the output's input hash is current")
    mode.add_argument("--check", action="store_true",
                      help="regenerate in memory and fail, listing the files, if the output differs")
    parser.add_argument("--tensor-limit", type=int, default=None,
                        help="largest coefficient count per element the tensor split accepts")
    parser.add_argument("--verbose", "-v", action="store_true", help="print stage times and refused splits")
    args = parser.parse_args(argv)
    root = args.root.resolve()
    output = (args.output or root / "generated").resolve()
    if args.if_stale and stale.is_current(root, output):
        if args.verbose:
            print(f"generator: {output} is up to date with its inputs")
        return 0
    try:
        import jinja2  # noqa: F401
        import sympy  # noqa: F401
    except ImportError as error:
        print(f"generator: {error.name} is missing; install python3-sympy and python3-jinja2 "
              f"and run the generator with /usr/bin/python3 (now {sys.executable})", file=sys.stderr)
        return 2
    from .compiler import differences, generate, write
    from .load import GeneratorInputError
    from .lower import DEFAULT_TENSOR_LIMIT

    started = time.perf_counter()
    try:
        files, report = generate(root, args.tensor_limit or DEFAULT_TENSOR_LIMIT)
    except GeneratorInputError as error:
        print(f"generator: error: {error}", file=sys.stderr)
        return 2
    if args.check:
        wrong = differences(files, output)
        if wrong:
            print("generator: generated/ differs from its inputs in:\n  " + "\n  ".join(wrong), file=sys.stderr)
            return 1
        print(f"generator: {len(files)} files match")
        return 0
    write(files, output, report)
    elapsed = time.perf_counter() - started
    print(f"generator: {len(report.kernels)} kernels, {len(report.refused)} splits refused, "
          f"{len(report.written)} files written, {len(report.removed)} removed, {elapsed:.1f} s")
    if args.verbose:
        for stage, seconds in report.timings.items():
            print(f"  stage {stage:<18} {seconds:7.2f} s")
        for law, element, split, why in report.refused:
            print(f"  refused {law}/{element}/{split}: {why}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
