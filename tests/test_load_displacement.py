"""The load-displacement record of crack growth, held against Irwin and Kies.

A crack grows under the force P when G = P^2 / 2 dC/da, C = delta / P the compliance
(unit thickness). The single-edge-notched beam in three-point bending grows straight up
from a/W = 0.4; every step records the force P at which it grows and its load-point
displacement delta. Between steps n and n + 2 (Simpson's rule, exact to da^4):
C(a_{n+2}) - C(a_n) = 2 int G / P^2 da, with G = (K_I^2 + K_II^2) / E' from the interaction
integral at the step's load. Measured (tdnns, maxh 0.2, tip_h 0.01, da = 0.1 = W / 20): below
0.1% on both pairs of steps; the trapezoidal rule, second order, is 0.6-1.1% off on the same steps.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.planar.tips import effective_modulus

DA = 0.1


@pytest.fixture(scope="module")
def bend():
    scene = nc.scenes.load("three-point-bend")
    return nc.grow(scene, da=DA, steps=2, K_Ic=2.0, criterion="mts", element="tdnns", maxh=0.2, tip_h=0.01,
                   frames=False)


def test_irwin_kies_along_the_path(bend):
    df = bend.table
    assert len(df) == 3 and list(df["step"]) == [0, 1, 2]
    mat = bend.scene.material
    e_prime = effective_modulus(mat.E, mat.nu, mat.plane)
    lam = df["load_factor"].to_numpy()
    G = lam**2 * (df["K_I"].to_numpy() ** 2 + df["K_II"].to_numpy() ** 2) / e_prime  # at the step's load
    assert np.allclose(G, 2.0**2 / e_prime, rtol=1e-9)  # every step grows at G = K_Ic^2 / E'
    P, delta = df["force"].to_numpy(), df["displacement"].to_numpy()
    assert np.allclose(P, lam * 1.0) and np.all(np.diff(P) < 0)  # the scene's force is 1; P falls as a grows
    C = delta / P
    assert np.allclose(C, df["compliance"], rtol=1e-12) and np.all(np.diff(C) > 0)
    a = df["y"].to_numpy()
    assert np.allclose(np.diff(a), DA, rtol=1e-6)  # straight up
    simpson = 2.0 * DA / 3.0 * (G[0] / P[0] ** 2 + 4.0 * G[1] / P[1] ** 2 + G[2] / P[2] ** 2)
    assert abs(simpson / (C[2] - C[0]) - 1.0) < 0.01, (simpson, C[2] - C[0])


def test_forces_and_displacements_in_the_json_steps(bend):
    steps = json.loads(json.dumps(bend.to_json_dict()))["steps"]
    for s in steps:
        F = s["force"]
        assert set(F) == {"support-left", "support-right", "load"}
        lam = s["load_factor"]
        assert F["load"] == pytest.approx([0.0, -lam], abs=1e-12)
        total = np.sum([F[k] for k in F], axis=0)
        assert np.abs(total).max() < 1e-9 * lam  # the supports' reactions balance the load
        u = s["displacement"]
        assert abs(u["support-left"][0]) < 1e-12 and abs(u["support-left"][1]) < 1e-12
        assert -u["load"][1] == pytest.approx(bend.table["displacement"][s["step"]], rel=1e-12)


def test_the_p_delta_curve_is_drawn(bend, tmp_path):
    fig = bend.plot(tmp_path / "pd.png", curve="P-delta")
    assert (tmp_path / "pd.png").stat().st_size > 0
    line = fig.axes[0].lines[1]
    assert np.allclose(line.get_xdata(), bend.table["displacement"]) and np.allclose(line.get_ydata(), bend.table["force"])
    with pytest.raises(ValueError, match="curve = 'x': allowed values are load-factor, P-delta"):
        bend.plot(curve="x")
