"""A posteriori estimates of the stress error in the energy (compliance) norm.

The error measured is ||sigma - sigma_h||_A = (A (sigma - sigma_h), sigma - sigma_h)^(1/2),
A the compliance (materials.py), sigma the exact stress and sigma_h the discrete one
(the weakly symmetric one for PEERS and BDM: its skew part counts as error).

Mixed elements (peers, bdm, tdnns), a Prager-Synge (hypercircle) estimate. For w a
displacement that is admissible on the cracked body (w = u_D on the Dirichlet edges,
w.n = 0 on rollers, continuous except across the crack, [w].nu >= 0 on it) and sigma_h
statically admissible (div sigma_h = -f, sigma_h n = g on traction edges, symmetric,
sigma_h nu . t = 0 and sigma_h,n <= 0 on the crack),

    ||sigma - sigma_h||_A^2 + ||sigma - C eps(w)||_A^2
        <= ||sigma_h - C eps(w)||_A^2 + 2 int_crack (-sigma_h,n) [w].nu ds,

(expand |a - b|^2 + |a - c|^2, integrate by parts; the crack terms -sigma_n [u].nu = 0,
sigma_n [w].nu <= 0 and sigma_h,n [u].nu <= 0 drop out).

The first term weighs the strain residual r = A sigma_h - eps(w) as
||r||_C^2 = 2 mu ||dev r||^2 + (lambda + mu) ||tr r||^2 (2D; dev includes the skew part),
and w, rebuilt from the discrete displacement, is not divergence free: its volumetric
part grows like lambda as nu -> 1/2 (up to sqrt(lambda / mu) in eta). The estimate is
made robust in lambda with the tr-dev-div inequality: the error e = sigma - sigma_h is
divergence free with e n = 0 on the traction edges, so ||tr e|| <= C_td ||dev e||, and

    ||e||_A^2 = (eps(w) - A sigma_h, e) = (dev(-r), dev e) + (tr(-r), tr e) / 2
              <= (sqrt(2 mu) ||dev r|| + sqrt(kappa) ||tr r||) ||e||_A,
    kappa = min(lambda + mu, C_td^2 mu / 2),

(||dev e|| <= sqrt(2 mu) ||e||_A, ||tr e|| <= 2 sqrt(lambda + mu) ||e||_A). So

    eta^2 = sum_T eta_T^2,
    eta_T^2 = 2 mu ||dev r||_T^2 + kappa ||tr r||_T^2 + contact_T + osc_T^2

(terms "deviatoric", "volumetric", "contact", "oscillation"; "stress" is the sum of the
first two), kappa = min(lambda + mu, VOLUMETRIC_WEIGHT mu). Up to nu = 0.3 in plane
strain (lambda + mu = 2.5 mu there) this is the plain Prager-Synge estimate above, which
is a guaranteed upper bound whenever the hypotheses hold; above, the volumetric weight
stays at its nu = 0.3 value (C_td^2 = 5 assumed: C_td depends on the body and is not
known, and the sum of two square roots costs a factor up to sqrt(2)), so that the
effectivity stays where it is at nu = 0.3 (the estimates guide's table, to nu = 0.4999).

w is reconstructed element by element. PEERS and BDM: from the facet displacement traces
(the crack's minus side seeing u_hat - j): PEERS' P0 traces are the Crouzeix-Raviart
values of a local P1 field, BDM's P1 traces give a local P2 field (vertex values averaged
over the element's two edges, mid points the edge means). TDNNS: a local post-processing
of its tangential-continuous u_h, the P2 field whose gradient is the L2-nearest to
A sigma_h + skew(grad u_h) with the mean of u_h (sampling u_h itself gives an O(h)
estimate of an O(h^2) stress error on smooth solutions). Local values are averaged node by node, each crack node
duplicated per side (interior tips are not: w is continuous there), so w is continuous
except across the crack; Dirichlet and roller nodes are then set to their data, and
the crack nodes are moved symmetrically until [w].nu >= 0 at the vertices and the
Bernstein coefficient of the quadratic jump is >= 0 too (so [w].nu >= 0 everywhere on
the edge). Crack models: "free" needs no sign, "bonded" sets [w].nu = 0.

Where the bound is not guaranteed (README, "Error estimates"):
- PEERS and BDM: sigma_h is symmetric only weakly. Its skew part enters the first
  term (A acts on it as c_dev), but the identity above also needs (as sigma_h, rot(u - w)/2),
  bounded only with a Korn constant that is unknown on a cracked body;
- TDNNS: sigma_h is normal-normal but not normal-tangential continuous (not in H(div));
- nu > 0.3 in plane strain: the capped volumetric weight assumes C_td^2 <= 5 (a note says so);
- body forces that are not P0 per triangle: the oscillation term
  osc_T = h_T / pi ||f - Pi_0 f||_T sqrt(c_dev) needs the same Korn constant;
- BDM's P1 crack pressure may be slightly positive between its constraint points:
  the contact term uses |sigma_h,n| (then [u].nu against it is unknown);
- non-constant traction data (its projection on the facet space is equilibrated);
- friction: not covered (the crack's shear traction is taken as zero).

The baselines h1p1, h1p2: the Zienkiewicz-Zhu recovery estimate eta_T =
||sigma* - sigma_h||_{A,T}, sigma* the node-averaged stress (continuous P_k per crack
side). Not a bound; asymptotically exact where the recovery superconverges.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np

from ..core.errors import InputError
from .elements import TRAITS
from .geometry import CrackMesh
from .local_fields import (
    INTORDER,
    INWARD,
    _average,
    _element_sizes,
    _evaluate,
    _facet_dof_table,
    _facet_values,
    _integrate,
    _Lagrange,
    _postprocessed,
    _Quadrature,
    _quadrature,
    _sample_local,
    _Topology,
    _topology,
)
from .materials import compliance, lame_parameters
from .scene.pressure import pressure_values

#: the crack models with an estimate (the sign condition on [w].nu differs per model)
ESTIMATE_CRACK_MODELS = ("contact", "free", "bonded")
#: the elements with an estimate, and which kind (each element's ElementTraits.estimate)
METHODS = {name: t.estimate for name, t in TRAITS.items() if t.estimate}
#: Gauss-Legendre points per crack edge for the contact term (exact for degree 5)
CRACK_GAUSS_POINTS = 3


#: kappa / mu at most: the weight of the volumetric strain residual (lambda + mu, capped at the
#: value of nu = 0.3 in plane strain: the estimate's robustness in lambda, see the module)
VOLUMETRIC_WEIGHT = 2.5


@dataclass
class ErrorEstimate:
    """The estimate of one solve.

    `energy` = eta (stress units times strain: sqrt of an energy), `relative` =
    eta / ||sigma_h||_A, `eta` the per-triangle indicators eta_T (NGSolve element
    order; sum of squares = energy^2), `terms` the squared totals of the parts
    ("stress", "contact", "oscillation"), `guaranteed` whether the theory makes energy
    an upper bound for this element and data (see the module), `notes` why not,
    `time` its seconds, `min_jump` the smallest [w].nu at the crack's quadrature points.
    """

    energy: float
    relative: float
    eta: np.ndarray
    terms: dict
    method: str
    guaranteed: bool
    notes: list[str]
    mesh: ngs.Mesh = field(repr=False)
    time: float = 0.0
    min_jump: float = 0.0
    def line(self) -> str:
        """The estimate in one line, as `ngcrack solve` prints it."""
        return (f"error estimate ({self.method}{'' if self.guaranteed else ', not a guaranteed bound'}): "
                f"energy norm {self.energy:.3e}, relative {self.relative:.2%}")

    def __repr__(self) -> str:
        return f"ErrorEstimate({self.line()})"

    def __str__(self) -> str:
        return self.line()

    @property
    def indicator(self) -> ngs.GridFunction:
        """eta_T as a piecewise constant NGSolve GridFunction (Draw it, or sample it)."""
        gf = ngs.GridFunction(ngs.L2(self.mesh, order=0))
        gf.vec.FV().NumPy()[:] = self.eta
        return gf

    def to_dict(self) -> dict:
        """The `error_estimate` entry of the solve --json contract."""
        return {"energy": float(self.energy), "relative": float(self.relative)}


# ------------------------------------------------------------------ mesh topology


# ---------------------------------------------------- piecewise Lagrange fields


# ----------------------------------------------- local displacements per element


def _hybrid_traces(sol, top: _Topology) -> tuple[np.ndarray, int]:
    """Local P1 (PEERS) or P2 (BDM) displacements from the facet traces: (ne, nk, 2)."""
    disc, gf, cmesh = sol.disc, sol.gf, sol.crack_mesh
    p = disc.facet_order
    ned = cmesh.mesh.nedge
    comps = gf.components
    table = _facet_dof_table(disc.fes.components[disc.uhat[0]], ned, p)
    uh = np.stack([np.where(table >= 0, comps[c].vec.FV().NumPy()[np.maximum(table, 0)], 0.0)
                   for c in disc.uhat], axis=-1)  # (ned, p+1, 2)
    minus_edges, minus = [], []  # crack edges, and the traces u_hat - j their minus sides see
    if disc.jn is not None and cmesh.cracks:
        for c in cmesh.cracks:
            jn = _facet_values(comps[disc.jn], p, c.edge, (disc.fes, disc.jn))
            jt = _facet_values(comps[disc.jt], p, c.edge, (disc.fes, disc.jt))
            jump = jn[:, :, None] * c.normal[:, None, :] + jt[:, :, None] * c.tangent[:, None, :]
            minus_edges.append(np.asarray(c.edge, dtype=int))
            minus.append(uh[c.edge] - jump)
    ne = len(top.T)
    # trace seen by each element on the edge opposite each of its vertices
    tr = uh[top.opp_edge]  # (ne, 3, p+1, 2)
    if minus:
        rows, slots = np.nonzero(top.crack_edge[top.opp_edge] & (top.side[:, None] < 0))
        at = np.full(ned, -1)
        at[np.concatenate(minus_edges)] = np.arange(sum(len(e) for e in minus_edges))
        tr[rows, slots] = np.concatenate(minus)[at[top.opp_edge[rows, slots]]]
    if p == 0:  # Crouzeix-Raviart: w(v_i) = sum_k t_k - 2 t_i
        t = tr[:, :, 0, :]
        return (t.sum(axis=1, keepdims=True) - 2.0 * t), 1
    # P1 traces: values at the edge's own vertex 0 and 1; match them to local vertices
    EV = top.edge_vertices[top.opp_edge]  # (ne, 3, 2)
    at0, at1 = tr[:, :, 0, :] - tr[:, :, 1, :], tr[:, :, 0, :] + tr[:, :, 1, :]
    vert = np.zeros((ne, 3, 2))
    for i in range(3):
        for s in range(3):
            if s == i:
                continue
            v = top.T[:, i]
            vert[:, i] += np.where((EV[:, s, 0] == v)[:, None], at0[:, s], at1[:, s])
    vert *= 0.5
    return np.concatenate([vert, tr[:, :, 0, :]], axis=1), 2


# ------------------------------------------------------------ boundary and crack data

def _boundary_nodes(cmesh: CrackMesh, top: _Topology, degree: int) -> list:
    """Per boundary element, in mesh order: (label, node ids, node points, outer normal)
    of the node copies of its own triangle (kept with the topology: mesh data only)."""
    kept = top.__dict__.setdefault("_boundary_nodes", {})
    if degree in kept:
        return kept[degree]
    mesh = cmesh.mesh
    ne = len(top.T)
    owner = np.full(mesh.nedge, -1)
    slot = np.full(mesh.nedge, -1)
    owner[top.opp_edge.ravel()] = np.repeat(np.arange(ne), 3)
    slot[top.opp_edge.ravel()] = np.tile(np.arange(3), ne)
    rows = []
    for el in mesh.Elements(ngs.BND):
        vs = [v.nr for v in el.vertices]
        e = el.edges[0].nr
        T, k = owner[e], slot[e]
        local = [int(np.flatnonzero(top.T[T] == v)[0]) for v in vs]
        ids = [int(top.vertex_node[T, i]) for i in local]
        pts = [top.P[v] for v in vs]
        if degree == 2:
            ids.append(int(top.edge_node[T, k]))
            pts.append(0.5 * (top.P[vs[0]] + top.P[vs[1]]))
        d = top.P[vs[1]] - top.P[vs[0]]
        rows.append((el.mat, ids, np.array(pts), np.array([d[1], -d[0]]) / np.linalg.norm(d)))
    kept[degree] = rows
    return rows


def _apply_boundary(W: np.ndarray, cmesh: CrackMesh, top: _Topology, loads, degree: int) -> None:
    """Dirichlet nodes take the data, roller nodes lose their normal component.

    Only the node copies of the boundary edge's own triangle are set: where a crack
    meets the boundary, the other face's copy belongs to the next boundary piece (the
    paper-1 crack ends between a clamped and a free edge)."""
    mesh = cmesh.mesh
    dirichlet = set(loads.dirichlet_labels)
    roller = set(loads.roller)
    if not dirichlet and not roller:
        return
    rows = _boundary_nodes(cmesh, top, degree)
    data = {}  # label -> the data at its nodes, one evaluation per label
    for lab in dirichlet:
        g = loads.displacement.get(lab)
        at = [r[2] for r in rows if r[0] == lab]
        if g is not None and at:
            pts = np.concatenate(at)
            data[lab] = iter(np.asarray(g(mesh(pts[:, 0], pts[:, 1]))).reshape(len(pts), -1)[:, :2])
    for lab, ids, _pts, n in rows:
        if lab in dirichlet:
            values = data.get(lab)
            for i in ids:
                W[i] = 0.0 if values is None else next(values)
        elif lab in roller:
            for i in ids:
                W[i] -= np.dot(W[i], n) * n


def _crack_node_pairs(cmesh: CrackMesh, top: _Topology, degree: int):
    """Per crack edge: (minus, plus) node ids of vertex a, vertex b and the mid point."""
    nv, ned = len(top.P), cmesh.mesh.nedge
    for c in cmesh.cracks:
        for k in range(len(c)):
            va, vb, e = int(c.va[k]), int(c.vb[k]), int(c.edge[k])
            pa = (va, va) if va in cmesh.tip_vertices else (va, va + nv)
            pb = (vb, vb) if vb in cmesh.tip_vertices else (vb, vb + nv)
            pm = (2 * nv + e, 2 * nv + e + ned)
            yield c, k, pa, pb, pm


def _admissible_crack(W: np.ndarray, cmesh: CrackMesh, top: _Topology, degree: int, crack_model: str) -> None:
    """Move the two sides of every crack node symmetrically along nu: [w].nu >= 0
    (contact) or [w].nu = 0 (bonded). Two passes settle the vertices shared at kinks."""
    if crack_model == "free" or not cmesh.cracks:
        return

    def push(pair, nu, target):
        m, p = pair
        if m == p:
            return
        jn = float(np.dot(W[p] - W[m], nu))
        if (crack_model == "bonded" and jn != target) or jn < target:
            delta = 0.5 * (target - jn) * nu
            W[p] += delta
            W[m] -= delta

    for _ in range(2):
        for c, k, pa, pb, _pm in _crack_node_pairs(cmesh, top, degree):
            nu = c.normal[k]
            push(pa, nu, 0.0)
            push(pb, nu, 0.0)
    if degree == 2:
        for c, k, pa, pb, pm in _crack_node_pairs(cmesh, top, degree):
            nu = c.normal[k]
            ja, jb = (float(np.dot(W[p[1]] - W[p[0]], nu)) for p in (pa, pb))
            # quadratic jump with end values ja, jb and mid value jm: Bernstein coefficient
            # 2 jm - (ja + jb)/2 >= 0 makes it >= 0 on the whole edge
            push(pm, nu, 0.0 if crack_model == "bonded" else 0.25 * (ja + jb))


def _crack_node_arrays(cmesh: CrackMesh, top: _Topology, c) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """`_crack_node_pairs` of one crack as arrays (len(c), 2): (minus, plus) of vertex a,
    vertex b and the mid point of each edge."""
    nv, ned = len(top.P), cmesh.mesh.nedge
    tips = np.array(sorted(cmesh.tip_vertices), dtype=int)
    va, vb, e = (np.asarray(v, dtype=int) for v in (c.va, c.vb, c.edge))
    pa = np.column_stack([va, np.where(np.isin(va, tips), va, va + nv)])
    pb = np.column_stack([vb, np.where(np.isin(vb, tips), vb, vb + nv)])
    pm = np.column_stack([2 * nv + e, 2 * nv + e + ned])
    return pa, pb, pm


def _crack_jump_quadrature(W: np.ndarray, cmesh: CrackMesh, top: _Topology, degree: int) -> dict | None:
    """Gauss points on the crack edges (edge, point, 2), their weights, [w].nu there, the
    normals, edge ids and lengths (one row per crack edge, all cracks); None without cracks."""
    g, wg = np.polynomial.legendre.leggauss(CRACK_GAUSS_POINTS)
    t = 0.5 * (g + 1.0)
    parts = []
    for c in cmesh.cracks:
        if not len(c):
            continue
        pa, pb, pm = _crack_node_arrays(cmesh, top, c)
        nu = np.asarray(c.normal, float)
        ja = np.sum((W[pa[:, 1]] - W[pa[:, 0]]) * nu, axis=1)[:, None]
        jb = np.sum((W[pb[:, 1]] - W[pb[:, 0]]) * nu, axis=1)[:, None]
        if degree == 1:
            j = (1 - t) * ja + t * jb
        else:
            jm = np.sum((W[pm[:, 1]] - W[pm[:, 0]]) * nu, axis=1)[:, None]
            j = ja * (1 - t) * (1 - 2 * t) + jb * t * (2 * t - 1) + jm * 4 * t * (1 - t)
        x = c.a[:, None, :] + t[None, :, None] * (c.b - c.a)[:, None, :]
        L = c.length
        parts.append({"x": x, "w": 0.5 * wg[None, :] * L[:, None], "j": j, "nu": nu,
                      "edge": np.asarray(c.edge, dtype=int), "L": L,
                      "s": c.s_mid[:, None] + (t[None, :] - 0.5) * L[:, None], "crack": np.full(len(c), c.index)})
    if not parts:
        return None
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


# ---------------------------------------------------------------------- estimate

def _zz_recovery(sol, top: _Topology, A, quad=None) -> tuple[dict[str, np.ndarray], np.ndarray | None]:
    """eta_T^2 = ||sigma* - sigma_h||_A,T^2, sigma* the node-averaged stress (per crack
    face); and sigma_h at the quadrature points (None without `quad`).

    sigma_h of h1p1, h1p2 is a polynomial of degree estimate_degree - 1 on each triangle, so its
    values at the quadrature points are the interpolation of its values at the
    element's (inward) nodes: one evaluation of the stress, not two."""
    cmesh, degree = sol.crack_mesh, sol.disc.traits.estimate_degree
    local = _sample_local(sol.sigma, cmesh, top, degree, 4)
    nodal, nodes = _average(top, local, degree)
    if quad is not None:
        ne, nq = quad.weights.shape
        sig_q = np.matmul(quad.basis(degree, INWARD)[None], local).reshape(ne, nq, 2, 2)
        recovered = np.matmul(quad.basis(degree)[None], nodal[nodes]).reshape(ne, nq, 2, 2)
        return {"stress": quad.energy(recovered - sig_q, A)}, sig_q
    lag = _Lagrange(cmesh.mesh, top, degree, 4)
    lag.set(nodal[nodes])
    s = lag.value()
    d = ngs.CF((s[0], s[1], s[2], s[3]), dims=(2, 2)) - sol.sigma
    return {"stress": _integrate(ngs.InnerProduct(A.apply(d), d), cmesh.mesh)}, None


