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
