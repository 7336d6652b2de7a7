"""3D cracks reaching the surface: scene checks, the clipped crack in the mesh, K along open fronts.

Every figure fails on a wrong answer: the arcs where an outline leaves the body against their closed
form, the crack faces' area against the exact clipped area, Newman and Raju's equation at a value
worked by hand, and K_I along the front of the built-in `surface-crack` against their equation (the
deepest point within 3%, every point within their stated 5%) and against the K of the crack's
opening behind the deepest point; a deep semicircular crack (a/t = 0.8) the same way.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.fields import SceneError
from ngcrack.solid.scene import SolidScene
from ngcrack.solid.surface import bump_inside, clip_segment, inside_arcs, surface_take
from ngcrack.studies.newman_raju import STATED_ACCURACY, corner_crack_K, opening_K_I, surface_crack_K

A, C, T, B = 0.6, 1.0, 1.5, 5.0  # the built-in scene's depth, half-length, thickness, half-width


def plate(**crack) -> dict:
    d = copy.deepcopy(nc.scenes.load("surface-crack").to_dict())
    d["crack"][0].update(crack)
    return d


# ------------------------------------------------------------------------------ scene checks
def test_surface_crack_scene_is_accepted_and_its_arc_is_the_half_ellipse():
    s = nc.scenes.load("surface-crack")
    (phi0, phi1), = inside_arcs(s.domain, s.cracks[0])
    assert abs(phi0) < 1e-9 and abs(phi1 - math.pi) < 1e-9


@pytest.mark.parametrize("center, message", [
    ([0.0, 0.0, 0.85], "comes within 0.05 of face zmax"),  # 0.05 below the face: not 0.1 inside nor across
    ([0.0, 0.0, 0.95], "crosses face zmax by only 0.05"),  # pokes 0.05 through the face
    ([0.0, 0.0, 2.2], "lies wholly outside"),
])
def test_cracks_near_a_face_are_refused_by_name(center, message):
    with pytest.raises(SceneError, match=message):
        SolidScene.from_dict(plate(center=center))


def test_a_sliver_below_the_front_is_refused_and_says_what_is_allowed():
    d = plate(semi_axes=[1.0, 1.45])  # a crack 1.45 deep in a plate 1.5 thick: a sliver 0.05 thick
    d["crack"][0]["major_axis"] = [0.0, 0.0, 1.0]
    d["crack"][0]["semi_axes"] = [1.45, 1.0]
    with pytest.raises(SceneError, match=r"sliver of body 0\.05 thick.*face zmin.*at least 0\.1 is needed"):
        SolidScene.from_dict(d)


def test_a_crack_crossing_a_supported_face_is_refused():
    d = plate()
    d["boundary"]["zmax"] = {"type": "roller"}
    with pytest.raises(SceneError, match="crosses face zmax, which carries a roller condition"):
        SolidScene.from_dict(d)


def test_corner_crack_and_through_crack_are_accepted():
    corner = plate(center=[-5.0, 0.0, 1.5], semi_axes=[1.0, 0.6])
    s = SolidScene.from_dict(corner)
    (phi0, phi1), = inside_arcs(s.domain, s.cracks[0])
    assert abs(phi0) < 1e-9 and abs(phi1 - 0.5 * math.pi) < 1e-9  # a quarter of the ellipse
    through = plate()
    through["crack"] = [{"shape": "polygon", "points": [[-0.5, 0.0, -0.5], [0.5, 0.0, -0.5], [0.5, 0.0, 2.0],
                                                         [-0.5, 0.0, 2.0]]}]
    s = SolidScene.from_dict(through)
    assert clip_segment(s.domain, np.array([0.5, 0.0, -0.5]), np.array([0.5, 0.0, 2.0])) == pytest.approx((0.2, 0.8))


def test_open_front_stations_and_bump():
    assert bump_inside(np.array([5.0]), 1.0, 10.0)[0] == pytest.approx(1.0)  # the whole bump: L
    assert bump_inside(np.array([0.0]), 1.0, 10.0)[0] == pytest.approx(0.5)  # half of it at an end
    s = np.array([0.0, 0.3, 0.5, 1.0, 1.5, 1.7, 2.0])
    kept, take = surface_take(s, 2.0, 0.3)
    assert kept.tolist() == [0, 1, 2, 3, 4, 5, 6] and take.tolist() == [1, 1, 2, 3, 4, 5, 5]


# ------------------------------------------------------------------------------ the reference
def test_newman_raju_at_a_value_worked_by_hand():
    # a/c = 0.6, a/t = 0.4, c/b = 0.2, deepest point: Q = 1.6301, M1 + M2 (a/t)^2 + M3 (a/t)^4 = 1.1599,
    # f_w = 1.0099: K = sqrt(pi 0.6 / Q) F = 1.2597
    assert surface_crack_K(1.0, A, C, T, B, math.pi / 2) == pytest.approx(1.2597, abs=2e-4)
    # the surface point: f_phi = sqrt(a/c), g = 1 + 0.1 + 0.35 (a/t)^2
    ratio = surface_crack_K(1.0, A, C, T, B, 0.0) / surface_crack_K(1.0, A, C, T, B, math.pi / 2)
    assert ratio == pytest.approx(math.sqrt(0.6) * (1.1 + 0.35 * 0.16), rel=1e-12)
    # a corner crack's two ends differ only by their g factors and f_phi
    k0, k90 = corner_crack_K(1.0, 0.5, 0.5, 5.0, 50.0, np.array([0.0, math.pi / 2]))
    assert k0 == pytest.approx(k90 * (1 + 0.08 + 0.4 * 0.01) / (1 + 0.08 + 0.15 * 0.01), rel=1e-12)
    assert STATED_ACCURACY == 0.05


# ------------------------------------------------------------------------------ mesh and solve
def test_the_clipped_crack_in_the_mesh():
    from ngcrack.solid.geometry import make_mesh

    scene = nc.scenes.load("surface-crack")
    sm = make_mesh(scene, front_h=0.2, crack_h=0.4)
    cf = sm.cracks[0]
    assert cf.area == pytest.approx(0.5 * math.pi * A * C, rel=2e-4)  # curved: the half ellipse's area
    pts = sm.points
    assert np.allclose(np.hypot(pts[cf.front_vertices, 0] / C, (T - pts[cf.front_vertices, 2]) / A), 1.0, atol=1e-9)
    mouth = set(cf.interior_edges.tolist())
    mouth_edges = [e for e in sm.mesh.edges if e.nr in mouth and all(abs(pts[v.nr, 2] - T) < 1e-9 for v in e.vertices)]
    assert len(mouth_edges) >= 4  # the mouth's edges carry the tangential jump (not front edges)


@pytest.fixture(scope="module")
def surface_solution():
    return nc.solve("surface-crack")


def test_surface_crack_against_newman_raju(surface_solution):
    sol = surface_solution
    f = sol.fronts[0]
    phi = np.arctan2((T - f.points[:, 2]) / A, f.points[:, 0] / C)
    ref = surface_crack_K(1.0, A, C, T, B, phi)
    err = f.K_I / ref - 1
    deep = int(np.argmin(np.abs(phi - math.pi / 2)))
    assert abs(phi[deep] - math.pi / 2) < 1e-6 and abs(err[deep]) < 0.03
    assert np.max(np.abs(err)) < STATED_ACCURACY
    assert abs(f.points[0, 2] - T) < 1e-9 and abs(f.points[-1, 2] - T) < 1e-9  # the surface points are in
    assert sol.kkt["max_penetration"] < 1e-8


def test_the_opening_behind_the_deepest_point_gives_the_same_K(surface_solution):
    """The crack's opening behind the deepest point (fitted to the plane-strain sqrt(r) law) is an extraction
    independent of the domain integral: it agrees with it and with Newman-Raju's equation within 3%."""
    f = surface_solution.fronts[0]
    k = int(np.argmin(np.abs(f.points[:, 0])))
    K_open = opening_K_I(surface_solution, f.points[k], [0.0, 0.0, 1.0], A)
    ref = float(surface_crack_K(1.0, A, C, T, B, 0.5 * math.pi))
    assert abs(K_open / f.K_I[k] - 1) < 0.03 and abs(K_open / ref - 1) < 0.03