def _admissible_displacement(sol, loads, crack_model: str, top: _Topology) -> tuple[np.ndarray, np.ndarray, int]:
    """Node values W of w (admissible: data on the boundary, [w].nu >= 0 on the crack),
    the element-node table and the degree."""
    if sol.disc.traits.hybrid_traces:
        local, degree = _hybrid_traces(sol, top)
    elif sol.disc.traits.gradient == "skew":  # TDNNS: the local post-processing of u
        from .tips import displacement_gradient

        quad = _quadrature(sol.crack_mesh, top) or _Quadrature.build(sol.crack_mesh, top, straight=True)
        ne, nq = quad.weights.shape
        grad = _evaluate(displacement_gradient(sol), quad.mips).reshape(ne, nq, 2, 2)
        u = _evaluate(sol.u, quad.mips).reshape(ne, nq, 2)
        local, degree = _postprocessed(quad, top, grad, u), 2
    else:
        degree = sol.disc.traits.estimate_degree
        local = _sample_local(sol.u, sol.crack_mesh, top, degree, 2)
    W, nodes = _average(top, local, degree)
    _apply_boundary(W, sol.crack_mesh, top, loads, degree)
    _admissible_crack(W, sol.crack_mesh, top, degree, crack_model)
    return W, nodes, degree


