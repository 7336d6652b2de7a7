"""Curve cracks crossing the body's faces: the scene's checks, the front's arc and measures, the grown curve
completed beyond the faces, K along the front against the ellipse's, and growth against the ellipse fit.

Every figure fails on a wrong answer: a curve through points of the built-in `surface-crack` ellipse has its
front where the ellipse's is (its depth and half-length to 1e-4, its front's length), the same K along the
front within the spread of two meshes of the same ellipse, a uniform advance grows a semicircle into the
semicircle of the grown radius (and a quarter circle on a corner) whose front ends where the advanced ends
do, and a non-uniform advance leaves a front without kinks (its turning measured).
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.errors import InputError
from ngcrack.core.fields import SceneError
from ngcrack.solid.curve import curve_point
from ngcrack.solid.scene import SolidScene
from ngcrack.solid.surface import inside_arcs
from ngcrack.studies.growth.surface3d import (
    check_surface_growable,
    depth_and_length,
    ellipse_arc,
    grown_surface_crack,
    is_surface_crack,
)
from ngcrack.studies.growth.surface_curve import curve_of_ellipse, front_points, symmetric_interpolant

A, C, T = 0.6, 1.0, 1.5  # the built-in scene's depth, half-length and plate thickness


def plate(crack: dict, **mesh) -> dict:
    d = copy.deepcopy(nc.scenes.load("surface-crack").to_dict())
    d["crack"] = [crack]
    if mesh:
        d["mesh"] = mesh
    return d


def ellipse(center=(0.0, 0.0, T), axes=(C, A)) -> dict:
    return {"shape": "ellipse", "center": list(center), "normal": [0.0, 1.0, 0.0], "semi_axes": list(axes),
            "major_axis": [1.0, 0.0, 0.0]}


def as_curve(crack: dict, n: int = 48) -> dict:
    return curve_of_ellipse(SolidScene.from_dict(plate(crack)).cracks[0], n)


def kink(scene) -> float:
    """The largest jump of the front's turning: at 257 points equally spaced in arc length, the turning between
    neighbouring chords less the mean of its neighbours' turnings, over the median turning (0.0005-0.016 on the
    curves through ellipses here; a corner in the front is a spike of order 1)."""
    p = front_points(scene.domain, scene.cracks[0], 257)
    d = np.diff(p, axis=0)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    t = np.arccos(np.clip(np.sum(d[1:] * d[:-1], axis=1), -1.0, 1.0))
    around = 0.5 * (np.r_[t[1], t[:-1]] + np.r_[t[1:], t[-2]])
    return float(np.max(np.abs(t - around)) / np.median(t))


# ------------------------------------------------------------------------------ scene and front
def test_a_curve_through_the_ellipse_has_the_ellipses_front():
    s = SolidScene.from_dict(plate(as_curve(ellipse())))
    crack = s.cracks[0]
    assert is_surface_crack(s.domain, crack)
    (phi0, phi1), = inside_arcs(s.domain, crack, curve_point(crack))
    ends = curve_point(crack)(np.array([phi0, phi1]))
    assert np.allclose(ends[:, 2], T, atol=1e-9) and np.allclose(np.abs(ends[:, 0]), C, atol=1e-5)
    assert depth_and_length(s.domain, crack) == pytest.approx((A, C), abs=1e-4)
    e = SolidScene.from_dict(plate(ellipse())).cracks[0]
    length = ellipse_arc(e, np.linspace(0.0, math.pi, 9))[-1]
    assert ellipse_arc(crack, np.linspace(phi0, phi1, 9))[-1] == pytest.approx(length, rel=1e-4)
    check_surface_growable(s.domain, 0, crack)


@pytest.mark.parametrize("center, message", [
    ((0.0, 0.0, 0.95), "crosses face zmax by only 0.05"),
    ((0.0, 0.0, 2.2), "lies wholly outside"),
])
def test_a_curve_crossing_a_face_is_checked_as_an_ellipse_is(center, message):
    with pytest.raises(SceneError, match=message):
        SolidScene.from_dict(plate(as_curve(ellipse(center))))


def test_a_curve_leaving_a_sliver_or_crossing_a_held_face_is_refused():
    with pytest.raises(SceneError, match=r"sliver of body 0\.05 thick.*face zmin"):
        SolidScene.from_dict(plate(as_curve(ellipse(axes=(1.0, 1.45)))))
    d = plate(as_curve(ellipse()))
    d["boundary"]["zmax"] = {"type": "roller"}
    with pytest.raises(SceneError, match="crosses face zmax, which carries a roller condition"):
        SolidScene.from_dict(d)


def test_a_curve_ending_on_a_cylinders_side_does_not_grow():
    d = {"name": "bar", "domain": {"cylinder": {"center": [0.0, 0.0, 0.0], "axis": [0.0, 0.0, 1.0], "radius": 1.0,
                                                "height": 4.0}},
         "crack": [{"shape": "disc", "center": [1.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0], "radius": 0.4}],
         "material": {"E": 1000.0, "nu": 0.3},
         "boundary": {"bottom": {"type": "clamped"}, "top": {"type": "traction", "value": [0.0, 0.0, 1.0]}}}
    disc = SolidScene.from_dict(d).cracks[0]
    d["crack"] = [curve_of_ellipse(disc)]
    s = SolidScene.from_dict(d)
    with pytest.raises(InputError, match="ends on face side, which is not planar"):
        check_surface_growable(s.domain, 0, s.cracks[0])


# ------------------------------------------------------------------------------ the grown curve
@pytest.mark.parametrize("center, axes, grown", [
    ((0.0, 0.0, T), (0.5, 0.5), (0.6, 0.6)),  # a semicircle on the face zmax
    ((-5.0, 0.0, T), (0.8, 0.5), (0.6, 0.9)),  # a quarter ellipse on the edge of xmin and zmax: (a, c)
])
def test_a_uniform_advance_grows_the_curve_by_it_and_the_front_ends_where_the_advanced_ends_do(center, axes, grown):
    s = SolidScene.from_dict(plate(as_curve(ellipse(center, axes))))
    (phi0, phi1), = inside_arcs(s.domain, s.cracks[0], curve_point(s.cracks[0]))
    angles = np.linspace(phi0, phi1, 11)
    d, lead = grown_surface_crack(s.domain, s.cracks[0], angles, np.full(11, 0.1), 5)
    assert lead == pytest.approx(0.1)
    new = SolidScene.from_dict({**plate(ellipse()), "crack": [d]})
    assert depth_and_length(new.domain, new.cracks[0]) == pytest.approx(grown, abs=1e-4)
    p = front_points(new.domain, new.cracks[0], 5)
    q = np.asarray(d["points"])
    assert np.min(np.linalg.norm(q - p[0], axis=1)) < 1e-9 and np.min(np.linalg.norm(q - p[-1], axis=1)) < 1e-9
    assert kink(new) < 0.02


def test_a_non_uniform_advance_leaves_a_front_without_kinks():
    """An advance falling from the ends (0.1) to the deepest point (0.06) over seven stations: the grown front has
    no kink (measured 0.0016 on a semicircle, 0.0074 on a quarter ellipse at a corner; the advance interpolated
    linearly between the stations put kinks of 0.67 and 2.7 there)."""
    s = SolidScene.from_dict(plate(as_curve(ellipse(axes=(0.5, 0.5)))))
    (phi0, phi1), = inside_arcs(s.domain, s.cracks[0], curve_point(s.cracks[0]))
    angles = np.linspace(phi0, phi1, 7)
    advance = 0.1 - 0.04 * np.sin(np.linspace(0.0, math.pi, 7)) ** 2
    d, _ = grown_surface_crack(s.domain, s.cracks[0], angles, advance, 0)
    new = SolidScene.from_dict({**plate(ellipse()), "crack": [d]})
    assert kink(new) < 0.02
    a, c = depth_and_length(new.domain, new.cracks[0])
    assert a == pytest.approx(0.56, abs=2e-3) and c == pytest.approx(0.6, abs=2e-3)


def test_the_advance_is_even_about_the_ends():
    s = np.array([0.0, 0.3, 0.7, 1.2, 1.5])
    f = symmetric_interpolant(s, np.array([1.0, 0.9, 0.7, 0.95, 1.1]))
    assert f(s) == pytest.approx([1.0, 0.9, 0.7, 0.95, 1.1])
    assert abs(f(0.0, 1)) < 1e-12 and abs(f(1.5, 1)) < 1e-12


# ------------------------------------------------------------------------------ K along the front
def test_a_curve_through_the_ellipse_gives_the_ellipses_K():
    """On the built-in scene's mesh sizes, K_I along the front of a curve through 48 points of the ellipse is within
    3% of the ellipse's at every point and 1.2% on average (measured 1.8% and 0.67%; the same ellipse moved by 1e-3,
    another mesh, differs from it by 1.4% and 0.56%, curves through 24 and 32 points by 1.2-1.9% and 0.7-0.9%)."""
    e = nc.solve(SolidScene.from_dict(plate(ellipse()))).fronts[0]
    c = nc.solve(SolidScene.from_dict(plate(as_curve(ellipse())))).fronts[0]
    assert len(c.K_I) == len(e.K_I) and np.allclose(c.points[[0, -1], 2], T, atol=1e-9)
    assert np.allclose(c.points, e.points, atol=2e-4)  # the same stations along the same front
    dev = np.abs(c.K_I / e.K_I - 1)
    assert dev.max() < 0.03 and dev.mean() < 0.012, dev


def test_the_example_is_a_semicircular_surface_curve():
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "examples" / "surface-curve.toml").read_text()
    s = nc.Scene.from_toml_string(text)
    assert s.cracks[0].shape == "curve" and is_surface_crack(s.domain, s.cracks[0])
    assert depth_and_length(s.domain, s.cracks[0]) == pytest.approx((0.5, 0.5), abs=1e-4)
    check_surface_growable(s.domain, 0, s.cracks[0])


# ------------------------------------------------------------------------------ growth
def test_one_paris_step_of_the_example_grows_the_curve_by_its_advance(tmp_path, capsys):
    """`ngcrack grow` on the example (a semicircle as a curve, front_h 0.15): one Paris step grows a curve whose depth
    is the semicircle's plus the deepest point's advance and whose half-length is its plus the surface points'
    (the front passes through the advanced points), its front in the crack's plane, its ends on the face, no kink."""
    import json
    from pathlib import Path

    from ngcrack.shell.cli import main

    path = Path(__file__).resolve().parents[1] / "examples" / "surface-curve.toml"
    out = tmp_path / "g.json"
    code = main(["grow", str(path), "--da", "0.1", "--steps", "1", "--paris", "1e-3", "3", "--json", str(out)])
    assert code == 0, capsys.readouterr().err
    data = json.loads(out.read_text())
    assert data["stopped"].startswith("steps") and data["cracks"][0]["shape"] == "curve"
    f0, f1 = (s["fronts"][0] for s in data["steps"])
    adv = np.asarray(f0["advance"])
    mid = len(adv) // 2
    assert f1["depth"] == pytest.approx(0.5 + adv[mid], abs=2e-3)
    assert f1["half_length"] == pytest.approx(0.5 + 0.5 * (adv[0] + adv[-1]), abs=1e-3)
    assert max(adv) == pytest.approx(0.1)
    p = np.asarray(f1["points"])
    assert np.max(np.abs(p[:, 1])) < 1e-9 and np.allclose(p[[0, -1], 2], T, atol=1e-9)
    grown = nc.Scene.from_dict({**nc.Scene.from_toml_string(path.read_text()).to_dict(), "crack": data["cracks"]})
    assert kink(grown) < 0.02


