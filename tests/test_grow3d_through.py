"""A surface or corner crack grown to the back face becomes a through crack (studies/growth/through.py).

The rule's numbers without meshing: the threshold (NASGRO's 0.95 t, or a ligament below 1.5 front_h; a
front that crossed the back face), the through crack's lengths on both faces (the area rule's closed
form for a semi-ellipse and a quarter ellipse), the polygon crossing both faces as the scene accepts it,
the refusals by name; slow: a deep surface crack grown through the transition, its event, cycles and the
through crack's K.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.solid.scene import SolidScene, crack_from_dict
from ngcrack.studies.growth.through import (
    MIN_BACK_FRACTION,
    THROUGH_FRONT_H,
    TRANSITION_DEPTH,
    through_crack,
    trapezoid_back_half_length,
)

T = 1.5  # the built-in surface-crack plate's thickness (z from 0 to 1.5), 10 wide


def _scene():
    return nc.scenes.load("surface-crack")


def _ellipse(a: float, c: float, center=(0.0, 0.0, T)):
    return crack_from_dict({"shape": "ellipse", "center": list(center), "normal": [0, 1, 0], "semi_axes": [c, a],
                            "major_axis": [1, 0, 0]}, 0)


def _x_at(points: np.ndarray, z: float) -> np.ndarray:
    """Where the polygon's sides cross the level z (its x values)."""
    p = np.asarray(points)
    out = []
    for A, B in zip(p, np.roll(p, -1, axis=0)):
        if (A[2] - z) * (B[2] - z) < 0:
            out.append(A[0] + (z - A[2]) / (B[2] - A[2]) * (B[0] - A[0]))
    return np.sort(out)


def test_the_area_rule_in_closed_form():
    # a semi-ellipse at a = 0.95 t keeps its area pi a c / 2 = t (c + c_b): c_b = c (pi 0.95 / 2 - 1)
    assert trapezoid_back_half_length(0.95 * T, 1.2, T) == pytest.approx(1.2 * (math.pi * 0.95 / 2 - 1), rel=1e-12)
    # a quarter ellipse: pi a c / 4 = t (c + c_b) / 2, the same ratio
    assert trapezoid_back_half_length(0.95 * T, 1.2, T, corner=True) == pytest.approx(0.4920 * 1.2, rel=1e-3)


@pytest.mark.parametrize("a, front_h, fires, words", [
    (1.30, 0.05, False, ""),  # ligament 0.2 >= max(0.05 t, 1.5 front_h) = 0.075
    (1.42, 0.01, False, ""),  # ligament 0.08 >= 0.075 = 0.05 t (a/t = 0.947)
    (1.43, 0.01, True, "reached 0.95 of the thickness"),  # ligament 0.07 < 0.075 (a/t = 0.953)
    (1.40, 0.10, True, "below 1.5 front_h"),  # ligament 0.1 < 0.15 = 1.5 front_h, above 0.05 t
    (1.60, 0.01, True, "crossed the back face zmin"),
])
def test_the_threshold(a, front_h, fires, words):
    s = _scene()
    d, info, why = through_crack(s.domain, s.cracks[0], _ellipse(a, 1.2), 0, front_h)
    ligament = T - a
    expected = ligament < max((1 - TRANSITION_DEPTH) * T, THROUGH_FRONT_H * front_h)
    assert why == "" and (d is not None) == expected == fires
    if d is not None:
        assert words in info["what"] and info["event"] == "through" and info["face"] == "zmin"


