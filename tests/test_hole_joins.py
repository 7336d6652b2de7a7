"""Cracks that end on a hole's edge: the scene accepts them (that end is no tip, like an edge
crack's on the outer boundary), the mesher puts the end on the hole's boundary, the parts
follow the cuts, a radial crack at a hole has Bowie's K, and a growing tip that reaches a hole
joins it (the body cut through where the cracks separate it)."""

import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.planar.geometry import make_mesh
from ngcrack.planar.scene import Scene, SceneError

PLATE = nc.scenes.load("hole-crack")  # 20 x 20, hole of radius 2 at (10, 10); rollers bottom and left, top pulled


def test_a_crack_may_start_on_a_hole_circle_or_polygon():
    s = PLATE.with_(cracks=[nc.Crack(points=((12.0, 10.0), (14.0, 10.0)))])
    assert s.tip_points() == [(0, (14.0, 10.0))] and s.hole_joins() == [(0, 0, 0)]
    assert s.crack_end_on_boundary(0) == (True, False) and s.through_cracks() == []
    assert len(s.parts()) == 1 and Scene.from_toml_string(s.to_toml_string()) == s
    off = (10 + 2 * math.cos(0.3), 10 + 2 * math.sin(0.3))  # on the circle, no vertex of its polygon
    t = PLATE.with_(cracks=[nc.Crack(points=(off, (15.0, 12.0)))])
    assert t.hole_joins() == [(0, 0, 0)] and [lab for lab in nc.tips.tip_labels(t)] == ["0,last"]
    square = PLATE.with_(holes=[{"polygon": [[8, 8], [12, 8], [12, 12], [8, 12]], "labels": ["h"] * 4}],
                         cracks=[nc.Crack(points=((12.0, 10.5), (14.0, 10.5)))])
    assert square.hole_joins() == [(0, 0, 0)] and square.tip_points() == [(0, (14.0, 10.5))]
    # a crack end near a hole's edge but not on it is still refused: the mesher cannot resolve the gap
    with pytest.raises(SceneError, match=r"crack\[0\]: the body is only 0\.01 wide"):
        PLATE.with_(cracks=[nc.Crack(points=((12.01, 10.0), (14.0, 10.0)))])
    for scene, start in ((t, off), (square, (12.0, 10.5))):
        cm = make_mesh(scene, maxh=2.0)
        va = cm.cracks[0].va[0]
        assert np.allclose(cm.points[va], start, atol=1e-12)  # the crack's end is the hole boundary's vertex
        assert va not in cm.tip_vertices and len(cm.tip_vertices) == 1


def test_cracks_through_a_hole_cut_the_body_in_two():
    """A crack from each side of the hole to the outer edges: two parts of equal area (the half
    plate less the half hole each), each with its crack faces; on rollers the upper one is free."""
    cracks = [nc.Crack(points=((12.0, 10.0), (20.0, 10.0))), nc.Crack(points=((0.0, 10.0), (8.0, 10.0)))]
    with pytest.raises(SceneError, match=r"the part of the body containing point \(.*\) is held only by roller"):
        PLATE.with_(cracks=cracks)
    s = PLATE.with_(cracks=cracks, boundary={"bottom": {"type": "clamped"}, "top": {"type": "clamped"}})
    parts = s.parts()
    assert len(parts) == 2
    half = (400.0 - s.holes[0].area) / 2
    assert [p.area for p in parts] == pytest.approx([half, half], rel=1e-4)  # the circle as its 256-gon
    assert sorted(p.labels for p in parts) == [("hole", "left", "bottom", "right"), ("hole", "right", "top", "left")]
    assert all(len(p.crack_faces) == 2 and p.cracks == (0, 1) for p in parts)
    # one crack alone does not cut the plate: the hole makes it a ring, one cut opens it
    assert len(PLATE.with_(cracks=cracks[:1]).parts()) == 1


#: Bowie's factors F = K / (sigma sqrt(pi a)) for one radial crack of length a at a circular hole of
#: radius R in an infinite plate under tension normal to the crack, as tabulated in the handbooks
BOWIE = {0.2: 2.30, 0.5: 1.73, 1.0: 1.37, 3.0: 0.94}


def _radial(a_over_R: float, size: float = 80.0):
    c = size / 2
    return PLATE.with_(polygon=[(0, 0), (size, 0), (size, size), (0, size)],
                       holes=[{"center": [c, c], "radius": 1.0, "label": "hole"}],
                       cracks=[nc.Crack(points=((c + 1.0, c), (c + 1.0 + a_over_R, c)))])


def _F(scene, a, **kw):
    (tip,) = nc.solve(scene, maxh=8.0, **kw).tips
    return tip.K_I / math.sqrt(math.pi * a)