def _contact_term(sol, W: np.ndarray, top: _Topology, degree: int) -> tuple[np.ndarray, float]:
    """2 int_e |sigma_h,n + p| [w].nu per crack edge (p the crack-face pressure, 0 without one:
    the contact's part of the traction), split between its two triangles; and min [w].nu."""
    cmesh = sol.crack_mesh
    mesh = cmesh.mesh
    out = np.zeros(mesh.ne)
    q = _crack_jump_quadrature(W, cmesh, top, degree)
    if q is None:
        return out, 0.0
    # sigma_h nu . nu is single-valued on the crack for the mixed elements: sample the minus side
    pts = (q["x"] - INWARD * q["L"][:, None, None] * q["nu"][:, None, :]).reshape(-1, 2)
    sig = np.asarray(sol.sigma(mesh(pts[:, 0], pts[:, 1]))).reshape(len(q["edge"]), -1, 2, 2)
    nu = q["nu"]
    sn = np.einsum("ei,epij,ej->ep", nu, sig, nu)
    # the contact's part of the normal traction: a crack-face pressure p is load data (sigma_n = -p - lam)
    for k, crack in enumerate(sol.scene.cracks):
        if getattr(crack, "pressure", None) is not None:
            on = q["crack"] == k
            sn[on] += pressure_values(crack.pressure, q["s"][on])
    per_edge = 2.0 * np.sum(q["w"] * np.abs(sn) * q["j"], axis=1)
    kept = top.__dict__.setdefault("_edge_elements", {})  # mesh data: kept with the topology
    for e, value in zip(q["edge"], per_edge):
        els = kept.get(int(e))
        if els is None:
            els = kept[int(e)] = [el.nr for el in mesh.edges[int(e)].elements]
        out[els] += value / len(els)
    return out, min(0.0, float(q["j"].min()))


