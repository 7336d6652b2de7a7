"""The crack faces' friction term in the front's interaction integrals (ngcrack.solid.front).

With a traction t on the crack faces the domain integrals gain a face integral (as the
pressure's, ngcrack.solid.face_pressure): I_m += - int t+ . d[u^m]/dx_1 q dA over the
crack's plane, t+ the traction on the + face and [u^m] the auxiliary jump (traction-free
faces: no term in the auxiliary stresses). The friction forces of a frictional solve
(ngcrack.core.sparse_friction) are point forces at the friction points (lam_t,q: minus the + face's
friction traction integrated against its point). Each face's forces are spread over it as
a uniform traction t+ = -(sum of its lam_t) / area and the term is integrated with
NGSolve's rule on the crack faces (at the points themselves, the faces along a curved
front, with their points a front_h / 1000 from it, gave weights 1/sqrt(r) of 15 and mode II
terms 10 times too large). The faces with a vertex on the front take the traction of the
nearest face without one: the jump's tangential component along the front is zero on the
front's edges, so their points' friction force along e3 is held down by the element, not by
friction (0.76 of the uniform traction along e3 and 1.18 along e1 on the sticking inclined
penny's tiny mesh, where they carry most of the 1/sqrt(r) weight: K_III kept 0.27 of its
frictionless value with every point sticking, 0.08-0.09 with the inner faces' traction):

    I_m += int q lam_t / area . d[u^m]/dx_1 dA,

with, r the distance behind the front (x_1 = -r), d sqrt(r)/dx_1 = -1 / (2 sqrt(r)):
[u^II] = (8 / E') sqrt(r / 2 pi) e1 and [u^III] = (4 / mu) sqrt(r / 2 pi) e3. Only the
shear modes: the normal pressure of closed faces does no work on K_II, K_III and K_I is 0
there. J (the reported G) has no friction term yet.

`face_friction` is the one call the front integral makes; it returns None without friction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..core.quadrature import FACE_TERM_ORDER

#: quadrature order on the crack faces (the auxiliary term has an integrable r^(-1/2): `ngcrack.core.quadrature`)
QUADRATURE_ORDER = FACE_TERM_ORDER


@dataclass
class FaceFriction:
    """One crack's friction points near its front with their weights in the shear modes' terms."""

    phi: np.ndarray  # the foot's parameter on the front
    r: np.ndarray  # distance behind the front
    weights: np.ndarray  # (q, 2): lam_t . d[u^m]/dx_1 for m = II, III

    def terms(self, q: np.ndarray) -> np.ndarray:
        """(the mode II, the mode III interaction term) for the q-function's values at the points."""
        return q @ self.weights


def face_friction(sol, index: int, geom, R: float, e_prime: float, mu: float) -> FaceFriction | None:
    """Crack `index`'s face quadrature points within R of its front, or None without friction on it."""
    res = sol.contact
    points = getattr(res, "points", None)
    if points is None or getattr(points, "crack", None) is None or not np.any(points.crack == index):
        return None
    faces = sol.smesh.cracks[index]
    first = sum(len(c.elements) for c in sol.smesh.cracks[:index])
    nf = len(faces.elements)
    # each face's friction force (global 3-vector), spread over the face as a uniform traction
    force = np.einsum("qi,qij->qj", res.lam_t, points.basis)
    mine = points.crack == index
    total = np.zeros((nf, 3))
    np.add.at(total, points.face[mine] - first, force[mine])
    mesh = sol.smesh.mesh
    rule = ngs.IntegrationRule(ngs.TRIG, QUADRATURE_ORDER)
    k = len(rule.weights)
    mp = mesh.MapToAllElements(rule, ngs.BND).reshape(mesh.GetNE(ngs.BND), k)[faces.elements].ravel()
    xyz = np.column_stack([np.asarray(c(mp)).ravel() for c in (ngs.x, ngs.y, ngs.z)])
    jac = np.asarray(ngs.specialcf.JacobianMatrix(3, 2)(mp)).reshape(-1, 3, 2)
    w = np.linalg.norm(np.cross(jac[:, :, 0], jac[:, :, 1]), axis=1) * np.tile(np.array(rule.weights), nf)
    area = w.reshape(nf, k).sum(axis=1)
    per_face = total / area[:, None]  # lam per unit area: minus the + face's traction
    per_face = _inner_traction(mesh, faces.elements, geom, per_face)
    traction = np.repeat(per_face, k, axis=0)
    phi, x1, _, _ = geom.coordinates(xyz)
    r = np.maximum(-x1, 0.0)
    near = (r < R) & (r > 0)
    e1, _, e3 = geom.frame(phi[near])
    d = -w[near] / (2.0 * np.sqrt(2.0 * math.pi * r[near]))  # d sqrt(r / 2 pi) / dx_1, times the weight
    weights = np.column_stack([8.0 / e_prime * d * np.sum(traction[near] * e1, axis=1),
                               4.0 / mu * d * np.sum(traction[near] * e3, axis=1)])
    return FaceFriction(phi[near], r[near], weights)


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
