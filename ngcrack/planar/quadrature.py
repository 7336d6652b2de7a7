"""Quadrature on a mesh's triangles as plain arrays: the rule behind every L2 error of ngcrack.

`quadrature_points(mesh, order)` gives the points and weights of NGSolve's rule exact for
polynomials of degree `order` on every triangle of `mesh`, mapped onto the triangles, in
netgen's element order. Sweeps measure their errors at these points (ngcrack.studies.sweeps), the
error estimate checks itself against a reference with them (ngcrack.planar.estimate). A low-level
module: it imports nothing of ngcrack.
"""

from __future__ import annotations

import numpy as np

#: degree for which the quadrature on the reference mesh's triangles is exact
QUADRATURE_ORDER = 4


def quadrature_points(mesh, order: int = QUADRATURE_ORDER) -> tuple[np.ndarray, np.ndarray]:
    """(points (N, 2), weights (N,)) of a rule exact for degree `order` on every triangle."""
    import ngsolve as ngs

    rule = ngs.IntegrationRule(ngs.TRIG, order)
    ref = np.array([p[:2] for p in rule.points])
    wref = np.array(rule.weights)  # sums to 1/2, the reference triangle's area
    # netgen's arrays: the vertices and triangles of NGSolve's mesh, in its order
    verts = np.array(mesh.ngmesh.Coordinates()[:, :2], dtype=float)
    tris = np.asarray(mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3], dtype=int) - 1
    a, b, c = verts[tris[:, 0]], verts[tris[:, 1]], verts[tris[:, 2]]
    pts = a[:, None, :] + ref[None, :, 0, None] * (b - a)[:, None, :] + ref[None, :, 1, None] * (c - a)[:, None, :]
    det = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    return pts.reshape(-1, 2), (det[:, None] * wref[None, :]).ravel()
