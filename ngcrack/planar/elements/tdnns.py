"""TDNNS (tangential-displacement normal-normal-stress; Pechstein and Schoeberl), hybridized.

Order k (k >= 1; the stress degree):
- stress sigma: symmetric, NGSolve's HDivDiv of order k with its interior "plus"
  bubbles, broken (local);
- displacement u: HCurl of order k+1 of the first kind (Nedelec type 1: tangential
  traces P_k; tangentially continuous; global);
- normal facet trace u_hat_n: NormalFacetFESpace of order k, restoring the
  normal-normal continuity of sigma (global);
- crack: the normal jump jn, P_k per crack edge, and the tangential jump, carried
  by a copy of u's dofs on the crack edges used on the crack's + side only
  (u = u_c + H+ u_e, H+ = 1 on the triangles on the + side of a crack edge). The
  edge functions of HCurl have tangential traces on their own edge only, so this
  duplicates exactly the tangential unknowns of the crack edges: [u].t = u_e.t.

With b(sigma; v, v_hat_n) = sum_T [ -(sigma, grad v)_T + <sigma_nn, v.n - v_hat_n>_dT ],

    (A sigma, tau) + b(tau; u, u_hat_n - chi jn)  = 0
    b(sigma; v, v_hat_n - chi kn)                  = -(f, v) - <g.n, v_hat_n> - <g.t, v.t>

chi = 1 on the minus side of a crack edge. Expected rates for smooth solutions:
||sigma - sigma_h||_L2 and ||u - u_h||_L2 of order h^(k+1). No rotation unknown: the
stress is symmetric by construction. Rollers are imposed on u_hat_n directly.

The crack-face shear: TDNNS stresses have no single-valued tangential traction on an
edge (sigma_nt jumps; the element's divergence residual balances it), so a point value
of (sigma nu).t means nothing (about 0.3-1.3 times the load on frictionless cracks).
The traction that the discrete equations transmit is the one tested by the crack's
tangential unknowns u_e: for each HCurl function phi of a crack edge, on the + side T+,

    int_e (sigma nu).t (phi.t) ds = -(sigma, grad phi)_T+ + <sigma_nn, phi.n>_dT+ + (f, phi)_T+

(exact for the true solution, by Green's formula). The profiles' shear_stress is the
P_k function on the crack with these moments, at the mid points
(`post.consistent_tractions`): the residual of the u_e equations, zero up to round-off
on a frictionless crack, the friction traction otherwise. sigma_nn is single-valued
and is sampled directly.

Why not a stress of degree 0: broken P0 stresses (3 per triangle) cannot control the
two facet unknowns per edge (u_t and u_hat_n) of the hybrid form, whose condensed
matrix is then singular; the non-hybrid lowest-order TDNNS has no such counterpart
here. The "plus" bubbles are needed for the same reason at every order.
"""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ...core.element_names import ORDERS as _ORDERS
from ...core.errors import InputError
from ...core.parallel import task_manager
from ..geometry import CrackMesh, boundary_regex, crack_frame_cf
from ..materials import Compliance
from .base import (
    PRESSURE_SPLIT_RTOL,
    SPHERICAL_FLOOR,
    ElementTraits,
    Loads,
    PlanarDiscretization,
    crack_boundary,
    crack_facet_space,
    displacement_data,
    load_vector,
    on_crack_edges,
)

ORDERS = _ORDERS["tdnns"]
DEFAULT_ORDER = 1
#: grad u from A sigma and the skew part of grad_u; a Prager-Synge estimate from u
TRAITS = ElementTraits(gradient="skew", estimate="prager-synge", estimate_degree=2,
                       estimate_note="tdnns stress is not in H(div): not a bound")



