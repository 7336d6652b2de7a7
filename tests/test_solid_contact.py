"""3D crack-face contact at order 2 and in any units (coarse meshes).

- Order 2 under compression: the contact constraints are the Bernstein coefficients of
  each face's normal jump, so a face pressed shut has a positive force on every one of
  them and closes entirely (with the values at the Lagrange points, the P2 vertex points
  carried no force under a uniform pressure and a third of the points stayed ajar, with
  K_I = -0.12 reported at the front on this mesh).
- The certificate in any units: the system is assembled in units of E, so the same
  scene in Pa and in MPa gives the same numbers (in Pa the order-2 residuals were 1e-11
  of the forces on this mesh, 0.58 of them on SSLV134's).
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
import scipy.sparse as sp

import ngcrack as nc
from ngcrack.solid.element import bernstein_at_lagrange
from ngcrack.solid.scene import SolidScene

TINY = {
    "name": "penny-tiny",
    "domain": {"box": [[-2.0, -2.0, -2.0], [2.0, 2.0, 2.0]]},
    "crack": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0}],
    "material": {"E": 1000.0, "nu": 0.3},
    "boundary": {"xmin": {"type": "roller"}, "ymin": {"type": "roller"}, "zmin": {"type": "roller"},
                 "zmax": {"type": "traction", "value": [0.0, 0.0, 1.0]}},
    "mesh": {"maxh": 1.5, "crack_h": 1.0, "front_h": 0.5},
}


def tiny(scale: float = 1.0, pressure: float = 1.0) -> SolidScene:
    """The tiny penny with E and the load both multiplied by `scale` (another unit of stress)."""
    d = copy.deepcopy(TINY)
    d["material"]["E"] *= scale
    d["boundary"]["zmax"]["value"] = [0.0, 0.0, pressure * scale]
    return SolidScene.from_dict(d)


@pytest.fixture(scope="module")
def tiny_mesh():
    from ngcrack.solid.geometry import make_mesh

    return make_mesh(tiny())


def test_bernstein_coefficients_of_the_lagrange_points():
    for k in (1, 2, 3):
        M = bernstein_at_lagrange(k)
        assert np.allclose(M.sum(axis=1), 1.0, atol=1e-14)  # a partition of unity
        assert np.allclose(M[:3, :3], np.eye(3), atol=1e-14)  # the vertex coefficients are the vertex values
    assert np.array_equal(bernstein_at_lagrange(1), np.eye(3))  # order 1: the values at the vertices
    # a P2 jump positive at its six Lagrange points but negative inside an edge has a negative coefficient
    values = np.array([1.0, 1.0, 1.0, 0.01, 0.01, 0.01])
    assert np.linalg.solve(bernstein_at_lagrange(2), values).min() < 0


def test_order_2_penny_in_pa_closes_under_compression(tiny_mesh):
    p = 1.0e6
    sol = nc.solve(tiny(scale=1.0e6, pressure=-1.0), crack_mesh=tiny_mesh, order=2)
    assert sol.contact.active.all()
    summary = sol.crack_summaries()[0]
    assert summary["closed_fraction"] == 1.0 and summary["max_opening"] == 0.0
    assert all(v < 1e-12 for v in sol.kkt.values()), sol.kkt
    # every Bernstein force is positive (no point carried by nothing) and they carry the load
    assert sol.contact.lam.min() > 0.005 * p
    assert abs(sol.contact.lam.sum() / (p * math.pi) - 1.0) < 0.01
    (front,) = sol.fronts
    assert front.closed.all() and np.all(front.K_I == 0.0)


def test_order_2_certificate_at_round_off_in_pa(tiny_mesh):
    sol = nc.solve(tiny(scale=1.0e6), crack_mesh=tiny_mesh, order=2)
    assert not sol.contact.active.any()
    assert all(v < 1e-12 for v in sol.kkt.values()), sol.kkt
    # the raw residual at the crack's rows, before any rounding bound: round-off of the forces
    assert np.max(np.abs(sol.contact.lam)) < 1e-12 * 1.0e6 * math.pi
    assert np.all(np.abs(sol.fronts[0].K_I / (2.0e6 / math.sqrt(math.pi)) - 1.0) < 0.25)


def test_order_2_certificate_at_round_off_at_nu_04999(tiny_mesh):
    """lambda/mu = 5000: the direct solve alone leaves a residual of the size of the forces
    at the crack's rows (a certificate of 1.27 with no face closed); refined, it is round-off."""
    d = copy.deepcopy(TINY)
    d["material"]["nu"] = 0.4999
    for pressure, closed in ((1.0, False), (-1.0, True)):
        d["boundary"]["zmax"]["value"] = [0.0, 0.0, pressure]
        sol = nc.solve(SolidScene.from_dict(d), crack_mesh=tiny_mesh, order=2)
        assert sol.contact.active.all() if closed else not sol.contact.active.any()
        assert all(v < 1e-10 for v in sol.kkt.values()), sol.kkt
        if not closed:
            assert np.max(np.abs(sol.contact.lam)) < 1e-10 * math.pi


