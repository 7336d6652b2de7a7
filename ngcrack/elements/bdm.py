"""The BDM-based element (Brezzi, Douglas, Marini; Arnold, Falk, Winther), hybridized.

Each stress row lies in BDM1 (full P1 vector fields), the displacement in P0^2 and the
rotation in P0: the lowest-order stable element for weakly symmetric stress. The rows
are broken; the facet trace u_hat is P1 per edge (the normal-trace space of BDM1), and
so is the crack jump, as in the paper's section 3.2 (piecewise affine multipliers).
"""

from __future__ import annotations

import ngsolve as ngs

from ..geometry import CrackMesh
from ..materials import Compliance
from .base import Discretization, Loads, weakly_symmetric_hybrid


def _rows(sym):
    s1, s2 = sym
    return (s1, s2), (ngs.div(s1), ngs.div(s2))


def build(crack_mesh: CrackMesh, compliance: Compliance, loads: Loads) -> Discretization:
    """The hybridized BDM1-P0-P0 discretization of one scene."""
    mesh = crack_mesh.mesh
    bdm1 = ngs.HDiv(mesh, order=1, RT=False, discontinuous=True)
    built = ["stress rows: BDM1, broken", "rotation: P0"]
    return weakly_symmetric_hybrid(
        "bdm",
        crack_mesh,
        compliance,
        loads,
        stress_spaces=[bdm1, bdm1],
        rows=_rows,
        rotation_spaces=[ngs.L2(mesh, order=0)],
        rotation=lambda sym: sym[0],
        facet_order=1,
        built=built,
    )
