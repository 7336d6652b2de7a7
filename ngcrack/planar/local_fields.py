"""Per-triangle polynomial fields on a crack mesh: topology, local Lagrange bases, sampling, quadrature.

What the error estimate (estimate.py) reconstructs its fields with: the element
vertices and edges with the two sides of each crack (`_Topology`, kept per CrackMesh
while it lives), the Lagrange nodes and bases of degree 1 and 2 on each triangle
(`_Lagrange`), the facet traces of the hybrid elements read from their GridFunctions
(`_facet_values`), fields sampled at the element nodes in their own element (no point
search: `_sample_local`), and NGSolve's own quadrature points on every triangle with the
stress evaluated there (`_Quadrature`). All of it vectorized over the triangles.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .crack_sides import crack_side
from .geometry import CrackMesh, element_points

#: quadrature order of the element integrals (sigma_h of degree <= 2 against eps(w) of degree <= 1)
INTORDER = 4

#: points sampled in an element are pulled this fraction of the way to its centroid, so
#: that the point search returns that element and not a neighbour
INWARD = 1e-3

#: the topologies of the last meshes estimated on, by id of their CrackMesh (a load change
#: keeps its mesh: building one takes a third of the estimate at 1e5 unknowns, measured)
_TOPOLOGIES: dict[int, tuple] = {}

#: dof numbers of the crack edges in the crack unknowns' spaces: (space, edges, dofs) of the last few
_EDGE_DOFS: list = []


@dataclass
class _Topology:
    """Element vertices and edges, the crack sides, and the Lagrange node numbering.

    opp_edge[T, i] is the NGSolve edge of triangle T opposite its local vertex i.
    Nodes: vertex nodes 0..2 nv (a crack vertex on the + side gets v + nv), then edge
    nodes offset 2 nv (a crack edge seen from the + side gets e + ned).
    """

    P: np.ndarray
    T: np.ndarray
    opp_edge: np.ndarray
    edge_vertices: np.ndarray
    side: np.ndarray
    crack_edge: np.ndarray  # bool per NGSolve edge
    vertex_node: np.ndarray  # (ne, 3)
    edge_node: np.ndarray  # (ne, 3), slot i = edge opposite local vertex i
    n_nodes: int

    @classmethod
    def build(cls, cmesh: CrackMesh) -> _Topology:
        mesh = cmesh.mesh
        P, T = cmesh.points, cmesh.triangles
        nv, ned = len(P), mesh.nedge
        EV = np.array([[v.nr for v in e.vertices] for e in mesh.edges], dtype=int)
        E = np.array([[e.nr for e in el.edges] for el in mesh.Elements(ngs.VOL)], dtype=int)
        # the edge opposite local vertex i is the one that does not contain T[:, i]
        opp = np.empty_like(E)
        for i in range(3):
            v = T[:, i][:, None]
            has = (EV[E][:, :, 0] == v) | (EV[E][:, :, 1] == v)  # (ne, 3) edge k holds vertex i
            opp[:, i] = E[np.arange(len(T)), np.argmin(has, axis=1)]
        side = crack_side(cmesh) if cmesh.cracks else np.zeros(len(T))
        crack_edge = np.zeros(ned, dtype=bool)
        split = np.zeros(nv, dtype=bool)
        for c in cmesh.cracks:
            crack_edge[c.edge] = True
            split[c.va] = True
            split[c.vb] = True
        split[list(cmesh.tip_vertices)] = False
        plus = (side > 0)[:, None]
        vertex_node = np.where(plus & split[T], T + nv, T)
        edge_node = 2 * nv + np.where(plus & crack_edge[opp], opp + ned, opp)
        return cls(P=P, T=T, opp_edge=opp, edge_vertices=EV, side=side, crack_edge=crack_edge,
                   vertex_node=vertex_node, edge_node=edge_node, n_nodes=2 * nv + 2 * ned)

    def nodes(self, degree: int) -> np.ndarray:
        return self.vertex_node if degree == 1 else np.hstack([self.vertex_node, self.edge_node])

    def node_points(self, degree: int) -> np.ndarray:
        """(ne, nk, 2) coordinates of the element nodes (vertices, then edge mid points opposite 0, 1, 2)."""
        X = self.P[self.T]
        if degree == 1:
            return X
        mids = np.stack([0.5 * (X[:, (i + 1) % 3] + X[:, (i + 2) % 3]) for i in range(3)], axis=1)
        return np.concatenate([X, mids], axis=1)


_TOPOLOGIES_KEPT = 4


def _topology(cmesh: CrackMesh) -> _Topology:
    """`_Topology.build(cmesh)`, reused while that very CrackMesh (its mesh, points,
    triangles and cracks the same objects) is alive."""
    key = id(cmesh)
    hit = _TOPOLOGIES.get(key)
    if hit is not None:
        ref, mesh, cracks, top = hit
        if ref() is cmesh and mesh is cmesh.mesh and cracks is cmesh.cracks and top.P is cmesh.points \
                and top.T is cmesh.triangles:
            return top
    top = _Topology.build(cmesh)
    while len(_TOPOLOGIES) >= _TOPOLOGIES_KEPT:
        _TOPOLOGIES.pop(next(iter(_TOPOLOGIES)), None)
    _TOPOLOGIES[key] = (weakref.ref(cmesh, lambda _, key=key: _TOPOLOGIES.pop(key, None)), cmesh.mesh,
                        cmesh.cracks, top)
    return top


def _average(top: _Topology, local: np.ndarray, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Node values (n_nodes, d) as the mean of the elements' local values (ne, nk, d)."""
    nodes = top.nodes(degree)
    d = local.shape[-1]
    flat, values = nodes.ravel(), local.reshape(-1, d)
    # (bincount adds in array order, as np.add.at does, and is ten times faster)
    acc = np.column_stack([np.bincount(flat, weights=values[:, k], minlength=top.n_nodes) for k in range(d)])
    cnt = np.bincount(flat, minlength=top.n_nodes).astype(float)
    return acc / np.maximum(cnt, 1.0)[:, None], nodes


