"""Loads and supports at points: the scene's [[point]] tables, the pin's mean constraint, the
three-point bend.

A pin holds its segment's mean displacement (not its rotation), a roller point its mean
normal displacement, a force is spread over its segment. Checks: every bad field refused by
name before meshing; the TOML round trip; the reactions of a statically determinate beam
balance the applied force to round-off for every element; the midspan deflection of a
slender simply supported beam lies within 1% of Timoshenko's formula, and the same beam on
two pins (a wrong support: its bottom fibre cannot stretch) is far outside that band.
"""

from __future__ import annotations

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.planar.load_points import load_displacement, load_point_values
from ngcrack.planar.scene import SceneError

E, NU = 1000.0, 0.3
LENGTH, HEIGHT, SPAN, WIDTH = 10.0, 1.0, 9.0, 0.1


def beam(supports=("pin", "roller"), force=1.0, crack=None) -> nc.Scene:
    """A slender beam (span / height 9) on two points of its bottom, a force at the top of its midspan."""
    x0, x1 = (LENGTH - SPAN) / 2, (LENGTH + SPAN) / 2
    return nc.Scene(
        name="beam", polygon=[[0, 0], [LENGTH, 0], [LENGTH, HEIGHT], [0, HEIGHT]],
        labels=["bottom", "right", "top", "left"], material={"E": E, "nu": NU, "plane": "stress"},
        cracks=[crack] if crack else [],
        points=[{"at": [x0, 0], "type": supports[0], "width": WIDTH},
                {"at": [x1, 0], "type": supports[1], "width": WIDTH},
                {"at": [LENGTH / 2, HEIGHT], "type": "force", "value": [0.0, -force], "width": WIDTH, "label": "load"}])


def timoshenko_deflection(P: float, kappa: float = 5.0 / 6.0) -> float:
    """P S^3 / (48 E I) + P S / (4 kappa G A): a simply supported beam under a central load, unit thickness."""
    inertia, G = HEIGHT**3 / 12.0, E / (2.0 * (1.0 + NU))
    return P * SPAN**3 / (48.0 * E * inertia) + P * SPAN / (4.0 * kappa * G * HEIGHT)


# ------------------------------------------------------------------ the scene


def test_points_insert_labelled_segments_and_round_trip():
    s = beam()
    assert s.labels.count("bottom") == 3 and "point0" in s.labels and "load" in s.labels
    i = s.labels.index("load")
    (ax, ay), (bx, by) = s.polygon[i], s.polygon[i + 1]
    assert (ay, by) == (HEIGHT, HEIGHT) and abs(abs(bx - ax) - WIDTH) < 1e-14 and abs(0.5 * (ax + bx) - 5.0) < 1e-14
    assert s.boundary["load"].type == "traction" and s.boundary["load"].value == pytest.approx((0.0, -1.0 / WIDTH))
    text = s.to_toml_string()
    assert "[[point]]" in text and "load" not in text.split("[[point]]")[0]  # written as the user wrote it
    again = nc.Scene.from_toml_string(text)
    assert again == s and again.polygon == s.polygon
    assert s.with_(nu=0.25).polygon == s.polygon  # re-validation inserts nothing twice
    moved = s.with_(points=[*s.points[:2], nc.PointCondition(at=(4.0, HEIGHT), value=(0.0, -2.0), width=0.2,
                                                              label="load")])
    assert len(moved.polygon) == len(s.polygon) and (3.9, HEIGHT) in moved.polygon
    assert moved.boundary["load"].value == pytest.approx((0.0, -10.0))


def test_scaled_scenes_carry_the_point_forces():
    s = beam()
    big = s.scaled(load=3.0, size=2.0)
    assert big.points[2].value == pytest.approx((0.0, -6.0))  # a stress times a length
    assert big.points[2].width == pytest.approx(2 * WIDTH) and big.points[2].at == pytest.approx((10.0, 2.0))
    from ngcrack.shell.explorer.loads import scaled_loads

    turned = scaled_loads(s, 2.0, 90.0)
    assert turned.points[2].value == pytest.approx((2.0, 0.0), abs=1e-12)


@pytest.mark.parametrize("bad, message", [
    ({"at": [3, 0.5], "type": "pin"}, "point[3].at = (3, 0.5): not on the body's outer boundary"),
    ({"at": [0, 0], "type": "pin"}, "point[3].at = (0, 0): lies at a corner"),
    ({"at": [3, 0], "type": "force"}, "point[3].value: missing"),
    ({"at": [3, 0], "type": "pin", "value": [1, 0]}, "point[3].value = [1, 0]: type = 'pin' takes no value"),
    ({"at": [3, 0], "type": "hinge"}, "point[3].type = 'hinge': allowed types are force, pin, roller"),
    ({"at": [3, 0], "type": "pin", "width": -1}, "point[3].width = -1"),
    ({"at": [0.1, 0], "type": "pin", "width": 0.5}, "point[3].width = 0.5: the segment centred at (0.1, 0) does not fit"),
    ({"at": [0.52, 0], "type": "pin"}, "point[3].at = (0.52, 0): lies on the segment of point[0]"),
    ({"at": [3, 0], "type": "pin", "label": "top"}, "point[3].label = 'top': already the label of a polygon edge"),
    ({"at": [3, 0], "type": "pin", "label": "load"}, "point[3].label = 'load': already the label of point[2]"),
    ({"at": [3, 0], "type": "pin", "colour": 1}, "point[3]"),
])
def test_bad_points_are_refused_by_name(bad, message):
    s = beam()
    with pytest.raises(SceneError) as err:
        s.with_(points=[*s.points, bad])
    assert str(err.value).startswith(message), str(err.value)


