"""The driver (generator/compiler.py): golden comparison of generated/,
byte-stability across runs and hash seeds, the stage report and the
SymPy-free staleness check."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys

from conftest import ROOT
from generator import stale
from generator.compiler import differences

STAGES = ["load", "symbolic", "optimise", "lower", "emit", "format"]


def test_generated_matches_inputs_byte_for_byte(regenerated):
    files, _ = regenerated
    wrong = differences(files, ROOT / "generated")
    assert not wrong, "generated/ is stale or edited by hand; run `cmake --build build --target generate`:\n" + \
        "\n".join(wrong)


def test_every_stage_is_timed(regenerated):
    _, report = regenerated
    assert list(report.timings) == STAGES


def test_registry_covers_every_pair_and_refuses_with_reasons(regenerated):
    _, report = regenerated
    kernels = set(report.kernels)
    laws = {p.stem for p in (ROOT / "laws").glob("*.toml")}
    elements = {p.stem for p in (ROOT / "elements").glob("*.toml")}
    for law in laws:
        for element in elements:
            assert (law, element, "whole") in kernels
            assert (law, element, "terms") in kernels
    for law, element, split, why in report.refused:
        assert split == "tensor" and why
    for element in ("tri3", "quad4", "tet4", "hex8", "prism6", "pyramid5"):
        assert ("stvk", element, "tensor") in kernels
        assert ("hooke", element, "tensor") in kernels


def test_if_stale_needs_no_sympy():
    """An up-to-date tree is detected with the standard library alone."""
    code = ("import sys; sys.modules['sympy'] = None; sys.modules['jinja2'] = None; "
            "from generator.__main__ import main; sys.exit(main(['--if-stale']))")
    result = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert stale.is_current(ROOT, ROOT / "generated")


def _small_project(root):
    """A project with two elements and two laws (every split offered), generated in seconds."""
    for folder, names in (("elements", ("tri3", "tet4")), ("laws", ("hooke", "stvk"))):
        (root / folder).mkdir()
        for name in names:
            shutil.copy(ROOT / folder / f"{name}.toml", root / folder)
    shutil.copytree(ROOT / "templates", root / "templates")


def _generate(root, output, seed: str) -> dict[str, bytes]:
    environment = dict(os.environ, PYTHONHASHSEED=seed)
    subprocess.run([sys.executable, "-m", "generator", "--root", str(root), "--output", str(output)],
                   cwd=ROOT, env=environment, check=True, capture_output=True)
    return {p.relative_to(output).as_posix(): p.read_bytes() for p in sorted(output.rglob("*")) if p.is_file()}


def test_two_runs_give_the_same_bytes(tmp_path):
    project = tmp_path / "project"
    project.mkdir()
    _small_project(project)
    first = _generate(project, tmp_path / "first", "1")
    second = _generate(project, tmp_path / "second", "2")
    assert len(first) > 10
    assert first == second
