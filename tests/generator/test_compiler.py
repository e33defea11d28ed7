"""The driver (generator/compiler.py): golden comparison of generated/,
byte-stability across runs, hash seeds, workers and the cache, the stage
report, the SymPy-free staleness check and the updates that regenerate only
what changed."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest

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
            assert (law, element, "terms") not in kernels  # generated on request only
    for law, element, split, why in report.refused:
        assert split in ("tensor", "fbar", "anp") and why
    for element in ("tri3", "quad4", "tet4", "hex8", "prism6", "pyramid5"):
        assert ("stvk", element, "tensor") in kernels
        assert ("hooke", element, "tensor") in kernels
    for law in laws:  # fbar: first-order elements with more than one point, but prism6
        for element in ("quad4", "hex8", "pyramid5"):
            assert (law, element, "fbar") in kernels
        for element in ("tri3", "tet4", "prism6", "tet10", "hex20"):
            assert (law, element, "fbar") not in kernels
    for law in laws:  # anp: the one-point elements and prism6, under the laws with a bulk part
        for element in ("tri3", "tet4", "prism6"):
            assert ((law, element, "anp") in kernels) == (law not in ("stvk", "corotational"))
        for element in ("quad4", "hex8", "tet10"):
            assert (law, element, "anp") not in kernels


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


def _files(output) -> dict[str, bytes]:
    return {p.relative_to(output).as_posix(): p.read_bytes() for p in sorted(output.rglob("*")) if p.is_file()}


def _update(project, output, **options):
    from generator.compiler import update
    return update(project, output, cache=None, **options)


def test_update_regenerates_only_what_changed_and_matches_a_full_generation(tmp_path):
    """A new element regenerates its pairs only and rewrites no other kernel; a removed law's files
    go; an unchanged tree writes nothing; each state equals a full generation of its inputs."""
    from generator.compiler import generate
    project, output = tmp_path / "project", tmp_path / "generated"
    project.mkdir()
    _small_project(project)
    first = _update(project, output)
    assert sorted(first.pairs) == sorted((law, element) for law in ("hooke", "stvk") for element in ("tet4", "tri3"))
    before = _files(output)

    assert not _update(project, output).written  # unchanged

    (project / "elements" / "tri3b.toml").write_text(
        (project / "elements" / "tri3.toml").read_text().replace('name = "tri3"', 'name = "tri3b"'))
    added = _update(project, output)
    assert sorted(added.pairs) == [("hooke", "tri3b"), ("stvk", "tri3b")]
    rewritten = {name for name in added.written if name.startswith("kernels/")}
    assert rewritten and all("_tri3b_" in name for name in rewritten), rewritten
    assert {name for name in added.written if not name.startswith("kernels/")} == {
        "registry.cpp", "elements.cpp", "sources.cmake", "manifest.json", stale.HASH_FILE}
    after = _files(output)
    assert all(after[name] == text for name, text in before.items() if name.startswith("kernels/"))
    assert not differences(generate(project, cache=None)[0], output)

    (project / "laws" / "hooke.toml").unlink()
    removed = _update(project, output)
    assert not removed.pairs and removed.removed and all(name.startswith("kernels/hooke_") for name in removed.removed)
    assert "hooke" not in (output / "registry.cpp").read_text()
    assert not differences(generate(project, cache=None)[0], output)


def test_hash_file_has_one_line_per_pair_and_the_elements(tmp_path):
    project, output = tmp_path / "project", tmp_path / "generated"
    project.mkdir()
    _small_project(project)
    _update(project, output)
    keys = [line.split()[1] for line in (output / stale.HASH_FILE).read_text().splitlines()]
    assert keys == sorted(["hooke/tet4", "hooke/tri3", "stvk/tet4", "stvk/tri3", stale.ELEMENTS_KEY])
    assert stale.is_current(project, output)
    (project / "laws" / "stvk.toml").write_text((project / "laws" / "stvk.toml").read_text() + "\n# edited\n")
    recorded, expected = stale.recorded_hashes(output), stale.expected_hashes(project)
    assert [key for key in expected if recorded.get(key) != expected[key]] == ["stvk/tet4", "stvk/tri3"]


def test_selected_pairs_are_generated_stale_or_not_and_a_lost_file_is_regenerated(tmp_path):
    project, output = tmp_path / "project", tmp_path / "generated"
    project.mkdir()
    _small_project(project)
    only = _update(project, output, laws=["stvk"], elements=["tet4"])
    assert only.pairs == [("stvk", "tet4")]
    assert {p.name for p in (output / "kernels").iterdir()} >= {"stvk_tet4_whole.cpp", "stvk_tet4_tensor.cpp"}
    assert not any("hooke" in p.name or "tri3" in p.name for p in (output / "kernels").iterdir())
    assert "tm_hooke" not in (output / "registry.cpp").read_text()  # the tables list the files present
    assert _update(project, output, laws=["stvk"], elements=["tet4"]).pairs == [("stvk", "tet4")]
    rest = _update(project, output)  # the other pairs were never generated: stale
    assert sorted(rest.pairs) == [("hooke", "tet4"), ("hooke", "tri3"), ("stvk", "tri3")]
    (output / "kernels" / "stvk_tet4_whole.cpp").unlink()
    assert _update(project, output).pairs == [("stvk", "tet4")]
    from generator.load import GeneratorInputError
    with pytest.raises(GeneratorInputError, match="--law nope"):
        _update(project, output, laws=["nope"])


def test_terms_split_is_generated_on_request_and_its_files_go_without_it(tmp_path):
    """--splits whole,terms,tensor adds the terms kernels of every pair (the hashes cover
    the splits, so every pair is stale); back to the default, their files are removed."""
    from generator.compiler import generate
    project, output = tmp_path / "project", tmp_path / "generated"
    project.mkdir()
    _small_project(project)
    _update(project, output)
    assert not any("_terms" in p.name for p in (output / "kernels").iterdir())
    with_terms = _update(project, output, splits=stale.SPLITS)
    assert len(with_terms.pairs) == 4
    assert {(law, element) for law, element, split in with_terms.kernels if split == "terms"} == \
        {(law, element) for law in ("hooke", "stvk") for element in ("tet4", "tri3")}
    assert stale.is_current(project, output, stale.SPLITS) and not stale.is_current(project, output)
    assert not differences(generate(project, cache=None, splits=stale.SPLITS)[0], output)
    without = _update(project, output)
    assert len(without.pairs) == 4 and any("_terms" in name for name in without.removed)
    assert not any("_terms" in p.name for p in (output / "kernels").iterdir())
    with pytest.raises(ValueError, match="unknown split 'nope'"):
        stale.split_selection(["whole", "nope"])


def test_workers_and_the_cache_do_not_change_a_byte(tmp_path):
    from generator.compiler import generate
    project = tmp_path / "project"
    project.mkdir()
    _small_project(project)
    inline, _ = generate(project, jobs=1, cache=None)
    parallel, report = generate(project, jobs=2, cache=tmp_path / "cache")
    cached, again = generate(project, jobs=2, cache=tmp_path / "cache")
    assert report.cached == 0 and again.cached == report.tasks
    assert inline == parallel == cached