def _oscillation(mesh, top: _Topology, f, A) -> np.ndarray:
    """osc_T^2 = (h_T / pi)^2 ||f - Pi_0 f||_T^2 c_dev (Poincare on the triangle; Korn not included)."""
    area = _integrate(ngs.CF(1.0), mesh)
    osc2 = _integrate(f * f, mesh)
    for i in range(2):
        osc2 -= _integrate(f[i], mesh) ** 2 / area
    return (_element_sizes(top) / math.pi) ** 2 * np.maximum(osc2, 0.0) * A.c_dev


def _robust_parts(dev_and_trace: tuple[np.ndarray, np.ndarray], A) -> dict:
    """The stress term split: ||dev r||^2 2 mu ("deviatoric") and kappa ||tr r||^2 ("volumetric"),
    r = A sigma_h - eps(w) = A d, from the per-triangle integrals of |dev d|^2 and (tr d)^2."""
    dev2, tr2 = dev_and_trace
    s = A.c_dev / 2.0 - A.c_tr  # (A tau) : tau = c_dev |dev tau|^2 + s (tr tau)^2; tr(A d) = 2 s tr d
    kappa = min(1.0 / (4.0 * s), VOLUMETRIC_WEIGHT / (2.0 * A.c_dev))  # min(lambda + mu, c mu)
    return {"deviatoric": A.c_dev * dev2, "volumetric": 4.0 * s * s * kappa * tr2}


