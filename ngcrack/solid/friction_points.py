"""The friction points of the 3D crack faces: where the slip is measured and its map B.

The tangential jump on a crack face is the tangential trace of the element's jump copy
u_e (an HCurl function: tangentially continuous, so its trace is the same from either
side; it is evaluated in the + side's tetrahedron, where [u] = u_e). Each face carries
friction points at a quadrature rule of degree 2k (k the element order: 3, 6, 12 points,
positive weights omega summing to 1 on the face): their slips outnumber the jump's
functions on the face and its edges, so that all its points sticking leaves no slip on
it. The sticking points' constraints are then redundant (the method of
ngcrack.core.sparse_friction regularises their block by round-off). B maps the condensed unknowns y to the slips,
two rows per point in its crack's plane basis (e_a, e_b): exactly (the covariant shape
functions of the tetrahedron at the mapped point), block-sparse, built without a solve.

A point's normal force is its face's: the sum of the face's contact forces (the
Bernstein constraints of element.constraint_map, which integrate the contact pressure
against a partition of unity), times omega.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..core.sparse_friction import FrictionPoints

#: each face's friction points: NGSolve's triangle rule of this degree times the element order
#: (3, 6 and 12 points at orders 1, 2, 3: positive weights; two slips per point are at least
#: as many as the face's and its edges' jump functions, so that a face that sticks at all
#: its points has no slip left)
RULE_DEGREE = 2


def rule(order: int) -> tuple[np.ndarray, np.ndarray]:
    """The barycentric coordinates (w.r.t. the face's vertices) and the weights (sum 1) of the points."""
    r = ngs.IntegrationRule(ngs.TRIG, RULE_DEGREE * order)
    xy = np.array([p[:2] for p in r.points])
    w = np.array(r.weights)
    return np.column_stack([xy[:, 0], xy[:, 1], 1.0 - xy.sum(axis=1)]), w / w.sum()
#: the reference tetrahedron's vertices (NGSolve's numbering)
REF_TET = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]])


def positions_in_y(system, fes_dofs: np.ndarray) -> np.ndarray:
    """The positions in the condensed unknowns y of NGSolve dofs (-1 where a dof is not one of them)."""
    free = system._free
    T = sp.csr_matrix(system._T)
    at = np.searchsorted(free, fes_dofs)
    ok = (at < len(free)) & (free[np.minimum(at, len(free) - 1)] == fes_dofs)
    out = -np.ones(len(fes_dofs), dtype=int)
    rows = at[ok]
    count = np.diff(T.indptr)[rows]
    single = count == 1
    first = T.indptr[rows]
    pos = np.where(single, T.indices[np.minimum(first, len(T.indices) - 1)], -1)
    unit = np.where(single, T.data[np.minimum(first, len(T.data) - 1)] == 1.0, False)
    out[np.flatnonzero(ok)] = np.where(unit, pos, -1)
    return out


def friction_points(smesh, disc, system, mu: list[float]) -> FrictionPoints:
    """The friction points of every crack with mu > 0 (`mu`: per crack), B on the condensed unknowns."""
    if disc.tangential is None:
        raise ValueError(f"friction: element {disc.element!r} has no tangential jump unknowns")
    mesh = smesh.mesh
    ue = disc.fes.components[disc.tangential]
    offset = disc.fes.Range(disc.tangential).start
    bary, weights = rule(disc.order)
    per = (disc.order + 1) * (disc.order + 2) // 2
    table = disc.face_points if disc.face_points is not None else np.arange(len(disc.constraint_points)).reshape(-1, per)
    rows, cols, vals = [], [], []
    face, omega, mus, where, basis, crack = [], [], [], [], [], []
    q = 0
    start = 0
    for c in smesh.cracks:
        frame = np.array([c.crack.e_a, c.crack.e_b])
        for i, (el, tet) in enumerate(zip(c.elements, c.plus, strict=True)):
            if mu[c.index] <= 0:
                continue
            ei = ngs.ElementId(ngs.VOL, int(tet))
            tet_verts = [v.nr for v in mesh[ei].vertices]
            face_verts = [v.nr for v in mesh[ngs.ElementId(ngs.BND, int(el))].vertices]
            local = REF_TET[[tet_verts.index(v) for v in face_verts]]
            trafo = mesh.GetTrafo(ei)
            fe = ue.GetFE(ei)
            dofs = np.array(ue.GetDofNrs(ei))
            active = dofs >= 0
            ydofs = positions_in_y(system, offset + dofs[active])
            if np.any(ydofs < 0):
                raise AssertionError("a crack jump unknown is not among the condensed unknowns")
            for lam, wq in zip(bary, weights, strict=True):
                mip = trafo(*(lam @ local))
                shape = np.array(fe.CalcShape(mip))[active]  # (dofs, 3), physical
                tang = shape @ frame.T  # (dofs, 2)
                for j in range(2):
                    rows += [2 * q + j] * len(ydofs)
                    cols += list(ydofs)
                    vals += list(tang[:, j])
                face.append(start + i)
                omega.append(wq)
                mus.append(mu[c.index])
                where.append(np.array(mip.point))
                basis.append(frame)
                crack.append(c.index)
                q += 1
        start += len(c.elements)
    B = sp.csr_matrix((vals, (rows, cols)), shape=(2 * q, system.n))
    return FrictionPoints(B=B, face=np.array(face, dtype=int), omega=np.array(omega), mu=np.array(mus),
                          face_rows=np.asarray(table), where=np.array(where).reshape(-1, 3),
                          basis=np.array(basis).reshape(-1, 2, 3), crack=np.array(crack, dtype=int))
