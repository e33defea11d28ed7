"""Shared by the generator tests: the project root on sys.path and one full
generation of the project (about 30 s), reused by every test that needs it."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))


@pytest.fixture(scope="session")
def regenerated():
    """(files, report) of `generate(ROOT)`: every generated file's text and the stage report."""
    from generator.compiler import generate
    return generate(ROOT)


def value_inside(limit, index: int = 0) -> float:
    """A parameter value inside a law's limits (generator.model.ParamLimit),
    away from the bounds and different per parameter index."""
    lower = None if limit.lower is None else float(limit.lower)
    upper = None if limit.upper is None else float(limit.upper)
    if lower is not None and upper is not None:
        return lower + (0.77 - 0.05 * index) * (upper - lower)
    if lower is not None:
        return lower + 1.3 + 0.4 * index
    if upper is not None:
        return upper - 1.3 - 0.4 * index
    return 1.3 + 0.4 * index


def values_outside(limit) -> list[float]:
    """Finite values a law's limits refuse: on an exclusive bound, beyond an inclusive one."""
    values = []
    if limit.lower is not None:
        values.append(float(limit.lower) - (1.0 if limit.lower_inclusive else 0.0))
    if limit.upper is not None:
        values.append(float(limit.upper) + (1.0 if limit.upper_inclusive else 0.0))
    return values
