"""What every split's lowering takes and returns.

Input: `Triple`, one (law, element) with its element tables, optimised law
block, law derivatives and the tensor split's coefficient limit.
Output: `SplitLowering`, the split's IR with its flops, the constants it adds
after the per-point data and the C names of its own symbols; or `SplitRefused`.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..ir import Flops, SplitIR
from ..model import ElementSpec, ElementTables, LawDerivatives, LawKernelIR, LawSpec


class SplitRefused(Exception):
    """This split is not offered for this (law, element); the message says why."""


@dataclass(frozen=True)
class Triple:
    """One (law, element) to lower, with what the earlier stages computed for it."""
    law: LawSpec
    element: ElementSpec
    tables: ElementTables
    law_ir: LawKernelIR
    derivatives: LawDerivatives
    tensor_limit: int


@dataclass(frozen=True)
class SplitLowering:
    """A split's part of a KernelIR."""
    split_ir: SplitIR
    flops: Flops
    extra_consts: int  # doubles after the derived parameters and the per-point data
    symbol_names: tuple[tuple[str, str], ...]  # the split's own symbols -> C expressions


def point_stride(element: ElementSpec) -> int:
    """Doubles per quadrature point in the constants: w, then G^T (dim by nodes)."""
    return 1 + element.dim * element.node_count
