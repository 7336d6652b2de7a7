"""The open / stick / slip state of every crack sample agrees with the numbers of that sample.

A sample is open only where its normal jump is positive beyond round-off (CLOSED_RTOL
of the crack's largest jump) and its normal stress is zero within round-off (CLOSED_RTOL
of the largest |sigma| at the crack's samples), for every element:
- a closed shear-compression case (a 40 x 40 m plate, E = 25 GPa, a crack of half-length
  2 m at 60 degrees under 100 MPa of compression): tdnns used to call the sample next to
  a tip open while it reported -12.3 MPa of normal stress; every sample is closed now;
- the Griffith crack under tension: open everywhere (no sample closed by round-off);
- paper example 1, partly open and partly closed: the open samples carry no stress
  (bdm and tdnns used to call samples pressed by up to 0.3% of the stress scale open).
The state follows the profile's numbers when its tractions are replaced.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.constraints import CLOSED_RTOL
from ngcrack.planar.post import profile_states

ANGLE, HALF_LENGTH, SIDE = 60.0, 2.0, 40.0


def shear_compression() -> nc.Scene:
    t = math.radians(ANGLE)
    dx, dy = HALF_LENGTH * math.cos(t), HALF_LENGTH * math.sin(t)
    h = SIDE / 2
    return nc.Scene.from_toml_string(f"""
name = "shear-compression"
[domain]
polygon = [[{-h}, {-h}], [{h}, {-h}], [{h}, {h}], [{-h}, {h}]]
labels = ["bottom", "right", "top", "left"]
[[crack]]
points = [[{-dx}, {-dy}], [{dx}, {dy}]]
[material]
E = 25e9
nu = 0.25
plane = "strain"
[boundary.bottom]
type = "roller"
[boundary.left]
type = "roller"
[boundary.top]
type = "traction"
value = [0.0, -100e6]
""")


def _check_agreement(sol) -> tuple[int, int]:
    """Every sample's state against its numbers; returns (open, closed) counts."""
    n_open = n_closed = 0
    for p in sol.profiles:
        W = np.max(np.hypot(p.normal_jump, p.tangential_jump))
        assert p.stress_scale > 0
        is_open = p.state == "open"
        separate = p.normal_jump > CLOSED_RTOL * W
        free = np.abs(p.normal_stress) <= CLOSED_RTOL * p.stress_scale
        assert np.all(separate[is_open] & free[is_open]), (sol.element, p.normal_jump[is_open], p.normal_stress[is_open])
        # a closed sample: its faces touch or are pressed together
        assert np.all(~separate[~is_open] | (p.normal_stress[~is_open] < -CLOSED_RTOL * p.stress_scale))
        assert set(p.state) <= {"open", "slip"}  # frictionless
        n_open, n_closed = n_open + int(is_open.sum()), n_closed + int((~is_open).sum())
    return n_open, n_closed


@pytest.mark.parametrize("element", nc.ELEMENTS)
def test_a_closed_crack_under_shear_and_compression_is_closed_everywhere(element):
    sol = nc.solve(shear_compression(), element=element, maxh=2.0, tip_h=0.1, crack_h=0.25)
    n_open, n_closed = _check_agreement(sol)
    assert n_open == 0 and n_closed == len(sol.profiles[0].s) == 18
    p = sol.profiles[0]
    assert np.all(p.normal_stress < -1e6)  # pressed everywhere, by at least 1 MPa of the 100
    assert np.max(np.abs(p.tangential_jump)) > 1e-3  # and sliding, by millimetres


@pytest.mark.parametrize("element", nc.ELEMENTS)
def test_an_open_crack_is_open_everywhere_and_a_partly_closed_one_agrees(element):
    n_open, n_closed = _check_agreement(nc.solve(nc.scenes.load("griffith"), element=element))
    assert n_closed == 0 and n_open == 36
    n_open, n_closed = _check_agreement(nc.solve(nc.scenes.load("paper-1"), element=element))
    assert n_open + n_closed == 40
    if element != "h1p1":  # h1p1 closes the whole crack of paper-1
        assert n_open >= 20 and n_closed >= 10


def test_states_follow_the_numbers_when_the_tractions_are_replaced():
    sol = nc.solve(nc.scenes.load("griffith"), element="bdm", maxh=2.0)
    p = sol.profiles[0]
    assert (p.state == "open").all()
    pressed = dataclasses.replace(p, normal_stress=np.full(len(p.s), -1e-3 * p.stress_scale))
    assert (pressed.state == "slip").all()
    rough = dataclasses.replace(pressed, friction=0.5, tangential_jump=np.zeros(len(p.s)))
    assert (rough.state == "stick").all()
    # round-off in the stress keeps a sample open, a compression beyond it closes it
    jn, jt = np.array([1.0, 1.0, 1.0, 0.0]), np.zeros(4)
    sn = np.array([-1e-12, 1e-12, -1e-6, 0.0])
    assert list(profile_states(jn, jt, sn, 0.0, stress_scale=1.0)) == ["open", "open", "slip", "slip"]
    assert p.to_dict().keys() == {"s", "x", "y", "normal_jump", "tangential_jump", "normal_stress", "shear_stress",
                                  "state"}