def _prager_synge(sol, loads, crack_model: str, top: _Topology, A, notes: list[str], quad=None,
                  sig_q=None) -> tuple[dict, float]:
    """The squared per-triangle parts of the mixed elements' estimate (see the module)."""
    mat = sol.scene.material
    lam, mu = lame_parameters(mat.E, mat.nu, mat.plane)
    if not math.isfinite(lam):
        raise InputError("material.nu = 0.5: the Prager-Synge estimate needs a finite C (nu < 1/2 in plane strain)")
    mesh = sol.crack_mesh.mesh
    W, nodes, degree = _admissible_displacement(sol, loads, crack_model, top)
    if quad is not None:
        # (grad w)_ij = d w_i / d x_j = sum_k W_k,i d phi_k / d x_j, component by component
        G, Wn = quad.basis_gradient(top, degree), W[nodes]  # (ne, nq, nk, 2), (ne, nk, 2)
        g = [[np.einsum("ek,eqk->eq", Wn[:, :, i], G[:, :, :, j]) for j in range(2)] for i in range(2)]
        e01 = 0.5 * (g[0][1] + g[1][0])
        tr = g[0][0] + g[1][1]
        d = np.empty_like(sig_q)
        d[..., 0, 0] = sig_q[..., 0, 0] - (2 * mu * g[0][0] + lam * tr)
        d[..., 1, 1] = sig_q[..., 1, 1] - (2 * mu * g[1][1] + lam * tr)
        d[..., 0, 1] = sig_q[..., 0, 1] - 2 * mu * e01
        d[..., 1, 0] = sig_q[..., 1, 0] - 2 * mu * e01
        parts = _robust_parts(quad.deviatoric_and_trace(d), A)
    else:
        lag = _Lagrange(mesh, top, degree, 2)
        lag.set(W[nodes])
        g = lag.gradient()
        eps = 0.5 * (g + g.trans)
        d = sol.sigma - (2 * mu * eps + lam * ngs.Trace(eps) * ngs.Id(2))
        tr = ngs.Trace(d)
        dev = d - 0.5 * tr * ngs.Id(2)
        parts = _robust_parts((_integrate(ngs.InnerProduct(dev, dev), mesh), _integrate(tr * tr, mesh)), A)
    min_jump = 0.0
    if sol.crack_mesh.cracks and crack_model == "contact":
        parts["contact"], min_jump = _contact_term(sol, W, top, degree)
    if loads.body_force is not None:
        parts["oscillation"] = _oscillation(mesh, top, loads.body_force, A)
        if parts["oscillation"].sum() > 0:
            notes.append("body force not P0: oscillation term with an unknown Korn constant")
    if sol.disc.traits.estimate_note:
        notes.append(sol.disc.traits.estimate_note)
    if min_jump < 0:
        notes.append(f"reconstructed crack jump negative somewhere ({min_jump:.2e})")
    if any(getattr(c, "friction", 0.0) for c in sol.scene.cracks):
        notes.append("friction: the crack's shear traction times [w].t is not included (not covered)")
    if lam + mu > VOLUMETRIC_WEIGHT * mu * (1 + 1e-12):  # (nu = 0.3 itself: not capped)
        notes.append(f"lambda + mu > {VOLUMETRIC_WEIGHT:g} mu: the volumetric residual's weight is capped there "
                     f"(robust in lambda; assumes a tr-dev-div constant C_td^2 <= {2 * VOLUMETRIC_WEIGHT:g})")
    return parts, min_jump