def test_a_deep_semicircular_crack_against_newman_raju():
    """a/c = 1, a/t = 0.8 (the ligament below the front 0.25 a, 1.5 front_h): the domain integral's tube is
    squeezed ahead of the front. At this default mesh the deepest point is within 2% of Newman-Raju's equation
    and every point off the surface within 3% (measured +0.07% and 1.8%; a guard of the squeezed tube: refined,
    the deepest point settles 2-6% below the equation, BENCHMARKS "Deep and slender surface cracks"), and the
    opening's K, an extraction without the tube, within 4% of the domain integral's (measured 2.8% below)."""
    a, t, b = 0.6, 0.75, 3.0
    d = {"name": "deep", "domain": {"box": [[-b, -2 * b, 0.0], [b, 2 * b, t]]},
         "crack": [{"shape": "disc", "center": [0.0, 0.0, t], "normal": [0.0, 1.0, 0.0], "radius": a}],
         "material": {"E": 1000.0, "nu": 0.3},
         "boundary": {"ymin": {"type": "clamped"}, "ymax": {"type": "traction", "value": [0.0, 1.0, 0.0]}},
         "mesh": {"front_h": a / 6, "crack_h": a / 3}}
    sol = nc.solve(SolidScene.from_dict(d))
    f = sol.fronts[0]
    phi = np.arctan2((t - f.points[:, 2]) / a, f.points[:, 0] / a)
    err = f.K_I / surface_crack_K(1.0, a, a, t, b, phi) - 1
    deep = int(np.argmin(np.abs(phi - math.pi / 2)))
    assert abs(err[deep]) < 0.02 and np.max(np.abs(err[1:-1])) < 0.03
    K_open = opening_K_I(sol, f.points[deep], [0.0, 0.0, 1.0], a)
    assert abs(K_open / f.K_I[deep] - 1) < 0.04


