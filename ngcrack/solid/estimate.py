"""An a posteriori estimate of the 3D stress error: Prager-Synge with a rebuilt displacement.

As the 2D estimate of the mixed elements (ngcrack.planar.estimate), for sigma_h the discrete
stress and w a displacement admissible on the cracked body (w = u_D on clamped faces,
w.n = 0 on rollers, continuous except across the crack, [w].nu >= 0 on it):

    ||sigma - sigma_h||_A^2 <= eta^2 = ||A sigma_h - eps(w)||_C^2 + 2 int_crack lam_h [w].nu dA

(||r||_C^2 = 2 mu |r|^2 + lambda (tr r)^2, the plain, not lambda-robust, weight). w is the
L2 projection of the solution's displacement onto the continuous P2 space with the crack's
nodes duplicated (the h1p2 element's space, ngcrack.solid.h1), its normal jump then raised
where needed so that its Bernstein coefficients (vertex values, and 2 w(mid) - (w_a + w_b)/2
on each crack edge) are >= 0: [w].nu >= 0 on the whole crack. lam_h = -sigma_h,nn - p is the
discrete contact pressure: a crack-face pressure p (uniform or varying over the crack,
`solid.loads`, evaluated at the quadrature points) is load data, sigma_nn = -p - lam with
lam >= 0 and lam [u].nu = 0, so only the contact's part of the normal stress enters (as
in 2D); an open crack under a pressure has a crack term of the order of the error.

The data term: TDNNS holds the normal-normal traction of a traction face weakly, as the
L2 projection of g.n on its normal-facet space (exact for a uniform traction, to round-off),
so a traction that varies over a face (a table or a callable, `solid.loads`: the
CoefficientFunction the element took) leaves sigma_h,nn - g.n on it; with the trace
inequality (its constant taken as 1, not known on the body: not part of a bound)

    data^2 = sum over the traction faces' triangles F of h_F ||sigma_h,nn - g.n||_F^2 / (2 mu),

h_F the diameter of an equilateral triangle of F's area, reported as "data" and added to
eta^2 (eta^2 = stress^2 + contact + data^2). Its tangential part is not data: TDNNS's
sigma_h n . t is not continuous at all (the non-admissibility below). The patches of the
point supports and forces are left out (their traction is a mean, `solid.points`).

Not a guaranteed bound for TDNNS (its stress is normal-normal but not normal-tangential
continuous, so not statically admissible), as in 2D; body forces enter through the
element's weak equilibrium only (no oscillation term). Per tetrahedron: eta_T^2 (the first
term's share), the crack term is reported on its own.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from . import h1
from .loads import coefficients, is_varying

#: quadrature order on the crack faces for the contact term
FACE_ORDER = 6


def rebuilt_displacement(sol, loads) -> tuple[object, ngs.GridFunction]:
    """(the h1p2 discretization, w): the admissible displacement described in the module docstring."""
    E, nu = sol.scene.material.E, sol.scene.material.nu
    disc = h1.build(sol.smesh, E, nu, loads, "h1p2")
    fes = disc.fes
    u, v = disc.displacement_of(fes.TrialFunction()), disc.displacement_of(fes.TestFunction())
    m = ngs.BilinearForm(fes)
    m += (u * v) * ngs.dx
    f = ngs.LinearForm(fes)
    f += (sol.u * v) * ngs.dx
    m.Assemble()
    f.Assemble()
    w = ngs.GridFunction(fes)
    disc.boundary_values(w, loads)
    rhs = f.vec.CreateVector()
    rhs.data = f.vec - m.mat * w.vec
    w.vec.data += m.mat.Inverse(fes.FreeDofs(), "sparsecholesky") * rhs
    if disc.jn is not None:
        _admissible_jump(w, disc)
    return disc, w


def _admissible_jump(w: ngs.GridFunction, disc) -> None:
    """Raise the normal jump where needed: vertex values >= 0, each crack edge's Bernstein
    coefficient 2 w(mid) - (w_a + w_b) / 2 >= 0 (G: coefficients -> vertex and mid-point values)."""
    rng = disc.fes.Range(disc.jn)
    x = w.vec.FV().NumPy()[rng.start:rng.stop].copy()
    G = sp.csr_matrix(disc.constraint_map())
    vals = G @ x
    edge = np.diff(G.indptr) > 1  # an edge's row holds its end vertices' 0.5 (front vertices: none)
    vals[~edge] = np.maximum(vals[~edge], 0.0)
    for r in np.flatnonzero(edge):
        cols = G.indices[G.indptr[r]:G.indptr[r + 1]]
        ends = [c for c in cols if c != r]
        vals[r] = max(vals[r], 0.25 * sum(vals[c] for c in ends))
    w.vec.FV().NumPy()[rng.start:rng.stop] = spla.spsolve(G.tocsc(), vals)


def _applied(pressure, xyz: np.ndarray) -> np.ndarray:
    """A crack's applied pressure at the points: a number (None: none) or a varying field (solid.loads.is_varying)."""
    if is_varying(pressure):
        return pressure.values(xyz)[:, 0]
    return np.full(len(xyz), float(pressure or 0.0))