def estimate(sol, loads, crack_model: str = "contact") -> ErrorEstimate:
    """The error estimate of a Solution (see the module); loads are the solve's Loads."""
    t0 = time.perf_counter()
    method = sol.disc.traits.estimate
    if not method:
        raise InputError(f"element = {sol.element!r}: estimates exist for {', '.join(METHODS)}")
    if crack_model not in ESTIMATE_CRACK_MODELS:
        raise InputError(f"crack_model = {crack_model!r}: estimates exist for {', '.join(ESTIMATE_CRACK_MODELS)}")
    mat = sol.scene.material
    A = compliance(mat.E, mat.nu, mat.plane)
    mesh = sol.crack_mesh.mesh
    top = _topology(sol.crack_mesh)
    notes: list[str] = []
    min_jump = 0.0
    quad = _quadrature(sol.crack_mesh, top)
    if method == "zz-recovery":
        parts, sig_q = _zz_recovery(sol, top, A, quad)
        notes.append("recovery (ZZ) estimate: not a bound")
    else:
        sig_q = quad.stress(sol.sigma) if quad is not None else None
        parts, min_jump = _prager_synge(sol, loads, crack_model, top, A, notes, quad, sig_q)
    eta2 = sum(parts.values())
    terms = {k: float(parts[k].sum()) if k in parts else 0.0 for k in ("stress", "deviatoric", "volumetric", "contact", "oscillation")}
    if "deviatoric" in parts:
        terms["stress"] = terms["deviatoric"] + terms["volumetric"]
    if quad is not None:
        norm2 = float(np.sum(quad.energy(sig_q, A)))
    else:
        norm2 = float(np.sum(_integrate(ngs.InnerProduct(A.apply(sol.sigma), sol.sigma), mesh)))
    eta = np.sqrt(np.maximum(eta2, 0.0))
    if not np.all(np.isfinite(eta)):
        raise ValueError("the error estimate is not finite (check the loads and material data)")
    energy = float(np.sqrt(np.sum(eta**2)))
    relative = energy / math.sqrt(norm2) if norm2 > 0 else energy
    # no element's bound is guaranteed today (module docstring: weak symmetry, H(div), recovery)
    return ErrorEstimate(energy=energy, relative=relative, eta=eta, terms=terms, method=method,
                         guaranteed=False, notes=notes, mesh=mesh, time=time.perf_counter() - t0,
                         min_jump=min_jump)


