"""The displacement baselines h1p1 and h1p2 in 3D: continuous P1 / P2 with the crack's jump.

What a user would pick instead of a mixed element, kept to show locking as nu -> 1/2.
The displacement is u = u_c + H+ u_e: u_c continuous P_k (three scalar components, so
that a roller on a face normal to a coordinate axis fixes one of them), and u_e a copy of
the P_k dofs on the crack (its vertices off the front, and for k = 2 its edges off the
front) used on the crack's + side only (H+ = 1 on the + side's tetrahedra that touch such
a vertex or edge). That is a mesh whose crack nodes are duplicated: [u] = u_e on the
crack and [u] = 0 on the front. In the crack's frame (nu, t1, t2), constant on a planar
crack, u_e = jn nu + jt1 t1 + jt2 t2; jn is the contact unknown, as the TDNNS element's.

The contact constraints are jn >= 0 at the crack's nodes: its vertices and, for k = 2,
its edge mid points, G mapping the hierarchical P2 coefficients to those values (square
and triangular: invertible). The stress is post-computed, sigma = C eps(u).

A roller on a face that is not normal to a coordinate axis (a cylinder's side) is refused:
the components are Cartesian.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..core.errors import InputError
from ..core.parallel import task_manager
from ..planar.elements.base import Loads
from ..planar.geometry import boundary_regex
from .geometry import SolidMesh

#: the element names and their polynomial order
ORDER_OF = {"h1p1": 1, "h1p2": 2}


def lame(E: float, nu: float) -> tuple[float, float]:
    """(lambda, mu) of the material."""
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def check_scene(scene) -> None:
    """Refuse, before meshing, a roller the Cartesian components cannot hold: one on a face
    not normal to a coordinate axis (a cylinder's side, or its ends when its axis is oblique)."""
    from .scene import Cylinder

    for label, cond in scene.boundary.items():
        if cond.type != "roller" or not isinstance(scene.domain, Cylinder):
            continue
        axis = np.abs(np.asarray(scene.domain.axis, dtype=float))
        if label == "side" or not np.isclose(axis.max(), 1.0, atol=1e-12):
            raise InputError(f"boundary.{label}.type = 'roller': the h1 baselines support rollers on faces normal "
                             "to a coordinate axis only; use element = 'tdnns'")


def _axis_rollers(mesh: ngs.Mesh, roller) -> list[set[str]]:
    """Per coordinate axis i, the roller labels whose faces are normal to e_i (others refused)."""
    out: list[set[str]] = [set(), set(), set()]
    if not roller:
        return out
    pts = np.array([v.point for v in mesh.vertices])
    for label in sorted(roller):
        normals = []
        for el in mesh.Elements(ngs.BND):
            if el.mat == label:
                p = pts[[v.nr for v in el.vertices]]
                nrm = np.cross(p[1] - p[0], p[2] - p[0])
                normals.append(nrm / np.linalg.norm(nrm))
        axis = np.argmax(np.abs(normals[0]))
        if not np.allclose(np.abs(np.array(normals)[:, axis]), 1.0, atol=1e-8):
            raise InputError(f"boundary.{label}.type = 'roller': the h1 baselines support rollers on faces normal "
                             "to a coordinate axis only; use element = 'tdnns'")
        out[axis].add(label)
    return out


def _jump_nodes(smesh: SolidMesh, order: int) -> tuple[list[ngs.NodeId], np.ndarray, np.ndarray]:
    """The crack's nodes that carry a jump (vertices off the front; order 2: edges off the front),
    with each one's crack index and position (the vertex, the edge's mid point)."""
    mesh, pts = smesh.mesh, smesh.points
    nodes, owner, where = [], [], []
    for c in smesh.cracks:
        verts = {v.nr for el in c.elements for v in smesh.mesh[ngs.ElementId(ngs.BND, int(el))].vertices}
        for v in sorted(verts - set(c.front_vertices.tolist())):
            nodes.append(ngs.NodeId(ngs.VERTEX, v))
            owner.append(c.index)
            where.append(pts[v])
        if order == 2:
            for e in c.interior_edges:
                ev = [v.nr for v in mesh[ngs.NodeId(ngs.EDGE, int(e))].vertices]
                nodes.append(ngs.NodeId(ngs.EDGE, int(e)))
                owner.append(c.index)
                where.append(pts[ev].mean(axis=0))
    return nodes, np.array(owner), np.array(where).reshape(-1, 3)


def _plus_tets(smesh: SolidMesh, nodes: list[ngs.NodeId], owner: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """H+ (per tetrahedron, 0/1) and the crack index of each (-1: none): the + side's
    tetrahedra that touch a jump node. A crack is planar and a jump node off its front, so
    each tetrahedron touching the node lies on one side of the crack's plane."""
    mesh, pts = smesh.mesh, smesh.points
    H = np.zeros(mesh.ne)
    which = -np.ones(mesh.ne, dtype=int)
    for nd, i in zip(nodes, owner):
        c = smesh.cracks[i]
        for el in mesh[nd].elements:
            centroid = pts[[v.nr for v in mesh[el].vertices]].mean(axis=0)
            if np.dot(centroid - c.crack.center, c.normal) > 0:
                H[el.nr] = 1.0
                which[el.nr] = i
    return H, which


def _frame(mesh: ngs.Mesh, smesh: SolidMesh, which: np.ndarray) -> list[ngs.CoefficientFunction]:
    """(nu, t1, t2): each crack's frame at the vertices of its + side's tetrahedra (P1, so
    constant on those tetrahedra and on the crack's faces, and defined on surface elements too)."""
    tets = np.array([[v.nr for v in el.vertices] for el in mesh.Elements(ngs.VOL)])
    out = []
    for k in range(3):
        comps = []
        for d in range(3):
            g = ngs.GridFunction(ngs.H1(mesh, order=1))
            vals = np.zeros(mesh.nv)
            for c in smesh.cracks:
                vec = (c.normal, c.crack.e_a, np.cross(c.normal, c.crack.e_a))[k]
                vals[tets[which == c.index].ravel()] = vec[d]
            g.vec.FV().NumPy()[:] = vals
            comps.append(g)
        out.append(ngs.CF(tuple(comps)))
    return out


def _constraint_map(jump: ngs.FESpace, full: ngs.FESpace, nodes, order: int) -> sp.csr_matrix:
    """jn's coefficients -> its values at the nodes (vertex: the value; edge mid point:
    the mean of its end vertices' values plus the edge function's value there)."""
    n = jump.ndof
    rows, cols, vals = [], [], []
    mesh = full.mesh
    bubble = None
    for nd in nodes:
        (d,) = [x for x in jump.GetDofNrs(nd) if x >= 0][:1]
        rows.append(d)
        cols.append(d)
        if nd.type == ngs.VERTEX:
            vals.append(1.0)
            continue
        if bubble is None:  # the P2 edge function's value at the edge's mid point (one per space)
            gf = ngs.GridFunction(full)
            gf.vec[:] = 0.0
            gf.vec[full.GetDofNrs(nd)[0]] = 1.0
            ev = [mesh[v].point for v in mesh[nd].vertices]
            mid = 0.5 * (np.array(ev[0]) + np.array(ev[1]))
            bubble = float(gf(mesh(*mid)))
        vals.append(bubble)
        for v in mesh[nd].vertices:
            dv = [x for x in jump.GetDofNrs(ngs.NodeId(ngs.VERTEX, v.nr)) if x >= 0]
            if dv:  # a front vertex has no jump: its value is 0
                rows.append(d)
                cols.append(dv[0])
                vals.append(0.5)
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))