def test_a_semi_ellipse_becomes_a_trapezoid_of_its_area_crossing_both_faces():
    s = _scene()
    a, c = 1.45, 1.2
    d, info, _ = through_crack(s.domain, s.cracks[0], _ellipse(a, c), 0, 0.01)
    c_b = trapezoid_back_half_length(a, c, T)
    assert info["back_half_length"] == pytest.approx(c_b, rel=2e-3)  # the area on a grid of 400^2 points
    assert info["surface_half_length"] == pytest.approx(c, rel=1e-9) and info["depth"] == pytest.approx(T, rel=1e-12)
    assert info["ligament"] == pytest.approx(T - a, rel=1e-6) and info["half_height"] == pytest.approx(a, rel=1e-6)
    # the same keys as a break-through's event, and the back face's length
    assert {"crack", "event", "face", "ligament", "half_height", "half_length", "depth", "surface_half_length",
            "embedded_size", "what", "back_half_length"} <= set(info)
    assert _x_at(d["points"], T) == pytest.approx([-c, c], abs=1e-6)  # the mouth's length on the front face
    assert _x_at(d["points"], 0.0) == pytest.approx([-info["back_half_length"], info["back_half_length"]], abs=1e-9)
    scene = SolidScene.from_dict({**s.to_dict(), "crack": [d]})  # the scene takes it (both faces crossed far enough)
    assert np.dot(scene.cracks[0].normal, [0, 1, 0]) == pytest.approx(1.0)  # the old crack's normal kept


def test_a_corner_crack_becomes_a_through_crack_of_one_front():
    s = _scene()
    old = _ellipse(0.6, 1.0, center=(-5.0, 0.0, T))
    a, c = 1.45, 1.2
    d, info, _ = through_crack(s.domain, old, _ellipse(a, c, center=(-5.0, 0.0, T)), 0, 0.01)
    assert info["surface_half_length"] == pytest.approx(c, rel=1e-9)
    assert info["back_half_length"] == pytest.approx(trapezoid_back_half_length(a, c, T, corner=True), rel=2e-3)
    inside = [x for x in _x_at(d["points"], T) if x > -5.0]  # one side inside the plate: the front
    assert inside == pytest.approx([-5.0 + c], abs=1e-6)
    assert [x for x in _x_at(d["points"], 0.0) if x > -5.0] == pytest.approx([-5.0 + info["back_half_length"]], abs=1e-9)
    SolidScene.from_dict({**s.to_dict(), "crack": [d]})


def test_a_transition_too_early_is_refused_by_name():
    s = _scene()  # a coarse mesh's ligament rule firing at a = 0.6 t: the trapezoid of its area has no back face
    d, info, why = through_crack(s.domain, s.cracks[0], _ellipse(0.9, 1.2), 0, 0.5)
    assert d is None and f"below {MIN_BACK_FRACTION:g} of its" in why and "give a smaller front_h" in why


def test_a_crack_far_from_the_back_face_is_left_alone():
    s = _scene()
    assert through_crack(s.domain, s.cracks[0], s.cracks[0], 0, 0.1) == (None, None, "")


# ------------------------------------------------------------------------------ slow: growth through the transition
@pytest.mark.slow
def test_a_deep_surface_crack_grows_into_a_through_crack():
    d = copy.deepcopy(_scene().to_dict())
    d["crack"][0]["semi_axes"] = [1.5, 1.1]
    d["mesh"] = {"front_h": 0.15, "crack_h": 0.3}
    r = nc.grow(SolidScene.from_dict(d), da=0.1, steps=8, paris=(1e-3, 3.0))
    assert r.stopped.startswith("through: crack[0] became a through crack at the back face zmin")
    (e,) = r.transitions
    assert e["event"] == "through" and e["step"] == len(r.steps) - 1  # the last step is the through crack's solve
    assert e["ligament"] < THROUGH_FRONT_H * 0.15 and e["ligament"] >= THROUGH_FRONT_H * 0.15 - 0.1 - 1e-9
    assert r.to_json_dict()["events"][0]["back_half_length"] == pytest.approx(e["back_half_length"])
    cyc = r.cycles()
    assert np.all(np.diff(cyc[:-1]) > 0) and cyc[-1] > cyc[-2]  # the step to the transition counted, none after
    assert r.final_scene.cracks[0].shape == "polygon"
    front = r.steps[-1]["fronts"][0]
    P, K = np.array(front["points"]), np.array(front["K_I"])
    mid = [float(K[int(np.argmin(np.abs(P[:, 2] - 0.75) + 99 * (np.sign(P[:, 0]) != side)))]) for side in (-1, 1)]
    assert mid[0] == pytest.approx(mid[1], rel=0.03)  # the two fronts agree (symmetry)
    cm = 0.5 * (e["surface_half_length"] + e["back_half_length"])  # the trapezoid against the straight crack's K
    assert mid[0] == pytest.approx(math.sqrt(math.pi * cm / math.cos(math.pi * cm / 10.0)), rel=0.07)  # 1.05 measured


