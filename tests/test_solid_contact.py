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
