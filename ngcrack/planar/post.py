"""Post-processing along the cracks: traces of facet unknowns, crack profiles, KKT residuals.

Sign conventions: t is the unit tangent of the crack from its first point
towards its last, nu is t turned by +90 degrees, [u] = u+ - u- with + the side nu points
into. normal_jump = [u].nu, tangential_jump = [u].t, normal_stress = (sigma nu).nu,
shear_stress = (sigma nu).t; compression is negative.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np

from ..core.constraints import CLOSED_RTOL, faces_closed
from ..core.csr import distinct
from .elements.facets import endpoint_map, facet_basis, facet_moments  # noqa: F401  (re-exported)
from .geometry import CrackEdges, CrackMesh

# a sample is "open" where its faces are not closed (constraints.faces_closed: the same rule
# as the crack problem's point states) and sigma_n is not below -CLOSED_RTOL times the
# stress scale (compressed beyond round-off)


def profile_states(normal_jump, tangential_jump, normal_stress, friction: float = 0.0,
                   stress_scale: float = 0.0, face_pressure=None) -> np.ndarray:
    """open / stick / slip per sample, from that sample's own jump and stress.

    A sample is open where its faces separate, [u].nu > CLOSED_RTOL W (W the crack's
    largest |[u]|: constraints.faces_closed), and carry no compression, sigma_n >= -CLOSED_RTOL S (S the stress
    scale: in `crack_profile` the largest |sigma|, Frobenius, at the crack's samples): a
    sample with a small positive jump that is pressed together (the edge next to a tip,
    partly in contact) is closed. Closed samples stick where the crack carries friction
    and |[u].t| <= CLOSED_RTOL W, else slip (a frictionless closed crack slides: "slip").
    With a crack-face pressure p (`face_pressure`), the compression is the net one,
    sigma_n + p (the contact's part of the face traction).
    """
    jn = np.asarray(normal_jump, dtype=float)
    jt = np.asarray(tangential_jump, dtype=float)
    sn = np.asarray(normal_stress, dtype=float)
    if face_pressure is not None:
        sn = sn + np.asarray(face_pressure, dtype=float)
    W = float(np.max(np.hypot(jn, jt), initial=0.0))
    closed = np.where((friction > 0) & (np.abs(jt) <= CLOSED_RTOL * W), "stick", "slip")
    return np.where(~faces_closed(jn, W) & (sn >= -CLOSED_RTOL * stress_scale), "open", closed)


@dataclass(frozen=True)
class CrackProfile:
    """Samples at the mid point of every crack edge, ordered along the crack.

    `state` is "open", "stick" or "slip" per sample (`profile_states`), always computed
    from the profile's own normal_jump, tangential_jump and normal_stress (a profile
    whose tractions are replaced gets the states of the new ones); `friction` is the
    crack's Coulomb coefficient and `stress_scale` the stress scale it uses (the largest
    |sigma| at the samples). `face_pressure` is the crack-face pressure p at the samples
    (zeros without one): normal_stress is the faces' whole normal traction, -p where they
    are open, and normal_stress + p the contact's part (not written by to_dict).
    """

    s: np.ndarray
    x: np.ndarray
    y: np.ndarray
    normal_jump: np.ndarray
    tangential_jump: np.ndarray
    normal_stress: np.ndarray
    shear_stress: np.ndarray
    friction: float = 0.0
    stress_scale: float = 0.0
    face_pressure: np.ndarray | None = None
    state: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        if self.face_pressure is None:
            object.__setattr__(self, "face_pressure", np.zeros(len(self.s)))
        object.__setattr__(self, "state", profile_states(self.normal_jump, self.tangential_jump, self.normal_stress,
                                                         self.friction, self.stress_scale, self.face_pressure))

    #: the per-sample arrays (what to_dict writes besides the state)
    SAMPLES = ("s", "x", "y", "normal_jump", "tangential_jump", "normal_stress", "shear_stress")

    def to_dict(self) -> dict:
        out = {k: [float(v) for v in getattr(self, k)] for k in self.SAMPLES}
        out["state"] = [str(v) for v in self.state]
        return out


#: offset (times the edge length) of the two sides' stress samples for two-sided tractions:
#: large enough for the point search to land on the intended side at any scale
SIDE_OFFSET = 1e-3


def crack_profile(crack_mesh: CrackMesh, crack: CrackEdges, jumps: tuple[np.ndarray, np.ndarray], sigma,
                  two_sided: bool = False, friction: float = 0.0) -> CrackProfile:
    """The crack profile of one crack from its jumps and the stress field.

    `jumps` = ([u].nu, [u].t) at the edges' mid points (`Discretization.crack_jumps`).
    `two_sided`: average the traction of both sides (post-computed stresses).
    `friction`: the crack's Coulomb coefficient, for the samples' open / stick / slip state
    (`profile_states`, with the largest |sigma| at the samples as the stress scale).
    """
    mesh = crack_mesh.mesh
    nu = crack.normal
    mid = crack.mid
    jn, jt = jumps
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
        friction=float(friction),
        # the whole stress tensor at the samples (sigma_tt and the tips' field included),
        # already evaluated: the scale that the normal stress's round-off is measured by
        stress_scale=float(np.max(np.linalg.norm(sig.reshape(len(sig), -1), axis=1), initial=0.0)),
    )


#: J or P below this fraction of the body's displacement or stress scale counts as zero
ZERO_RTOL = 1e-8


def kkt_residuals(profiles: list[CrackProfile], u_scale: float = 0.0, sigma_scale: float = 0.0) -> dict:
    """Relative KKT residuals over all crack mid-point samples: the solution's `kkt_sampled`.

    A diagnostic next to `kkt` (the residuals where the QP's constraints live): a P1
    jump sampled on the edge where the contact zone ends carries both a small opening
    and a small pressure, so the sampled complementarity is of the order of that
    edge's opening there. J = max |[u]|, P = max |sigma nu|; max_penetration = max(0, -min [u].nu)/J,
    max_tension = max(0, max sigma_n)/P, complementarity = max |sigma_n [u].nu|/(J P), with
    sigma_n the contact's part of the normal traction (sigma_n + p under a face pressure p).
    Where J (or P) is zero, up to round-off (below ZERO_RTOL times the body's
    displacement scale `u_scale`, or stress scale `sigma_scale`), the residual is taken
    relative to that body scale instead (or absolute if the scale is zero too).
    friction: 0.0 (frictionless). No crack: all zero.
    """
    if not profiles or sum(len(p.s) for p in profiles) == 0:
        return {"max_penetration": 0.0, "max_tension": 0.0, "complementarity": 0.0, "friction": 0.0}
    jn = np.concatenate([p.normal_jump for p in profiles])
    jt = np.concatenate([p.tangential_jump for p in profiles])
    # the contact's part of the normal traction (the crack-face pressure taken off)
    sn = np.concatenate([p.normal_stress + p.face_pressure for p in profiles])
    st = np.concatenate([p.shear_stress for p in profiles])
    J = float(np.max(np.hypot(jn, jt)))
    P = float(np.max(np.hypot(sn, st)))
    J_ = J if J > ZERO_RTOL * u_scale and J > 0 else (u_scale or 1.0)
    P_ = P if P > ZERO_RTOL * sigma_scale and P > 0 else (sigma_scale or 1.0)
    return {
        "max_penetration": float(max(0.0, -jn.min()) / J_),
        "max_tension": float(max(0.0, sn.max()) / P_),
        "complementarity": float(np.max(np.abs(sn * jn)) / (J_ * P_)),
        "friction": 0.0,
    }


def field_scales(crack_mesh: CrackMesh, u, sigma) -> tuple[float, float]:
    """max |u| and max |sigma| (Frobenius) over the triangles' centroids."""
    mesh = crack_mesh.mesh
    # every centroid mapped from the reference triangle at once (no point search)
    mp = mesh.MapToAllElements({ngs.ET.TRIG: ngs.IntegrationRule([(1 / 3, 1 / 3, 0)], [0.5])}, ngs.VOL)
    uu = np.asarray(u(mp)).reshape(mesh.ne, -1)
    ss = np.asarray(sigma(mp)).reshape(mesh.ne, -1)
    return float(np.max(np.linalg.norm(uu, axis=1))), float(np.max(np.linalg.norm(ss, axis=1)))


def _component_rows(system, comp: int) -> tuple[np.ndarray, np.ndarray]:
    """(dofs of compound component `comp`, their positions in the condensed vector y).

    Only dofs that are free and unrolled (a unit column of the change of basis T) have
    a row of their own; the others are left out.
    """
    fes = system.disc.fes
    rng = fes.Range(comp)
    free_pos = -np.ones(fes.ndof, dtype=int)
    free_pos[system._free] = np.arange(len(system._free))
    T = system._T_csr
    dofs, rows = [], []
    for d in range(rng.start, rng.stop):
        p = free_pos[d]
        if p < 0 or T.indptr[p + 1] - T.indptr[p] != 1 or T.data[T.indptr[p]] != 1.0:
            continue
        dofs.append(d - rng.start)
        rows.append(T.indices[T.indptr[p]])
    return np.array(dofs, dtype=int), np.array(rows, dtype=int)


def consistent_tractions(system, y: np.ndarray, crack_mesh: CrackMesh, skip=()) -> list[dict[str, np.ndarray]]:
    """The variationally consistent crack-face tractions at the crack edges' mid points.

    For a component c of `disc.traction_rows` (the unknowns carrying the crack's normal
    or tangential condition: a jump on the + face), every basis function phi of c on
    the crack satisfies, by Green's formula on the + side (outward normal -nu),
    (K y - F)_phi = -int_crack (sigma nu).d phi ds, d = nu or t the direction that c
    carries. The traction is the function t_h in c's trace space on the crack with
    M t_h = -(K y - F)_c, M the crack mass matrix of those traces, evaluated at the mid
    points: the contact forces divided out by the mass matrix for the normal part, the
    residual of the tangential equations (zero up to round-off when frictionless) for
    the shear. Returns per crack {"normal_stress": ..., "shear_stress": ...} for the
    components the element names (an empty dict per crack if none), except the keys in
    `skip`.
    """
    disc = system.disc
    out = [dict() for _ in crack_mesh.cracks]
    r = None
    for key, comp in zip(("normal_stress", "shear_stress"), disc.traction_rows):
        if comp is None or key in skip:
            continue
        if r is None:
            r = np.asarray(system.K_csr @ y - system.F)
        space = disc.fes.components[comp]
        dofs, rows = _component_rows(system, comp)
        u, v = space.TnT()
        region = ngs.ds(definedon=crack_mesh.crack_region, bonus_intorder=2)
        t = ngs.specialcf.tangential(2)
        vector = u.dim > 1
        m = ngs.BilinearForm(space, check_unused=False)
        m += ((u.Trace() * t) * (v.Trace() * t) if vector else u * v) * region
        m.Assemble()
        # M t = rhs on the traces' unknowns (M's nonzero diagonal), by NGSolve's sparse Cholesky
        rows_, cols_, vals_ = m.mat.COO()
        rows_, cols_, vals_ = np.asarray(rows_), np.asarray(cols_), np.asarray(vals_)
        on = distinct(rows_[(rows_ == cols_) & (np.abs(vals_) > 0)])
        free = ngs.BitArray(space.ndof)
        free.Clear()
        for d in on:
            free[int(d)] = True
        rhs = m.mat.CreateColVector()
        rhs.FV().NumPy()[:] = 0.0
        rhs.FV().NumPy()[dofs] = -r[rows]
        gf = ngs.GridFunction(space)
        if len(on):
            gf.vec.data = m.mat.Inverse(freedofs=free, inverse="sparsecholesky") * rhs
        for k, crack in enumerate(crack_mesh.cracks):
            mp = crack_mesh.mesh(crack.mid[:, 0], crack.mid[:, 1])
            vals = np.asarray(gf(mp)).reshape(len(crack), -1)
            if vals.shape[1] == 2:  # a vector trace: its tangential component
                vals = np.einsum("ei,ei->e", vals, crack.tangent)[:, None]
            out[k][key] = vals[:, 0]
    return out


def component_forces(system, y: np.ndarray, comp: int, G) -> np.ndarray:
    """The nodal forces G^{-T} (K y - F)_c on the rows of compound component `comp`.

    For a jump component with nodal constraint points (the baselines), these are the
    forces that the crack faces exert at those points, in the direction the component
    carries (as `constraints.discrete_contact_forces` for the normal one).
    """
    from ..core.constraints import _inverse_map

    rng = system.disc.fes.Range(comp)
    dofs, rows = _component_rows(system, comp)
    res = np.zeros(rng.stop - rng.start)
    res[dofs] = np.asarray(system.K_csr[rows] @ y - system.F[rows]).ravel()
    Ginv = _inverse_map(G, len(res))
    return res if Ginv is None else np.asarray(Ginv.T @ res).ravel()


def tributary_lengths(jump_space: ngs.FESpace, crack_mesh: CrackMesh, G: np.ndarray) -> np.ndarray:
    """w_i = int psi_i ds of every constraint point's nodal basis function (w = G^{-T} m)."""
    m = facet_moments(jump_space, crack_mesh, 0)[:, 0]
    return np.linalg.solve(np.asarray(G, dtype=float).T, m)


def lumped_traction(jump_space: ngs.FESpace, crack_mesh: CrackMesh, G: np.ndarray,
                    forces: np.ndarray, w: np.ndarray | None = None) -> list[np.ndarray]:
    """A crack-face traction component at the edge mid points from discrete nodal forces (normal or shear).

    For elements whose constraint points are nodes of the jump space (h1p1: the crack
    vertices; h1p2: vertices and edge mid points), each contact force lam_i acts on the
    tributary length w_i = int psi_i ds of its nodal basis function psi_i (the dual of
    G: w = G^{-T} m, m_d = int phi_d ds of the jump basis), so sigma_n,i = -lam_i / w_i:
    never tensile where lam >= 0 (the consistent mass-matrix traction oscillates in sign
    next to a concentrated force). At a mid point: the edge's own mid-point value (P2),
    else the mean of the end points that carry a constraint (a tip has none). The same
    lumping of the tangential forces (`component_forces`) gives the shear: a uniform
    traction is reproduced exactly, also next to the tips, where the consistent
    mass-matrix traction (no unknown at the tip) is off by up to 40%.
    """
    if w is None:  # `tributary_lengths`, passed in where several force vectors share them
        w = tributary_lengths(jump_space, crack_mesh, G)
    with np.errstate(divide="ignore", invalid="ignore"):
        p = np.where(w > 0, -np.asarray(forces) / np.where(w > 0, w, 1.0), 0.0)
    out = []
    for crack in crack_mesh.cracks:
        vals = np.zeros(len(crack))
        for k in range(len(crack)):
            mid = [d for d in jump_space.GetDofNrs(ngs.NodeId(ngs.EDGE, int(crack.edge[k]))) if d >= 0]
            if mid:
                vals[k] = p[mid[0]]
                continue
            ends = [d for v in (int(crack.va[k]), int(crack.vb[k]))
                    for d in jump_space.GetDofNrs(ngs.NodeId(ngs.VERTEX, v)) if d >= 0]
            vals[k] = float(np.mean(p[ends])) if ends else 0.0
        out.append(vals)
    return out