def build(smesh: SolidMesh, E: float, nu: float, loads: Loads, element: str = "h1p2", pressure=None):
    """The P_k displacement discretization (k = ORDER_OF[element]) with the crack's jump."""
    from .element import LOAD_BONUS_ORDER, SolidDiscretization

    k = ORDER_OF[element]
    mesh = smesh.mesh
    lam, mu = lame(E, nu)
    rollers = _axis_rollers(mesh, loads.roller)
    fixed = set(loads.dirichlet_labels)
    comps = [ngs.H1(mesh, order=k, dirichlet=boundary_regex(fixed | rollers[i])) for i in range(3)]
    spaces = list(comps)
    built = [f"u: continuous P{k}^3", "stress: post-computed C eps(u)"]
    has_crack = bool(smesh.cracks)
    G = where = owner = face_points = None
    if has_crack:
        nodes, owner, where_n = _jump_nodes(smesh, k)
        full = ngs.H1(mesh, order=k)
        active = ngs.BitArray(full.ndof)
        active.Clear()
        for nd in nodes:
            for d in full.GetDofNrs(nd):
                active[d] = True
        jump = ngs.Compress(full, active_dofs=active)
        spaces += [jump, jump, jump]
        Hv, which = _plus_tets(smesh, nodes, owner)
        H = ngs.GridFunction(ngs.L2(mesh, order=0))
        H.vec.FV().NumPy()[:] = Hv
        nu_cf, t1_cf, t2_cf = _frame(mesh, smesh, which)
        G = _constraint_map(jump, full, nodes, k)
        # the constraint points in jn's numbering
        order_ = np.array([[x for x in jump.GetDofNrs(nd) if x >= 0][0] for nd in nodes])
        where = np.zeros((jump.ndof, 3))
        where[order_] = where_n
        own = np.zeros(jump.ndof, dtype=int)
        own[order_] = owner
        owner = own
        dof_of = {(nd.type, nd.nr): d for nd, d in zip(nodes, order_)}
        face_points = []
        for c in smesh.cracks:
            for el in c.elements:
                face = mesh[ngs.ElementId(ngs.BND, int(el))]
                row = [dof_of.get((ngs.VERTEX, v.nr), -1) for v in face.vertices]
                if k == 2:
                    row += [dof_of.get((ngs.EDGE, e.nr), -1) for e in face.edges]
                face_points.append(row)
        face_points = np.array(face_points, dtype=int)
        built.append(f"crack: P{k} jump at {len(nodes)} crack nodes (the front's held at zero)")
    fes = ngs.FESpace(spaces)

    def displacement(sym):
        u = ngs.CF((sym[0], sym[1], sym[2]))
        return u + H * jump_of(sym) if has_crack else u

    def jump_of(sym):
        return sym[3] * nu_cf + sym[4] * t1_cf + sym[5] * t2_cf

    def grad_c(sym):
        return ngs.CF((ngs.grad(sym[0]), ngs.grad(sym[1]), ngs.grad(sym[2])), dims=(3, 3))

    def grad_e(sym):  # the frame is constant on each tetrahedron
        return (ngs.OuterProduct(nu_cf, ngs.grad(sym[3])) + ngs.OuterProduct(t1_cf, ngs.grad(sym[4]))
                + ngs.OuterProduct(t2_cf, ngs.grad(sym[5])))

    def grad_displacement(sym):
        return grad_c(sym) + H * grad_e(sym) if has_crack else grad_c(sym)

    def stress_of(g):
        eps = 0.5 * (g + g.trans)
        return 2.0 * mu * eps + lam * ngs.Trace(eps) * ngs.Id(3)

    trial, test = fes.TrialFunction(), fes.TestFunction()
    a = ngs.BilinearForm(fes, condense=True)
    gc, gct = grad_c(trial), grad_c(test)
    a += ngs.InnerProduct(stress_of(gc), gct).Compile() * ngs.dx
    if has_crack:
        plus = ngs.BitArray(mesh.ne)
        plus.Clear()
        for el in np.flatnonzero(Hv > 0):
            plus[int(el)] = True
        ge, get = grad_e(trial), grad_e(test)
        a += (ngs.InnerProduct(stress_of(gc), get) + ngs.InnerProduct(stress_of(ge), gct)
              + ngs.InnerProduct(stress_of(ge), get)) * ngs.dx(definedonelements=plus)
    with task_manager():
        a.Assemble()
    f = ngs.LinearForm(fes)
    v = displacement(test)
    if loads.body_force is not None:
        f += (loads.body_force * v) * ngs.dx
        built.append("body force")
    def traction_of(g):  # the work of a boundary traction g
        return g * ngs.CF((test[0], test[1], test[2]))

    for label, g in sorted(loads.traction.items()):
        f += traction_of(g) * ngs.ds(definedon=mesh.Boundaries(label), bonus_intorder=LOAD_BONUS_ORDER)
    for c in smesh.cracks if has_crack and pressure else ():
        if pressure[c.index] is not None:  # the work of the pressure on the two faces: p [v].nu
            f += pressure[c.index] * test[3] * ngs.ds(definedon=mesh.Boundaries(c.label), bonus_intorder=LOAD_BONUS_ORDER)
            built.append(f"crack[{c.index}]: pressure on the faces")
    with task_manager():
        f.Assemble()

    def fields(gf: ngs.GridFunction) -> dict[str, ngs.CoefficientFunction]:
        cs = gf.components
        g = grad_displacement(cs)
        out = {"sigma": stress_of(g), "u": displacement(cs), "grad_u": g}
        if has_crack:
            out["jump"] = jump_of(cs)
        return out

    def boundary_values(gf: ngs.GridFunction, loads: Loads) -> None:
        for label, g in loads.displacement.items():
            reg = mesh.Boundaries(label)
            for i in range(3):
                gf.components[i].Set(g[i], ngs.BND, definedon=reg)

    return SolidDiscretization(
        element=element, crack_mesh=smesh, fes=fes, a=a, f=f, uhat=(0, 1), jn=3 if has_crack else None, jt=None,
        facet_order=k, fields=fields, built=built, boundary_values=boundary_values, roller_pairs=lambda roller: [],
        definite=True, sign=1.0, tangential=4 if has_crack else None,
        constraint_map=(lambda: G) if has_crack else None, constraint_points=where, order=k,
        point_crack=owner, face_points=face_points, displacement_of=displacement, traction_of=traction_of,
    )
