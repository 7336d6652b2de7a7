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
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ...core.errors import InputError
from ...core.parallel import task_manager
from ..geometry import CrackMesh, boundary_regex, boundary_region, crack_frame_cf, crack_side
from ..materials import Compliance
from .base import (
    ElementTraits,
    Loads,
    PlanarDiscretization,
    cartesian_roller_pairs,
    displacement_data,
    load_vector,
    roller_edges,
)

#: per order: grad u is the field grad_u; a ZZ recovery estimate of the order's degree; no nu = 1/2
TRAITS = {k: ElementTraits(gradient="gradient", estimate="zz-recovery", estimate_degree=k, incompressible=False)
          for k in (1, 2)}



@dataclass(eq=False)
class H1Discretization(PlanarDiscretization):
    """The P_k displacement element with duplicated crack faces: u = u_c + H+ (jn nu_h + jt t_h)
    (module docstring). `frame` = (nu_x, nu_y) the nodal crack normal (P1 GridFunctions),
    `plus` the + side's indicator, `lame` = (lambda, mu), `jump` the jump's space."""

    frame: tuple | None = None
    plus: ngs.GridFunction | None = None
    lame: tuple[float, float] = (0.0, 0.0)
    jump: ngs.FESpace | None = None

    def _nu_t(self) -> tuple[ngs.CoefficientFunction, ngs.CoefficientFunction]:
        nu_x, nu_y = self.frame
        return ngs.CF((nu_x, nu_y)), ngs.CF((nu_y, -nu_x))

    def displacement(self, sym) -> ngs.CoefficientFunction:
        """u of the symbols `sym`."""
        u = ngs.CF((sym[0], sym[1]))
        if self.has_crack:
            nu_cf, t_cf = self._nu_t()
            u = u + self.plus * (sym[2] * nu_cf + sym[3] * t_cf)
        return u

    @staticmethod
    def grad_continuous(sym) -> ngs.CoefficientFunction:
        """grad u_c of the symbols `sym`."""
        return ngs.CF((ngs.grad(sym[0]), ngs.grad(sym[1])), dims=(2, 2))

    def grad_jump(self, sym) -> ngs.CoefficientFunction:
        """grad(u_e) where H+ = 1; nu_h varies only at kinks (linear), so the product rule."""
        nu_x, nu_y = self.frame
        nu_cf, t_cf = self._nu_t()
        grad_nu = ngs.CF((ngs.grad(nu_x), ngs.grad(nu_y)), dims=(2, 2))  # row i: grad nu_i
        grad_t = ngs.CF((ngs.grad(nu_y), -ngs.grad(nu_x)), dims=(2, 2))
        return ngs.OuterProduct(nu_cf, ngs.grad(sym[2])) + sym[2] * grad_nu \
            + ngs.OuterProduct(t_cf, ngs.grad(sym[3])) + sym[3] * grad_t

    def grad_displacement(self, sym) -> ngs.CoefficientFunction:
        """grad u of the symbols `sym` (H+ is constant per triangle)."""
        g = self.grad_continuous(sym)
        return g + self.plus * self.grad_jump(sym) if self.has_crack else g

    def stress_of(self, eps) -> ngs.CoefficientFunction:
        """C eps."""
        lam, mu = self.lame
        return 2.0 * mu * eps + lam * ngs.Trace(eps) * ngs.Id(2)

    def fields(self, gf: ngs.GridFunction) -> dict[str, ngs.CoefficientFunction]:
        comps = gf.components
        grad = self.grad_displacement(comps)
        return {"sigma": self.stress_of(_sym_part(grad)), "u": self.displacement(comps), "grad_u": grad}

    def boundary_values(self, gf: ngs.GridFunction, loads: Loads) -> None:
        g, reg = displacement_data(self.crack_mesh.mesh, loads.displacement)
        for i in (0, 1):
            gf.components[i].Set(g[i], ngs.BND, definedon=reg)

    def roller_pairs(self, labels) -> list:
        return cartesian_roller_pairs(self.fes, self.crack_mesh.mesh, (0, 1), labels, nodal=True)

    def traction(self, g: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        return g * self.displacement(self.fes.TestFunction())

    def constraint_map(self) -> np.ndarray:
        return _constraint_map(self.jump, self.crack_mesh, self.facet_order)

    def crack_jumps(self, gf: ngs.GridFunction, crack) -> tuple[np.ndarray, np.ndarray]:
        """The jump at the edge mid points, projected onto each edge's own frame (the nodal
        frame equals it on straight segments; at kinks it is averaged)."""
        mid = crack.mid
        mp = self.crack_mesh.mesh(mid[:, 0], mid[:, 1])
        jn = np.asarray(gf.components[2](mp)).reshape(-1)
        jt = np.asarray(gf.components[3](mp)).reshape(-1)
        nu_m = np.asarray(self._nu_t()[0](mp)).reshape(-1, 2)
        t_m = np.column_stack([nu_m[:, 1], -nu_m[:, 0]])
        jump_vec = jn[:, None] * nu_m + jt[:, None] * t_m
        return (np.einsum("ei,ei->e", jump_vec, crack.normal), np.einsum("ei,ei->e", jump_vec, crack.tangent))


def _sym_part(g) -> ngs.CoefficientFunction:
    return 0.5 * (g + g.trans)


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


def build(crack_mesh: CrackMesh, compliance: Compliance, loads: Loads, order: int = 1) -> H1Discretization:
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
        H = ngs.GridFunction(ngs.L2(mesh, order=0))
        H.vec.FV().NumPy()[:] = (crack_side(crack_mesh) > 0).astype(float)
        built.append(f"crack faces duplicated: P{order} jump at {len(nodes)} crack vertices and the crack edges")
    fes = ngs.FESpace(spaces)
    disc = H1Discretization(
        element=name, crack_mesh=crack_mesh, fes=fes, a=ngs.BilinearForm(fes, condense=True), f=None, uhat=(0, 1),
        jn=2 if has_crack else None, jt=3 if has_crack else None, facet_order=order, built=built, sign=1.0,
        two_sided_traction=True, fixed_dofs=tuple(sorted(set(
            _roller_fixed_dofs(fes, mesh, loads, nodes, jump) if has_crack and loads.roller else []))),
        traction_rows=(2, 3) if has_crack else (None, None), nodal_constraints=True, traits=TRAITS[order],
        frame=(nu_x, nu_y) if has_crack else None, plus=H if has_crack else None, lame=(lam, mu),
        jump=jump if has_crack else None)
    trial, test = fes.TrialFunction(), fes.TestFunction()
    a = disc.a
    # eps(u) = eps(u_c) + H+ eps(u_e): the u_c part everywhere, the terms with u_e on the
    # + side's triangles only (H+ = 1 there, 0 elsewhere); the same matrix as with H+ in
    # every element, up to round-off
    eps_c, eps_c_test = _sym_part(disc.grad_continuous(trial)), _sym_part(disc.grad_continuous(test))
    a += ngs.InnerProduct(disc.stress_of(eps_c), eps_c_test).Compile() * ngs.dx
    if has_crack:
        plus = ngs.BitArray(mesh.ne)
        plus.Clear()
        for el in np.flatnonzero(H.vec.FV().NumPy() > 0):
            plus[int(el)] = True
        eps_e, eps_e_test = _sym_part(disc.grad_jump(trial)), _sym_part(disc.grad_jump(test))
        a += (ngs.InnerProduct(disc.stress_of(eps_c), eps_e_test) + ngs.InnerProduct(disc.stress_of(eps_e), eps_c_test)
              + ngs.InnerProduct(disc.stress_of(eps_e), eps_e_test)) * ngs.dx(definedonelements=plus)
    with task_manager():
        a.Assemble()
    crack_load = None
    if has_crack:
        seg_normal, _ = crack_frame_cf(crack_mesh)
        nu_cf, t_cf = disc._nu_t()

        def crack_load(p):
            # [v] = u_e = jn nu_h + jt t_h, its normal part against the edge's own normal
            return p * ((test[2] * nu_cf + test[3] * t_cf) * seg_normal)
    disc.f = load_vector(fes, mesh, loads, built, body=lambda b: b * disc.displacement(test), traction=disc.traction,
                         crack=crack_load)
    return disc
