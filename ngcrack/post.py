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

from .geometry import CrackEdges, CrackMesh, crack_frame_cf



def crack_moments(space: ngs.FESpace, crack_mesh: CrackMesh) -> tuple[np.ndarray, np.ndarray]:
    """M0[d] = int phi_d ds and Mt[d] = int phi_d (x.t) ds over the crack edges.

    Integrated over the minus side's element boundary, so each crack edge counts once.
    """
    nu, t = crack_frame_cf(crack_mesh)
    chi = ngs.IfPos(ngs.specialcf.normal(2) * nu - 0.5, 1.0, 0.0)
    v = space.TestFunction()
    xt = ngs.x * t[0] + ngs.y * t[1]
    out = []
    for weight in (chi, chi * xt):
        lf = ngs.LinearForm(space)
        lf += weight * v * ngs.dx(element_boundary=True, bonus_intorder=2)
        lf.Assemble()
        out.append(lf.vec.FV().NumPy().copy())
    return out[0], out[1]


def facet_basis(space: ngs.FESpace, crack_mesh: CrackMesh, crack: CrackEdges, params, moments=None):
    """Dofs and basis values of a facet space (P0 or P1 per edge) along the crack edges.

    Returns (dofs, B): dofs[e, k] is the k-th dof of crack edge e, and B[e, k, p] the
    value of its basis function at parameter params[p] (0 = a, 1 = b) of that edge.
    The values come exactly from the two moments of each (linear) basis function.
    """
    M0, Mt = moments if moments is not None else crack_moments(space, crack_mesh)
    dofs = np.array([space.GetDofNrs(ngs.NodeId(ngs.EDGE, int(e))) for e in crack.edge], dtype=int)
    dofs = dofs.reshape(len(crack), -1)
    L = crack.length[:, None]
    at = np.einsum("ei,ei->e", crack.a, crack.tangent)[:, None]
    m0 = M0[dofs] / L  # int_0^1 phi
    m1 = (Mt[dofs] - at * M0[dofs]) / L**2  # int_0^1 phi sigma
    c1 = 12.0 * (m1 - 0.5 * m0)
    c0 = m0 - 0.5 * c1
    params = np.asarray(params, dtype=float)
    B = c0[:, :, None] + c1[:, :, None] * params[None, None, :]
    return dofs, B


def endpoint_map(space: ngs.FESpace, crack_mesh: CrackMesh, order: int) -> np.ndarray:
    """G: the jump-space dofs -> the values that must be >= 0.

    P0: the edge value (G = I). P1: the values at both end points of each edge,
    extrapolated exactly from the quarter points (never evaluated on a vertex).
    """
    n = space.ndof
    if order == 0:
        return np.eye(n)
    G = np.zeros((n, n))
    moments = crack_moments(space, crack_mesh)
    for crack in crack_mesh.cracks:
        dofs, B = facet_basis(space, crack_mesh, crack, [0.0, 1.0], moments)
        for e in range(len(crack)):
            G[np.ix_(dofs[e], dofs[e])] = B[e].T
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


def crack_profile(crack_mesh: CrackMesh, crack: CrackEdges, jump_space, jn_vals, jt_vals, sigma, moments=None) -> CrackProfile:
    """The crack profile of one crack from the jump dof values and the stress field."""
    mesh = crack_mesh.mesh
    dofs, B = facet_basis(jump_space, crack_mesh, crack, [0.5], moments)
    jn = np.einsum("ek,ek->e", jn_vals[dofs], B[:, :, 0])
    jt = np.einsum("ek,ek->e", jt_vals[dofs], B[:, :, 0])
    nu = crack.normal
    mid = crack.mid
    # sigma nu is single-valued on an edge (the facet trace enforces normal continuity
    # exactly), so either neighbour of the mid point gives the same traction
    sig = np.asarray(sigma(mesh(mid[:, 0], mid[:, 1]))).reshape(-1, 2, 2)
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


#: J or P below this fraction of the body's displacement or stress scale counts as zero
ZERO_RTOL = 1e-8


def kkt_residuals(profiles: list[CrackProfile], u_scale: float = 0.0, sigma_scale: float = 0.0) -> dict:
    """Relative KKT residuals over all crack samples (DESIGN.md section 3).

    J = max |[u]|, P = max |sigma nu|; max_penetration = max(0, -min [u].nu)/J,
    max_tension = max(0, max sigma_n)/P, complementarity = max |sigma_n [u].nu|/(J P).
    Where J (or P) is zero, up to round-off (below ZERO_RTOL times the body's
    displacement scale `u_scale`, or stress scale `sigma_scale`), the residual is taken
    relative to that body scale instead (or absolute if the scale is zero too).
    No crack: all zero.
    """
    if not profiles or sum(len(p.s) for p in profiles) == 0:
        return {"max_penetration": 0.0, "max_tension": 0.0, "complementarity": 0.0}
    jn = np.concatenate([p.normal_jump for p in profiles])
    jt = np.concatenate([p.tangential_jump for p in profiles])
    sn = np.concatenate([p.normal_stress for p in profiles])
    st = np.concatenate([p.shear_stress for p in profiles])
    J = float(np.max(np.hypot(jn, jt)))
    P = float(np.max(np.hypot(sn, st)))
    J_ = J if J > ZERO_RTOL * u_scale and J > 0 else (u_scale or 1.0)
    P_ = P if P > ZERO_RTOL * sigma_scale and P > 0 else (sigma_scale or 1.0)
    return {
        "max_penetration": float(max(0.0, -jn.min()) / J_),
        "max_tension": float(max(0.0, sn.max()) / P_),
        "complementarity": float(np.max(np.abs(sn * jn)) / (J_ * P_)),
    }


def field_scales(mesh: ngs.Mesh, u, sigma) -> tuple[float, float]:
    """max |u| and max |sigma| (Frobenius) over the triangles' centroids."""
    pts = np.array([np.mean([mesh[v].point for v in el.vertices], axis=0) for el in mesh.Elements(ngs.VOL)])
    mp = mesh(pts[:, 0], pts[:, 1])
    uu = np.asarray(u(mp)).reshape(len(pts), -1)
    ss = np.asarray(sigma(mp)).reshape(len(pts), -1)
    return float(np.max(np.linalg.norm(uu, axis=1))), float(np.max(np.linalg.norm(ss, axis=1)))
