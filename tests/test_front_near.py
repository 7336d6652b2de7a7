"""The closed form of the front integral's curvature terms next to a curved front (ngcrack.solid.front_near)."""

import numpy as np

from ngcrack.solid import front_near
from ngcrack.solid.front_near import blend, near_matrix

E, NU = 1000.0, 0.3


def test_near_matrix_vanishes_on_a_straight_front_and_decouples_the_modes():
    assert not near_matrix(0.0, 0.2, E, NU).any()
    C = near_matrix(1.0, 0.2, E, NU)
    # the mode I field is even in the angle, mode II and III odd: no cross terms over the disc
    assert np.max(np.abs(C - np.diag(np.diag(C)))) < 1e-12 * np.max(np.abs(C))
    assert np.all(np.diag(C) < 0)


def test_near_matrix_grows_as_kappa_r0_next_to_the_front():
    """The curvature terms grow as 1/r: their disc's part is kappa r0 times a constant to leading order."""
    a, b = near_matrix(1.0, 0.01, E, NU) / 0.01, near_matrix(1.0, 0.02, E, NU) / 0.02
    assert np.allclose(np.diag(a), np.diag(b), rtol=0.01)
    assert np.allclose(np.diag(near_matrix(0.5, 0.02, E, NU)) / 0.01, np.diag(b), rtol=0.01)


def test_near_matrix_is_converged_in_its_own_grid(monkeypatch):
    C = near_matrix(1.0, 0.2, E, NU)
    monkeypatch.setattr(front_near, "DISC_RADIAL_POINTS", 2 * front_near.DISC_RADIAL_POINTS)
    monkeypatch.setattr(front_near, "DISC_ANGULAR_POINTS", 2 * front_near.DISC_ANGULAR_POINTS)
    assert np.allclose(near_matrix(1.0, 0.2, E, NU), C, rtol=1e-8, atol=1e-12 * np.max(np.abs(C)))


def test_blend_rises_from_zero_at_the_front_to_one_at_r0():
    r = np.linspace(0.0, 0.3, 31)
    w = blend(r, 0.2)
    assert w[0] == 0.0 and np.all(w[r >= 0.2] == 1.0) and np.all(np.diff(w) >= 0)
    assert np.all(blend(r, 0.0) == 1.0)
