"""Displacement baselines h1p1 and h1p2: continuous P1 / P2 elements with duplicated crack faces.

These are what a user would pick instead of a mixed element; they show locking as
nu -> 1/2. The displacement is u = u_c + H+ u_e: u_c continuous P_k, and u_e a copy of
the P_k dofs on the crack (its vertices other than interior tips, and its edges) used
on the crack's + side only (H+ = 1 there, 0 elsewhere). That is exactly a mesh whose
crack nodes are duplicated: [u] = u_e on the crack, and [u] = 0 at interior tips.
The jump is written u_e = jn nu_h + jt t_h with nu_h, t_h the crack normal and tangent
(averaged at kinks), interpolated from nodal values that are constant across each
crack vertex's patch, so jn >= 0 at the crack nodes (and, for P2, at the edge
mid points) is the contact constraint: the same QP as the mixed elements.

The stress is post-computed, sigma = C eps(u), and is discontinuous; crack-face
tractions are the average of the two sides' values at the edge mid points.
Plane strain at nu = 1/2 has no finite C: the baselines refuse it.
"""

from __future__ import annotations

import math

import ngsolve as ngs
import numpy as np

from ..errors import InputError
from ..geometry import CrackMesh, boundary_regex, boundary_region, crack_frame_cf, crack_side
from ..materials import Compliance
from ..parallel import task_manager
from .base import (
    Discretization,
    ElementTraits,
    Loads,
    cartesian_roller_pairs,
    displacement_data,
    load_vector,
    roller_edges,
)

#: per order: grad u is the field grad_u; a ZZ recovery estimate of the order's degree
TRAITS = {k: ElementTraits(gradient="gradient", estimate="zz-recovery", estimate_degree=k) for k in (1, 2)}


def _lame(compliance: Compliance) -> tuple[float, float]:
    """(lambda, mu) from A sigma = c_dev sigma - c_tr tr(sigma) I (2D)."""
    mu = 0.5 / compliance.c_dev
    # A(I) = (c_dev - 2 c_tr) I = I / (2 mu + 2 lambda)
    lam = 0.5 / compliance.spherical - mu
    return lam, mu


def _crack_nodes(crack_mesh: CrackMesh, fixed_vertices: set[int]):
    """Crack vertices that carry a jump, with their nodal normals (averaged at kinks)."""
    normals: dict[int, np.ndarray] = {}
    for c in crack_mesh.cracks:
        for k in range(len(c)):
            for v in (int(c.va[k]), int(c.vb[k])):
                normals[v] = normals.get(v, np.zeros(2)) + c.normal[k]
    free = {v: n / np.linalg.norm(n) for v, n in normals.items() if v not in crack_mesh.tip_vertices and v not in fixed_vertices}
    return free


def _fixed_vertices(mesh: ngs.Mesh, loads: Loads) -> set[int]:
    """The vertices on the Dirichlet edges (a crack vertex there carries no jump)."""
    if not loads.dirichlet_labels:
        return set()
    fixed_bnd = boundary_region(mesh, loads.dirichlet_labels).Mask()
    return {v.nr for el in mesh.Elements(ngs.BND) if fixed_bnd[el.index] for v in el.vertices}


def _jump_space(crack_mesh: CrackMesh, order: int, nodes: dict) -> ngs.FESpace:
    """P_order on the jump's crack vertices (`nodes`) and the crack edges, compressed."""
    full = ngs.H1(crack_mesh.mesh, order=order)
    active = ngs.BitArray(full.ndof)
    active.Clear()
    node_ids = [ngs.NodeId(ngs.VERTEX, v) for v in nodes]
    node_ids += [ngs.NodeId(ngs.EDGE, int(e)) for c in crack_mesh.cracks for e in c.edge]
    for node in node_ids:
        for d in full.GetDofNrs(node):
            active[d] = True
    return ngs.Compress(full, active_dofs=active)


def _nodal_frame(crack_mesh: CrackMesh, nodes: dict) -> tuple[ngs.GridFunction, ngs.GridFunction]:
    """The nodal normal field nu_h (P1): the nodes' normals, constant across each crack
    vertex's patch.

    Tips and fixed crack vertices carry no jump; they get a normal for the interpolation.
    The frame must be constant across each crack vertex's patch: a frame that fell to zero
    at the patch's other vertices would make the rigid opening of a face cost strain
    energy of order 1/h and lock the jump (one pass in element order, a vertex taking the
    value of the first framed vertex of the first triangle that reaches it).
    """
    mesh = crack_mesh.mesh
    nu_x = ngs.GridFunction(ngs.H1(mesh, order=1))
    nu_y = ngs.GridFunction(ngs.H1(mesh, order=1))
    frame = {}
    for c in crack_mesh.cracks:
        for k in range(len(c)):
            for v in (int(c.va[k]), int(c.vb[k])):
                frame.setdefault(v, nodes.get(v, c.normal[k]))
    framed = bytearray(len(crack_mesh.points))
    for v in frame:
        framed[v] = 1
    for nrs in crack_mesh.triangles.tolist():
        src = next((v for v in nrs if framed[v]), -1)
        if src < 0:
            continue
        for v in nrs:
            if not framed[v]:
                framed[v] = 1
                frame[v] = frame[src]
    if frame:
        where = np.fromiter(frame, dtype=int, count=len(frame))
        values = np.array(list(frame.values()), dtype=float).reshape(-1, 2)
        nu_x.vec.FV().NumPy()[where] = values[:, 0]
        nu_y.vec.FV().NumPy()[where] = values[:, 1]
    return nu_x, nu_y