@dataclass(eq=False)
class TdnnsDiscretization(PlanarDiscretization):
    """The hybridized TDNNS element: u = u_c + H+ u_e with H+ (`plus`) the + side's
    indicator and u_e (component `tangential`) the crack edges' HCurl copy; `pressure` the
    component of the incompressible split's element pressure (None without it)."""

    plus: ngs.GridFunction | None = None
    pressure: int | None = None

    def displacement(self, sym) -> ngs.CoefficientFunction:
        """u of the symbols `sym`."""
        return sym[1] + self.plus * sym[self.tangential] if self.has_crack else sym[1]

    def grad_displacement(self, sym) -> ngs.CoefficientFunction:
        """grad u of the symbols `sym` (H+ is constant on each triangle: grad(H+ u_e) = H+ grad(u_e))."""
        g = ngs.Grad(sym[1])
        return g + self.plus * ngs.Grad(sym[self.tangential]) if self.has_crack else g

    def stress(self, sym) -> ngs.CoefficientFunction:
        """sigma of the symbols `sym` (plus the element pressure with the split)."""
        return sym[0] + sym[self.pressure] * ngs.Id(2) if self.pressure is not None else sym[0]

    def fields(self, gf: ngs.GridFunction) -> dict[str, ngs.CoefficientFunction]:
        comps = gf.components
        return {"sigma": self.stress(comps), "u": self.displacement(comps), "grad_u": self.grad_displacement(comps)}

    def boundary_values(self, gf: ngs.GridFunction, loads: Loads) -> None:
        g, reg = displacement_data(self.crack_mesh.mesh, loads.displacement)
        gf.components[1].Set(g, ngs.BND, definedon=reg)
        gf.components[2].Set(g, ngs.BND, definedon=reg)

    def traction(self, g: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        test = self.fes.TestFunction()
        n, t = ngs.specialcf.normal(2), ngs.specialcf.tangential(2)
        return -((g * n) * (test[2].Trace() * n) + (g * t) * (test[1].Trace() * t))

    def tangential_jump(self, gf: ngs.GridFunction) -> ngs.CoefficientFunction:
        """u_e: its tangential trace on a crack edge is single-valued and equals [u].t."""
        return gf.components[self.tangential]


def plus_side(crack_mesh: CrackMesh) -> ngs.GridFunction:
    """H+: 1 on the triangles on the + side of a crack edge (nu points into them), else 0."""
    mesh = crack_mesh.mesh
    H = ngs.GridFunction(ngs.L2(mesh, order=0))
    vals = H.vec.FV().NumPy()
    vals[:] = 0.0
    minus = np.zeros(mesh.ne, dtype=bool)
    verts, tris = crack_mesh.points, crack_mesh.triangles
    for crack in crack_mesh.cracks:
        for e, mid, nu in zip(crack.edge, crack.mid, crack.normal):
            for el in mesh.edges[int(e)].elements:
                c = verts[tris[el.nr]].mean(axis=0)
                if np.dot(c - mid, nu) > 0:
                    vals[el.nr] = 1.0
                else:
                    minus[el.nr] = True
    if np.any(minus & (vals > 0)):
        raise InputError("maxh: a triangle touches two cracks from opposite sides; refine the mesh near the cracks")
    return H


def tdnns_order(order, where: str = "") -> int:
    """The stress degree k of a TDNNS element: `order` (one of ORDERS), DEFAULT_ORDER for None;
    an InputError naming the allowed values otherwise (`where`: " in 3D", for the message)."""
    k = DEFAULT_ORDER if order is None else order
    if isinstance(k, bool) or k not in ORDERS:
        raise InputError(f"order = {order!r}: allowed values for tdnns{where} are {', '.join(map(str, ORDERS))}")
    return k


def tdnns_spaces(mesh: ngs.Mesh, k: int, loads: Loads) -> tuple[list, list[str]]:
    """The spaces of the hybridized TDNNS element of stress degree k, in 2D or 3D (stress, u, u_hat_n), and their
    description: clamped boundaries fix u and u_hat_n, rollers fix u_hat_n."""
    dirichlet = boundary_regex(loads.dirichlet_labels)
    normal_fixed = boundary_regex(set(loads.dirichlet_labels) | set(loads.roller))
    spaces = [
        ngs.HDivDiv(mesh, order=k, discontinuous=True, plus=True),
        ngs.HCurl(mesh, order=k + 1, type1=True, dirichlet=dirichlet),
        ngs.NormalFacetFESpace(mesh, order=k, dirichlet=normal_fixed),
    ]
    built = [f"stress: HDivDiv P{k}+, broken", f"u: HCurl order {k + 1}, type 1", f"u_hat_n: normal facet P{k}"]
    return spaces, built


def tdnns_terms(A_sig, sig, tau, trial, test, n, ue: int | None = None):
    """The integrands of the TDNNS form in any dimension (u = trial[1], u_hat_n = trial[2]): (A sigma, tau) plus
    b(tau; u) and b(sigma; v) over the elements, then over their boundaries (the module docstring's b); with `ue`,
    the index of the tangential jump u_e, b's terms of u_e instead (the + side's elements only)."""
    if ue is None:
        volume = ngs.InnerProduct(A_sig, tau) - ngs.InnerProduct(tau, ngs.Grad(trial[1])) \
            - ngs.InnerProduct(sig, ngs.Grad(test[1]))
        un_hat, vn_hat = trial[2] * n, test[2] * n
        boundary = (n * (tau * n)) * (trial[1] * n - un_hat) + (n * (sig * n)) * (test[1] * n - vn_hat)
        return volume, boundary
    volume = -ngs.InnerProduct(tau, ngs.Grad(trial[ue])) - ngs.InnerProduct(sig, ngs.Grad(test[ue]))
    boundary = (n * (tau * n)) * (trial[ue] * n) + (n * (sig * n)) * (test[ue] * n)
    return volume, boundary


def build(crack_mesh: CrackMesh, compliance: Compliance, loads: Loads, order: int | None = None) -> TdnnsDiscretization:
    """The hybridized TDNNS discretization of stress degree k = `order` (default 1)."""
    k = tdnns_order(order)
    mesh = crack_mesh.mesh
    spaces, built = tdnns_spaces(mesh, k, loads)
    has_crack = bool(crack_mesh.cracks)
    if has_crack:
        spaces += [crack_facet_space(crack_mesh, k), on_crack_edges(ngs.HCurl(mesh, order=k + 1, type1=True), crack_mesh)]
        H = plus_side(crack_mesh)
        built.append(f"crack: normal jump P{k} per edge, tangential jump from the crack edges' HCurl dofs")
    split = compliance.spherical <= PRESSURE_SPLIT_RTOL * compliance.c_dev
    if split:
        compliance = compliance.with_spherical_floor(SPHERICAL_FLOOR)
        pressure = ngs.L2(mesh, order=k)
        pressure.SetCouplingType(ngs.IntRange(0, pressure.ndof), ngs.COUPLING_TYPE.INTERFACE_DOF)
        spaces += [pressure, ngs.L2(mesh, order=k)]
        built.append(f"incompressible split: global P{k} element pressure, local trace multiplier")
    fes = ngs.FESpace(spaces)
    idx_jn, idx_ue = (3, 4) if has_crack else (None, None)
    disc = TdnnsDiscretization(
        element="tdnns", crack_mesh=crack_mesh, fes=fes, a=ngs.BilinearForm(fes, condense=True), f=None, uhat=(2, 2),
        jn=idx_jn, jt=None, facet_order=k, built=built, definite=not split,
        traction_rows=(None, idx_ue) if has_crack else (None, None), tangential=idx_ue, traits=TRAITS,
        plus=H if has_crack else None, pressure=len(spaces) - 2 if split else None)
    trial, test = fes.TrialFunction(), fes.TestFunction()
    sig, tau = disc.stress(trial), disc.stress(test)
    v = disc.displacement(test)
    n = ngs.specialcf.normal(2)
    a = disc.a
    # u = u_c + H+ u_e: the u_c terms everywhere, the u_e terms on the + side's triangles
    # only (H+ = 1 there, 0 elsewhere), the crack jump jn on the crack's triangles only
    # (chi = 0 on every other element boundary): the same matrix as with H+ and chi in
    # every element, up to round-off
    volume, boundary = tdnns_terms(compliance.apply(sig), sig, tau, trial, test, n)
    a += volume.Compile() * ngs.dx
    if split:
        a += (ngs.Trace(trial[0]) * test[disc.pressure + 1] + ngs.Trace(test[0]) * trial[disc.pressure + 1]) * ngs.dx
    a += boundary.Compile() * ngs.dx(element_boundary=True)
    if has_crack:
        plus = ngs.BitArray(mesh.ne)
        plus.Clear()
        for el in np.flatnonzero(H.vec.FV().NumPy() > 0):
            plus[int(el)] = True
        volume, boundary = tdnns_terms(None, sig, tau, trial, test, n, ue=idx_ue)
        a += volume * ngs.dx(definedonelements=plus)
        a += boundary * ngs.dx(element_boundary=True, definedonelements=plus)
        nu, _ = crack_frame_cf(crack_mesh)
        chi = ngs.IfPos(n * nu - 0.5, 1.0, 0.0)
        a += ((n * (tau * n)) * (chi * trial[idx_jn]) + (n * (sig * n)) * (chi * test[idx_jn])) * crack_boundary(crack_mesh)
    with task_manager():
        a.Assemble()
    disc.f = load_vector(fes, mesh, loads, built, body=lambda b: -(b * v), traction=disc.traction,
                         crack=(lambda p: -(p * test[idx_jn])) if has_crack else None)
    return disc