# ------------------------------------------------------------------------------ slow: corner and through cracks
@pytest.mark.slow
def test_corner_crack_against_newman_raju():
    d = plate(center=[-5.0, 0.0, 1.5])  # a quarter ellipse centred on the edge x = -5, z = 1.5
    sol = nc.solve(SolidScene.from_dict(d))
    f = sol.fronts[0]
    phi = np.arctan2(np.maximum(T - f.points[:, 2], 0.0) / A, (f.points[:, 0] + 5.0) / C)
    err = f.K_I / corner_crack_K(1.0, A, C, T, 2 * B, phi) - 1
    assert abs(phi[0]) < 1e-6 and abs(phi[-1] - math.pi / 2) < 1e-6  # both ends on the surface
    assert np.max(np.abs(err[1:-1])) < STATED_ACCURACY  # off the surface, within their stated accuracy


@pytest.mark.slow
def test_through_crack_is_symmetric_and_near_the_plane_strain_value():
    d = plate()
    d["crack"] = [{"shape": "polygon", "points": [[-0.6, 0.0, -0.5], [0.6, 0.0, -0.5], [0.6, 0.0, 2.0],
                                                   [-0.6, 0.0, 2.0]]}]
    sol = nc.solve(SolidScene.from_dict(d))
    f = sol.fronts[0]
    right, left = f.points[:, 0] > 0, f.points[:, 0] < 0
    assert np.all(np.isclose(f.points[:, 2].min(), 0.0) & np.isclose(f.points[:, 2].max(), T))  # surface points in
    mid = [int(np.argmin(np.abs(f.points[:, 2] - 0.75) + 9 * ~side)) for side in (left, right)]
    assert f.K_I[mid[0]] == pytest.approx(f.K_I[mid[1]], rel=0.01)  # the two sides agree (symmetry)
    # a through crack of half-length 0.6 in a plate 10 wide: sigma sqrt(pi a) sqrt(sec(pi a / W)) at mid-thickness,
    # which 3D effects raise by a few percent
    assert f.K_I[mid[0]] == pytest.approx(math.sqrt(math.pi * 0.6 / math.cos(math.pi * 0.06)), rel=0.05)


def test_a_crack_through_a_cylinder_side_has_the_clipped_area():
    from ngcrack.solid.geometry import make_mesh
    from ngcrack.solid.surface import clipped_area

    d = {"name": "bar", "domain": {"cylinder": {"center": [0, 0, 0], "axis": [0, 0, 1], "radius": 2.0, "height": 8.0}},
         "crack": [{"shape": "disc", "center": [2.0, 0, 0], "normal": [0, 0, 1], "radius": 0.8}],
         "material": {"E": 1000.0, "nu": 0.3},
         "boundary": {"bottom": {"type": "clamped"}, "top": {"type": "traction", "value": [0, 0, 1]}}}
    s = SolidScene.from_dict(d)
    (phi0, phi1), = inside_arcs(s.domain, s.cracks[0])
    # the disc's outline meets the side where |c + 0.8 (cos, sin)| = 2: cos(phi) = -0.2
    assert phi1 - phi0 == pytest.approx(2 * math.acos(0.2), abs=1e-9)
    sm = make_mesh(s, front_h=0.2, crack_h=0.4)
    assert sm.cracks[0].area == pytest.approx(clipped_area(s.domain, s.cracks[0]), rel=5e-4)
    assert "mouth0" in sm.mesh.GetBBoundaries()  # (the side's seam may split the mouth in two edges)