# ------------------------------------------------------------------ true errors

def energy_error(sol, sigma_exact) -> float:
    """||sigma - sigma_h||_A on sol's mesh for an exact stress given as a CoefficientFunction."""
    mat = sol.scene.material
    A = compliance(mat.E, mat.nu, mat.plane)
    d = sigma_exact - sol.sigma
    return math.sqrt(max(float(ngs.Integrate(ngs.InnerProduct(A.apply(d), d), sol.mesh, order=2 * INTORDER)), 0.0))


def energy_error_against(sol, reference, order: int = INTORDER) -> float:
    """||sigma_ref - sigma_h||_A at the quadrature points of the reference (finer) mesh."""
    from .quadrature import quadrature_points

    mat = sol.scene.material
    A = compliance(mat.E, mat.nu, mat.plane)
    pts, wts = quadrature_points(reference.mesh, order)
    s_ref = np.asarray(reference.sigma(reference.mesh(pts[:, 0], pts[:, 1]))).reshape(-1, 2, 2)
    s_h = np.asarray(sol.sigma(sol.mesh(pts[:, 0], pts[:, 1]))).reshape(-1, 2, 2)
    d = s_ref - s_h
    Ad = A.c_dev * d - A.c_tr * np.trace(d, axis1=1, axis2=2)[:, None, None] * np.eye(2)
    return math.sqrt(max(float(wts @ np.einsum("pij,pij->p", Ad, d)), 0.0))