def _sum(terms):
    """Sum of CoefficientFunctions (the builtin sum starts from the scalar 0)."""
    out = terms[0]
    for t in terms[1:]:
        out = out + t
    return out


class _Lagrange:
    """Per-triangle P1 / P2 fields given by nodal values, as NGSolve CoefficientFunctions.

    lambda_i = alpha_i + b_i (x - x_c) + c_i (y - y_c) with the coefficients stored in
    piecewise constant GridFunctions; the field is sum_k W_k phi_k(lambda), phi the
    Lagrange basis (vertices, then edge mid points opposite vertex 0, 1, 2).
    """

    def __init__(self, mesh: ngs.Mesh, top: _Topology, degree: int, ncomp: int):
        self.degree, self.ncomp = degree, ncomp
        self.nk = 3 if degree == 1 else 6
        X = top.P[top.T]
        xc = X.mean(axis=1)
        M = np.concatenate([np.ones((len(X), 3, 1)), X - xc[:, None, :]], axis=2)  # rows: vertices
        C = np.linalg.inv(M)  # column i: coefficients (alpha, b, c) of lambda_i
        ne = len(X)
        n_geo = 2 + 9
        self.space = ngs.L2(mesh, order=0) ** (n_geo + self.nk * ncomp)
        self.gf = ngs.GridFunction(self.space)
        arr = self.gf.vec.FV().NumPy().reshape(-1, ne)
        arr[0], arr[1] = xc[:, 0], xc[:, 1]
        for i in range(3):
            arr[2 + 3 * i: 5 + 3 * i] = C[:, :, i].T
        self.arr = arr
        comps = self.gf.components
        dx, dy = ngs.x - comps[0], ngs.y - comps[1]
        self.lam = [comps[2 + 3 * i] + comps[3 + 3 * i] * dx + comps[4 + 3 * i] * dy for i in range(3)]
        self.glam = [ngs.CF((comps[3 + 3 * i], comps[4 + 3 * i])) for i in range(3)]
        self.W = [[comps[n_geo + k * ncomp + c] for c in range(ncomp)] for k in range(self.nk)]

    def set(self, values: np.ndarray) -> None:
        """values (ne, nk, ncomp)."""
        ne = values.shape[0]
        self.arr[11:] = values.reshape(ne, -1).T

    def _basis(self):
        lam, g = self.lam, self.glam
        if self.degree == 1:
            return lam, g
        phi = [lam[i] * (2 * lam[i] - 1) for i in range(3)]
        grad = [(4 * lam[i] - 1) * g[i] for i in range(3)]
        for o in range(3):
            i, j = (o + 1) % 3, (o + 2) % 3
            phi.append(4 * lam[i] * lam[j])
            grad.append(4 * (lam[i] * g[j] + lam[j] * g[i]))
        return phi, grad

    def value(self) -> ngs.CoefficientFunction:
        phi, _ = self._basis()
        return ngs.CF(tuple(_sum([self.W[k][c] * phi[k] for k in range(self.nk)]) for c in range(self.ncomp)))

    def gradient(self) -> ngs.CoefficientFunction:
        """For ncomp = 2: the 2x2 matrix (grad w)_ij = d w_i / d x_j."""
        _, grad = self._basis()
        rows = [_sum([self.W[k][c] * grad[k] for k in range(self.nk)]) for c in range(2)]
        return ngs.CF((rows[0][0], rows[0][1], rows[1][0], rows[1][1]), dims=(2, 2))


