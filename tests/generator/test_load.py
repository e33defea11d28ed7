"""Stage 1 (load): every malformed element or law file is refused with an
error naming the file and the key; the stage output is typed."""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import sympy

from conftest import ROOT
from generator.load import GeneratorInputError, load_all, load_element, load_law
from generator.model import ElementSpec, Inputs, LawSpec


def _copy_element(tmp_path: Path, name: str = "tet4") -> Path:
    target = tmp_path / f"{name}.toml"
    shutil.copy(ROOT / "elements" / f"{name}.toml", target)
    return target


@pytest.mark.parametrize("edit, key", [
    (lambda t: "surprise = 1\n" + t, "surprise"),
    (lambda t: t.replace('"1 - r - s - t"', '"1 - r - s - q"'), "shape_functions[0]"),
    (lambda t: t.replace('name = "tet4"', 'name = "tet5"'), "name"),
    (lambda t: t.replace('default_quadrature = "gauss1"', 'default_quadrature = "nope"'), "default_quadrature"),
    (lambda t: t.replace('weights = ["1/6"]', 'weights = [0.1666]'), "quadrature.gauss1.weights[0]"),
    (lambda t: t.replace("node_order = [0, 1, 2, 3]\n\n[vtk]", "node_order = [0, 1, 1, 3]\n\n[vtk]"), "gmsh.node_order"),
    (lambda t: t.replace("[1, 2, 3], [2, 0, 3]]", "[1, 2, 3], [2, 0, 7]]"), "faces[3]"),
    (lambda t: t.replace("edges = [[0, 1],", "edges = [[0, 1, 2],"), "edges"),
    (lambda t: t.replace("edges = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]]", "edges = []"), "edges"),
])
def test_element_errors_name_file_and_key(tmp_path, edit, key):
    path = _copy_element(tmp_path)
    text = path.read_text()
    assert edit(text) != text, "the edit no longer matches elements/tet4.toml"
    path.write_text(edit(text))
    with pytest.raises(GeneratorInputError) as error:
        load_element(path)
    assert str(path) in str(error.value)
    assert f"'{key}'" in str(error.value)


def test_edges_of_mixed_sizes_are_refused_at_load(tmp_path):
    """The runtime's edge table has one stride per element: checked by load, not at emit time."""
    path = _copy_element(tmp_path)
    path.write_text(path.read_text().replace("edges = [[0, 1],", "edges = [[0, 1, 2],"))
    with pytest.raises(GeneratorInputError, match=r"key 'edges': all edges must have the same number of nodes"):
        load_element(path)


def test_invalid_toml_names_file(tmp_path):
    path = tmp_path / "tet4.toml"
    path.write_text("name = \n")
    with pytest.raises(GeneratorInputError, match=str(path)):
        load_element(path)


def test_law_derived_parameter_errors_name_the_key(tmp_path):
    path = tmp_path / "stvk.toml"
    text = (ROOT / "laws" / "stvk.toml").read_text()
    path.write_text(text.replace('mu = "young/(2*(1 + poisson))"', 'mu = "young/(2*(1 + nu))"'))
    with pytest.raises(GeneratorInputError, match="derived.mu"):
        load_law(path)


def test_load_all_returns_typed_sorted_inputs():
    inputs = load_all(ROOT / "elements", ROOT / "laws")
    assert isinstance(inputs, Inputs)
    assert all(isinstance(e, ElementSpec) for e in inputs.elements)
    assert all(isinstance(law, LawSpec) for law in inputs.laws)
    assert [e.name for e in inputs.elements] == sorted(p.stem for p in (ROOT / "elements").glob("*.toml"))
    assert [law.name for law in inputs.laws] == sorted(p.stem for p in (ROOT / "laws").glob("*.toml"))
    assert inputs.dims == (2, 3)


def test_load_all_needs_files(tmp_path):
    with pytest.raises(GeneratorInputError, match="no element files"):
        load_all(tmp_path, ROOT / "laws")


def test_law_invertible_must_be_a_boolean(tmp_path):
    path = tmp_path / "stable_neohookean.toml"
    path.write_text((ROOT / "laws" / "stable_neohookean.toml").read_text().replace("invertible = true",
                                                                                   'invertible = "yes"'))
    with pytest.raises(GeneratorInputError, match=r"stable_neohookean.toml.*invertible.*true or false"):
        load_law(path)


def _law_with_limits(tmp_path: Path, limits: str) -> Path:
    """A copy of a law file with (young, poisson) whose `limits` line is replaced."""
    source = next(p for p in sorted((ROOT / "laws").glob("*.toml"))
                  if 'parameters = ["young", "poisson"]' in p.read_text())
    lines = [line for line in source.read_text().splitlines() if not line.startswith("limits")]
    lines.insert(next(i for i, line in enumerate(lines) if line.startswith("parameters")) + 1, limits)
    path = tmp_path / source.name
    path.write_text("\n".join(lines) + "\n")
    return path


