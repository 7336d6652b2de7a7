"""Hybridized TDNNS in 3D with the crack's jumps; the H1-P2 displacement baseline.

Order k (1, 2 or 3; the stress degree), on tetrahedra:
- stress sigma: symmetric, HDivDiv of order k with its "plus" bubbles, broken (local);
- displacement u: HCurl of order k+1 of type 1 (tangentially continuous; global);
- normal facet trace u_hat_n: NormalFacetFESpace of order k (global), restoring the
  normal-normal continuity of sigma; rollers fix it, clamped faces fix it and u;
- crack normal jump jn: P_k per crack face (a facet space on the crack faces only): the
  tetrahedron on the - side sees u_hat_n - jn there; this is the contact unknown;
- crack tangential jump: a copy u_e of u's HCurl dofs on the crack's interior edges and
  faces (the front's edges excluded), used on the + side only: u = u_c + H+ u_e with
  H+ = 1 on the tetrahedra on the + side that hold such an edge. An HCurl function of
  an edge or face has a tangential trace on the faces through it only, so [u]_t = u_e
  on the crack and u stays tangentially continuous everywhere else.

The weak form is the gradient form of the 2D element (ngcrack.planar.elements.tdnns), with
b(sigma; v, v_hat_n) = sum_T [ -(sigma, grad v)_T + <sigma_nn, v.n - v_hat_n>_dT ]:

    (A sigma, tau) + b(tau; u, u_hat_n - chi jn) = 0
    b(sigma; v, v_hat_n - chi kn)                = -(f, v) - <g.n, v_hat_n> - <g_t, v_t>

A sigma = ((1 + nu) sigma - nu tr(sigma) I) / E, finite up to nu -> 1/2 (no locking at
0.4999: tests/test_solid.py). The form div(sigma).v - sigma_nn v_n of the tutorials gave
displacements about 30 times too small on a clamped cube against H1-P2; this one agrees.

G (`constraint_map`) maps the jn coefficients of each crack face to the Bernstein
coefficients of its P_k jump (its values at the vertices for k = 1): the contact
constraints w = G jn >= 0, which make the jump >= 0 on the whole face.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..core.discretization import Discretization, Loads
from ..core.parallel import task_manager
from ..planar.elements.tdnns import ORDERS, tdnns_order, tdnns_spaces, tdnns_terms  # noqa: F401  (ORDERS: the 3D orders too)
from .geometry import SolidMesh

#: extra quadrature order of the face tractions and crack pressures: a load varying in space
#: (solid.loads: its table's ramps count as order 0 to NGSolve) integrated to its degree
LOAD_BONUS_ORDER = 2


def compliance(E: float, nu: float) -> Callable:
    """sigma -> A sigma = ((1 + nu) sigma - nu tr(sigma) I) / E for a 3x3 CoefficientFunction."""
    c_dev, c_tr = (1.0 + nu) / E, nu / E
    return lambda s: c_dev * s - c_tr * ngs.Trace(s) * ngs.Id(3)


def _compress(space: ngs.FESpace, nodes: list[ngs.NodeId]) -> ngs.FESpace:
    active = ngs.BitArray(space.ndof)
    active.Clear()
    for node in nodes:
        for d in space.GetDofNrs(node):
            active[d] = True
    return ngs.Compress(space, active_dofs=active)


def _element_set(mesh: ngs.Mesh, elements) -> ngs.BitArray:
    ba = ngs.BitArray(mesh.ne)
    ba.Clear()
    for e in elements:
        ba[int(e)] = True
    return ba


def plus_side(smesh: SolidMesh) -> ngs.GridFunction:
    """H+: 1 on the + side's tetrahedra at a crack's interior edges, else 0."""
    mesh = smesh.mesh
    H = ngs.GridFunction(ngs.L2(mesh, order=0))
    h = np.zeros(mesh.ne)
    pts = smesh.points
    for c in smesh.cracks:
        for e in c.interior_edges:
            for el in mesh[ngs.NodeId(ngs.EDGE, int(e))].elements:
                centroid = pts[[v.nr for v in mesh[el].vertices]].mean(axis=0)
                if np.dot(centroid - c.crack.center, c.normal) > 0:
                    h[el.nr] = 1.0
    H.vec.FV().NumPy()[:] = h
    return H


def lagrange_points(k: int) -> np.ndarray:
    """The P_k Lagrange points of the reference triangle (x, y), vertices first."""
    pts = [(1.0, 0.0), (0.0, 1.0), (0.0, 0.0)]
    for i in range(k + 1):
        for j in range(k + 1 - i):
            p = (i / k, j / k)
            if p not in pts:
                pts.append(p)
    return np.array(pts)


def bernstein_at_lagrange(k: int) -> np.ndarray:
    """M[m, n] = B_n(p_m): the degree-k Bernstein polynomials of the triangle (indexed by the
    domain points, which are the Lagrange points of `lagrange_points`) at those points."""
    pts = lagrange_points(k)
    lam = np.column_stack([pts[:, 0], pts[:, 1], 1.0 - pts[:, 0] - pts[:, 1]])
    idx = np.rint(k * lam).astype(int)
    coef = np.array([math.factorial(k) / math.prod(math.factorial(int(i)) for i in row) for row in idx])
    return coef[None, :] * np.prod(lam[:, None, :] ** idx[None, :, :], axis=2)


def constraint_map(smesh: SolidMesh, jn_space: ngs.FESpace, full: ngs.FESpace, k: int):
    """(G, V, points): G maps the jn coefficients of each crack face to the Bernstein
    coefficients of its P_k normal jump (sparse, block diagonal per face), V to its values at
    the face's P_k Lagrange points, `points` those points in space, in jn's numbering.

    The Bernstein coefficients are the contact constraints: they are the values at the
    vertices, and all >= 0 makes the jump >= 0 on the whole face (the jump lies in the convex
    hull of its coefficients). Their dual forces are the contact tractions integrated against
    the Bernstein polynomials, which are positive with positive integrals: a face pressed
    shut has every force > 0. With values at the Lagrange points instead (the same for
    k = 1), a uniform pressure puts no force on the vertex points at k = 2 (the P2 vertex
    functions integrate to 0 over a triangle) and faces under compression stayed ajar there.
    """
    ref = lagrange_points(k)
    to_bernstein = np.linalg.inv(bernstein_at_lagrange(k))
    blocks_g, blocks_v, cols_all, where = [], [], [], []
    pts = smesh.points
    for c in smesh.cracks:
        for el in c.elements:
            eid = ngs.ElementId(ngs.BND, int(el))
            fe = full.GetFE(eid)
            dofs = list(jn_space.GetDofNrs(eid))
            verts = pts[[v.nr for v in smesh.mesh[eid].vertices]]
            V = np.array([np.array(fe.CalcShape(x, y, 0.0)) for x, y in ref])
            blocks_v.append(V)
            blocks_g.append(to_bernstein @ V)
            cols_all.append(dofs)
            where += [x * verts[0] + y * verts[1] + (1.0 - x - y) * verts[2] for x, y in ref]
    n = jn_space.ndof
    per = len(ref)
    r = per * len(blocks_v)
    if r != n:
        raise AssertionError(f"the crack's constraint points ({r}) do not match its jump unknowns ({n})")
    rows = np.repeat(np.arange(r), per)
    cols = np.repeat(np.array(cols_all).reshape(-1, 1, per), per, axis=1).ravel()

    def matrix(blocks):
        return sp.csr_matrix((np.concatenate([b.ravel() for b in blocks]), (rows, cols)), shape=(n, n))

    return matrix(blocks_g), matrix(blocks_v), np.array(where)


@dataclass(eq=False)
class SolidDiscretization(Discretization):
    """A Discretization (ngcrack.core.discretization) with the 3D crack's constraint points.

    Its methods are the element's own maps, handed in by `build` (all required; the
    constraint map only with a crack)."""

    constraint_points: np.ndarray | None = None
    order: int = 1
    value_map: sp.csr_matrix | None = None  # jn coefficients -> values at the constraint points
    force_unit: float = 1.0  # the system's forces (K y, F, the contact forces) are in this unit (E)
    #: the crack index of each constraint point (None: the faces' points crack by crack, P_order per face)
    point_crack: np.ndarray | None = None
    #: per crack face (crack by crack) its constraint points, vertices first; -1 where the face's node
    #: carries no jump (on the front). None: P_order points per face, numbered face by face
    face_points: np.ndarray | None = None
    #: the displacement of a trial, test or grid function's components (the displacement elements)
    displacement_of: Callable | None = None
    fields: Callable | None = None
    boundary_values: Callable | None = None
    roller_pairs: Callable | None = None
    constraint_map: Callable | None = None
    #: g -> the element's integrand of a boundary traction g (its load vector's), for the point supports' means
    traction_of: Callable | None = None

    def __post_init__(self):
        missing = [k for k in ("fields", "boundary_values", "roller_pairs") if getattr(self, k) is None]
        if missing or (self.has_crack and self.constraint_map is None):
            raise TypeError(f"SolidDiscretization: the element's maps {missing or ['constraint_map']} are required")

    def assemble_load(self) -> None:
        """Assemble `f` again, in the system's force unit (`force_unit`)."""
        self.f.Assemble()
        self.f.vec.data *= 1.0 / self.force_unit

    def tangential_jump(self, gf: ngs.GridFunction) -> ngs.CoefficientFunction:
        """u_e, the crack's HCurl copy: its tangential trace on the crack is [u]_t."""
        return gf.components[self.tangential]

    def held_mean_rows(self, held_mean: dict, T, free: np.ndarray) -> tuple[np.ndarray, list]:
        """The point supports' mean constraints on the condensed unknowns (`solid.point_means`)."""
        from .point_means import constraint_rows

        return constraint_rows(self, held_mean, T, free)