def _edge_dofs(space: ngs.FESpace, edges: np.ndarray, owner=None) -> np.ndarray:
    """(len(edges), k) dof numbers of `space` on `edges`, kept for the last few spaces (a
    load change keeps its discretization). `owner`: (compound space, component number),
    which stay the same objects while the space does (a component's Python object is made
    anew on every access)."""
    key = (space,) if owner is None else tuple(owner)
    for kept_key, kept_edges, ndof, dofs in list(_EDGE_DOFS):
        if len(kept_key) == len(key) and all(a is b or (isinstance(a, int) and a == b) for a, b in zip(kept_key, key)) \
                and kept_edges is edges and ndof == space.ndof:
            return dofs
    dofs = np.array([space.GetDofNrs(ngs.NodeId(ngs.EDGE, int(e))) for e in edges], dtype=int).reshape(len(edges), -1)
    _EDGE_DOFS.append((key, edges, space.ndof, dofs))
    del _EDGE_DOFS[:-8]
    return dofs


def _facet_values(gf_comp: ngs.GridFunction, order: int, edges: np.ndarray, owner=None) -> np.ndarray:
    """Dof values (len(edges), order + 1) of a FacetFESpace GridFunction (mean, then the
    linear coefficient: value at the edge's vertex 0 = d0 - d1, at vertex 1 = d0 + d1)."""
    space = gf_comp.space
    vec = gf_comp.vec.FV().NumPy()
    dofs = _edge_dofs(space, edges, owner)
    return np.where(dofs >= 0, vec[np.maximum(dofs, 0)], 0.0)[:, : order + 1]


def _facet_dof_table(space: ngs.FESpace, ned: int, order: int) -> np.ndarray:
    """(ned, order + 1) dof numbers of a whole-mesh facet space (-1 for the edges without
    dofs: a refined mesh keeps its bisected parent edges). The layout (order + 1) e + j
    of an unrefined mesh is checked on the first and last edges, else read edge by edge."""
    guess = (order + 1) * np.arange(ned)[:, None] + np.arange(order + 1)[None, :]
    probe = [0, ned - 1]
    if space.ndof == guess.size and all(tuple(space.GetDofNrs(ngs.NodeId(ngs.EDGE, e))) == tuple(guess[e]) for e in probe):
        return guess
    table = -np.ones((ned, order + 1), dtype=int)
    for e in range(ned):
        d = space.GetDofNrs(ngs.NodeId(ngs.EDGE, e))
        if len(d) == order + 1:
            table[e] = d
    return table


def _node_barycentric(degree: int) -> np.ndarray:
    """(nk, 3) barycentric coordinates of the element nodes (vertices, then the edge mid
    points opposite vertex 0, 1, 2), pulled INWARD of the way to the centroid."""
    lam = np.eye(3)
    if degree == 2:
        lam = np.vstack([lam, [[0.0, 0.5, 0.5], [0.5, 0.0, 0.5], [0.5, 0.5, 0.0]]])
    return lam + INWARD * (1.0 / 3.0 - lam)


def _element_mesh_points(cmesh: CrackMesh, top: _Topology, lam: np.ndarray) -> np.ndarray | None:
    """NGSolve mesh points at barycentric coordinates `lam` (nk, 3) in every element, in
    element order (no point search: `geometry.element_points`); None where they cannot
    be built that way."""
    return element_points(cmesh, lam)