@pytest.mark.slow
def test_order_2_same_answer_and_certificate_in_two_unit_systems(tiny_mesh):
    for pressure in (1.0, -1.0):
        a = nc.solve(tiny(1.0, pressure), crack_mesh=tiny_mesh, order=2)
        b = nc.solve(tiny(1.0e6, pressure), crack_mesh=tiny_mesh, order=2)
        assert np.array_equal(a.contact.active, b.contact.active)
        for key, value in a.kkt.items():
            assert value < 1e-12 and abs(b.kkt[key] - value) < 1e-13, (key, a.kkt, b.kkt)
        force = math.pi  # the load on the crack, in the first unit system
        assert np.max(np.abs(b.contact.lam / 1.0e6 - a.contact.lam)) < 1e-12 * force
        assert np.max(np.abs(b.normal_jumps() - a.normal_jumps())) < 1e-10 * np.max(np.abs(a.y))
        fa, fb = a.fronts[0], b.fronts[0]
        for name in ("K_I", "K_II", "K_III"):
            ka, kb = getattr(fa, name), getattr(fb, name) / 1.0e6
            assert np.max(np.abs(kb - ka)) < 1e-9 * 2.0 / math.sqrt(math.pi), (name, ka, kb)


# ------------------------------------------------------------------------ Coulomb friction
def _coulomb_kkt(K, F, contact, G, points, res):
    """The Coulomb KKT conditions checked from scratch: y, the normal forces from the residual,
    the friction forces of the result; every residual relative to the largest normal force."""
    y = res.y
    r = K @ y - F
    lam = np.linalg.solve(G.toarray().T, r[contact])
    L = lam.max()
    w = G @ y[contact]
    s = (points.B @ y).reshape(-1, 2)
    g = points.mu * points.omega * np.maximum(lam[points.face_rows].sum(axis=1), 0.0)[points.face]
    t = res.lam_t
    stat = r + points.B.T @ t.ravel()
    stat[contact] = 0.0
    ns = np.linalg.norm(s, axis=1)
    return {"penetration": max(0.0, -w.min()) / max(abs(w).max(), 1e-300), "tension": max(0.0, -lam.min()) / L,
            "complementarity": np.max(np.abs(w * lam)) / (max(abs(w).max(), 1e-300) * L),
            "cone": np.max(np.linalg.norm(t, axis=1) - g) / L,
            "slip_law": np.max(np.linalg.norm(g[:, None] * s - ns[:, None] * t, axis=1)) / (max(ns.max(), 1e-8 * np.abs(y).max()) * L),
            "stationarity": np.max(np.abs(stat)) / L, "stick": int(np.sum(ns < 1e-12 * ns.max())), "g": g, "s": s}


def test_sparse_coulomb_solver_meets_the_cone_conditions():
    from ngcrack.core.sparse_friction import FrictionPoints, solve_friction

    rng = np.random.default_rng(3)
    n = 120
    A = sp.random(n, n, density=0.04, random_state=4)
    K = sp.csr_matrix(A @ A.T + sp.diags(2.0 + rng.random(n)))
    contact = np.arange(0, 30)  # 10 faces of 3 constraints, block-diagonal G
    G = sp.block_diag([np.eye(3) + 0.2 * rng.random((3, 3)) for _ in range(10)], format="csr")
    nq = 10  # one friction point per face, its slip on two unknowns of its own plus a coupling
    rows, cols, vals = [], [], []
    for q in range(nq):
        for j in range(2):
            rows += [2 * q + j] * 3
            cols += [40 + 2 * q + j, 40 + 2 * q + 1 - j, 80 + q]
            vals += [1.0, 0.3, 0.2]
    B = sp.csr_matrix((vals, (rows, cols)), shape=(2 * nq, n))
    points = FrictionPoints(B=B, face=np.arange(nq), omega=np.ones(nq), mu=np.full(nq, 0.3),
                            face_rows=np.arange(30).reshape(10, 3))
    F = np.zeros(n)
    F[contact] = -1.0 - rng.random(30)  # pressed shut ...
    F[40:60] = 0.8 * rng.standard_normal(20)  # ... and sheared
    F[[0, 1, 2]] = 5.0  # one face pulled open
    res = solve_friction(K, F, contact, G, points)
    chk = _coulomb_kkt(K, F, contact, G, points, res)
    for key in ("penetration", "tension", "complementarity", "cone", "slip_law", "stationarity"):
        assert chk[key] < 1e-12, (key, chk[key])
    assert all(v < 1e-12 for v in res.kkt.values()), res.kkt
    # the test means something: faces open and closed, points sticking and slipping
    assert 0 < res.active.sum() < 30 and 0 < chk["stick"] < nq and chk["g"].min() < 1e-12 * chk["g"].max()
    # slipping points: the force on the cone's edge, along the slip
    ns = np.linalg.norm(chk["s"], axis=1)
    slip = ns > 1e-12 * ns.max()
    assert np.allclose(np.linalg.norm(res.lam_t[slip], axis=1), chk["g"][slip], rtol=1e-12, atol=1e-14)


