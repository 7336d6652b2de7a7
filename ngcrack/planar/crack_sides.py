"""Which side of a crack a triangle lies on, and the crack's frame as coefficient functions.

The elements need, on the mesh edges of a crack, its normal ``nu`` and tangent ``t``
(to tell the crack's minus side, where the element's outward normal is ``nu``, from its
plus side), and some estimators need, per triangle, the side of the crack it touches.
Both are read from a :class:`~ngcrack.planar.geometry.CrackMesh`. This module sits below
``geometry`` (which re-exports its functions) and imports nothing of it at run time.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from ..core.errors import InputError

#: relative distance (times the polygon's diameter) under which a point counts as on an edge
ON_EDGE_RTOL = 1e-9
#: a point within this many times ON_EDGE_RTOL * diameter of a crack segment lies on it
ON_CRACK_FACTOR = 10


def crack_frame_cf(crack_mesh):
    """CoefficientFunctions (nu, t) equal to the crack normal and tangent on crack edges.

    Both are constant on each crack edge (its segment's normal and tangent) and zero on
    every other edge: lowest-order facet functions, for element boundaries and boundary
    elements, where they tell the crack's minus side (n = nu) from its plus side. Their
    cost per point does not grow with the number of crack segments (a sum of one
    indicator per segment did: a grown crack of 100 segments made the crack terms'
    assembly the larger part of a solve).
    """
    fes = ngs.FacetFESpace(crack_mesh.mesh, order=0)
    comps = [ngs.GridFunction(fes) for _ in range(4)]  # nu_x, nu_y, t_x, t_y
    values = [gf.vec.FV().NumPy() for gf in comps]
    for v in values:
        v[:] = 0.0
    for crack in crack_mesh.cracks:
        dofs = np.array([fes.GetDofNrs(ngs.NodeId(ngs.EDGE, int(e)))[0] for e in crack.edge], dtype=int)
        for v, col in zip(values, (crack.normal[:, 0], crack.normal[:, 1], crack.tangent[:, 0], crack.tangent[:, 1])):
            v[dofs] = col
    return ngs.CF((comps[0], comps[1])), ngs.CF((comps[2], comps[3]))


def segment_cf(p: np.ndarray, q: np.ndarray, tol: float):
    """The segment p-q as seen from a point (x, y): its length L, its unit tangent (tx, ty), and the
    CoefficientFunctions `along` (the distance from p along the tangent) and `on` (1 within `tol` of the
    segment, 0 elsewhere)."""
    x, y = ngs.x, ngs.y
    L = float(np.linalg.norm(q - p))
    tx, ty = (q - p) / L
    along = (x - p[0]) * tx + (y - p[1]) * ty
    across = -(x - p[0]) * ty + (y - p[1]) * tx
    inside = ngs.IfPos(along + tol, 1.0, 0.0) * ngs.IfPos(L + tol - along, 1.0, 0.0)
    on = inside * ngs.IfPos(tol - ngs.sqrt(across * across), 1.0, 0.0)
    return L, (tx, ty), along, on



def crack_side(crack_mesh) -> np.ndarray:
    """+1 for triangles on the + side (nu points into them) of the crack at a crack
    vertex they touch, -1 on the - side, 0 for triangles touching no crack vertex.

    Decided by the angle of the triangle's centroid around that vertex, measured from
    the crack's forward direction, so kinks are classified exactly.
    """
    verts, tris = crack_mesh.points, crack_mesh.triangles
    around: dict[int, list] = {}  # vertex -> [forward direction, backward direction]
    for c in crack_mesh.cracks:
        for k in range(len(c)):
            d = c.b[k] - c.a[k]
            around.setdefault(int(c.va[k]), [None, None])[0] = d
            around.setdefault(int(c.vb[k]), [None, None])[1] = -d
    side = np.zeros(len(tris))
    touching = np.flatnonzero(np.isin(tris, list(around)).any(axis=1))
    for el in touching:
        nrs = list(tris[el])
        for v in nrs:
            if v not in around:
                continue
            fwd, bwd = around[v]
            x = verts[nrs].mean(axis=0) - verts[v]
            if fwd is None or bwd is None:  # a crack end point: one crack edge there
                d = fwd if fwd is not None else -bwd
                s = 1.0 if d[0] * x[1] - d[1] * x[0] > 0 else -1.0
            else:  # the + side (left of the crack) spans the angles from fwd to bwd, ccw
                a_f = np.arctan2(fwd[1], fwd[0])
                span = (np.arctan2(bwd[1], bwd[0]) - a_f) % (2 * np.pi)
                s = 1.0 if (np.arctan2(x[1], x[0]) - a_f) % (2 * np.pi) < span else -1.0
            if side[el] not in (0.0, s):
                raise InputError("maxh: a triangle lies on both sides of the cracks; refine the mesh near the cracks")
            side[el] = s
    return side
