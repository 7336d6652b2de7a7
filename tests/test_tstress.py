"""The T-stress by the interaction integral with the point-force auxiliary field (ngcrack.planar.tstress).

Without a mesh: the auxiliary field is an elastic field (its strain is the compliance of its
stress, it is in equilibrium, its faces are traction free), and the domain integral over a
polar grid picks out a uniform sigma_11 = T exactly while the Williams fields give zero.
On meshes: T = sigma_xx - sigma_yy at a crack along x under remote biaxial stress: adding
sigma_xx = s shifts T by s to round-off (a uniform sigma_xx leaves the faces free, so the
finite body's T moves by exactly s), and under sigma_yy = 1 alone the griffith plate's T is
its own converged -1.01102 (tdnns and bdm of order 2 on two meshes agree to 4e-6) to 1e-4,
1.1% from the infinite plate's -1, as its K_I is 0.94% above p sqrt(pi a). The handbook: an
edge crack in a half plane under tension has T = -0.526 sigma, the biaxiality ratio
beta = T sqrt(pi a) / K_I = -0.469 (Cardew, Goldthorpe, Howard and Kfouri 1985; Fett's
compendium), which the edge-cracked strip approaches as a/b -> 0 (-0.467 at a/b = 0.1);
the centre-cracked strip's T tends to -sigma (-1.006 at a/b = 0.1).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.planar.materials import compliance
from ngcrack.planar.tips import effective_modulus, kolosov, williams_dx1, williams_stress
from ngcrack.planar.tstress import (
    interaction_integrand,
    point_force_displacement,
    point_force_dx1,
    point_force_stress,
    t_stress,
)
from ngcrack.scenes import handbook

E, NU = 1000.0, 0.3
#: the griffith plate's T, converged (tdnns order 2 at maxh 1 and 0.5: -1.0110217, -1.0110256)
GRIFFITH_T = -1.01102
#: the edge crack in a half plane under tension: beta = T sqrt(pi a) / K_I (T = -0.526 sigma, K_I = 1.1215 sigma sqrt(pi a))
EDGE_BETA = -0.469


@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_the_auxiliary_field_is_elastic_and_traction_free(plane):
    A, mu, kappa = compliance(E, NU, plane), E / (2 * (1 + NU)), kolosov(NU, plane)
    rng = np.random.default_rng(0)
    h = 1e-6
    for r, th in zip(rng.uniform(0.2, 2.0, 8), rng.uniform(-3.0, 3.0, 8)):
        x, y = r * math.cos(th), r * math.sin(th)

        def u(x, y):
            return np.array(point_force_displacement(math.hypot(x, y), math.atan2(y, x), kappa, mu))

        def s(x, y):
            return np.array(point_force_stress(math.hypot(x, y), math.atan2(y, x)))

        gx, gy = (u(x + h, y) - u(x - h, y)) / (2 * h), (u(x, y + h) - u(x, y - h)) / (2 * h)
        assert np.allclose(gx, point_force_dx1(r, th, kappa, mu), rtol=1e-7, atol=0)
        s11, s22, s12 = s(x, y)
        eps = A.apply(np.array([[s11, s12], [s12, s22]]))
        assert np.allclose(eps, [[gx[0], 0.5 * (gy[0] + gx[1])], [0.5 * (gy[0] + gx[1]), gy[1]]], rtol=1e-6, atol=1e-12)
        ds_dx, ds_dy = (s(x + h, y) - s(x - h, y)) / (2 * h), (s(x, y + h) - s(x, y - h)) / (2 * h)
        assert abs(ds_dx[0] + ds_dy[2]) < 1e-6 * abs(s11) / r and abs(ds_dx[2] + ds_dy[1]) < 1e-6 * abs(s11) / r
    for th in (math.pi, -math.pi):  # the faces: sigma e2 = (sigma_12, sigma_22) = 0
        s11, s22, s12 = point_force_stress(1.0, th)
        assert abs(s22) < 1e-15 and abs(s12) < 1e-15 and s11 > 0


def test_the_domain_integral_picks_out_T_and_ignores_the_singular_fields():
    A, mu, kappa = compliance(E, NU, "strain"), E / (2 * (1 + NU)), kolosov(NU, "strain")
    e_prime = effective_modulus(E, NU, "strain")
    R = 1.0  # q = 1 for r <= R/2, linear to 0 at R: grad q = -2/R e_r on the annulus
    xr, wr = np.polynomial.legendre.leggauss(40)
    xt, wt = np.polynomial.legendre.leggauss(200)
    r, th = np.meshgrid(0.75 * R + 0.25 * R * xr, math.pi * xt, indexing="ij")
    w = (np.outer(0.25 * R * wr, math.pi * wt) * r).ravel()
    r, th = r.ravel(), th.ravel()
    gq = -2.0 / R * np.column_stack([np.cos(th), np.sin(th)])

    def I_T(sig, du1):
        val, _ = interaction_integrand(sig, du1, gq, r, th, A, kappa, mu)
        return float(w @ val)

    for T in (2.5, -0.7):
        sig = np.zeros((len(r), 2, 2))
        sig[:, 0, 0] = T
        assert t_stress(I_T(sig, A.apply(sig)[:, :, 0]), e_prime) == pytest.approx(T, rel=1e-12)
    for mode in (1, 2):
        s11, s22, s12 = williams_stress(r, th, mode)
        sig = np.stack([np.stack([s11, s12], -1), np.stack([s12, s22], -1)], -2)
        assert abs(t_stress(I_T(sig, np.column_stack(williams_dx1(r, th, mode, kappa, mu))), e_prime)) < 1e-12


def test_T_under_remote_biaxial_stress():
    g = nc.scenes.load("griffith")
    base = g.with_(boundary={**g.boundary, "right": {"type": "traction", "value": [0.0, 0.0]}})
    pipe = nc.Pipeline()
    T = {}
    for s in (0.0, 0.5, -2.0):  # sigma_xx = s on the right edge; one factorization for the three
        sol = pipe.run(base.with_(boundary={**g.boundary, "right": {"type": "traction", "value": [s, 0.0]}}))
        T[s] = sol.tips[0].T
        assert sol.tips[0].K_I == pytest.approx(1.78909, rel=2e-4)  # sigma_xx leaves K alone
    assert abs(T[0.0] / GRIFFITH_T - 1.0) < 1e-4
    assert 0.005 < T[0.0] / -1.0 - 1.0 < 0.02  # the finite plate, beside the infinite plate's T = -p
    for s in (0.5, -2.0):
        assert T[s] - T[0.0] == pytest.approx(s, abs=1e-7)


@pytest.mark.parametrize("a_over_b", [0.05, 0.1])
def test_edge_crack_biaxiality_ratio(a_over_b):
    sol = nc.solve(handbook.edge_cracked_strip(a_over_b), element="bdm")
    tip = sol.tips[0]
    beta = tip.T * math.sqrt(math.pi * a_over_b) / tip.K_I
    assert abs(beta / EDGE_BETA - 1.0) < 0.015, beta


def test_centre_crack_T_tends_to_minus_the_load():
    sol = nc.solve(handbook.centre_cracked_strip(0.1), element="bdm")
    for tip in sol.tips:
        assert tip.T == pytest.approx(-1.0, rel=0.01)
        assert tip.T < -1.0  # the finite strip: T/sigma grows in size with a/b
