"""The crack faces' friction term in the front's interaction integrals (ngcrack.solid.front).

With a traction t on the crack faces the domain integrals gain a face integral (as the
pressure's, ngcrack.solid.face_pressure): I_m += - int t+ . d[u^m]/dx_1 q dA over the
crack's plane, t+ the traction on the + face and [u^m] the auxiliary jump (traction-free
faces: no term in the auxiliary stresses). With r the distance behind the front (x_1 = -r),
d sqrt(r)/dx_1 = -1 / (2 sqrt(r)), [u^II] = (8 / E') sqrt(r / 2 pi) e1 and
[u^III] = (4 / mu) sqrt(r / 2 pi) e3:

    I_m += int q t . d[u^m]/dx_1 dA,      t = -t+ (lam_t per unit area),

integrated with NGSolve's rule on the crack faces. Only the shear modes: the normal pressure
of closed faces does no work on K_II, K_III and K_I is 0 there. J (the reported G) has no
friction term yet.

The traction. The friction forces of a frictional solve (ngcrack.core.sparse_friction) are
point forces lam_t at the friction points (minus the + face's friction traction integrated
against its point). Where points stick they are not unique (two slips per point outnumber the
jump functions: the forces that balance the residual form an affine family), and a face's
own sum of them depends on the member the solver picked. What is unique is their work on
the jump functions, f = B' lam_t. Each face's traction is the uniform one whose point forces
(omega times the area times t) do that work best, in the norm of the jumps' mass matrix at
the points (`fitted_traction`); a uniform traction's own point forces come back exactly. (The
term before spread each face's forces over it: on the 20a box at full stick K then moved by
0.002-0.004 of the frictionless K between mu = 2 and 5, the same sticking answer.) The faces
with a vertex on the front take the traction of the nearest face without one: the jump's
tangential component along the front is zero on the front's edges, so their forces along e3
are held down by the element, not by friction (without it, at full stick on the 20a box,
K_III kept 0.14 of its frictionless value with the spread forces).

The uniform part, integrated consistently. The identity that makes the face term right
(domain integral + face integral = the front's K) holds for exact integrals only: the face
integrand has the weight 1/sqrt(r) and the domain integrand the auxiliary stresses' 1/sqrt(r)
along the front (where the bump's derivative along the front does not vanish), and the
rules integrate each to a few percent, with errors that do not cancel. A uniform shear
s = tau n + n tau (tau in the crack's plane) is a smooth field with K = 0 and the face
traction tau; on the tiny mesh of the tests its computed K_II and K_III are 0.068 and 0.091
of the frictionless ones, and that was nearly the whole residue of a crack whose faces stick
everywhere (0.061, 0.089). So the term is split: tau_bar, the mean traction near the front
(weighted as the face term weighs it, w / sqrt(r)), is taken out of the face traction (the
face integral of t - tau_bar only) and the domain integral of the uniform shear with traction
tau_bar is subtracted from the front's K (`FaceFriction.less_uniform`: the same front integral
on the same points, run on the uniform field: one more run of the integral). Both changes add
K = 0 in the continuum; the extraction becomes exact for a uniform face traction, and at full
stick the residue falls to the extraction's own error on the remaining uniform stress (normal
and in-plane, `uniform_stress_solution`), which the frictionless K of a closed crack carries
too (BENCHMARKS: 3D friction at full stick: 0.003 and 0.002 of the frictionless K on the 20a
box at the default sizes, where the term before left 0.024 and 0.056-0.060).

`face_friction` is the one call the front integral makes; it returns None without friction.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..core.quadrature import FACE_TERM_ORDER

#: quadrature order on the crack faces (the auxiliary term has an integrable r^(-1/2): `ngcrack.core.quadrature`)
QUADRATURE_ORDER = FACE_TERM_ORDER
#: the consistent term (module docstring: the fitted traction, the uniform part taken out); False: the term before
#: (each face's point forces spread over it, the face rule alone), kept for the comparisons of the benchmark
CONSISTENT = True


@dataclass
class FaceFriction:
    """One crack's friction points near its front with their weights in the shear modes' terms."""

    phi: np.ndarray  # the foot's parameter on the front
    r: np.ndarray  # distance behind the front
    weights: np.ndarray  # (q, 2): (t - tau_bar) . d[u^m]/dx_1 for m = II, III, times the weight
    sol: object = None  # the solution (for the uniform field's run)
    tau_bar: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))  # the mean traction taken out (in the plane)
    normal: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))  # the crack's normal

    def terms(self, q: np.ndarray) -> np.ndarray:
        """(the mode II, the mode III interaction term) for the q-function's values at the points."""
        return q @ self.weights

    def uniform_solution(self):
        """The solution with its fields replaced by the uniform shear s = tau_bar n + n tau_bar, without contact."""
        n = np.asarray(self.normal, dtype=float)
        return uniform_stress_solution(self.sol, np.outer(self.tau_bar, n) + np.outer(n, self.tau_bar))

    def less_uniform(self, K_II: np.ndarray, K_III: np.ndarray, run: Callable) -> tuple[np.ndarray, np.ndarray]:
        """K_II, K_III less those of the uniform shear, `run` the front integral of a solution (its FrontParameters)."""
        if not np.any(self.tau_bar):
            return K_II, K_III
        ref = run(self.uniform_solution())
        return K_II - ref.K_II, K_III - ref.K_III