def test_limits_give_one_interval_per_parameter(tmp_path):
    from generator.model import ParamLimit
    law = load_law(_law_with_limits(tmp_path, 'limits = ["young > 0", "poisson >= -1", "poisson < 1/2"]'))
    assert law.limits == (ParamLimit(lower=0, upper=None), ParamLimit(lower=-1, upper=sympy.Rational(1, 2),
                                                                      lower_inclusive=True))
    assert law.limit("poisson").upper == sympy.Rational(1, 2)
    unbounded = load_law(_law_with_limits(tmp_path, ""))
    assert unbounded.limit("young") == ParamLimit()


@pytest.mark.parametrize("limits, key, message", [
    ('limits = ["nu > 0"]', "limits[0]", "not a parameter"),
    ('limits = ["young > 0", "young >> 1"]', "limits[1]", "op one of"),
    ('limits = ["young = 1"]', "limits[0]", "op one of"),
    ('limits = ["young > q"]', "limits[0]", "not a finite real number"),
    ('limits = ["young > 0", "young >= 1"]', "limits[1]", "second lower bound"),
    ('limits = ["young > 1", "young < 1"]', "limits", "no value"),
    ('limits = "young > 0"', "limits", "list of inequalities"),
    ('limits = [1]', "limits[0]", "parameter op number"),
])
def test_limit_errors_name_file_and_key(tmp_path, limits, key, message):
    path = _law_with_limits(tmp_path, limits)
    with pytest.raises(GeneratorInputError) as error:
        load_law(path)
    assert str(path) in str(error.value) and f"'{key}'" in str(error.value) and message in str(error.value)


_SPLIT_LAW = '''name = "split"
description = "a law file given as isochoric + volumetric"
parameters = ["c10", "kappa"]
'''


@pytest.mark.parametrize("body, key", [
    ('energy = "c10*(I1bar - 3)"\nisochoric = "c10*(I1bar - 3)"\nvolumetric = "kappa*(J - 1)**2"\n', "isochoric"),
    ('isochoric = "c10*(I1bar - 3)"\n', "volumetric"),
    ('volumetric = "kappa*(J - 1)**2"\n', "isochoric"),
    ("", "energy"),
    ('energy = "c10*(I1bar - 3)"\nrotation_invariant = "yes"\n', "rotation_invariant"),
    ('energy = "c10*(I1bar - 3)"\nparameters = ["c10", "c10"]\n', "parameters"),
])
def test_energy_keys_errors_name_file_and_key(tmp_path, body, key):
    path = tmp_path / "split.toml"
    text = _SPLIT_LAW + body
    if body.count("parameters"):
        text = text.replace('parameters = ["c10", "kappa"]\n', "")
    path.write_text(text)
    with pytest.raises(GeneratorInputError) as error:
        load_law(path)
    assert str(path) in str(error.value) and f"'{key}'" in str(error.value)


def test_split_energy_without_derived_reads_its_parameters(tmp_path):
    path = tmp_path / "split.toml"
    path.write_text(_SPLIT_LAW + 'isochoric = "c10*(I1bar - 3)"\nvolumetric = "kappa/2*(J - 1)**2"\n')
    law = load_law(path)
    assert law.split_volumetric and law.rotation_invariant and law.derived == ()
    assert law.energy == "(c10*(I1bar - 3)) + (kappa/2*(J - 1)**2)"
    assert law.constants == ((("c10", sympy.Symbol("c10", real=True)), ("kappa", sympy.Symbol("kappa", real=True))))


@pytest.mark.parametrize("body, message", [
    ('isochoric = "c10*(I1bar - 3)"\nvolumetric = "kappa/2*(J - 1)**2"\nbulk = "kappa/2*(J - 1)**2"\n', "drop `bulk`"),
    ('energy = "c10*(I1 - 3)"\nbulk = 3\n', "expected a string"),
])
def test_bulk_key_errors_name_file_and_key(tmp_path, body, message):
    path = tmp_path / "split.toml"
    path.write_text(_SPLIT_LAW + body)
    with pytest.raises(GeneratorInputError) as error:
        load_law(path)
    assert str(path) in str(error.value) and "'bulk'" in str(error.value) and message in str(error.value)


def test_bulk_part_is_the_files_bulk_or_its_volumetric_part(tmp_path):
    path = tmp_path / "split.toml"
    path.write_text(_SPLIT_LAW + 'energy = "c10*(I1 - 3) + kappa/2*(J - 1)**2"\nbulk = "kappa/2*(J - 1)**2"\n')
    assert load_law(path).bulk == "kappa/2*(J - 1)**2" and not load_law(path).split_volumetric
    path.write_text(_SPLIT_LAW + 'isochoric = "c10*(I1bar - 3)"\nvolumetric = "kappa/2*(J - 1)**2"\n')
    assert load_law(path).bulk == "kappa/2*(J - 1)**2"
    path.write_text(_SPLIT_LAW + 'energy = "c10*(I1 - 3)"\n')
    assert load_law(path).bulk == ""