def test_a_straight_through_crack_against_the_closed_form():
    # a through crack of half-length c = 1.2 in the plate (width 2b = 10, t = 1.5, S = 1), as through.py writes it
    # when c_b = c: S sqrt(pi c) sec(pi c / 2b)^(1/2) at mid-thickness, which 3D effects raise by a few percent
    d = copy.deepcopy(_scene().to_dict())
    d["mesh"] = {"front_h": 0.15, "crack_h": 0.3}
    c, m = 1.2, 0.45
    d["crack"] = [{"shape": "polygon", "points": [[-c, 0.0, -m], [c, 0.0, -m], [c, 0.0, T + m], [-c, 0.0, T + m]]}]
    sol = nc.solve(SolidScene.from_dict(d))
    P, K = np.asarray(sol.fronts[0].points), np.asarray(sol.fronts[0].K_I)
    mid = [float(K[int(np.argmin(np.abs(P[:, 2] - 0.75) + 99 * (np.sign(P[:, 0]) != side)))]) for side in (-1, 1)]
    closed = math.sqrt(math.pi * c / math.cos(math.pi * c / 10.0))
    assert mid[0] == pytest.approx(mid[1], rel=0.01)
    assert 1.0 < mid[0] / closed < 1.05 and 1.0 < mid[1] / closed < 1.05  # 1.040, 1.046 measured (1.031, 1.036 finer)


def test_a_curve_crossing_the_face_becomes_the_same_through_crack():
    from ngcrack.studies.growth.surface_curve import curve_of_ellipse

    s = _scene()  # the grown crack a curve (a free front shape) through points of the same ellipse
    old = crack_from_dict(curve_of_ellipse(s.cracks[0]), 0)
    grown = crack_from_dict(curve_of_ellipse(_ellipse(1.45, 1.2)), 0)
    d, info, why = through_crack(s.domain, old, grown, 0, 0.01)
    assert why == "" and d["shape"] == "polygon"
    assert info["surface_half_length"] == pytest.approx(1.2, rel=1e-5)
    assert info["back_half_length"] == pytest.approx(trapezoid_back_half_length(1.45, 1.2, T), rel=2e-3)


def test_the_growth_step_makes_the_through_crack_where_the_sliver_stopped_the_run():
    """The step of the loop (loop3d._grown_scene, no solve): grown by 0.25 all round, the crack 1.2 deep in the plate
    1.5 thick would leave a sliver 0.05 thick (the run stopped there before); given the mesh's front_h it becomes
    the through crack; a short step leaves it a surface crack."""
    from types import SimpleNamespace

    from ngcrack.studies.growth.loop3d import _grown_scene

    d = copy.deepcopy(_scene().to_dict())
    d["crack"][0]["semi_axes"] = [1.5, 1.2]
    scene = SolidScene.from_dict(d)
    sol = SimpleNamespace(fronts=[SimpleNamespace(crack=0, angle=np.linspace(0.0, math.pi, 15))])
    broke: list = []
    new, why, _ = _grown_scene(scene, sol, None, [np.full(15, 0.25)], 0.25, True, 0, broke, 0.1)
    assert why == "" and new.cracks[0].shape == "polygon"
    (e,) = broke
    assert e["event"] == "through" and e["face"] == "zmin" and e["ligament"] == pytest.approx(0.05, abs=2e-3)
    assert e["surface_half_length"] == pytest.approx(1.75, abs=2e-3)  # the fitted ellipse's c = 1.5 + 0.25
    broke = []
    new, why, _ = _grown_scene(scene, sol, None, [np.full(15, 0.02)], 0.02, True, 0, broke, 0.1)
    assert why == "" and new.cracks[0].shape == "ellipse" and broke == []
