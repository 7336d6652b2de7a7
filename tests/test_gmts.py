"""The generalized maximum tangential stress criterion (growth.criteria.gmts_*), against closed forms.

Without a mesh: T = 0 is MTS; in pure mode I the straight path is the maximum while
T < 3 K_I / (8 sqrt(2 pi r_c)) and beyond it the kink is +-2 acos(c), c = (k + sqrt(k^2 + 8)) / 4,
k = 3 K_I / (8 sqrt(2 pi r_c) T); in mixed mode the angle is a stationary point and the global
maximum of the hoop stress at r_c. With a mesh: grow and `ngcrack grow` take gmts with r_c,
record T, and refuse a missing or misplaced r_c by name.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.shell.cli import main
from ngcrack.studies.growth.criteria import check_r_c, gmts_angle, gmts_hoop, gmts_keq, mts_angle, mts_keq

R_C = 0.01
A = math.sqrt(2.0 * math.pi * R_C)


@pytest.mark.parametrize("K_I, K_II", [(1.0, 0.0), (1.0, 0.3), (1.0, -0.7), (0.2, 1.0), (0.0, 1.0), (0.0, -1.0)])
def test_without_T_it_is_mts(K_I, K_II):
    assert gmts_angle(K_I, K_II, 0.0, R_C) == pytest.approx(mts_angle(K_I, K_II), abs=1e-9)
    assert gmts_keq(K_I, K_II, 0.0, R_C) == pytest.approx(mts_keq(K_I, K_II), rel=1e-12)


def test_mode_I_stays_straight_below_the_threshold_and_kinks_above():
    K_I = 2.0
    T_c = 3.0 * K_I / (8.0 * A)
    for T in (-5.0, 0.0, 0.5 * T_c, 0.99 * T_c):
        assert abs(gmts_angle(K_I, 0.0, T, R_C)) < 1e-12
        assert gmts_keq(K_I, 0.0, T, R_C) == pytest.approx(K_I, rel=1e-14)
    for T in (1.2 * T_c, 2.0 * T_c, 10.0 * T_c):
        k = 3.0 * K_I / (8.0 * A * T)
        expected = 2.0 * math.acos((k + math.sqrt(k * k + 8.0)) / 4.0)
        theta = gmts_angle(K_I, 0.0, T, R_C)
        assert theta == pytest.approx(expected, abs=1e-8)
        assert gmts_keq(K_I, 0.0, T, R_C) == pytest.approx(gmts_hoop(-expected, K_I, 0.0, T, R_C), rel=1e-12)
        assert gmts_keq(K_I, 0.0, T, R_C) > K_I


@pytest.mark.parametrize("K_I, K_II, T", [(1.0, 0.3, -8.0), (1.0, 0.3, 8.0), (1.0, -0.5, 3.0), (0.0, 1.0, -5.0),
                                          (0.0, 1.0, 5.0), (0.4, 1.0, 20.0)])
def test_mixed_mode_angle_is_the_global_maximum(K_I, K_II, T):
    theta = gmts_angle(K_I, K_II, T, R_C)
    h = 1e-5
    slope = (gmts_hoop(theta + h, K_I, K_II, T, R_C) - gmts_hoop(theta - h, K_I, K_II, T, R_C)) / (2 * h)
    assert abs(slope) < 1e-6
    grid = np.linspace(-math.pi + 1e-6, math.pi - 1e-6, 200001)
    best = max(gmts_hoop(t, K_I, K_II, T, R_C) for t in grid[::10])
    assert gmts_keq(K_I, K_II, T, R_C) >= best - 1e-12
    # K_II > 0 kinks clockwise, as MTS; a negative T holds the kink closer to the crack's line
    assert np.sign(theta) == -np.sign(K_II)
    if T < 0:
        assert abs(theta) < abs(mts_angle(K_I, K_II))


def test_r_c_is_checked_by_name():
    assert check_r_c(0.5, "gmts") == 0.5 and check_r_c(None, "mts") is None
    for bad in (None, 0.0, -1.0, math.inf, True, "1"):
        with pytest.raises(ValueError, match="^r_c = .*: criterion = 'gmts' needs the critical distance"):
            check_r_c(bad, "gmts")
    with pytest.raises(ValueError, match="^r_c = 0.1: only criterion = 'gmts'"):
        check_r_c(0.1, "pls")
    with pytest.raises(ValueError, match="r_c"):
        nc.grow(nc.scenes.load("three-point-bend"), da=0.1, steps=1, criterion="gmts")


def test_grow_with_gmts_records_T(tmp_path):
    """The bend specimen in mode I (T < 0 at a/W = 0.4): straight, at the MTS load factor."""
    scene = nc.scenes.load("three-point-bend")
    out = tmp_path / "g.json"
    code = main(["grow", "three-point-bend", "--da", "0.1", "--steps", "1", "--K-Ic", "2", "--criterion", "gmts",
                 "--r-c", "0.05", "--json", str(out)])
    assert code == 0
    d = json.loads(out.read_text())
    assert d["criterion"] == "gmts" and d["r_c"] == 0.05
    tip = d["steps"][0]["tips"][0]
    assert tip["T"] < 0 and abs(tip["kink_deg"]) < 0.1
    assert tip["K_eq"] == pytest.approx(tip["K_I"], rel=1e-3)  # sin^2(theta) T ~ 0 on a straight path
    assert d["steps"][0]["load_factor"] == pytest.approx(2.0 / tip["K_eq"], rel=1e-12)
    assert main(["grow", "three-point-bend", "--da", "0.1", "--steps", "1", "--criterion", "gmts", "--json",
                 str(tmp_path / "h.json")]) == 2
    assert not (tmp_path / "h.json").exists()
    assert scene.points  # the scene's supports are points