def _roller_fixed_dofs(fes: ngs.FESpace, mesh: ngs.Mesh, loads: Loads, nodes: dict, jump: ngs.FESpace) -> list[int]:
    """A crack node on a roller edge: both faces keep u.n_r = 0, so the jump has no
    component along n_r there (the jn or jt dofs held at zero)."""
    fixed = []
    offs = fes.Range(2).start, fes.Range(3).start
    for el, n_r in roller_edges(mesh, loads.roller):
        for vtx in (v for v in el.vertices if v.nr in nodes):
            nrm = nodes[vtx.nr]
            along_t = abs(nrm[1] * n_r[0] - nrm[0] * n_r[1])  # |t . n_r|
            which = 1 if along_t > 1 - 1e-9 else (0 if along_t < 1e-9 else None)
            if which is None:
                raise InputError("boundary: a crack meets a roller edge obliquely; the h1 baselines support "
                                 "cracks normal or parallel to roller edges only")
            fixed += [offs[which] + d for d in jump.GetDofNrs(vtx)]
    return fixed


def _constraint_map(jump: ngs.FESpace, crack_mesh: CrackMesh, order: int) -> np.ndarray:
    """Nodal values of jn at crack vertices, and for P2 its values at edge mid points."""
    G = np.eye(jump.ndof)
    if order == 1:
        return G
    mesh = crack_mesh.mesh
    gf = ngs.GridFunction(jump)
    for c in crack_mesh.cracks:
        mp = mesh(c.mid[:, 0], c.mid[:, 1])
        edge_dofs = [list(jump.GetDofNrs(ngs.NodeId(ngs.EDGE, int(e)))) for e in c.edge]
        gf.vec[:] = 0.0
        for ds in edge_dofs:
            gf.vec[ds[0]] = 1.0
        bubble = np.asarray(gf(mp)).reshape(-1)
        for k, ds in enumerate(edge_dofs):
            row = ds[0]
            G[row, :] = 0.0
            G[row, row] = bubble[k]
            vertex_dofs = [d for v in (int(c.va[k]), int(c.vb[k])) for d in jump.GetDofNrs(ngs.NodeId(ngs.VERTEX, v))]
            G[row, [d for d in vertex_dofs if d >= 0]] = 0.5  # tips and fixed vertices have no jump dof (-1)
    return G


