"""Cracks crossing a STEP part's faces and the measures of a crack's part inside the body.

The examples examples/hole-through-crack.toml and examples/hole-corner-cracks.toml (a plate with a
hole written by benchmarks/hole_cracks.py): the parts inside against their closed forms (a quarter
disc's area and arc), and coarse solves against the handbook: the corner cracks against Newman and
Raju's equation for two corner cracks at a hole, the through crack against Bowie's plane value (which
the plate's thickness raises by a few percent at mid-thickness). A deep semicircular surface crack
(a/t = 0.8) against Newman and Raju's equation at its deepest point.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.solid.scene import SolidScene
from ngcrack.solid.surface import inside_arcs, inside_measures
from ngcrack.studies.newman_raju import STATED_ACCURACY, bowie_F, hole_corner_cracks_K

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
R, T, W, A = 1.0, 1.0, 12.0, 0.5  # the hole's radius, the plate's thickness and half-width, the cracks' size


@pytest.fixture(scope="module")
def corner():
    return nc.Scene.from_toml(EXAMPLES / "hole-corner-cracks.toml")


def test_the_corner_crack_is_a_quarter_disc_inside_the_part(corner):
    (phi0, phi1), = inside_arcs(corner.domain, corner.cracks[0])
    # from the top face to the bore (OCC classifies points within 1e-3 of a face as outside: 0.002 rad here)
    assert phi1 - phi0 == pytest.approx(0.5 * math.pi, abs=5e-3)
    diameter, area, front = inside_measures(corner.domain, corner.cracks[0])
    assert area == pytest.approx(0.25 * math.pi * A ** 2, rel=1e-6)  # OCC's area of the cut face
    # from 128 outline samples on a STEP part (the size guard's estimate): within a sample's spacing or two
    assert front == pytest.approx(0.5 * math.pi * A, rel=0.05)
    assert diameter == pytest.approx(math.sqrt(2) * A, rel=0.06)
    d = corner.to_dict()
    d.pop("mesh")
    assert SolidScene.from_dict(d).mesh_sizes()["front_h"] == pytest.approx(0.1 * diameter, rel=1e-12)
    assert 0.1 * diameter < 0.1 * corner.cracks[0].size  # the quarter's diameter, not the disc's


def test_a_surface_crack_measures_half_its_ellipse():
    s = nc.scenes.load("surface-crack")
    diameter, area, front = inside_measures(s.domain, s.cracks[0])
    assert area == pytest.approx(0.5 * math.pi * 0.6 * 1.0, rel=2e-3)
    full = float(np.sum(np.linalg.norm(np.diff(s.cracks[0].outline(4096), axis=0), axis=1)))
    assert front == pytest.approx(0.5 * full, rel=0.01) and diameter == pytest.approx(2.0, rel=1e-3)


def test_corner_cracks_at_a_hole_against_newman_raju(corner):
    sol = nc.solve(corner.with_(front_h=0.125, crack_h=0.25, maxh=3.0))
    assert len(sol.fronts) == 2 and sol.kkt["max_penetration"] < 1e-8
    # the summaries probe each crack's faces towards its own centre (the mean over both lies in the hole)
    for summary in sol.to_json_dict()["cracks"]:
        assert summary["area"] == pytest.approx(0.25 * math.pi * A ** 2, rel=1e-4) and summary["closed_fraction"] == 0
        assert 0 < summary["max_sliding"] < 0.1 * summary["max_opening"]
    for f in sol.fronts:
        phi = np.arctan2((T - f.points[:, 2]) / A, (np.abs(f.points[:, 1]) - R) / A)
        assert phi.min() == pytest.approx(0.0, abs=5e-3) and phi.max() == pytest.approx(0.5 * math.pi, abs=5e-3)
        ratio = f.K_I / hole_corner_cracks_K(1.0, A, A, T, R, W, phi)
        inner = (phi > 0.01) & (phi < 0.5 * math.pi - 0.01)  # off the surfaces
        # measured 1.02-1.08 at this coarse mesh (front_h = a/4), 1.04-1.06 at a/6 and 1.03-1.06 at a/9: about 5%
        # above their equation, at the edge of their stated accuracy
        assert inner.sum() >= 3 and np.all((ratio[inner] > 1.0) & (ratio[inner] < 1.0 + 2 * STATED_ACCURACY)), ratio


@pytest.mark.slow
def test_a_through_crack_at_a_hole_against_bowie():
    sol = nc.solve(nc.Scene.from_toml(EXAMPLES / "hole-through-crack.toml"))
    (f,) = sol.fronts
    mid = int(np.argmin(np.abs(f.points[:, 2] - 0.5 * T)))
    ratio = f.K_I[mid] / (math.sqrt(math.pi * A) * bowie_F(A / R))
    # measured 1.085 at the example's mesh and at front_h = 0.055: Bowie's plane value raised by the plate's
    # thickness (the hole's concentration and the crack's K at mid-thickness) and its finite width (1%)
    assert 1.0 < ratio < 1.12