def _crack_term(sol, wdisc, w) -> float:
    """2 int_crack (-sigma_h,nn - p) [w].nu dA: sigma_h,nn the mean of the two sides' values, p the applied pressure."""
    mesh = sol.smesh.mesh
    total = 0.0
    rule = ngs.IntegrationRule(ngs.TRIG, FACE_ORDER)
    k = len(rule.weights)
    jump = w.components[wdisc.jn]
    for c in sol.smesh.cracks:
        mp = mesh.MapToAllElements(rule, ngs.BND).reshape(mesh.GetNE(ngs.BND), k)[c.elements].ravel()
        xyz = np.column_stack([np.asarray(q(mp)).ravel() for q in (ngs.x, ngs.y, ngs.z)])
        jac = np.asarray(ngs.specialcf.JacobianMatrix(3, 2)(mp)).reshape(-1, 3, 2)
        weight = np.linalg.norm(np.cross(jac[:, :, 0], jac[:, :, 1]), axis=1) * np.tile(np.array(rule.weights), len(c.elements))
        wn = np.asarray(jump(mp)).ravel()
        centre = np.repeat(xyz.reshape(-1, k, 3).mean(axis=1), k, axis=0)
        snn = np.zeros(len(xyz))
        for side in (1.0, -1.0):
            y = xyz + side * 1e-6 * sol.scene.size * c.normal + 1e-6 * (centre - xyz)
            s = np.asarray(sol.sigma(mesh(y[:, 0], y[:, 1], y[:, 2]))).reshape(-1, 3, 3)
            snn += 0.5 * np.einsum("i,kij,j->k", c.normal, s, c.normal)
        p = _applied(getattr(sol.scene.cracks[c.index], "pressure", 0.0), xyz)
        total += 2.0 * float(weight @ ((-snn - p) * wn))
    return total


def traction_data(sol) -> float:
    """The data term of the traction faces (module docstring): sqrt(sum_F h_F ||sigma_h,nn - g.n||_F^2 / (2 mu))."""
    scene, mesh = sol.scene, sol.smesh.mesh
    patches = {pc.label for pc in getattr(scene, "points", ())}
    constant = {k: ngs.CF(tuple(map(float, c.value))) for k, c in scene.boundary.items() if c.type == "traction"}
    _, faces = coefficients(scene, constant)
    faces = {k: g for k, g in faces.items() if k not in patches}
    if not faces:
        return 0.0
    n = ngs.specialcf.normal(3)
    s = ngs.BoundaryFromVolumeCF(sol.sigma)
    order = 2 * max(sol.disc.order, 2) + 2
    _, mu = h1.lame(scene.material.E, scene.material.nu)
    total = 0.0
    for label, g in sorted(faces.items()):
        r = n * (s * n) - g * n
        on = mesh.Boundaries(label)
        sq = np.asarray(ngs.Integrate(r * r, mesh, ngs.BND, order=order, definedon=on, element_wise=True)).ravel()
        area = np.asarray(ngs.Integrate(ngs.CF(1.0), mesh, ngs.BND, definedon=on, element_wise=True)).ravel()
        h = np.sqrt(4.0 * area / np.sqrt(3.0))
        total += float(h @ np.maximum(sq, 0.0))
    return float(np.sqrt(total / (2.0 * mu)))


def prager_synge(sol, loads) -> dict:
    """{"total": eta, "stress": the first term's root, "contact": the crack term, "data": the traction faces' data
    term, "per_element": eta_T^2 (the first term's)}."""
    E, nu = sol.scene.material.E, sol.scene.material.nu
    lam, mu = h1.lame(E, nu)
    wdisc, w = rebuilt_displacement(sol, loads)
    g = wdisc.fields(w)["grad_u"]
    s = sol.sigma
    s = 0.5 * (s + s.trans)
    c_dev, c_tr = (1.0 + nu) / E, nu / E
    r = c_dev * s - c_tr * ngs.Trace(s) * ngs.Id(3) - 0.5 * (g + g.trans)
    density = 2.0 * mu * ngs.InnerProduct(r, r) + lam * ngs.Trace(r) ** 2
    order = 2 * max(sol.disc.order, 2) + 2
    per = np.asarray(ngs.Integrate(density, sol.smesh.mesh, order=order, element_wise=True)).ravel()
    contact = _crack_term(sol, wdisc, w) if sol.smesh.cracks else 0.0
    stress = float(per.sum())
    data = traction_data(sol)
    return {"total": float(np.sqrt(max(stress + contact + data ** 2, 0.0))), "stress": float(np.sqrt(stress)),
            "contact": contact, "data": data, "per_element": per}
