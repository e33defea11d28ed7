"""The anp split: averaged nodal pressure (Bonet and Burton 1998, in the
variational form). The element keeps the whole split's kernel of the full
energy; the runtime (assembly/nodal_pressure.hpp) subtracts the law's bulk
part U(J) at the element and adds it at the nodes, each node's J the volume
ratio of its patch of cells. One volume constraint per node instead of one
per cell: a tetrahedral mesh has about 5.5 times more cells than nodes, so
the constraints no longer outnumber the displacements.

Input: `Triple`. Output: `SplitLowering` with `NodalPressureIR` (the bulk
part and its derivatives), or `SplitRefused` off the one-point elements or
for a law without a bulk part.
"""
from __future__ import annotations

from ..ir import Flops, NodalPressureIR
from ..symbolic import law_bulk
from .common import SplitLowering, SplitRefused, Triple
from .whole import batch_pays, quadrature_flops


def lower(triple: Triple) -> SplitLowering:
    element = triple.element
    if len(triple.tables.weights) != 1 or element.order != 1:
        raise SplitRefused("offered on the one-point elements (tet4, tri3); the others with more points "
                           "take fbar (docs/formulations.md)")
    if not triple.law.bulk:
        raise SplitRefused("the law file declares no bulk part U(J) (`bulk`, or `isochoric` + `volumetric`)")
    flops = quadrature_flops(element, 1, triple.law_ir)
    return SplitLowering(split_ir=NodalPressureIR(batched=batch_pays(element, triple.law_ir), bulk=law_bulk(triple.law)),
                         flops=Flops(energy=flops.energy, gradient=flops.gradient, hessian=flops.hessian),
                         extra_consts=0, symbol_names=())