def build(crack_mesh: CrackMesh, compliance: Compliance, loads: Loads, order: int = 1) -> Discretization:
    """The P_order displacement discretization with duplicated crack faces."""
    if compliance.spherical <= 0.0 or not math.isfinite(0.5 / compliance.spherical):
        raise InputError("material.nu = 0.5: the displacement baselines h1p1/h1p2 need nu < 1/2 in plane strain "
                          "(lambda is infinite); use a mixed element (peers, bdm, tdnns)")
    lam, mu = _lame(compliance)
    mesh = crack_mesh.mesh
    dirichlet = boundary_regex(loads.dirichlet_labels)
    Vc = ngs.H1(mesh, order=order, dirichlet=dirichlet)
    spaces = [Vc, Vc]
    name = f"h1p{order}"
    built = [f"u: continuous P{order}^2", "stress: post-computed C eps(u)"]
    has_crack = bool(crack_mesh.cracks)
    if has_crack:
        nodes = _crack_nodes(crack_mesh, _fixed_vertices(mesh, loads))
        jump = _jump_space(crack_mesh, order, nodes)
        spaces += [jump, jump]
        # nodal normal field nu_h (P1) and the side indicator H+
        nu_x, nu_y = _nodal_frame(crack_mesh, nodes)
        nu_cf = ngs.CF((nu_x, nu_y))
        t_cf = ngs.CF((nu_y, -nu_x))
        grad_nu = ngs.CF((ngs.grad(nu_x), ngs.grad(nu_y)), dims=(2, 2))  # row i: grad nu_i
        grad_t = ngs.CF((ngs.grad(nu_y), -ngs.grad(nu_x)), dims=(2, 2))
        H = ngs.GridFunction(ngs.L2(mesh, order=0))
        H.vec.FV().NumPy()[:] = (crack_side(crack_mesh) > 0).astype(float)
        built.append(f"crack faces duplicated: P{order} jump at {len(nodes)} crack vertices and the crack edges")
    fes = ngs.FESpace(spaces)

    def displacement(sym):
        u = ngs.CF((sym[0], sym[1]))
        if has_crack:
            u = u + H * (sym[2] * nu_cf + sym[3] * t_cf)
        return u

    def grad_continuous(sym):
        return ngs.CF((ngs.grad(sym[0]), ngs.grad(sym[1])), dims=(2, 2))

    def grad_jump(sym):
        # grad(u_e) where H+ = 1; nu_h varies only at kinks (linear), so the product rule
        return ngs.OuterProduct(nu_cf, ngs.grad(sym[2])) + sym[2] * grad_nu \
            + ngs.OuterProduct(t_cf, ngs.grad(sym[3])) + sym[3] * grad_t

    def grad_displacement(sym):
        g = grad_continuous(sym)
        if has_crack:
            g = g + H * grad_jump(sym)  # H+ is constant per triangle
        return g

    def sym_part(g):
        return 0.5 * (g + g.trans)

    def strain(sym):
        return sym_part(grad_displacement(sym))

    def stress_of(eps):
        return 2.0 * mu * eps + lam * ngs.Trace(eps) * ngs.Id(2)

    trial, test = fes.TrialFunction(), fes.TestFunction()
    a = ngs.BilinearForm(fes, condense=True)
    # eps(u) = eps(u_c) + H+ eps(u_e): the u_c part everywhere, the terms with u_e on the
    # + side's triangles only (H+ = 1 there, 0 elsewhere); the same matrix as with H+ in
    # every element, up to round-off
    eps_c, eps_c_test = sym_part(grad_continuous(trial)), sym_part(grad_continuous(test))
    a += ngs.InnerProduct(stress_of(eps_c), eps_c_test).Compile() * ngs.dx
    if has_crack:
        plus = ngs.BitArray(mesh.ne)
        plus.Clear()
        for el in np.flatnonzero(H.vec.FV().NumPy() > 0):
            plus[int(el)] = True
        eps_e, eps_e_test = sym_part(grad_jump(trial)), sym_part(grad_jump(test))
        a += (ngs.InnerProduct(stress_of(eps_c), eps_e_test) + ngs.InnerProduct(stress_of(eps_e), eps_c_test)
              + ngs.InnerProduct(stress_of(eps_e), eps_e_test)) * ngs.dx(definedonelements=plus)
    with task_manager():
        a.Assemble()
    v = displacement(test)
    crack_load = None
    if has_crack:
        seg_normal, _ = crack_frame_cf(crack_mesh)

        def crack_load(p):
            # [v] = u_e = jn nu_h + jt t_h, its normal part against the edge's own normal
            return p * ((test[2] * nu_cf + test[3] * t_cf) * seg_normal)
    traction = lambda g: g * v  # noqa: E731
    f = load_vector(fes, mesh, loads, built, body=lambda b: b * v, traction=traction, crack=crack_load)

    def fields(gf: ngs.GridFunction) -> dict[str, ngs.CoefficientFunction]:
        comps = gf.components
        return {"sigma": stress_of(strain(comps)), "u": displacement(comps), "grad_u": grad_displacement(comps)}

    fixed = _roller_fixed_dofs(fes, mesh, loads, nodes, jump) if has_crack and loads.roller else []

    def constraint_map() -> np.ndarray:
        return _constraint_map(jump, crack_mesh, order)

    def crack_jumps(gf: ngs.GridFunction, crack) -> tuple[np.ndarray, np.ndarray]:
        mid = crack.mid
        mp = mesh(mid[:, 0], mid[:, 1])
        jn = np.asarray(gf.components[2](mp)).reshape(-1)
        jt = np.asarray(gf.components[3](mp)).reshape(-1)
        # the nodal frame (nu_h, t_h) equals the edge's own frame on straight segments;
        # at kinks project the jump onto the edge's frame
        nu_m = np.asarray(nu_cf(mp)).reshape(-1, 2)
        t_m = np.column_stack([nu_m[:, 1], -nu_m[:, 0]])
        jump_vec = jn[:, None] * nu_m + jt[:, None] * t_m
        return (np.einsum("ei,ei->e", jump_vec, crack.normal), np.einsum("ei,ei->e", jump_vec, crack.tangent))

    def boundary_values(gf: ngs.GridFunction, loads: Loads) -> None:
        g, reg = displacement_data(mesh, loads.displacement)
        for i in (0, 1):
            gf.components[i].Set(g[i], ngs.BND, definedon=reg)

    return Discretization(
        element=name,
        traction=traction,
        crack_mesh=crack_mesh,
        fes=fes,
        a=a,
        f=f,
        uhat=(0, 1),
        jn=2 if has_crack else None,
        jt=3 if has_crack else None,
        facet_order=order,
        fields=fields,
        built=built,
        boundary_values=boundary_values,
        roller_pairs=lambda roller: cartesian_roller_pairs(fes, mesh, (0, 1), roller, nodal=True),
        sign=1.0,
        constraint_map=constraint_map if has_crack else None,
        crack_jumps=crack_jumps if has_crack else None,
        two_sided_traction=True,
        fixed_dofs=tuple(sorted(set(fixed))),
        traction_rows=(2, 3) if has_crack else (None, None),
        traits=TRAITS[order],
    )
