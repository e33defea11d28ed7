"""Stage 4 (lower): the dispatcher, the split-specific lowering
(generator/splits/) and the typed, immutable lowered IR."""
from __future__ import annotations

import dataclasses
import functools

import pytest
import sympy

from conftest import ROOT
from generator.ir import (ElementIR, Flops, KernelIR, LoweredIR, TensorIR, TensorLayout, TermsIR,
                          WholeIR)
from generator.load import load_element, load_law
from generator.lower import SPLITS, SplitRefused, build_kernel_ir, lower
from generator.model import Inputs
from generator.optimize import optimise
from generator.splits.tensor import tensor_layout
from generator.symbolic import derive


@functools.lru_cache(maxsize=None)
def _lowered() -> LoweredIR:
    """hooke, neohookean and stvk on tri3, tet4 and tet10: every split, offered or refused."""
    elements = tuple(load_element(ROOT / "elements" / f"{n}.toml") for n in ("tet10", "tet4", "tri3"))
    laws = tuple(load_law(ROOT / "laws" / f"{n}.toml") for n in ("hooke", "neohookean", "stvk"))
    return lower(optimise(derive(Inputs(elements=elements, laws=laws))))


def _kernel(law: str, element: str, split: str) -> KernelIR:
    return next(k for k in _lowered().kernels
                if (k.law.name, k.element.name, k.split) == (law, element, split))


def test_tensor_split_refusals():
    stvk = load_law(ROOT / "laws" / "stvk.toml")
    hex8 = load_element(ROOT / "elements" / "hex8.toml")
    tet10 = load_element(ROOT / "elements" / "tet10.toml")
    optimised = optimise(derive(Inputs(elements=(hex8, tet10), laws=(stvk,))))
    with pytest.raises(SplitRefused, match="first-order"):
        build_kernel_ir(optimised, stvk, tet10, "tensor")
    with pytest.raises(SplitRefused, match="over the limit 100"):
        build_kernel_ir(optimised, stvk, hex8, "tensor", tensor_limit=100)
    assert build_kernel_ir(optimised, stvk, hex8, "tensor").consts_size > 2000


def test_lower_orders_kernels_and_gives_refusals_reasons():
    lowered = _lowered()
    triples = [(k.law.name, k.element.name, k.split) for k in lowered.kernels]
    assert triples == sorted(triples, key=lambda t: (t[0], t[1], SPLITS.index(t[2])))
    refused = {(r.law, r.element, r.split): r.reason for r in lowered.refused}
    assert "first-order" in refused[("stvk", "tet10", "tensor")]
    assert "one strain measure" in refused[("neohookean", "tet4", "tensor")]
    assert all(split in ("tensor", "fbar", "anp") for _, _, split in refused)
    assert "one quadrature point" in refused[("stvk", "tet4", "fbar")]
    assert "first-order" in refused[("stvk", "tet10", "fbar")]
    assert "one-point" in refused[("hooke", "tet10", "anp")]
    assert "bulk part" in refused[("stvk", "tet4", "anp")]
    assert len(lowered.kernels) + len(lowered.refused) == 3 * 3 * len(SPLITS)


def test_each_split_has_its_typed_ir():
    assert isinstance(_kernel("stvk", "tet4", "whole").split_ir, WholeIR)
    terms = _kernel("stvk", "tet4", "terms").split_ir
    assert isinstance(terms, TermsIR)
    assert sorted(n for p in terms.parts for n in p.nodes) == [0, 1, 2, 3]
    assert [a.target for a in terms.h_block.assignments if not a.declare] == [f"H[{i}]" for i in range(9)]
    tensor = _kernel("stvk", "tet4", "tensor").split_ir
    assert isinstance(tensor, TensorIR) and tensor.green
    assert tensor.layout == tensor_layout(load_element(ROOT / "elements" / "tet4.toml"), "E")
    assert not _kernel("hooke", "tri3", "tensor").split_ir.green


