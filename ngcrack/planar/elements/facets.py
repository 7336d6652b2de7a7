"""Facet unknowns along the 2D crack edges: their moments, their values at points of an
edge, and the map from a jump's dofs to its values at the edges' equispaced points.

NGSolve cannot evaluate a facet function at a point; its p + 1 moments against s^j on
each edge (s the edge's local coordinate) determine its polynomial exactly. The element
families read their crack jumps and their constraint map through these; the crack
profiles (`ngcrack.planar.post`) and the hp measurements too.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from ..geometry import CrackEdges, CrackMesh


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
