"""Post-processing along the cracks: traces of facet unknowns, crack profiles, KKT residuals.

Sign conventions (DESIGN.md): t is the unit tangent of the crack from its first point
towards its last, nu is t turned by +90 degrees, [u] = u+ - u- with + the side nu points
into. normal_jump = [u].nu, tangential_jump = [u].t, normal_stress = (sigma nu).nu,
shear_stress = (sigma nu).t; compression is negative.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import ngsolve as ngs

from .geometry import CrackEdges

#: offset (relative to the edge length) of the stress sample point into the minus side
STRESS_SAMPLE_OFFSET = 1e-7


def edge_points(crack: CrackEdges, params) -> np.ndarray:
    """Points at the given parameters (0 = a, 1 = b) along every crack edge: (n, p, 2)."""
    params = np.asarray(params, dtype=float)
    return crack.a[:, None, :] + params[None, :, None] * (crack.b - crack.a)[:, None, :]


def facet_basis(space: ngs.FESpace, mesh: ngs.Mesh, crack: CrackEdges, params) -> tuple[np.ndarray, np.ndarray]:
    """Dofs and basis values of a facet space along the crack edges.

    Returns (dofs, B): dofs[e, k] is the k-th dof of crack edge e, and B[e, k, p] the
    value of its basis function at parameter params[p] of that edge (strictly inside).
    """
    dofs = np.array([space.GetDofNrs(ngs.NodeId(ngs.EDGE, int(e))) for e in crack.edge], dtype=int)
    dofs = dofs.reshape(len(crack), -1)
    pts = edge_points(crack, params).reshape(-1, 2)
    mpts = mesh(pts[:, 0], pts[:, 1], ngs.BND)
    gf = ngs.GridFunction(space)
    B = np.empty((dofs.shape[0], dofs.shape[1], len(params)))
    for k in range(dofs.shape[1]):
        gf.vec[:] = 0.0
        gf.vec.FV().NumPy()[dofs[:, k]] = 1.0
        B[:, k, :] = np.asarray(gf(mpts)).reshape(len(crack), len(params))
    return dofs, B


def endpoint_map(space: ngs.FESpace, mesh: ngs.Mesh, cracks, order: int) -> np.ndarray:
    """G: the jump-space dofs -> the values that must be >= 0.

    P0: the edge value (G = I). P1: the values at both end points of each edge,
    extrapolated exactly from the quarter points (never evaluated on a vertex).
    """
    n = space.ndof
    if order == 0:
        return np.eye(n)
    G = np.zeros((n, n))
    for crack in cracks:
        dofs, B = facet_basis(space, mesh, crack, [0.25, 0.75])
        ends = np.stack([1.5 * B[:, :, 0] - 0.5 * B[:, :, 1], 1.5 * B[:, :, 1] - 0.5 * B[:, :, 0]], axis=1)
        for e in range(len(crack)):
            G[np.ix_(dofs[e], dofs[e])] = ends[e]
    return G


@dataclass(frozen=True)
class CrackProfile:
    """Samples at the mid point of every crack edge, ordered along the crack."""

    s: np.ndarray
    x: np.ndarray
    y: np.ndarray
    normal_jump: np.ndarray
    tangential_jump: np.ndarray
    normal_stress: np.ndarray
    shear_stress: np.ndarray

    def to_dict(self) -> dict:
        return {k: [float(v) for v in getattr(self, k)] for k in self.__dataclass_fields__}


def crack_profile(mesh, crack: CrackEdges, jn_space, jn_vals, jt_vals, sigma) -> CrackProfile:
    """The crack profile of one crack from the jump dof values and the stress field."""
    dofs, B = facet_basis(jn_space, mesh, crack, [0.5])
    jn = np.einsum("ek,ek->e", jn_vals[dofs], B[:, :, 0])
    jt = np.einsum("ek,ek->e", jt_vals[dofs], B[:, :, 0])
    nu = crack.normal
    mid = crack.mid
    p = mid - STRESS_SAMPLE_OFFSET * crack.length[:, None] * nu
    sig = np.asarray(sigma(mesh(p[:, 0], p[:, 1]))).reshape(-1, 2, 2)
    traction = np.einsum("eij,ej->ei", sig, nu)
    return CrackProfile(
        s=crack.s_mid,
        x=mid[:, 0],
        y=mid[:, 1],
        normal_jump=jn,
        tangential_jump=jt,
        normal_stress=np.einsum("ei,ei->e", traction, nu),
        shear_stress=np.einsum("ei,ei->e", traction, crack.tangent),
    )


def kkt_residuals(profiles: list[CrackProfile]) -> dict:
    """Relative KKT residuals over all crack samples (DESIGN.md section 3).

    J = max |[u]|, P = max |sigma nu|; max_penetration = max(0, -min [u].nu)/J,
    max_tension = max(0, max sigma_n)/P, complementarity = max |sigma_n [u].nu|/(J P);
    each is absolute where J or P is zero. No crack: all zero.
    """
    if not profiles or sum(len(p.s) for p in profiles) == 0:
        return {"max_penetration": 0.0, "max_tension": 0.0, "complementarity": 0.0}
    jn = np.concatenate([p.normal_jump for p in profiles])
    jt = np.concatenate([p.tangential_jump for p in profiles])
    sn = np.concatenate([p.normal_stress for p in profiles])
    st = np.concatenate([p.shear_stress for p in profiles])
    J = float(np.max(np.hypot(jn, jt)))
    P = float(np.max(np.hypot(sn, st)))
    J_ = J if J > 0 else 1.0
    P_ = P if P > 0 else 1.0
    return {
        "max_penetration": float(max(0.0, -jn.min()) / J_),
        "max_tension": float(max(0.0, sn.max()) / P_),
        "complementarity": float(np.max(np.abs(sn * jn)) / (J_ * P_)),
    }
