"""The BDM-based element (Brezzi, Douglas, Marini; Arnold, Falk, Winther), hybridized.

Order k = 1, 2, 3 (`order`, default 1), the Arnold-Falk-Winther family for weakly
symmetric stress (Arnold, Falk, Winther 2007, Math. Comp. 76; Boffi, Brezzi, Fortin
2009, Comput. Methods Appl. Mech. Engrg. 198):
- each stress row: BDM_k (full P_k vector fields, H(div)), broken;
- displacement u: discontinuous P_{k-1}^2; rotation r (the multiplier of weak
  symmetry): discontinuous P_{k-1};
- facet trace u_hat: P_k per edge (the normal-trace space of BDM_k), two components;
- crack jump (normal and tangential): P_k per crack edge, so the crack QP has
  k + 1 unknowns per edge and per component; jn >= 0 is imposed at k + 1 equispaced
  points of each edge, end points included (`post.endpoint_map`): exactly jn >= 0 on
  the edge for k = 1, at the points for k >= 2.

k = 1 is the paper's section 3.2 (piecewise affine multipliers). Expected rates for
smooth solutions: ||sigma - sigma_h||_L2 and ||u - u_h||_L2 of order h^k, uniformly in
nu up to 1/2 (the incompressible split of `base.py` needs only one pressure per
triangle at every k: c I with c constant is the only local stress that A, div and as
all annihilate).
"""

from __future__ import annotations

import ngsolve as ngs

from ...core.element_names import ORDERS as _ORDERS
from ...core.errors import InputError
from ..geometry import CrackMesh
from ..materials import Compliance
from .base import Discretization, ElementTraits, Loads, weakly_symmetric_hybrid

ORDERS = _ORDERS["bdm"]
DEFAULT_ORDER = 1
#: the rotation field completes grad u; a Prager-Synge estimate from the hybrid traces
TRAITS = ElementTraits(gradient="rotation", estimate="prager-synge", estimate_degree=2, hybrid_traces=True,
                       estimate_note="weak symmetry: the bound needs a Korn constant (not included)")


def _rows(sym):
    s1, s2 = sym
    return (s1, s2), (ngs.div(s1), ngs.div(s2))


def build(crack_mesh: CrackMesh, compliance: Compliance, loads: Loads, order: int | None = None) -> Discretization:
    """The hybridized BDM_k-P_{k-1}-P_{k-1} discretization of one scene, k = `order`."""
    k = DEFAULT_ORDER if order is None else order
    if isinstance(k, bool) or k not in ORDERS:
        raise InputError(f"order = {order!r}: allowed values for bdm are {', '.join(map(str, ORDERS))}")
    mesh = crack_mesh.mesh
    bdm = ngs.HDiv(mesh, order=k, RT=False, discontinuous=True)
    built = [f"stress rows: BDM{k}, broken", f"rotation: P{k - 1}"]
    return weakly_symmetric_hybrid(
        "bdm",
        crack_mesh,
        compliance,
        loads,
        stress_spaces=[bdm, bdm],
        rows=_rows,
        rotation_spaces=[ngs.L2(mesh, order=k - 1)],
        facet_order=k,
        built=built,
        displacement_order=k - 1,
        traits=TRAITS,
    )
