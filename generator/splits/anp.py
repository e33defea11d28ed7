"""The anp split: averaged nodal pressure (Bonet and Burton 1998, in the
variational form). The element keeps a kernel of the full energy, with one
volume ratio J_e per cell: the whole split's on the one-point elements
(tet4, tri3), the fbar split's (J_e = J̄) on the first-order elements the
mean dilatation alone does not free (prism6). The runtime
(assembly/nodal_pressure.hpp) subtracts the law's bulk part U(J_e) at the
element and adds it at the nodes, each node's J the volume ratio of its
patch of cells. One volume constraint per node instead of one per cell: a
tetrahedral mesh has about 5.5 times more cells than nodes, so the
constraints no longer outnumber the displacements.

Input: `Triple`. Output: `SplitLowering` with `NodalPressureIR` (the bulk
part and its derivatives, the base split), or `SplitRefused` on the other
elements or for a law without a bulk part.
"""
from __future__ import annotations

from ..ir import NodalPressureIR
from ..symbolic import law_bulk
from .common import SplitLowering, SplitRefused, Triple
from .fbar import NOT_FREED, formulation_flops
from .whole import batch_pays, quadrature_flops


def lower(triple: Triple) -> SplitLowering:
    element = triple.element
    points = len(triple.tables.weights)
    one_point = points == 1 and element.order == 1
    if not one_point and element.name not in NOT_FREED:
        raise SplitRefused("offered on the one-point elements (tet4, tri3) and those the mean dilatation "
                           "does not free (prism6); the others take fbar (docs/formulations.md)")
    if not triple.law.bulk:
        raise SplitRefused("the law file declares no bulk part U(J) (`bulk`, or `isochoric` + `volumetric`)")
    bulk = law_bulk(triple.law)
    if one_point:
        split_ir = NodalPressureIR(batched=batch_pays(element, triple.law_ir), bulk=bulk, base="whole")
        flops = quadrature_flops(element, 1, triple.law_ir)
    else:
        split_ir = NodalPressureIR(batched=False, bulk=bulk, base="fbar")
        flops = formulation_flops(element, points, triple.law_ir)
    return SplitLowering(split_ir=split_ir, flops=flops, extra_consts=0, symbol_names=())