@pytest.mark.parametrize("energy, families", [("c*(I1 - 3)", 0), ("c*(I1 - 3) + c*(I4 - 1)**2", 1),
                                              ("c*(I5 - 1)", 1), ("c*(I4bar - 1) + c*I8bar", 2),
                                              ("c*(I6 - 1)", 2)])
def test_fibre_invariants_append_the_direction_parameters(tmp_path, energy, families):
    path = tmp_path / "fibred.toml"
    path.write_text(f'name = "fibred"\ndescription = "d"\nenergy = "{energy}"\nparameters = ["c"]\n'
                    'limits = ["c > 0"]\n')
    law = load_law(path)
    directions = ("fibre_x", "fibre_y", "fibre_z", "fibre2_x", "fibre2_y", "fibre2_z")[: 3 * families]
    assert law.fibre_families == families
    assert law.parameters == ("c",) + directions
    assert law.own_parameters == ("c",)
    assert len(law.limits) == len(law.parameters)
    assert [name for name, _ in law.constants] == ["c"] + ["a0x", "a0y", "a0z", "g0x", "g0y", "g0z"][: 3 * families]


def test_fibre_direction_names_are_reserved(tmp_path):
    path = tmp_path / "fibred.toml"
    path.write_text('name = "fibred"\ndescription = "d"\nenergy = "fibre_x*(I4 - 1)"\nparameters = ["fibre_x"]\n')
    with pytest.raises(GeneratorInputError, match=r"fibred.toml: key 'parameters': .*fibre directions"):
        load_law(path)


_VISCOUS_LAW = ('name = "viscous"\ndescription = "d"\nisochoric = "c10*(I1bar - 3)"\n'
                'volumetric = "kappa/2*(J - 1)**2"\nparameters = ["c10", "kappa", "g1", "tau1", "k1"]\n')


def test_a_prony_series_names_its_parameters_term_by_term(tmp_path):
    path = tmp_path / "viscous.toml"
    path.write_text(_VISCOUS_LAW + '[viscoelastic]\nweights = ["g1"]\ntimes = ["tau1"]\n')
    law = load_law(path)
    assert law.viscoelastic and law.prony_weights == ("g1",) and law.prony_times == ("tau1",)
    assert law.prony_volumetric_weights == ()
    assert law.parameters == ("c10", "kappa", "g1", "tau1", "k1")
    assert [name for name, _ in law.constants] == ["c10", "kappa", "k1"]
    path.write_text(_VISCOUS_LAW + '[viscoelastic]\nweights = ["g1"]\ntimes = ["tau1"]\nvolumetric_weights = ["k1"]\n')
    law = load_law(path)
    assert law.prony_volumetric_weights == ("k1",)
    assert [name for name, _ in law.constants] == ["c10", "kappa"]  # the kernels never read g1, tau1, k1


@pytest.mark.parametrize("table, key, message", [
    ('weights = ["g1"]\n', "viscoelastic.times", "missing"),
    ('weights = ["g1"]\ntimes = ["tau1"]\nshift = 2\n', "viscoelastic.shift", "unknown key"),
    ('weights = ["g1"]\ntimes = ["tau9"]\n', "viscoelastic.times", "'tau9' is not a parameter"),
    ('weights = ["g1"]\ntimes = []\n', "viscoelastic.times", "non-empty list"),
    ('weights = ["g1", "tau1"]\ntimes = ["tau1"]\n', "viscoelastic.times", "1 times for 2 weights"),
    ('weights = ["c10"]\ntimes = ["tau1"]\n', "viscoelastic.weights", "read by the energy"),
    ('weights = ["g1"]\ntimes = ["g1"]\n', "viscoelastic", "named twice"),
    ('weights = ["g1"]\ntimes = ["tau1"]\nvolumetric_weights = ["k1", "g1"]\n', "viscoelastic.volumetric_weights",
     "2 volumetric weights for 1 terms"),
])

def test_prony_series_errors_name_file_and_key(tmp_path, table, key, message):
    path = tmp_path / "viscous.toml"
    path.write_text(_VISCOUS_LAW + "[viscoelastic]\n" + table)
    with pytest.raises(GeneratorInputError) as error:
        load_law(path)
    assert str(path) in str(error.value) and f"'{key}'" in str(error.value) and message in str(error.value)


def test_volumetric_weights_need_a_bulk_part(tmp_path):
    path = tmp_path / "viscous.toml"
    path.write_text('name = "viscous"\ndescription = "d"\nenergy = "c10*(I1 - 3)"\nparameters = ["c10", "g1", "tau1", "k1"]\n'
                    '[viscoelastic]\nweights = ["g1"]\ntimes = ["tau1"]\nvolumetric_weights = ["k1"]\n')
    with pytest.raises(GeneratorInputError, match=r"viscous.toml: key 'viscoelastic.volumetric_weights': .*no bulk part"):
        load_law(path)