def test_tensor_layout_matches_tensor_split_hpp():
    """Pairs j <= k row-major, K, V, D sizes as tensormass::kernel::tensor::Layout."""
    layout = tensor_layout(load_element(ROOT / "elements" / "tet4.toml"), "E")
    assert layout.pairs[:5] == ((0, 0), (0, 1), (0, 2), (0, 3), (1, 1))
    assert (layout.k_size, layout.v_size, layout.d_size, layout.total) == (144, 120, 100, 364)
    linear = tensor_layout(load_element(ROOT / "elements" / "tri3.toml"), "eps")
    assert (linear.k_size, linear.v_size, linear.d_size, linear.total) == (36, 0, 0, 36)


def test_kernel_constants_and_flops():
    whole, tensor = _kernel("stvk", "tet4", "whole"), _kernel("stvk", "tet4", "tensor")
    assert whole.consts_size == 2 + 1 * (1 + 3 * 4)  # lam, mu; one point: w and G^T
    assert tensor.consts_size == whole.consts_size + 364
    assert isinstance(whole.flops, Flops) and whole.flops.hessian > whole.flops.gradient > 0
    assert _kernel("hooke", "tri3", "tensor").flops.hessian == 0  # a constant K is copied


def test_elasticity_entries_are_the_non_zero_ones():
    tensor = _kernel("hooke", "tri3", "tensor").split_ir
    lam, mu = sympy.Symbol("lam", real=True), sympy.Symbol("mu", real=True)
    entries = dict(tensor.elasticity)
    assert entries[0] == lam + 2 * mu  # CC[0][0][0][0]
    assert entries[((0 * 2 + 1) * 2 + 0) * 2 + 1] == mu  # CC[0][1][0][1]
    assert ((0 * 2 + 0) * 2 + 0) * 2 + 1 not in entries  # CC[0][0][0][1] = 0
    assert all(value != 0 for value in entries.values())


def test_terms_symbol_names_map_to_c_storage():
    names = dict(_kernel("stvk", "tri3", "terms").symbol_names)
    assert names["H3"] == "H[3]" and names["u5"] == "u[5]"
    assert names["G1_2"] == "GT[5]"  # G_{c=1, j=2} at GT[c * n + j], n = 3
    assert names["wP2"] == "wP[2]" and names["wA0"] == "wA[0]"


def test_element_ir():
    lowered = _lowered()
    tet4 = next(e for e in lowered.elements if e.name == "tet4")
    assert isinstance(tet4, ElementIR)
    assert tet4.edge_size == 2 and len(tet4.edges) == 6
    assert tet4.face_offsets == (0, 3, 6, 9)
    assert tet4.reference_nodes[3:6] == (1.0, 0.0, 0.0)
    assert tet4.shape_values == (0.25, 0.25, 0.25, 0.25)
    tri3 = next(e for e in lowered.elements if e.name == "tri3")
    assert tri3.faces == () and tri3.face_offsets == ()


def _fields_are_immutable(value, path="ir"):
    """No dict, list or set anywhere in a lowered IR value; every dataclass frozen."""
    assert not isinstance(value, (dict, list, set)), f"{path} is a {type(value).__name__}"
    if dataclasses.is_dataclass(value):
        assert type(value).__dataclass_params__.frozen, f"{path}: {type(value).__name__} is not frozen"
        for f in dataclasses.fields(value):
            _fields_are_immutable(getattr(value, f.name), f"{path}.{f.name}")
    elif isinstance(value, tuple):
        for i, item in enumerate(value[:50]):
            _fields_are_immutable(item, f"{path}[{i}]")


def test_lowered_ir_has_no_untyped_or_mutable_containers():
    lowered = _lowered()
    _fields_are_immutable(lowered)
    with pytest.raises(dataclasses.FrozenInstanceError):
        lowered.kernels[0].flops.energy = 0
    for cls in (Flops, TermsIR, TensorIR, TensorLayout, WholeIR, KernelIR, ElementIR, LoweredIR):
        annotations = " ".join(str(f.type) for f in dataclasses.fields(cls))
        assert "dict" not in annotations and "list" not in annotations, cls.__name__