@pytest.mark.slow
def test_a_semicircle_grown_as_a_curve_follows_the_ellipse_fit():
    """A semicircular crack (a = 0.5, front_h 0.15, m = 3) grown three Paris steps of 0.1 as a curve and as the
    fitted ellipse: a within 3.5% and c within 2% at every step (measured 2.9% at the first step, where the fit
    pulls the deepest point to the front's mean shape, then under 1%; c 0.3-1.5%), the cycles within 10% (the
    curve's leading point advances by da, the fitted ellipse's by what the fit gives it: 2-9% more), the curve's
    front without kinks at every step (about 50 s)."""
    d = plate(ellipse(axes=(0.5, 0.5)), front_h=0.15, crack_h=0.3, maxh=1.5)
    runs = [nc.grow(SolidScene.from_dict(d), da=0.1, steps=3, paris=(1e-3, 3.0))]
    runs.append(nc.grow(SolidScene.from_dict({**d, "crack": [as_curve(d["crack"][0])]}), da=0.1, steps=3,
                        paris=(1e-3, 3.0)))
    (ac_e, ac_c), (N_e, N_c) = (r.depth_and_length() for r in runs), (r.cycles() for r in runs)
    assert len(ac_c) == len(ac_e) == 4, runs[1].stopped
    assert np.max(np.abs(ac_c[:, 0] / ac_e[:, 0] - 1)) < 0.035 and np.max(np.abs(ac_c[:, 1] / ac_e[:, 1] - 1)) < 0.02
    assert np.max(np.abs(N_c[1:] / N_e[1:] - 1)) < 0.10
    assert all(kink(s) < 0.02 for s in runs[1].scenes)