def _local_mesh_points(cmesh: CrackMesh, top: _Topology, degree: int) -> np.ndarray:
    """The element nodes of `_sample_local` as mesh points in their own element (or
    found by the point search where `_element_mesh_points` cannot build them)."""
    lam = _node_barycentric(degree)
    mips = _element_mesh_points(cmesh, top, lam)
    if mips is None:
        pts = np.einsum("kv,evd->ekd", lam, top.P[top.T]).reshape(-1, 2)
        return cmesh.mesh(pts[:, 0], pts[:, 1])
    return mips


def _evaluate(cf, mips) -> np.ndarray:
    """A field at mesh points; a tree of CoefficientFunctions is compiled first (the same
    operations, three times faster at 1e5 points: measured)."""
    if not isinstance(cf, ngs.GridFunction):
        cf = cf.Compile()
    return np.asarray(cf(mips))


def _sample_local(cf, cmesh: CrackMesh, top: _Topology, degree: int, ncomp: int) -> np.ndarray:
    """Values (ne, nk, ncomp) of an element-wise field at each element's own nodes
    (pulled INWARD of the way to the element's centroid)."""
    vals = _evaluate(cf, _local_mesh_points(cmesh, top, degree)).reshape(len(top.T), -1, ncomp)
    return vals


def _element_sizes(top: _Topology) -> np.ndarray:
    X = top.P[top.T]
    return np.max(np.stack([np.linalg.norm(X[:, i] - X[:, (i + 1) % 3], axis=1) for i in range(3)]), axis=0)


def _integrate(cf, mesh) -> np.ndarray:
    """Element-wise integrals; the compiled tree is 10-20 times faster (measured)."""
    return np.asarray(ngs.Integrate(cf.Compile(), mesh, order=INTORDER, element_wise=True)).reshape(-1)


