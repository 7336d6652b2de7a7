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

from .geometry import CrackEdges, CrackMesh



def _local_coordinate(crack_mesh: CrackMesh) -> ngs.CoefficientFunction:
    """s = (x - mid_e).t_e / L_e on every crack edge e: in [-1/2, 1/2] along each edge.

    Built from constants per boundary element (SurfaceL2 of order 0), so it is exact
    on every crack edge whatever its position: no cancellation far from the origin.
    """
    mesh = crack_mesh.mesh
    space = ngs.SurfaceL2(mesh, order=0)
    coeffs = [ngs.GridFunction(space) for _ in range(3)]  # t_x / L, t_y / L, -(mid.t) / L
    arrays = [c.vec.FV().NumPy() for c in coeffs]
    for crack in crack_mesh.cracks:
        for k in range(len(crack)):
            d = space.GetDofNrs(ngs.ElementId(ngs.BND, int(crack.bnd[k])))[0]
            t, L, mid = crack.tangent[k], crack.length[k], crack.mid[k]
            arrays[0][d], arrays[1][d], arrays[2][d] = t[0] / L, t[1] / L, -np.dot(mid, t) / L
    return coeffs[0] * ngs.x + coeffs[1] * ngs.y + coeffs[2]


def facet_moments(space: ngs.FESpace, crack_mesh: CrackMesh, degree: int) -> np.ndarray:
    """M[d, j] = int phi_d s^j ds over the crack edges, j = 0..degree (s as above)."""
    s_loc = _local_coordinate(crack_mesh)
    v = space.TestFunction()
    out = np.empty((space.ndof, degree + 1))
    for j in range(degree + 1):
        lf = ngs.LinearForm(space)
        lf += (s_loc**j if j else ngs.CF(1.0)) * v * ngs.ds(definedon=crack_mesh.crack_region, bonus_intorder=degree + 2)
        lf.Assemble()
        out[:, j] = lf.vec.FV().NumPy()
    return out


def facet_basis(space: ngs.FESpace, crack_mesh: CrackMesh, crack: CrackEdges, params, moments=None):
    """Dofs and basis values of a facet space (P_p per edge) along the crack edges.

    Returns (dofs, B): dofs[e, k] is the k-th dof of crack edge e, and B[e, k, q] the
    value of its basis function at parameter params[q] (0 = a, 1 = b) of that edge.
    NGSolve cannot evaluate facet functions at points; their p + 1 moments against
    s^j on each edge determine the polynomial of degree p exactly.
    """
    dofs = np.array([space.GetDofNrs(ngs.NodeId(ngs.EDGE, int(e))) for e in crack.edge], dtype=int)
    dofs = dofs.reshape(len(crack), -1)
    p = dofs.shape[1] - 1
    M = moments if moments is not None else facet_moments(space, crack_mesh, p)
    # int_{-1/2}^{1/2} s^(i+j) ds, times the edge length, maps monomial coefficients to moments
    i = np.arange(p + 1)
    e_ = i[:, None] + i[None, :]
    H = np.where(e_ % 2 == 0, 2.0 * 0.5 ** (e_ + 1) / (e_ + 1), 0.0)
    m = M[dofs][:, :, : p + 1] / crack.length[:, None, None]  # (edge, basis, j)
    coef = np.linalg.solve(H[None], np.transpose(m, (0, 2, 1)))  # (edge, i, basis)
    W = np.vander(np.asarray(params, dtype=float) - 0.5, p + 1, increasing=True)  # (q, i)
    B = np.einsum("qi,eik->ekq", W, coef)
    return dofs, B


def endpoint_map(space: ngs.FESpace, crack_mesh: CrackMesh, order: int) -> np.ndarray:
    """G: the jump-space dofs -> the values that must be >= 0.

    P0: the edge value (G = I). P_p, p >= 1: the values at p + 1 equispaced points of
    each edge, end points included (for P1 exactly non-negativity on the edge).
    """
    n = space.ndof
    if order == 0:
        return np.eye(n)
    G = np.zeros((n, n))
    points = np.linspace(0.0, 1.0, order + 1)
    moments = facet_moments(space, crack_mesh, order)
    for crack in crack_mesh.cracks:
        dofs, B = facet_basis(space, crack_mesh, crack, points, moments)
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


#: offset (times the edge length) of the two sides' stress samples for two-sided tractions:
#: large enough for the point search to land on the intended side at any scale
SIDE_OFFSET = 1e-3


def crack_profile(crack_mesh: CrackMesh, crack: CrackEdges, jump_space, jn_vals, jt_vals, sigma,
                  displacement=None, jumps=None, two_sided: bool = False) -> CrackProfile:
    """The crack profile of one crack from the jump dof values and the stress field.

    `jumps` = (normal, tangential) at the mid points, where the element computes them
    itself; otherwise the normal jump comes from the jn facet unknowns, the tangential
    jump from the jt facet unknowns or, with `displacement` given, from the tangential component of that
    field at the mid point: a field whose tangential trace on a crack edge is
    single-valued and equal to [u].t (TDNNS: the crack edges' HCurl copy u_e).
    `two_sided`: average the traction of both sides (post-computed stresses).
    """
    mesh = crack_mesh.mesh
    nu = crack.normal
    mid = crack.mid
    if jumps is not None:
        jn, jt = jumps
    else:
        dofs, B = facet_basis(jump_space, crack_mesh, crack, [0.5])
        jn = np.einsum("ek,ek->e", jn_vals[dofs], B[:, :, 0])
        if displacement is None:
            jt = np.einsum("ek,ek->e", jt_vals[dofs], B[:, :, 0])
        else:
            vals = np.asarray(displacement(mesh(mid[:, 0], mid[:, 1]))).reshape(len(crack), 2)
            jt = np.einsum("ei,ei->e", vals, crack.tangent)
    # the mixed elements' sigma nu is single-valued on an edge (the facet trace enforces
    # normal continuity exactly), so either neighbour of the mid point gives it
    if two_sided:
        d = SIDE_OFFSET * crack.length[:, None] * nu
        sig = 0.5 * sum(np.asarray(sigma(mesh(p[:, 0], p[:, 1]))).reshape(-1, 2, 2) for p in (mid + d, mid - d))
    else:
        sig = np.asarray(sigma(mesh(mid[:, 0], mid[:, 1]))).reshape(-1, 2, 2)
    traction = np.einsum("eij,ej->ei", sig, nu)
    shear = np.einsum("ei,ei->e", traction, crack.tangent)
    return CrackProfile(
        s=crack.s_mid,
        x=mid[:, 0],
        y=mid[:, 1],
        normal_jump=jn,
        tangential_jump=jt,
        normal_stress=np.einsum("ei,ei->e", traction, nu),
        shear_stress=shear,
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


def field_scales(crack_mesh: CrackMesh, u, sigma) -> tuple[float, float]:
    """max |u| and max |sigma| (Frobenius) over the triangles' centroids."""
    mesh = crack_mesh.mesh
    # every centroid mapped from the reference triangle at once (no point search)
    mp = mesh.MapToAllElements({ngs.ET.TRIG: ngs.IntegrationRule([(1 / 3, 1 / 3, 0)], [0.5])}, ngs.VOL)
    uu = np.asarray(u(mp)).reshape(mesh.ne, -1)
    ss = np.asarray(sigma(mp)).reshape(mesh.ne, -1)
    return float(np.max(np.linalg.norm(uu, axis=1))), float(np.max(np.linalg.norm(ss, axis=1)))
