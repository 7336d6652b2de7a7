"""PEERS (Arnold, Brezzi, Douglas 1984), hybridized: the paper's section 3.1.

Each stress row lies in RT0 + curl(b_T), b_T = lambda_1 lambda_2 lambda_3 the cubic
bubble; the displacement is P0^2, the rotation (the multiplier of weak symmetry) is
continuous P1. The rows are broken (no normal continuity between triangles); the facet
trace u_hat (P0 per edge) restores it, and the crack jump is P0 per crack edge.

Only the lowest order. PEERS has a stable higher-order family (Arnold, Brezzi, Douglas
1984: RT_k + curl(b_T P_k) rows, P_k displacement, continuous P_{k+1} rotation), but its
continuous rotation is a global unknown that static condensation cannot remove, so the
condensed system grows by the rotation's vertex, edge and interior dofs at every order;
the Arnold-Falk-Winther family (`bdm` with `order=k`) reaches the same rates h^k with
only the facet traces global. Use bdm for higher order.
"""

from __future__ import annotations

import ngsolve as ngs

from ..geometry import CrackMesh
from ..materials import Compliance
from .base import Discretization, ElementTraits, Loads, weakly_symmetric_hybrid

#: the rotation field completes grad u; a Prager-Synge estimate from the hybrid traces
TRAITS = ElementTraits(gradient="rotation", estimate="prager-synge", estimate_degree=1, hybrid_traces=True,
                       estimate_note="weak symmetry: the bound needs a Korn constant (not included)")


def cubic_bubbles(mesh: ngs.Mesh) -> ngs.FESpace:
    """The span of the cubic bubble b_T on each triangle: the interior dofs of H1 order 3.

    The edges are given order 1 (no edge dofs), so that each triangle's element has 4
    shape functions (3 vertex, 1 bubble) instead of the 10 of a full cubic element;
    NGSolve's face bubble of order 3 does not depend on the edge orders, so the
    compressed space (the bubbles only) is the same. The bubbles are the space's local
    dofs (free, but not coupling).
    """
    h1 = ngs.H1(mesh, order=3)
    h1.SetOrder(ngs.ET.SEGM, 1)
    h1.Update()
    interior = ngs.BitArray(h1.FreeDofs(False)) & ~h1.FreeDofs(True)
    return ngs.Compress(h1, active_dofs=interior)


def _rows(sym):
    s1, s2, b1, b2 = sym

    def curl(b):
        g = ngs.grad(b)
        return ngs.CF((g[1], -g[0]))

    return (s1 + curl(b1), s2 + curl(b2)), (ngs.div(s1), ngs.div(s2))


def _normal_trace_rows(sym):
    """The rows without the bubble curls: curl(b_T).n is the tangential derivative of
    b_T along dT, where b_T vanishes, so the normal traces are those of the RT0 parts."""
    s1, s2, _, _ = sym
    return s1, s2


def build(crack_mesh: CrackMesh, compliance: Compliance, loads: Loads) -> Discretization:
    """The hybridized PEERS discretization of one scene."""
    mesh = crack_mesh.mesh
    rt0 = ngs.HDiv(mesh, order=0, discontinuous=True)
    bubble = cubic_bubbles(mesh)
    built = ["stress rows: RT0 + curl(cubic bubble), broken", "rotation: continuous P1"]
    rotation_spaces = [ngs.H1(mesh, order=1)]
    return weakly_symmetric_hybrid(
        "peers",
        crack_mesh,
        compliance,
        loads,
        stress_spaces=[rt0, rt0, bubble, bubble],
        rows=_rows,
        rotation_spaces=rotation_spaces,
        facet_order=0,
        built=built,
        trace_rows=_normal_trace_rows,
        traits=TRAITS,
    )