def uniform_stress_solution(sol, stress: np.ndarray):
    """`sol` with the uniform stress `stress` (3 x 3, symmetric; grad u its strain) for fields and no contact: the front
    integral of it gives the extraction's K of a smooth field (0 in the continuum, but for the faces' traction)."""
    mat = sol.scene.material
    return dataclasses.replace(sol, contact=None, disc=_UniformStress(sol.disc, np.asarray(stress, dtype=float), mat.E, mat.nu))


class _UniformStress:
    """A discretization's stand-in whose fields are a uniform stress and its strain (no rotation)."""

    def __init__(self, disc, stress: np.ndarray, E: float, nu: float):
        self._disc = disc
        self._stress = stress
        self._strain = ((1.0 + nu) * stress - nu * np.trace(stress) * np.eye(3)) / E

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        return getattr(self._disc, name)

    def fields(self, gf) -> dict:
        cf = lambda m: ngs.CF(tuple(float(v) for v in m.ravel()), dims=(3, 3))  # noqa: E731
        return {"sigma": cf(self._stress), "grad_u": cf(self._strain), "u": ngs.CF((0.0, 0.0, 0.0))}


def face_friction(sol, index: int, geom, R: float, e_prime: float, mu: float) -> FaceFriction | None:
    """Crack `index`'s face quadrature points within R of its front, or None without friction on it."""
    res = sol.contact
    points = getattr(res, "points", None)
    if points is None or getattr(points, "crack", None) is None or not np.any(points.crack == index):
        return None
    faces = sol.smesh.cracks[index]
    first = sum(len(c.elements) for c in sol.smesh.cracks[:index])
    nf = len(faces.elements)
    mine = points.crack == index
    face = points.face[mine] - first
    mesh = sol.smesh.mesh
    rule = ngs.IntegrationRule(ngs.TRIG, QUADRATURE_ORDER)
    k = len(rule.weights)
    mp = mesh.MapToAllElements(rule, ngs.BND).reshape(mesh.GetNE(ngs.BND), k)[faces.elements].ravel()
    xyz = np.column_stack([np.asarray(c(mp)).ravel() for c in (ngs.x, ngs.y, ngs.z)])
    jac = np.asarray(ngs.specialcf.JacobianMatrix(3, 2)(mp)).reshape(-1, 3, 2)
    w = np.linalg.norm(np.cross(jac[:, :, 0], jac[:, :, 1]), axis=1) * np.tile(np.array(rule.weights), nf)
    area = w.reshape(nf, k).sum(axis=1)
    if CONSISTENT:  # lam per unit area: minus the + face's traction
        per_face = fitted_traction(points.B[np.flatnonzero(np.repeat(mine, 2))], res.lam_t[mine], face,
                                   points.omega[mine] * area[face], points.basis[mine], nf)
    else:  # each face's friction force spread over it
        per_face = np.zeros((nf, 3))
        np.add.at(per_face, face, np.einsum("qi,qij->qj", res.lam_t[mine], points.basis[mine]))
        per_face /= area[:, None]
    per_face = _inner_traction(mesh, faces.elements, geom, per_face)
    traction = np.repeat(per_face, k, axis=0)
    phi, x1, _, _ = geom.coordinates(xyz)
    r = np.maximum(-x1, 0.0)
    near = (r < R) & (r > 0)
    e1, _, e3 = geom.frame(phi[near])
    d = -w[near] / (2.0 * np.sqrt(2.0 * math.pi * r[near]))  # d sqrt(r / 2 pi) / dx_1, times the weight
    n = np.asarray(faces.crack.normal, dtype=float)
    tau_bar = np.zeros(3)
    if CONSISTENT and near.any():  # the mean traction as the face term weighs it, in the crack's plane
        tau_bar = d @ traction[near] / d.sum()
        tau_bar -= (tau_bar @ n) * n
    rest = traction[near] - tau_bar
    weights = np.column_stack([8.0 / e_prime * d * np.sum(rest * e1, axis=1), 4.0 / mu * d * np.sum(rest * e3, axis=1)])
    return FaceFriction(phi[near], r[near], weights, sol, tau_bar, n)