INCLINED = {
    "name": "inclined-tiny",
    "domain": {"box": [[-2.0, -2.0, -2.0], [2.0, 2.0, 2.0]]},
    "crack": [{"shape": "disc", "center": [0, 0, 0], "normal": [math.sqrt(0.5), 0.0, math.sqrt(0.5)], "radius": 1.0}],
    "material": {"E": 1000.0, "nu": 0.3},
    "boundary": {"xmin": {"type": "roller"}, "ymin": {"type": "roller"}, "zmin": {"type": "roller"},
                 "zmax": {"type": "traction", "value": [0.0, 0.0, -1.0]}},
    "mesh": {"maxh": 1.5, "crack_h": 1.0, "front_h": 0.5},
}


@pytest.mark.slow
def test_closed_inclined_penny_slip_is_reduced_by_the_coulomb_bound():
    from ngcrack.solid.friction_points import friction_points
    from ngcrack.solid.geometry import make_mesh

    d = copy.deepcopy(INCLINED)
    smesh = make_mesh(SolidScene.from_dict(d))
    free = nc.solve(SolidScene.from_dict(d), crack_mesh=smesh)
    pts = friction_points(free.smesh, free.disc, free.system, [1.0])
    s0 = (pts.B @ free.y).reshape(-1, 2)
    # tau = sigma_n = 1/2 on the plane: the driving shear |tau| - mu |sigma_n| = (1 - mu) / 2
    for mu in (0.4, 1.5):
        d["crack"][0]["friction"] = mu
        sol = nc.solve(SolidScene.from_dict(d), crack_mesh=smesh)
        res = sol.contact
        assert res.active.all() and all(v < 1e-10 for v in sol.kkt.values()), sol.kkt
        chk = _coulomb_kkt(sol.system.K, sol.system.F, sol.system.contact, sol.G, res.points,
                           type(res)(**{**res.__dict__, "lam_t": res.lam_t / 1000.0}))
        # (the sticking points' slip is that of the iterated regularisation: 3e-11 of the scale at mu = 1.5)
        assert chk["cone"] < 1e-12 and chk["slip_law"] < 1e-10 and chk["stationarity"] < 1e-10, chk
        s = res.slip
        big = np.linalg.norm(s0, axis=1) > 0.3 * np.linalg.norm(s0, axis=1).max()
        ratio = np.sum(s[big] * s0[big], axis=1) / np.sum(s0[big] ** 2, axis=1)
        # the shear modes with the faces' friction term (ngcrack.solid.face_friction, consistent: the
        # traction fitted to the forces' work, the uniform shear's K subtracted): measured 0.592-0.609
        # (K_II) and 0.595-0.608 (K_III) of the frictionless values at mu = 0.4, -0.010-0.009 and
        # -0.001-0.007 at mu = 1.5 (the term before: 0.612-0.631, 0.628-0.635, 0.046-0.076, 0.082-0.093)
        target = max(1.0 - mu, 0.0)
        for name, tol in (("K_II", 0.08), ("K_III", 0.1)):
            k0, k = getattr(free.fronts[0], name), getattr(sol.fronts[0], name)
            strong = np.abs(k0) > 0.5 * np.abs(k0).max()
            assert np.all(np.abs(k[strong] / k0[strong] - target) < tol), (name, k[strong] / k0[strong])
        if mu < 1.0:
            # the slip where it is largest, over the frictionless one: measured 0.565-0.603 against
            # 1 - mu = 0.6 (tiny mesh, order 1)
            assert np.all(np.abs(ratio - (1 - mu)) < 0.05) and abs(ratio.mean() - (1 - mu)) < 0.02, ratio
        else:
            # mu >= tau / sigma_n: every point sticks, no slip left at them
            assert res.stick.all() and np.max(np.abs(s)) < 1e-12 * np.max(np.abs(s0))
