"""The hybridized Hellinger-Reissner form with weakly imposed symmetry (PEERS and BDM).

Unknowns on each triangle T (all element-local, removed by static condensation):
stress rows sigma_1, sigma_2 (broken H(div)), displacement u (P0^2; P_{k-1}^2 for BDM_k)
and, for BDM, the rotation r (P0; P_{k-1} for BDM_k). Global unknowns: the facet displacement trace u_hat (one vector
polynomial per edge), the PEERS rotation (continuous P1) and, on crack edges, the jump
j = jn nu + jt t. The crack's minus side (the element whose outward normal is nu) sees
the trace u_hat - j, so that j = u+ - u- = [u].

    (A sigma, tau) + (div tau, u) + (as tau, r) - <tau n, u_hat - chi j>_dT     = 0
    (div sigma, v)                                                              = -(f, v)
    (as sigma, eta)                                                             = 0
  - <sigma n, mu - chi k>_dT                                                    = -<g, mu>_traction

with as(tau) = tau_21 - tau_12, n the element's outward normal and chi = 1 on the minus
side of a crack edge (0 elsewhere). The test function of jt gives sigma_t = 0 on the
crack; the test function of jn, after the sign flip in `hybrid.py`, gives the multiplier
-sigma_n >= 0 of the constraint jn >= 0.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ...core.discretization import Discretization, ElementTraits, Loads  # noqa: F401  (the element's protocol)
from ...core.parallel import task_manager
from ..geometry import CrackMesh, boundary_regex, boundary_region, crack_bc, crack_frame_cf
from ..held_means import constraint_rows
from ..materials import Compliance
from .facets import endpoint_map, facet_basis

#: extra quadrature order for element-boundary terms that carry the crack indicator
CRACK_BONUS_INTORDER = 2
#: A(I) below this fraction of A's deviatoric part counts as incompressible (nu -> 1/2,
#: plane strain): the element pressure is then kept out of the local solves
PRESSURE_SPLIT_RTOL = 1e-6
#: in the incompressible split, A(I) is kept at least this fraction of A's deviatoric part.
#: At nu = 1/2 exactly the element pressures couple only through the discrete divergence;
#: where that map is not onto the pressure space (TDNNS), pressure modes would be fixed by
#: round-off. The floor selects the minimum-norm pressure, i.e. the limit nu -> 1/2, and
#: changes nothing else beyond 1e-10 relative.
SPHERICAL_FLOOR = 1e-10


@dataclass(eq=False)
class PlanarDiscretization(Discretization):
    """What the 2D families share: the crack's constraint points and jumps read from the
    facet jump unknowns along the crack edges (`facets`). The displacement baselines,
    whose constraint points are crack nodes, override `constraint_map`, `crack_jumps`."""

    def constraint_map(self) -> np.ndarray:
        """G: the facet jump's dofs -> its values at k + 1 equispaced points of each crack edge."""
        return endpoint_map(self.fes.components[self.jn], self.crack_mesh, self.facet_order)

    def friction_points(self, crack_mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(crack index, arc length, Newton-Cotes or nodal weight) of every constrained value."""
        from .friction_points import constraint_points

        return constraint_points(self, crack_mesh)

    def tangential_point_map(self, crack_mesh, normal_map: np.ndarray) -> np.ndarray:
        """Gt: the tangential jump dofs -> the tangential jumps at the constraint points."""
        from .friction_points import tangential_point_map

        return tangential_point_map(self, crack_mesh, normal_map)

    def constraint_positions(self) -> tuple[np.ndarray, np.ndarray]:
        """(crack index, arc length s) of every constrained value w_i = (G j)_i.

        For the facet end-point map the value i of an edge of order p sits at the i-th of
        p + 1 equispaced points of that edge (P0: the mid point); with nodal constraint
        points the mid point of the dof's edge is used.
        """
        space = self.fes.components[self.jn]
        n = space.ndof
        crack_of = np.full(n, -1, dtype=int)
        s_of = np.zeros(n)
        for k, crack in enumerate(self.crack_mesh.cracks):
            for e in range(len(crack)):
                dofs = list(space.GetDofNrs(ngs.NodeId(ngs.EDGE, int(crack.edge[e]))))
                p = len(dofs) - 1
                for q, d in enumerate(dofs):
                    if d < 0:
                        continue
                    param = 0.5 if p == 0 or self.nodal_constraints else q / p
                    crack_of[d] = k
                    s_of[d] = crack.s_mid[e] + (param - 0.5) * crack.length[e]
        return crack_of, s_of

    def crack_jumps(self, gf: ngs.GridFunction, crack) -> tuple[np.ndarray, np.ndarray]:
        """([u].nu, [u].t) at the crack edges' mid points: the normal jump from the jn facet
        unknowns; the tangential one from the jt facet unknowns or, without them, from the
        tangential component of `tangential_jump` at the mid point."""
        comps = gf.components
        dofs, B = facet_basis(self.fes.components[self.jn], self.crack_mesh, crack, [0.5])
        jn = np.einsum("ek,ek->e", comps[self.jn].vec.FV().NumPy()[dofs], B[:, :, 0])
        if self.jt is not None:
            jt = np.einsum("ek,ek->e", comps[self.jt].vec.FV().NumPy()[dofs], B[:, :, 0])
        else:
            mid = crack.mid
            vals = np.asarray(self.tangential_jump(gf)(self.crack_mesh.mesh(mid[:, 0], mid[:, 1])))
            jt = np.einsum("ei,ei->e", vals.reshape(len(crack), 2), crack.tangent)
        return jn, jt

    def tangential_jump(self, gf: ngs.GridFunction) -> ngs.CoefficientFunction:
        """jt t on the crack edges (t the crack's tangent): the facet tangential jump as a vector."""
        _, t = crack_frame_cf(self.crack_mesh)
        return gf.components[self.jt] * t

    def held_mean_rows(self, held_mean: dict, T, free: np.ndarray) -> tuple[np.ndarray, list]:
        """The mean constraints of the pin and roller points as integrals over their
        boundary edges (`held_means.constraint_rows`)."""
        return constraint_rows(self, held_mean, T, free)


@dataclass(eq=False)
class WeaklySymmetricHybrid(PlanarDiscretization):
    """The hybrid form of weakly imposed symmetry (PEERS, BDM): `rows` maps the stress
    spaces' symbols to the two stress rows and their divergences; `layout` = (number of
    stress spaces, index of u, index of the rotation, index of the element pressure or
    None without the incompressible split)."""

    rows: Callable | None = None
    layout: tuple = ()

    def stress(self, sym) -> tuple:
        """(sigma_h, sigma, div sigma) of the symbols `sym` (sigma = sigma_h + p I with the split)."""
        ns, _, _, idx_p = self.layout
        (r1, r2), (d1, d2) = self.rows(sym[:ns])
        sig_h = stress_matrix(r1, r2)
        sig = sig_h + sym[idx_p] * ngs.Id(2) if idx_p is not None else sig_h
        return sig_h, sig, ngs.CF((d1, d2))

    def trace(self, sym) -> ngs.CoefficientFunction:
        """The facet displacement trace u_hat of the symbols `sym`."""
        return ngs.CF((sym[self.uhat[0]], sym[self.uhat[1]]))

    def fields(self, gf: ngs.GridFunction) -> dict[str, ngs.CoefficientFunction]:
        _, idx_u, idx_r, _ = self.layout
        comps = gf.components
        return {"sigma": self.stress(comps)[1], "u": comps[idx_u], "rotation": comps[idx_r]}

    def boundary_values(self, gf: ngs.GridFunction, loads: Loads) -> None:
        g, reg = displacement_data(self.crack_mesh.mesh, loads.displacement)
        for i, comp_i in enumerate(self.uhat):
            gf.components[comp_i].Set(g[i], ngs.BND, definedon=reg)

    def roller_pairs(self, labels) -> list:
        return cartesian_roller_pairs(self.fes, self.crack_mesh.mesh, self.uhat, labels)

    def traction(self, g: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        return -(g * self.trace(self.fes.TestFunction()))



def crack_facet_space(crack_mesh: CrackMesh, order: int) -> ngs.FESpace:
    """A facet space with dofs on the crack edges only (P`order` per edge).

    Built as the whole-mesh facet space compressed to the crack edges, so that element
    boundary integrals of volume elements see it (a `definedon` boundary region would not).
    """
    return on_crack_edges(ngs.FacetFESpace(crack_mesh.mesh, order=order), crack_mesh)


def crack_elements(crack_mesh: CrackMesh) -> ngs.BitArray:
    """The triangles with an edge on a crack (both sides), as a BitArray over the elements."""
    mesh = crack_mesh.mesh
    els = ngs.BitArray(mesh.ne)
    els.Clear()
    for crack in crack_mesh.cracks:
        for e in crack.edge:
            for el in mesh.edges[int(e)].elements:
                els[el.nr] = True
    return els


def crack_boundary(crack_mesh: CrackMesh) -> ngs.comp.DifferentialSymbol:
    """Element-boundary integration over the crack's triangles only.

    The crack indicator chi (and the crack frame) vanish on every other element
    boundary, so the crack terms need not be evaluated there: assembling them on the
    few triangles at the crack instead of in every element's boundary integral gives
    the same matrix up to round-off, at a fraction of the cost (BENCHMARKS.md section 9).
    """
    return ngs.dx(element_boundary=True, bonus_intorder=CRACK_BONUS_INTORDER, definedonelements=crack_elements(crack_mesh))


def on_crack_edges(space: ngs.FESpace, crack_mesh: CrackMesh) -> ngs.FESpace:
    """`space` compressed to the dofs that belong to the crack edges."""
    active = ngs.BitArray(space.ndof)
    active.Clear()
    for crack in crack_mesh.cracks:
        for e in crack.edge:
            for d in space.GetDofNrs(ngs.NodeId(ngs.EDGE, int(e))):
                active[d] = True
    return ngs.Compress(space, active_dofs=active)


def roller_edges(mesh: ngs.Mesh, roller):
    """(boundary element, outward unit normal) for every mesh edge on the roller labels."""
    if not roller:
        return
    mask = boundary_region(mesh, roller).Mask()
    for el in mesh.Elements(ngs.BND):
        if mask[el.index]:
            p, q = (np.array(mesh[v].point) for v in el.vertices)
            t = (q - p) / np.linalg.norm(q - p)
            # the polygon is counter-clockwise: the outward normal is t turned by -90 degrees
            yield el, np.array([t[1], -t[0]])



def load_vector(fes: ngs.FESpace, mesh: ngs.Mesh, loads: Loads, built: list[str],
                body: Callable, traction: Callable, crack: Callable | None = None) -> ngs.LinearForm:
    """The assembled load vector of an element: int body(f) dx + sum over loaded edges of int traction(g) ds
    + sum over pressurized cracks of int crack(p) ds.

    `body(f)` and `traction(g)` give the integrands of the element's test functions for
    the body force f and an edge's traction g (signs and traces are the element's);
    `crack(p)` the integrand of the crack-face pressure p, whose virtual work is
    int p [v].nu ds over the crack (the element's sign convention applied), integrated on
    the crack's own edges; what is loaded is recorded in `built`.
    """
    f = ngs.LinearForm(fes)
    if loads.body_force is not None:
        f += body(loads.body_force) * ngs.dx
        built.append("body force")
    for label, g in sorted(loads.traction.items()):
        f += traction(g) * ngs.ds(definedon=boundary_region(mesh, [label]))
    if loads.traction:
        built.append("traction load on " + ", ".join(sorted(loads.traction)))
    if loads.crack_pressure and crack is not None:
        for k, p in sorted(loads.crack_pressure.items()):
            f += crack(p) * ngs.ds(definedon=mesh.Boundaries(crack_bc(k)), bonus_intorder=CRACK_BONUS_INTORDER)
        built.append("crack-face pressure on crack " + ", ".join(str(k) for k in sorted(loads.crack_pressure)))
    with task_manager():
        f.Assemble()
    return f


def displacement_data(mesh: ngs.Mesh, displacement: dict) -> tuple[ngs.CoefficientFunction, ngs.Region]:
    """One CoefficientFunction holding every prescribed displacement, and its region.

    Set it once: NGSolve's GridFunction.Set clears the whole vector first, so one Set
    per label would keep only the last label's data.
    """
    cf = mesh.BoundaryCF({re.escape(lab): g for lab, g in displacement.items()}, default=ngs.CF((0.0, 0.0)))
    return cf, boundary_region(mesh, displacement)


def cartesian_roller_pairs(fes: ngs.FESpace, mesh: ngs.Mesh, comps: tuple[int, int], roller, nodal: bool = False) -> list:
    """(dof of ux, dof of uy, outward unit normal) for every dof on a roller edge.

    `comps` are the compound components holding the x and y displacement, two copies
    of one space with the same dof numbering. With `nodal`, the vertex dofs of the
    roller edges are included too (a vertex on two rollers appears once per edge).
    """
    ix, iy = comps
    comp = fes.components[ix]
    off_x, off_y = fes.Range(ix).start, fes.Range(iy).start
    pairs = []
    for el, nrm in roller_edges(mesh, roller):
        dofs = list(comp.GetDofNrs(el.edges[0]))
        if nodal:
            dofs += [d for v in el.vertices for d in comp.GetDofNrs(v)]
        for d in dofs:
            pairs.append((off_x + d, off_y + d, nrm))
    return pairs


def stress_matrix(row1, row2) -> ngs.CoefficientFunction:
    """The 2x2 stress from its two rows (each a vector CoefficientFunction)."""
    return ngs.CF((row1[0], row1[1], row2[0], row2[1]), dims=(2, 2))


def skew(tau) -> ngs.CoefficientFunction:
    """as(tau) = tau_21 - tau_12, the scalar skew part in 2D."""
    return tau[1, 0] - tau[0, 1]


def weakly_symmetric_hybrid(
    element: str,
    crack_mesh: CrackMesh,
    compliance: Compliance,
    loads: Loads,
    stress_spaces: list[ngs.FESpace],
    rows: Callable[[tuple], tuple[list, list]],
    rotation_spaces: list[ngs.FESpace],
    facet_order: int,
    built: list[str],
    trace_rows: Callable[[tuple], tuple] | None = None,
    displacement_order: int = 0,
    traits: ElementTraits | None = None,
) -> WeaklySymmetricHybrid:
    """Assemble the hybrid form above for the given stress and rotation spaces.

    `rows(symbols)` maps the stress-space symbols (trial or test functions) to the two
    stress rows and their divergences; the first rotation space holds the scalar
    rotation r. `trace_rows(symbols)`, where given, maps them to
    two rows with the same normal traces on every element boundary as the stress rows
    (the parts with zero normal trace left out; PEERS: the curls of the bubbles), used in
    the element-boundary terms. `displacement_order` is the degree of the discontinuous
    displacement u (0 for PEERS and BDM_1; k - 1 for BDM_k).

    Incompressible limit (plane strain, nu -> 1/2): A annihilates the spherical stress
    c I, and c I with c constant on a triangle is divergence free and symmetric, so the
    local problem of a broken stress becomes singular (and ill-conditioned near 1/2).
    There the stress is split as sigma = sigma_h + p_T I with p_T one pressure per
    triangle, kept global (not condensed; it is fixed by the facet traces through
    <u_hat, p_T n>), and the element mean of tr(sigma_h) held at zero by a local
    multiplier. The local problems are then uniformly well posed, and the condensed
    system is a symmetric saddle point in (u_hat, p).
    """
    mesh = crack_mesh.mesh
    uhat_space = ngs.FacetFESpace(mesh, order=facet_order, dirichlet=boundary_regex(loads.dirichlet_labels))
    spaces = list(stress_spaces) + [ngs.VectorL2(mesh, order=displacement_order)] + list(rotation_spaces) \
        + [uhat_space, uhat_space]
    built += [f"u: P{displacement_order}^2", f"u_hat: P{facet_order} per edge, 2 components"]
    has_crack = bool(crack_mesh.cracks)
    if has_crack:
        jump = crack_facet_space(crack_mesh, facet_order)
        spaces += [jump, jump]
        built.append(f"crack jump: P{facet_order} per crack edge (normal and tangential)")
    split = compliance.spherical <= PRESSURE_SPLIT_RTOL * compliance.c_dev
    if split:
        compliance = compliance.with_spherical_floor(SPHERICAL_FLOOR)
        pressure = ngs.L2(mesh, order=0)
        pressure.SetCouplingType(ngs.IntRange(0, pressure.ndof), ngs.COUPLING_TYPE.INTERFACE_DOF)
        spaces += [pressure, ngs.L2(mesh, order=0)]
        built.append("incompressible split: global P0 element pressure, local mean-trace multiplier")
    fes = ngs.FESpace(spaces)
    ns, nr = len(stress_spaces), len(rotation_spaces)
    idx_u, idx_r = ns, ns + 1
    idx_ux, idx_uy = ns + 1 + nr, ns + 2 + nr
    idx_jn, idx_jt = ns + 3 + nr, ns + 4 + nr
    idx_p = len(spaces) - 2 if split else None
    disc = WeaklySymmetricHybrid(
        element=element, crack_mesh=crack_mesh, fes=fes, a=ngs.BilinearForm(fes, condense=True), f=None,
        uhat=(idx_ux, idx_uy), jn=idx_jn if has_crack else None, jt=idx_jt if has_crack else None,
        facet_order=facet_order, built=built, definite=not split,
        traits=traits if traits is not None else ElementTraits(), rows=rows, layout=(ns, idx_u, idx_r, idx_p))
    trial, test = fes.TrialFunction(), fes.TestFunction()

    def unpack(sym):
        _, sig, div = disc.stress(sym)
        return sig, div, sym[idx_u], sym[idx_r], disc.trace(sym)

    def boundary_stress(sym):
        if trace_rows is None:
            return disc.stress(sym)[1]
        sig_n = stress_matrix(*trace_rows(sym[:ns]))
        return sig_n + sym[idx_p] * ngs.Id(2) if split else sig_n

    sig, div_sig, u, r, uh = unpack(trial)
    tau, div_tau, v, eta, muh = unpack(test)
    n = ngs.specialcf.normal(2)
    a = disc.a
    volume = ngs.InnerProduct(compliance.apply(sig), tau) + div_tau * u + div_sig * v + skew(tau) * r + skew(sig) * eta
    a += volume.Compile() * ngs.dx
    if split:
        lam, mu_l = trial[idx_p + 1], test[idx_p + 1]
        a += (ngs.Trace(disc.stress(trial)[0]) * mu_l + ngs.Trace(disc.stress(test)[0]) * lam) * ngs.dx
    sig, tau = boundary_stress(trial), boundary_stress(test)
    a += (-((tau * n) * uh + (sig * n) * muh)).Compile() * ngs.dx(element_boundary=True)
    if has_crack:
        # the crack part of the traces, -chi j and -chi k, on the crack's triangles only
        nu, t = crack_frame_cf(crack_mesh)
        chi = ngs.IfPos(n * nu - 0.5, 1.0, 0.0)
        jn, jt = trial[idx_jn], trial[idx_jt]
        kn, kt = test[idx_jn], test[idx_jt]
        a += ((tau * n) * (chi * (jn * nu + jt * t)) + (sig * n) * (chi * (kn * nu + kt * t))) * crack_boundary(crack_mesh)
    with task_manager():
        a.Assemble()
    disc.f = load_vector(fes, mesh, loads, built, body=lambda b: -(b * v), traction=disc.traction,
                         crack=(lambda p: -(p * test[idx_jn])) if has_crack else None)
    return disc
