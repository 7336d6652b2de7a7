"""Crack-face pressure: the load term of every element, the tips' face term, the closed forms.

- Superposition, exact for a finite body: the Griffith plate under remote tension p is
  the uniform state (no jump) plus the crack pressurized by p with the outer edges free,
  so both give the same jumps and K_I to round-off, for every element family.
- Sneddon: a uniformly pressurized crack opens as 4 (1 - nu^2) p / E sqrt(a^2 - x^2),
  K_I = p sqrt(pi a): within 0.1% of the finite body's extrapolated answer, the closed
  form beside it.
- A crack pressurized on |x| < c only, under remote compression sigma: open on |x| < L,
  L = c / sin(pi sigma / (2 p)), closed beyond with K_I = 0; KKT at round-off.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.planar.scene import Scene, SceneError

E, NU = 1000.0, 0.3
E_PRIME = E / (1 - NU**2)
FAMILIES = ["tdnns", "bdm", "peers", "h1p1", "h1p2"]
COARSE = dict(maxh=2.0, tip_h=0.02, crack_h=0.1)


def half_plate(size: float, pressure, top: float = 0.0) -> Scene:
    """The right half of a 2 size x 2 size plate with a crack of half-length 1 along y = 0
    (its centre on the symmetry line x = 0, rollers there and on the bottom edge)."""
    boundary = {"bottom": {"type": "roller"}, "sym-upper": {"type": "roller"}, "sym-lower": {"type": "roller"}}
    if top:
        boundary["top"] = {"type": "traction", "value": [0.0, top]}
    return Scene(name="pressurized", polygon=[[0, -size], [size, -size], [size, size], [0, size], [0, 0]],
                 labels=["bottom", "right", "top", "sym-upper", "sym-lower"],
                 cracks=[{"points": [[0, 0], [1, 0]], "pressure": pressure}],
                 material={"E": E, "nu": NU}, boundary=boundary)


@pytest.mark.parametrize("element", FAMILIES)
def test_superposition_with_remote_tension(element):
    griffith = nc.scenes.load("griffith")
    pressurized = griffith.with_(boundary={**griffith.boundary, "top": {"type": "traction", "value": [0.0, 0.0]}},
                                 pressure=1.0)
    a = nc.solve(griffith, element=element, **COARSE)
    b = nc.solve(pressurized, element=element, **COARSE)
    ja, jb = a.profiles[0].normal_jump, b.profiles[0].normal_jump
    assert np.max(np.abs(ja - jb)) <= 1e-9 * np.max(ja)
    assert abs(a.tips[0].K_I - b.tips[0].K_I) <= 1e-8 * a.tips[0].K_I
    # the faces carry the pressure, and the crack is open everywhere
    assert np.allclose(b.profiles[0].normal_stress, -1.0, atol=1e-9)
    assert set(b.profiles[0].state) == {"open"}
    assert max(b.kkt_sampled.values()) < 1e-10
    # the error estimate takes the pressure as load data: the same stress error, the same estimate
    assert abs(b.error_estimate.energy / a.error_estimate.energy - 1) < 1e-3


def test_zero_pressure_is_the_unloaded_answer():
    griffith = nc.scenes.load("griffith")
    for element in ("tdnns", "h1p1"):
        a = nc.solve(griffith, element=element, **COARSE)
        b = nc.solve(griffith.with_(pressure=0.0), element=element, **COARSE)
        assert np.array_equal(a.profiles[0].normal_jump, b.profiles[0].normal_jump)
        assert np.array_equal(a.profiles[0].normal_stress, b.profiles[0].normal_stress)
        assert (a.tips[0].K_I, a.tips[0].G) == (b.tips[0].K_I, b.tips[0].G)


def _sneddon(tip_h):
    sol = nc.solve(half_plate(40.0, 1.0), element="tdnns", maxh=8.0, tip_h=tip_h, crack_h=2.5 * tip_h, grading=0.2)
    prof = sol.profiles[0]
    c = sol.crack_mesh.cracks[0]
    volume = float(np.sum(prof.normal_jump * c.length))  # half the crack's area
    return np.array([sol.tips[0].K_I, prof.normal_jump[0] / math.sqrt(1 - prof.s[0] ** 2), volume])


def test_sneddon_within_a_tenth_of_a_percent():
    coarse, fine = _sneddon(0.008), _sneddon(0.004)
    converged = 2 * fine - coarse  # the opening and the volume converge as h (measured), K_I faster
    assert np.all(np.abs(fine / converged - 1) < 1e-3), fine / converged
    exact = np.array([math.sqrt(math.pi), 4 / E_PRIME, math.pi / E_PRIME])
    # the 80a x 80a body's own effect: the closed form within 0.2%
    assert np.all(np.abs(converged / exact - 1) < 2e-3), converged / exact


def test_partial_pressure_under_compression():
    c, p, sigma = 0.3, 1.0, 1.0 / 3.0
    L_exact = c / math.sin(math.pi * sigma / (2 * p))  # 0.6
    table = [[0, p], [c, p], [c, 0], [1, 0]]
    sol = nc.solve(half_plate(40.0, table, top=-sigma), element="tdnns", maxh=8.0, tip_h=0.01, crack_h=0.01,
                   grading=0.2)
    prof = sol.profiles[0]
    w = prof.normal_jump
    i = np.flatnonzero(w > 1e-6 * w.max())[-1]
    # the opening closes as (L - x)^(3/2): L from the last two open samples
    r = (w[i - 1] / w[i]) ** (2 / 3)
    L = (r * prof.s[i] - prof.s[i - 1]) / (r - 1)
    assert abs(L / L_exact - 1) < 0.02
    assert np.all(prof.state[prof.s > 1.05 * L_exact] != "open")
    assert abs(sol.tips[0].K_I) < 1e-3 * p * math.sqrt(math.pi)
    assert max(sol.kkt.values()) < 1e-10


def test_callable_and_table_agree():
    def linear(s):
        return 1.0 + s

    a = nc.solve(half_plate(10.0, ((0.0, 1.0), (1.0, 2.0))), element="bdm", maxh=2.0, tip_h=0.05, crack_h=0.1)
    b = nc.solve(half_plate(10.0, linear), element="bdm", maxh=2.0, tip_h=0.05, crack_h=0.1)
    assert np.allclose(a.profiles[0].normal_jump, b.profiles[0].normal_jump, rtol=1e-10, atol=0)
    assert np.allclose(b.profiles[0].face_pressure, 1.0 + b.profiles[0].s)


@pytest.mark.parametrize("value, words", [
    ("high", "crack[0].pressure"),
    ([[0, 1], [0.5]], "crack[0].pressure[1]"),
    ([[0.5, 1], [0.2, 1]], "non-decreasing"),
    ([[-1, 1], [1, 1]], "s must be >= 0"),
    (float("nan"), "crack[0].pressure"),
    (lambda s: 1 / 0, "the callable failed"),
    (lambda s: "x", "the callable returned"),
    (1e200, "out of range"),
])
def test_bad_pressure_refused_by_name(value, words):
    with pytest.raises(SceneError, match=words.replace("[", r"\[").replace("]", r"\]")):
        half_plate(10.0, value)


def test_pressure_round_trips_through_toml():
    scene = half_plate(10.0, ((0.0, 1.0), (0.5, 2.0)))
    again = Scene.from_toml_string(scene.to_toml_string())
    assert again.cracks[0].pressure == ((0.0, 1.0), (0.5, 2.0))
    assert Scene.from_toml_string(half_plate(10.0, 2.5).to_toml_string()).cracks[0].pressure == 2.5
    with pytest.raises(SceneError, match="callable cannot be written"):
        half_plate(10.0, lambda s: 1.0).to_toml_string()


def test_explorer_pressure_control():
    model = nc.Explorer("griffith", "tdnns", maxh=2.0, solve_options=dict(tip_h=0.02, crack_h=0.1))
    K_tension = model.solution.tips[0].K_I
    model.update(pressure=1.0)  # the remote tension and the pressure add up
    assert abs(model.solution.tips[0].K_I / K_tension - 2) < 1e-8
    factorized = model.counts["factorize"]
    model.update(load=0.0)  # the pressure alone: Griffith's answer, one more solve on the same factorization
    assert abs(model.solution.tips[0].K_I / K_tension - 1) < 1e-8
    assert model.counts["factorize"] == factorized
    model.update(pressure=1e9)
    assert model.error is not None and "pressure" in model.error and model.state["pressure"] == 1.0


def test_pressure_lowers_the_friction_of_a_closed_crack():
    """The inclined crack under compression with Coulomb friction: a fluid pressure p_f < |sigma_n|
    keeps it closed and lowers the normal traction to sigma_n + p_f, so it slips with
    K_II = (|tau| - mu |sigma_n + p_f|) sqrt(pi a)."""
    scene = nc.scenes.load("inclined-compression").with_(friction=0.3, pressure=0.5)
    sol = nc.solve(scene, maxh=2.0, tip_h=0.01, crack_h=0.05)
    tau, sigma_n = math.sin(math.radians(30)) * math.cos(math.radians(30)), 0.75
    exact = (tau - 0.3 * (sigma_n - 0.5)) * math.sqrt(math.pi)
    assert all(abs(abs(t.K_II) / exact - 1) < 0.01 for t in sol.tips)
    assert set(sol.profiles[0].state) == {"slip"}
    assert max(sol.kkt.values()) < 1e-12


def test_growth_keeps_the_pressure():
    """A pressurized crack grown by nc.grow keeps its pressure: at the grown length a + da,
    K_I = p sqrt(pi (a + da)) (the load factor rescales the pressure with the other loads)."""
    res = nc.grow(half_plate(10.0, 1.0), da=0.1, steps=1, K_Ic=1.0, criterion="mts", frames=False,
                  maxh=2.0, tip_h=0.02, crack_h=0.05)
    assert res.scenes[1].cracks[0].pressure == 1.0
    K = res.table.query("step == 1")["K_I"].iloc[0]
    assert abs(K / math.sqrt(math.pi * 1.1) - 1) < 0.02