class _Quadrature:
    """NGSolve's order-INTORDER rule on every (straight) triangle, and the stress there.

    The element integrals of the estimate are sums over these points in numpy: the same
    points and weights as `ngs.Integrate(..., element_wise=True)`, the stress evaluated
    once at all of them (as mesh points in their own element, no point search), the
    reconstructed fields from their nodal values and the Lagrange basis. Measured at
    1e5 unknowns: 5-10 times faster than integrating the CoefficientFunction trees.
    None (`build`) where the mesh is curved: then the integrals go through NGSolve.
    """

    def __init__(self, lam: np.ndarray, weights: np.ndarray, mips: np.ndarray):
        self.lam = lam  # (nq, 3) barycentric coordinates of the points
        self.weights = weights  # (ne, nq) weights times |det J|
        self.mips = mips  # (ne * nq) mesh points
        self._gradients: dict[int, np.ndarray] = {}

    @classmethod
    def build(cls, cmesh: CrackMesh, top: _Topology, straight: bool = False) -> _Quadrature | None:
        """The rule on the mesh; None where it is curved or the points cannot be built without
        a point search. ``straight``: the rule on the straight triangles in any case, its points
        found by the point search where needed (the same points and weights)."""
        mesh = cmesh.mesh
        if not straight and getattr(mesh, "GetCurveOrder", lambda: 1)() > 1:
            return None
        ir = ngs.IntegrationRule(ngs.TRIG, INTORDER)
        ref = np.array([tuple(p)[:2] for p in ir.points], float)
        lam = np.column_stack([ref[:, 0], ref[:, 1], 1.0 - ref[:, 0] - ref[:, 1]])
        X = top.P[top.T]
        det = np.abs((X[:, 0, 0] - X[:, 2, 0]) * (X[:, 1, 1] - X[:, 2, 1])
                     - (X[:, 1, 0] - X[:, 2, 0]) * (X[:, 0, 1] - X[:, 2, 1]))
        mips = _element_mesh_points(cmesh, top, lam)
        if mips is None and straight:
            pts = np.einsum("qv,evd->eqd", lam, X).reshape(-1, 2)
            mips = mesh(pts[:, 0], pts[:, 1])
        if mips is None:
            return None
        return cls(lam=lam, weights=det[:, None] * np.asarray(ir.weights, float)[None, :], mips=mips)

    def stress(self, sigma) -> np.ndarray:
        """(ne, nq, 2, 2) values of a 2x2 matrix field at the points."""
        ne, nq = self.weights.shape
        return _evaluate(sigma, self.mips).reshape(ne, nq, 2, 2)

    def energy(self, d: np.ndarray, A) -> np.ndarray:
        """Per triangle: the integral of (A d) : d for d (ne, nq, 2, 2)."""
        tr = d[..., 0, 0] + d[..., 1, 1]
        dd = d[..., 0, 0] ** 2 + d[..., 0, 1] ** 2 + d[..., 1, 0] ** 2 + d[..., 1, 1] ** 2
        return np.sum(self.weights * (A.c_dev * dd - A.c_tr * tr * tr), axis=1)

    def deviatoric_and_trace(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per triangle: the integrals of |dev d|^2 and (tr d)^2 for d (ne, nq, 2, 2)."""
        tr = d[..., 0, 0] + d[..., 1, 1]
        dd = d[..., 0, 0] ** 2 + d[..., 0, 1] ** 2 + d[..., 1, 0] ** 2 + d[..., 1, 1] ** 2
        return np.sum(self.weights * (dd - 0.5 * tr * tr), axis=1), np.sum(self.weights * tr * tr, axis=1)

    def basis(self, degree: int, inward: float = 0.0) -> np.ndarray:
        """(nq, nk) Lagrange basis values at the points (vertices, then edge mid points
        opposite 0, 1, 2), of the nodes pulled `inward` of the way to the centroid."""
        lam = (self.lam - inward / 3.0) / (1.0 - inward)
        if degree == 1:
            return lam
        phi = [lam[:, i] * (2 * lam[:, i] - 1) for i in range(3)]
        phi += [4 * lam[:, (o + 1) % 3] * lam[:, (o + 2) % 3] for o in range(3)]
        return np.column_stack(phi)

    def basis_gradient(self, top: _Topology, degree: int) -> np.ndarray:
        """(ne, nq, nk, 2) gradients of the Lagrange basis at the points (kept: mesh data only)."""
        kept = self._gradients.get(degree)
        if kept is None:
            kept = self._gradients[degree] = self._basis_gradient(top, degree)
        return kept

    def _basis_gradient(self, top: _Topology, degree: int) -> np.ndarray:
        X = top.P[top.T]
        xc = X.mean(axis=1)
        M = np.concatenate([np.ones((len(X), 3, 1)), X - xc[:, None, :]], axis=2)
        g = np.transpose(np.linalg.inv(M)[:, 1:, :], (0, 2, 1))  # (ne, 3, 2): grad lambda_i
        lam = self.lam
        if degree == 1:
            return np.ascontiguousarray(np.broadcast_to(g[:, None, :, :], (len(X), len(lam), 3, 2)))
        out = [(4 * lam[None, :, i, None] - 1) * g[:, None, i, :] for i in range(3)]
        for o in range(3):
            i, j = (o + 1) % 3, (o + 2) % 3
            out.append(4 * (lam[None, :, i, None] * g[:, None, j, :] + lam[None, :, j, None] * g[:, None, i, :]))
        return np.stack(out, axis=2)


def _postprocessed(quad: _Quadrature, top: _Topology, grad: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Local P2 displacements (ne, 6, 2) at each element's nodes, from a gradient and a
    displacement at the quadrature points ((ne, nq, 2, 2), (ne, nq, 2)): per element and
    component, grad w_i is the L2-nearest to grad[..., i, :], with the mean of u_i (the
    local post-processing of mixed methods, from the stress's strain and the rotation)."""
    G = quad.basis_gradient(top, 2)  # (ne, nq, 6, 2)
    phi = quad.basis(2)  # (nq, 6)
    wq = quad.weights
    ne, nk = len(wq), phi.shape[1]
    M = np.zeros((ne, nk + 1, nk + 1))
    M[:, :nk, :nk] = np.einsum("eq,eqkd,eqld->ekl", wq, G, G)
    area = wq.sum(axis=1, keepdims=True)
    M[:, :nk, nk] = M[:, nk, :nk] = (wq @ phi) / area  # the mean (not the integral): rows of one size
    rhs = np.empty((ne, nk + 1, 2))
    rhs[:, :nk, :] = np.einsum("eq,eqkd,eqid->eki", wq, G, grad)
    rhs[:, nk, :] = np.einsum("eq,eqi->ei", wq, u) / area
    return np.linalg.solve(M, rhs)[:, :nk, :]


def _quadrature(cmesh: CrackMesh, top: _Topology) -> _Quadrature | None:
    """The `_Quadrature` of a mesh, kept with its topology (read only once built)."""
    q = getattr(top, "_quadrature", False)
    if q is False:
        q = _Quadrature.build(cmesh, top)
        object.__setattr__(top, "_quadrature", q)
    return q