def fitted_traction(B: sp.spmatrix, lam: np.ndarray, face: np.ndarray, share: np.ndarray, basis: np.ndarray,
                    n_faces: int) -> np.ndarray:
    """(n_faces, 3): per face the uniform traction whose point forces do the work of the forces `lam` on the jumps.

    B (2 q, n): the points' slips from the unknowns, `lam` (q, 2) their forces, `share` each point's
    share of its face's area (omega times the area), `basis` (q, 2, 3) its plane basis. The forces'
    work on the jump functions, f = B' lam, is unique where the forces are not; a uniform traction
    t_f per face has the forces share_q t_f and the work M t. Fitted in the norm that the jumps'
    mass matrix at the points, G = B' W B (W the shares), gives to work:
    min (M t - f)' G^-1 (M t - f). A uniform traction's own forces are fitted exactly.
    """
    B = sp.csc_matrix(B)
    A = B[:, np.flatnonzero(np.diff(B.indptr))].T.tocsr()  # (jump unknowns, 2 q)
    w = np.repeat(share, 2)
    q = np.arange(len(w))
    P = sp.csr_matrix((w, (q, 2 * np.repeat(face, 2) + q % 2)), shape=(len(w), 2 * n_faces))
    G = (A @ sp.diags(w) @ A.T).tocsc()
    M = (A @ P).toarray()
    try:
        X = spla.splu(G).solve(M)
    except RuntimeError:  # G singular (jump functions the points do not separate): its least-squares solutions
        X = np.linalg.lstsq(G.toarray(), M, rcond=None)[0]
    t, *_ = np.linalg.lstsq(M.T @ X, X.T @ (A @ np.asarray(lam, dtype=float).ravel()), rcond=None)
    out = np.zeros((n_faces, 3))
    out[face] = np.einsum("qi,qij->qj", t.reshape(n_faces, 2)[face], basis)
    return out


def _inner_traction(mesh, elements, geom, per_face: np.ndarray) -> np.ndarray:
    """The faces with a vertex on the front take the traction of the nearest face without one."""
    verts = np.array([v.point for v in mesh.vertices])
    tri = np.array([[v.nr for v in mesh[ngs.ElementId(ngs.BND, int(e))].vertices] for e in elements])
    _, x1, _, _ = geom.coordinates(verts[tri.ravel()])
    h = np.sqrt(np.median(np.linalg.norm(np.cross(verts[tri[:, 1]] - verts[tri[:, 0]], verts[tri[:, 2]] - verts[tri[:, 0]]), axis=1)))
    on_front = (np.abs(x1.reshape(-1, 3)) < 1e-6 * h).any(axis=1)
    if on_front.all() or not on_front.any():
        return per_face
    centre = verts[tri].mean(axis=1)
    inner = np.flatnonzero(~on_front)
    out = per_face.copy()
    for f in np.flatnonzero(on_front):
        out[f] = per_face[inner[np.argmin(np.linalg.norm(centre[inner] - centre[f], axis=1))]]
    return out