def build(smesh: SolidMesh, E: float, nu: float, loads: Loads, order: int | None = None,
          pressure=None, constraints: bool = True) -> SolidDiscretization:
    """The hybridized TDNNS discretization of stress degree `order` (1, 2 or 3; default 1);
    `pressure`: per crack, a uniform pressure on its faces (None or 0: none); `constraints`
    False: no constraint map (a subdomain of a distributed mesh, whose crack faces' surface
    elements may sit on another rank: ngcrack.distributed.solid places the map's blocks)."""
    k = tdnns_order(order, " in 3D")
    mesh = smesh.mesh
    spaces, built = tdnns_spaces(mesh, k, loads)
    has_crack = bool(smesh.cracks)
    G = V = where = None
    if has_crack:
        facet = ngs.FacetFESpace(mesh, order=k)
        jn_space = _compress(facet, [ngs.NodeId(ngs.FACE, int(f)) for c in smesh.cracks for f in c.faces])
        hcurl = ngs.HCurl(mesh, order=k + 1, type1=True)
        nodes = [ngs.NodeId(ngs.EDGE, int(e)) for c in smesh.cracks for e in c.interior_edges]
        nodes += [ngs.NodeId(ngs.FACE, int(f)) for c in smesh.cracks for f in c.faces]
        spaces += [jn_space, _compress(hcurl, nodes)]
        H = plus_side(smesh)
        if constraints:
            G, V, where = constraint_map(smesh, jn_space, facet, k)
        built.append(f"crack: normal jump P{k} per face, tangential jump from the crack's HCurl dofs (front excluded)")
    fes = ngs.FESpace(spaces)
    # the system is assembled in units of E (stresses and loads divided by E, displacements
    # unchanged): its numbers, the local condensation's rounding and so the certificate are
    # the same in any consistent units (in Pa the condensed matrix was 300 times less
    # symmetric than in MPa at order 2, and the contact residuals 1e4 times larger)
    A = compliance(1.0, nu)

    def displacement(sym):
        return sym[1] + H * sym[4] if has_crack else sym[1]

    def grad_displacement(sym):
        return ngs.Grad(sym[1]) + H * ngs.Grad(sym[4]) if has_crack else ngs.Grad(sym[1])

    trial, test = fes.TrialFunction(), fes.TestFunction()
    sig, tau = trial[0], test[0]
    n = ngs.specialcf.normal(3)
    # symmetric: NGSolve keeps one harmonic extension per element instead of it and its transpose (the
    # form is symmetric; the condensed matrix is bitwise the same, the process's peak 5% lower: BENCHMARKS,
    # "3D memory, the ellipse in 3 GB and the accuracy option"); the distributed subdomains (constraints
    # False) keep the form their BDDC was measured with
    a = ngs.BilinearForm(fes, condense=True, symmetric=constraints)
    volume, boundary = tdnns_terms(A(sig), sig, tau, trial, test, n)
    a += volume.Compile() * ngs.dx
    a += boundary.Compile() * ngs.dx(element_boundary=True)
    if has_crack:
        plus = _element_set(mesh, np.flatnonzero(H.vec.FV().NumPy() > 0))
        volume, boundary = tdnns_terms(None, sig, tau, trial, test, n, ue=4)
        a += volume * ngs.dx(definedonelements=plus)
        a += boundary * ngs.dx(element_boundary=True, definedonelements=plus)
        minus = np.concatenate([c.minus for c in smesh.cracks])
        nu_cf = ngs.GridFunction(ngs.VectorL2(mesh, order=0))
        nu_cf.Set(ngs.CF((0, 0, 0)))
        for c in smesh.cracks:  # the crack normal on its - side's tetrahedra (P0, exact)
            ind = ngs.GridFunction(ngs.L2(mesh, order=0))
            ind.vec.FV().NumPy()[c.minus] = 1.0
            tmp = ngs.GridFunction(nu_cf.space)
            tmp.Set(ind * ngs.CF(tuple(c.normal)))
            nu_cf.vec.data += tmp.vec
        chi = ngs.IfPos(n * nu_cf - 0.5, 1.0, 0.0)
        a += ((n * (tau * n)) * (chi * trial[3]) + (n * (sig * n)) * (chi * test[3])) * ngs.dx(
            element_boundary=True, definedonelements=_element_set(mesh, minus))
    with task_manager():
        a.Assemble()
    f = ngs.LinearForm(fes)
    v = displacement(test)
    if loads.body_force is not None:
        f += -(loads.body_force * v) * ngs.dx
        built.append("body force")
    def traction_of(g):  # the work of a boundary traction g, in the form's sign
        return -((g * n) * (test[2].Trace() * n) + (g - (g * n) * n) * test[1].Trace())

    for label, g in sorted(loads.traction.items()):
        f += traction_of(g) * ngs.ds(definedon=mesh.Boundaries(label), bonus_intorder=LOAD_BONUS_ORDER)
    for c in smesh.cracks if has_crack and pressure else ():
        if pressure[c.index] is not None:  # the work of the pressure on the two faces, p [v].nu = p kn (the form's sign)
            f += -pressure[c.index] * test[3].Trace() * ngs.ds(definedon=mesh.Boundaries(c.label), bonus_intorder=LOAD_BONUS_ORDER)
            built.append(f"crack[{c.index}]: pressure on the faces")
    with task_manager():
        f.Assemble()
    f.vec.data *= 1.0 / E

    def fields(gf: ngs.GridFunction) -> dict[str, ngs.CoefficientFunction]:
        comps = gf.components
        out = {"sigma": E * comps[0], "u": displacement(comps), "grad_u": grad_displacement(comps)}
        if has_crack:
            out["jump"] = comps[4]  # the + side's tangential jump copy
        return out

    def boundary_values(gf: ngs.GridFunction, loads: Loads) -> None:
        for label, g in loads.displacement.items():
            reg = mesh.Boundaries(label)
            gf.components[1].Set(g, ngs.BND, definedon=reg)
            gf.components[2].Set(g, ngs.BND, definedon=reg)

    return SolidDiscretization(
        element="tdnns", crack_mesh=smesh, fes=fes, a=a, f=f, uhat=(2, 2), jn=3 if has_crack else None, jt=None,
        facet_order=k, fields=fields, built=built, boundary_values=boundary_values, roller_pairs=lambda roller: [],
        definite=True, sign=-1.0, tangential=4 if has_crack else None,
        constraint_map=(lambda: G) if has_crack else None, constraint_points=where, order=k, value_map=V, force_unit=float(E),
        traction_of=traction_of,
    )
