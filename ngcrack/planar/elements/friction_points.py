"""Where the 2D families impose the Coulomb law: the crack's constraint points and weights.

The Coulomb law is imposed at the QP's constraint points (edge mid points for P0
jumps, the p + 1 equispaced points of each edge for P_p jumps, the nodes of the
displacement baselines), each with the nodal quadrature weight of the jump space
(`constraint_points`); the tangential jumps reach those points through
`tangential_point_map`. Both walk the crack edges of a 2D mesh; the elements reach them
through `Discretization.friction_points` and `Discretization.tangential_point_map`.
"""

from __future__ import annotations

import numpy as np

from ...core.friction import NEWTON_COTES


def constraint_points(disc, crack_mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(crack index, arc length s, quadrature weight) of every constrained value w_i.

    Points are numbered like the normal jump space's dofs (the rows of its constraint
    map). Facet P_p jumps: the p + 1 equispaced points of each edge, Newton-Cotes
    weights. Displacement baselines: crack nodes (trapezoidal: half of each adjacent
    edge, P1; Simpson: a sixth, P2) and, for P2, edge mid points (two thirds).
    """
    import ngsolve as ngs

    space = disc.fes.components[disc.jn]
    n = space.ndof
    crack_of = np.full(n, -1, dtype=int)
    s_of = np.zeros(n)
    weight = np.zeros(n)
    nodal = disc.nodal_constraints
    for k, crack in enumerate(crack_mesh.cracks):
        for e in range(len(crack)):
            L = crack.length[e]
            edge_dofs = [d for d in space.GetDofNrs(ngs.NodeId(ngs.EDGE, int(crack.edge[e])))]
            if not nodal:
                p = len(edge_dofs) - 1
                for q, d in enumerate(edge_dofs):
                    crack_of[d] = k
                    s_of[d] = crack.s_mid[e] + ((q / p if p else 0.5) - 0.5) * L
                    weight[d] += NEWTON_COTES[p][q] * L
                continue
            end_w = 0.5 if not edge_dofs else 1.0 / 6.0
            for d in edge_dofs:
                crack_of[d], s_of[d] = k, crack.s_mid[e]
                weight[d] += (1.0 - 2 * end_w) * L
            for v, sv in ((int(crack.va[e]), crack.s_mid[e] - 0.5 * L), (int(crack.vb[e]), crack.s_mid[e] + 0.5 * L)):
                for d in space.GetDofNrs(ngs.NodeId(ngs.VERTEX, v)):
                    if d >= 0:
                        crack_of[d], s_of[d] = k, sv
                        weight[d] += end_w * L
    return crack_of, s_of, weight


def tangential_point_map(disc, crack_mesh, normal_map: np.ndarray) -> np.ndarray:
    """Gt_full: tangential jump dofs -> tangential values at the constraint points.

    Where the tangential jump lives in the normal jump's space (peers, bdm, the
    baselines) it is the normal map. TDNNS: the crack edges' HCurl copy u_e, whose
    tangential trace on a crack edge is [u].t, a polynomial of degree k; it is
    sampled at k + 1 Gauss points inside each edge (one side's evaluation: the trace
    is single-valued) and extrapolated to the edge's k + 1 constraint points.
    """
    import ngsolve as ngs

    if disc.jt is not None:
        return normal_map
    space_n = disc.fes.components[disc.jn]
    space_t = disc.fes.components[disc.tangential]
    mesh = crack_mesh.mesh
    Gt = np.zeros((space_n.ndof, space_t.ndof))
    gf = ngs.GridFunction(space_t)
    for crack in crack_mesh.cracks:
        dn = np.array([space_n.GetDofNrs(ngs.NodeId(ngs.EDGE, int(e))) for e in crack.edge], dtype=int)
        dt = np.array([space_t.GetDofNrs(ngs.NodeId(ngs.EDGE, int(e))) for e in crack.edge], dtype=int)
        p = dn.shape[1] - 1
        if dt.shape[1] != p + 1:
            raise ValueError(f"friction: element {disc.element!r}: {dt.shape[1]} tangential dofs per crack edge "
                             f"against {p + 1} constraint points")
        gauss = 0.5 * (np.polynomial.legendre.leggauss(p + 1)[0] + 1.0)
        targets = np.linspace(0.0, 1.0, p + 1) if p else np.array([0.5])
        # values at the Gauss points -> values at the targets (exact for degree p)
        V = np.vander(gauss - 0.5, p + 1, increasing=True)
        T = np.vander(targets - 0.5, p + 1, increasing=True)
        extrap = T @ np.linalg.inv(V)  # (target, gauss)
        pts = crack.a[:, None, :] + gauss[None, :, None] * (crack.b - crack.a)[:, None, :]  # (edge, gauss, 2)
        flat = pts.reshape(-1, 2)
        mp = mesh(flat[:, 0], flat[:, 1])
        for j in range(p + 1):
            vec = gf.vec.FV().NumPy()
            vec[:] = 0.0
            vec[dt[:, j]] = 1.0
            vals = np.asarray(gf(mp)).reshape(len(crack), p + 1, 2)
            tang = np.einsum("egi,ei->eg", vals, crack.tangent)  # (edge, gauss)
            at_targets = tang @ extrap.T  # (edge, target)
            for e in range(len(crack)):
                Gt[dn[e], dt[e, j]] = at_targets[e]
    return Gt