def test_a_pin_alone_leaves_the_rotation_free_and_a_conflicting_boundary_is_refused():
    s = beam()
    with pytest.raises(SceneError, match="rotation about \\(0.5, 0\\) free"):
        s.with_(points=s.points[:1] + s.points[2:])
    with pytest.raises(SceneError, match="boundary.load: the segment of point\\[2\\] carries its force"):
        nc.Scene.from_dict({**s.to_dict(), "boundary": {"load": {"type": "traction", "value": [0, 5]}}})
    with pytest.raises(SceneError, match="boundary.point0: the segment of point\\[0\\] \\(a pin\\)"):
        nc.Scene.from_dict({**s.to_dict(), "boundary": {"point0": {"type": "clamped"}}})
    with pytest.raises(SceneError, match="^point = 3: must be an array of tables"):
        nc.Scene.from_dict({**s.to_dict(), "point": 3})


# ------------------------------------------------------------------ the solves


@pytest.mark.parametrize("element", ["tdnns", "bdm", "peers", "h1p1"])
def test_reactions_balance_the_applied_force(element):
    """Statically determinate: each support carries half the load, the pin no horizontal force."""
    sol = nc.solve(nc.scenes.load("three-point-bend"), element=element, maxh=0.5)
    v = load_point_values(sol)
    applied = np.array(v["load"]["force"])
    reactions = np.array([v["support-left"]["force"], v["support-right"]["force"]])
    assert np.abs(reactions.sum(axis=0) + applied).max() < 1e-9
    assert np.abs(reactions - [[0.0, 0.5], [0.0, 0.5]]).max() < 1e-9
    # the supports hold their segment's mean: the pin both components, the roller the vertical one
    assert max(map(abs, v["support-left"]["displacement"])) < 1e-12
    assert abs(v["support-right"]["displacement"][1]) < 1e-12 and v["support-right"]["displacement"][0] > 0
    (P, delta), = load_displacement({"load": v["load"]}).values()
    assert P == pytest.approx(1.0) and delta > 0


def test_midspan_deflection_against_timoshenko_and_a_wrong_support():
    """The neutral axis at midspan moves down by Timoshenko's deflection within 1% (converged
    h1p2: 0.18914 against 0.18927; bdm at maxh 0.1: 0.5% below); pinned at both ends the
    beam deflects half as much (its bottom fibre cannot stretch), far outside the band."""
    expected = timoshenko_deflection(1.0)
    mid = (LENGTH / 2, HEIGHT / 2)
    for element, maxh in (("h1p2", 0.2), ("bdm", 0.1)):
        sol = nc.solve(beam(), element=element, maxh=maxh)
        deflection = -float(sol.u(sol.mesh(*mid))[1])
        assert abs(deflection / expected - 1.0) < 0.01, (element, deflection, expected)
    sol = nc.solve(beam(("pin", "pin")), element="h1p2", maxh=0.2)
    wrong = -float(sol.u(sol.mesh(*mid))[1])
    assert abs(wrong / expected - 1.0) > 0.3
    v = load_point_values(sol)
    assert abs(v["point0"]["force"][0] + v["point1"]["force"][0]) < 1e-9 and v["point0"]["force"][0] > 0.5


def test_default_width_follows_the_mesh_size_and_points_can_be_removed():
    s = beam()
    free = s.with_(points=[{"at": p.at, "type": p.type, **({"value": p.value} if p.value else {})} for p in s.points])
    assert [p.width for p in free.points] == pytest.approx([0.5 * 0.1 * s.diameter] * 3)  # no maxh: a tenth of it
    fine = s.with_(maxh=0.2, points=[{"at": (3.0, 0.0), "type": "pin"}, *s.points[1:]])
    assert fine.points[0].width == pytest.approx(0.1)
    plain = s.with_(points=[], boundary={"bottom": {"type": "clamped"}})
    assert len(plain.polygon) == 4 and plain.labels == ("bottom", "right", "top", "left") and not plain.boundary.get("load")


def test_a_pin_on_the_crack_mouth_is_said_and_changes_K_as_said():
    """A pin whose segment holds the mouth of the beam's edge crack ties the faces there: one warning naming
    the point and the crack, and K_I drops by an order of magnitude (5.59 -> 0.41 at the scene's mesh); the
    scene's own pin, away from the crack, gives no warning."""
    beam = nc.scenes.load("three-point-bend")
    moved = [dict(p.to_dict(), at=[4.5, 0.0]) if p.label == "support-left" else p.to_dict() for p in beam.points]
    with pytest.warns(UserWarning, match=r"point\[0\] \(pin at \(4\.5, 0\).*holds the mouth of crack\[0\]"):
        held = beam.with_(points=moved)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        beam.with_(maxh=0.25)
    k_free = nc.solve(beam, estimate=False).tips[0].K_I
    k_held = nc.solve(held, estimate=False).tips[0].K_I
    assert k_free == pytest.approx(5.59, rel=0.01)
    assert k_held < 0.1 * k_free