def test_radial_crack_at_a_hole_against_bowie():
    """A plate 80 R wide (its rollers mirror it at 40 R from the hole). Measured, h1p2, tip_h 0.0125 R:
    F = 2.374, 1.7265, 1.3063, 0.9316 at a/R = 0.2, 0.5, 1, 3 against Bowie's 2.30, 1.73, 1.37, 0.94
    (+3.2%, -0.2%, -4.7%, -0.9%); converged: tip_h 0.05 R to 0.0125 R moves them by less than 0.1%,
    a plate half as wide by 0.4%, and at a/R = 1 the energy released (the load's work over a +- 0.02)
    gives 1.318 beside the domain integral's 1.312 in the plate 40 R wide. The band is 5%: the table's
    own accuracy is not stated, and a crack that did not feel the hole's concentration would be off by
    a factor 2 (a/R = 0.2)."""
    for aR, bowie in BOWIE.items():
        h = 0.0125 * min(1.0, aR / 0.5)
        F = _F(_radial(aR), aR, element="h1p2", tip_h=h)
        assert F == pytest.approx(bowie, rel=0.05), aR
        if aR == 0.5:
            assert F == pytest.approx(_F(_radial(aR), aR, element="h1p2", tip_h=4 * h), rel=1e-3)
            assert F == pytest.approx(bowie, rel=0.005)
            for element in ("bdm", "tdnns"):
                assert _F(_radial(aR), aR, element=element, tip_h=h) == pytest.approx(F, rel=5e-3), element


def test_growth_that_joins_a_hole_and_cuts_the_body_ends_cut_through():
    """An edge crack grows into the hole from the left while a crack already joins it to the right edge:
    when the tip joins the hole the plate comes apart; the run ends "cut through", its last segment
    kept, on the circle."""
    scene = PLATE.with_(cracks=[nc.Crack(points=((12.0, 10.0), (20.0, 10.0))), nc.Crack(points=((0.0, 10.0), (7.0, 10.0)))])
    res = nc.grow(scene, da=0.5, steps=4, K_Ic=1.0, criterion="mts", maxh=2.0)
    assert res.stopped.startswith("cut through: tip 1,last at (8.0") and "reached a hole" in res.stopped
    assert res.stopped.endswith("cut the body in 2 pieces")
    end = res.paths[1][-1]
    assert np.hypot(*(end - (10.0, 10.0))) == pytest.approx(2.0, abs=1e-12)
    assert len(res.steps) == 2


def test_a_near_miss_breaks_into_the_hole_radially():
    """A segment that would pass a circle 0.05 off its edge (thinner than the scene allows) ends on the
    circle at the point nearest to the tip (radially), if the turn is at most GRAZE_TURN; a polygon,
    or a turn beyond it, gives none."""
    from ngcrack.studies.growth import paths

    hole = nc.Hole(center=(1.0, 0.0), radius=0.25, labels=("h",))
    p, d = np.array([0.0, 0.3]), np.array([1.0, 0.0])
    assert paths.hole_hit(hole, p, d, 1.5) is None
    x = np.array(paths.graze_point(hole, p, d, 1.5))
    assert np.hypot(*(x - (1.0, 0.0))) == pytest.approx(0.25, abs=1e-15)
    u, w = x - p, np.array([1.0, 0.0]) - p
    assert u[0] * w[1] - u[1] * w[0] == pytest.approx(0.0, abs=1e-15)  # on the line from the tip to the centre
    assert paths.graze_point(hole, p, np.array([0.0, 1.0]), 1.5) is None  # a turn of 107 degrees
    assert paths.graze_point(hole, p, d, 0.5) is None  # out of reach
    x = np.array(paths.hole_hit(hole, np.array([0.0, 0.1]), d, 1.5))  # a hit: the first crossing, on the circle
    assert x[0] < 1.0 and np.hypot(*(x - (1.0, 0.0))) == pytest.approx(0.25, abs=1e-15)


def test_an_edge_crack_that_joins_a_hole_ends_the_run_with_the_reason():
    """An edge crack from the right edge grows into the hole: no tip is left, the plate is still one
    piece (the hole opens to the edge), and the run says so; the last scene has the joined crack."""
    scene = PLATE.with_(cracks=[nc.Crack(points=((20.0, 10.0), (13.0, 10.0)))])
    res = nc.grow(scene, da=0.6, steps=3, K_Ic=1.0, criterion="mts", maxh=2.0)
    assert res.stopped == "boundary: every tip reached the body's boundary or joined a hole"
    last = res.scenes[-1]
    assert last.tip_points() == [] and last.hole_joins() == [(0, -1, 0)] and len(last.parts()) == 1
    assert np.hypot(*(res.paths[0][-1] - (10.0, 10.0))) == pytest.approx(2.0, abs=1e-12)
