"""Planar growth of 3D cracks: the `curve` crack shape, the front-point rules, the cycle count, the input
checks, and growth runs against Sneddon's penny under Paris's law (the long runs are marked slow)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.errors import InputError
from ngcrack.core.fields import SceneError
from ngcrack.scenes.coarse3d import coarse_penny
from ngcrack.shell.cli import main
from ngcrack.solid.scene import SolidScene
from ngcrack.studies.growth.fronts3d import low_pass, new_front, paris_advance, quasi_static_advance
from ngcrack.studies.growth.loop3d import _Cycles


def circle(n, r=1.0, b=None, z=0.0):
    th = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    return [[r * math.cos(t), (r if b is None else b) * math.sin(t), z] for t in th]


def scene_with(crack, mesh=None, box=10.0):
    d = coarse_penny()
    d["crack"] = [crack]
    d["domain"] = {"box": [[-box] * 3, [box] * 3]}
    if mesh is not None:
        d["mesh"] = mesh
    return SolidScene.from_dict(d)


def sneddon_cycles(a, a0, C, m, sigma=1.0):
    """Paris's law integrated from a0 to a with Sneddon's K = 2 sigma sqrt(a / pi)."""
    k = C * (2.0 * sigma / math.sqrt(math.pi)) ** m
    return (a ** (1 - m / 2) - a0 ** (1 - m / 2)) / ((1 - m / 2) * k)


# ------------------------------------------------------------------------------ the curve shape
@pytest.mark.parametrize("points, field", [
    (circle(4), "crack[0].points"),  # too few
    (circle(8)[:3] + [circle(8)[2]] + circle(8)[3:], "crack[0].points[3]"),  # a repeated point
    ([[p[0], p[1], 0.1 * k] for k, p in enumerate(circle(8))], "off the curve's plane"),
    ([circle(5)[k % 5] for k in (0, 2, 4, 6, 8)], "crosses itself"),  # a pentagram
    ([[t, 2 * t, 0.0] for t in range(6)], "no area"),
    ([[0, 0, 0], [1, 0, 0], [1, 1], [0, 1, 0], [0.5, 1.5, 0]], "crack[0].points[2]"),
])
def test_a_bad_curve_is_refused_by_name(points, field):
    with pytest.raises(SceneError, match=field.replace("[", r"\[").replace("]", r"\]")):
        scene_with({"shape": "curve", "points": points})


def test_a_curve_through_a_circle_is_the_circle_with_its_front_geometry():
    from ngcrack.solid.curve import CurveFront

    s = scene_with({"shape": "curve", "points": circle(16)})
    (c,) = s.cracks
    assert np.allclose(c.normal, [0, 0, 1]) and np.linalg.norm(c.center) < 1e-12
    assert abs(c.area / math.pi - 1) < 2e-4  # a 16-point spline of the unit circle: within 2e-4
    assert np.max(np.abs(np.linalg.norm(c.outline(200), axis=1) - 1)) < 1e-3
    g = CurveFront(c)
    phi = np.linspace(0, 2 * np.pi, 37)
    assert abs(g.periodic / (2 * math.pi) - 1) < 1e-4
    assert np.max(np.abs(g.curvature(phi) - 1)) < 0.02 and np.max(np.abs(g.reach(phi) - 1)) < 0.02
    e1, e2, e3 = g.frame(phi)
    p = g.point(phi)
    assert np.max(np.abs(np.sum(e1 * p, axis=1) / np.linalg.norm(p, axis=1) - 1)) < 1e-4  # e1 outward
    assert np.allclose(np.cross(e1, e2), e3)
    _, x1, x2, _ = g.coordinates(np.array([[1.2, 0.0, 0.05], [0.0, -0.7, -0.1]]))
    assert np.allclose(x1, [0.2, -0.3], atol=1e-3) and np.allclose(x2, [0.05, -0.1])
    # the order of the points sets the normal; the scene round-trips through its dictionary
    assert np.allclose(scene_with({"shape": "curve", "points": circle(16)[::-1]}).cracks[0].normal, [0, 0, -1])
    assert SolidScene.from_dict(s.to_dict()) == s and s.to_dict()["crack"][0]["shape"] == "curve"


def test_a_curve_through_an_ellipse_has_the_ellipse_front():
    from ngcrack.solid.curve import CurveFront
    from ngcrack.solid.front import FrontGeometry

    a, b = 1.0, 0.5
    curve = scene_with({"shape": "curve", "points": circle(48, a, b)}).cracks[0]
    ellipse = scene_with({"shape": "ellipse", "center": [0, 0, 0], "normal": [0, 0, 1], "semi_axes": [a, b],
                          "major_axis": [1, 0, 0]}).cracks[0]
    g, h = CurveFront(curve), FrontGeometry(ellipse)
    assert abs(g.periodic / h.periodic - 1) < 1e-4 and abs(curve.area / ellipse.area - 1) < 1e-4
    theta = np.linspace(0, 2 * np.pi, 24, endpoint=False)  # the same points of both
    phi_c, _, _, _ = g.coordinates(h.point(theta))
    assert np.max(np.abs(g.curvature(phi_c) / (a * b / h.speed(theta) ** 3) - 1)) < 0.03  # a / b^2 = 4 at the tips
    assert np.max(np.abs(g.reach(phi_c) / h.reach(theta) - 1)) < 0.03


# ----------------------------------------------------------------------------------- the rules
def test_front_point_rules():
    K = np.array([1.0, 0.99, 0.975, 0.97, 0.9])
    adv = quasi_static_advance(K, 0.1, 0.02)  # within 2% of the largest: da; below 4%: none; a ramp between
    assert np.allclose(adv, [0.1, 0.1, 0.075, 0.05, 0.0])
    adv = paris_advance(K, 0.1, 3.0, 0.5, dK_th=0.47)  # Delta K = K / 2; none at or below the threshold
    assert np.allclose(adv, [0.1, 0.1 * 0.99 ** 3, 0.1 * 0.975 ** 3, 0.1 * 0.97 ** 3, 0.0])
    noisy = 1 + 0.1 * np.cos(2 * np.linspace(0, 2 * np.pi, 16, endpoint=False)) + 0.01 * (-1) ** np.arange(16)
    assert np.max(np.abs(low_pass(noisy) - noisy + 0.01 * (-1) ** np.arange(16))) < 1e-12  # the mode 8 goes, 2 stays


def test_a_uniform_advance_grows_a_disc_to_a_circle():
    disc = scene_with({"shape": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0}).cracks[0]
    angles = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    for smooth in (True, False):
        p = new_front(disc, np.full(12, 0.1), angles, smooth)
        grown = scene_with({"shape": "curve", "points": p.tolist()}).cracks[0]
        assert np.max(np.abs(np.linalg.norm(grown.outline(300), axis=1) - 1.1)) < 1e-4
        assert np.allclose(grown.normal, disc.normal)


def test_cycles_are_exact_where_K_grows_as_the_root_of_the_size():
    C, m, da = 1e-3, 3.5, 0.1
    cyc, a = _Cycles(C, m, 0.0, 0.0), 1.0
    total = cyc.step(a, 2 / math.sqrt(math.pi), None)
    for _ in range(4):
        a += da
        total = cyc.step(a, 2 * math.sqrt(a / math.pi), da)
    assert abs(total / sneddon_cycles(a, 1.0, C, m) - 1) < 1e-9
    # the first-order count da / (C K^m) at each step's start is 7.8% high after these four steps
    first = sum(da / (C * (2 * math.sqrt((1 + k * da) / math.pi)) ** m) for k in range(4))
    assert first / sneddon_cycles(a, 1.0, C, m) - 1 > 0.04


# ---------------------------------------------------------------------------- refused by name
@pytest.fixture
def no_solve(monkeypatch):
    """Any solve fails the test: the checks come before meshing."""
    import ngcrack.core.solve as core_solve

    monkeypatch.setattr(core_solve, "solve", lambda *a, **k: pytest.fail("solved before refusing"))


@pytest.mark.parametrize("kw, field", [
    ({"R": 0.5}, "R = 0.5"), ({"paris": (-1e-3, 3)}, "paris"), ({"paris": (1e-3, 0)}, "paris"),
    ({"paris": (1e-3, 3), "R": 1.0}, "R = 1.0"), ({"criterion": "mts"}, "criterion"), ({"r_c": 0.1}, "r_c"),
    ({"at_hole": 0.5}, "at_hole"), ({"da": 0.6}, "da = 0.6"), ({"da": 0.001}, "da = 0.001"), ({"steps": 0}, "steps"),
    ({"K_Ic": -1}, "K_Ic"), ({"tip_h": 0.1}, "tip_h"), ({"warm_start": None}, "warm_start"),
])
def test_3d_growth_refuses_bad_input_by_name_before_meshing(no_solve, kw, field):
    args = {"da": 0.1, "steps": 2, **kw}
    da, steps = args.pop("da"), args.pop("steps")
    with pytest.raises((InputError, SceneError, ValueError), match=field.replace("[", r"\[")):
        nc.grow(nc.Scene.from_dict(coarse_penny()), da=da, steps=steps, **args)


def test_a_polygon_and_a_crack_near_a_face_are_refused(no_solve):
    square = {"shape": "polygon", "points": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]}
    with pytest.raises(InputError, match=r"crack\[0\]: a polygon"):
        nc.grow(scene_with(square), da=0.1, steps=1)


@pytest.mark.parametrize("argv, field", [
    (["penny", "--paris", "1e-3"], "--paris 0.001"), (["penny", "--R", "0.2"], "R = 0.2"),
    (["penny", "--paris", "-1", "3"], "paris"), (["penny", "--tip-h", "0.1"], "--tip-h"),
    (["penny", "--criterion", "mts"], "--criterion mts"), (["penny", "--gif", "x.gif"], "--gif"),
    (["penny", "--at-hole", "0.1"], "--at-hole 0.1: an option of 2D growth; scene 'penny' is 3D (3D bodies have no holes)"),
    (["griffith", "--front-h", "0.1"], "--front-h"), (["griffith", "--paris", "1e-3", "3", "-1"], "paris"),
    (["griffith", "--R", "0.5"], "R = 0.5"),
])
def test_the_command_line_refuses_the_new_options_by_name(tmp_path, capsys, no_solve, argv, field):
    out = tmp_path / "g.json"
    code = main(["grow", *argv[:1], "--da", "0.1", "--steps", "2", "--json", str(out), *argv[1:]])
    err = capsys.readouterr().err
    assert code == 2 and field in err and not out.exists(), err


# ----------------------------------------------------------------------------------- growth runs
@pytest.mark.slow
def test_grow_3d_from_the_command_line_writes_fronts_and_cycles(tmp_path, capsys):
    """One Paris step of a coarse penny: the JSON contract, a front that grew by da all round."""
    path = tmp_path / "penny.toml"
    d = coarse_penny()
    d["mesh"] = {"maxh": 5.0, "crack_h": 0.8, "front_h": 0.4}
    path.write_text(SolidScene.from_dict(d).to_toml_string())
    out = tmp_path / "g.json"
    code = main(["grow", str(path), "--da", "0.1", "--steps", "1", "--paris", "1e-3", "3", "--json", str(out),
                 "--csv", str(tmp_path / "g.csv")])
    assert code == 0, capsys.readouterr().err
    data = json.loads(out.read_text())
    assert {"scene", "element", "criterion", "da", "K_Ic", "stopped", "steps", "cracks"} <= set(data)
    s0, s1 = data["steps"]
    assert {"step", "load_factor", "ndof", "time_s", "kkt", "tips", "fronts", "cycles"} <= set(s1)
    (f,) = s1["fronts"]
    assert {"crack", "points", "K_I", "K_II", "K_III", "G", "kink_deg"} <= set(f)
    assert s0["cycles"] == 0 and max(abs(k) for k in f["kink_deg"]) < 2.0  # mode I: planar growth is honest
    assert max(s0["fronts"][0]["advance"]) == pytest.approx(0.1)
    r = np.linalg.norm(np.array(f["points"])[:, :2], axis=1)
    assert np.all(np.abs(r - 1.1) < 0.015)  # every point advanced by about da (K within 3% on this mesh)
    # one step's cycles against Sneddon's closed form at the crack's equivalent radius (coarse: 5%)
    assert abs(s1["cycles"] / sneddon_cycles(f["size"], 1.0, 1e-3, 3.0) - 1) < 0.05
    assert data["cracks"][0]["shape"] == "curve"


@pytest.mark.slow
def test_a_penny_under_paris_fatigue_stays_round_and_follows_sneddon():
    C, m = 1e-3, 3.0
    res = nc.grow(nc.Scene.from_dict(coarse_penny()), da=0.1, steps=4, paris=(C, m))
    for k, s in enumerate(res.scenes):
        r = np.linalg.norm(s.cracks[0].outline(256)[:, :2], axis=1)
        assert (r.max() - r.min()) / r.mean() < 0.015
        if k:
            a = res.sizes()[k]
            assert abs(res.steps[k]["cycles"] / sneddon_cycles(a, 1.0, C, m) - 1) < 0.03


@pytest.mark.slow
def test_an_ellipse_grows_towards_a_circle():
    a, b = 1.0, 0.6
    s = scene_with({"shape": "ellipse", "center": [0, 0, 0], "normal": [0, 0, 1], "semi_axes": [a, b],
                    "major_axis": [1, 0, 0]}, mesh={"maxh": 5.0, "crack_h": 0.3, "front_h": 0.15})
    res = nc.grow(s, da=0.1, steps=2, paris=(1e-3, 3.0))
    ratios = []
    for sc in res.scenes:
        p = sc.cracks[0].outline(512)
        ratios.append(np.ptp(p[:, 1]) / np.ptp(p[:, 0]))
    assert ratios[0] == pytest.approx(b / a) and ratios[1] > ratios[0] + 0.02 and ratios[2] > ratios[1] + 0.02


@pytest.mark.slow
def test_quasi_static_growth_advances_only_the_points_at_K_Ic():
    s = scene_with({"shape": "ellipse", "center": [0, 0, 0], "normal": [0, 0, 1], "semi_axes": [1.0, 0.6],
                    "major_axis": [1, 0, 0]}, mesh={"maxh": 5.0, "crack_h": 0.3, "front_h": 0.15})
    res = nc.grow(s, da=0.1, steps=1, K_Ic=1.5)
    (f,) = res.steps[0]["fronts"]
    K, adv = np.array(f["K_drive"]), np.array(f["advance"])
    assert res.steps[0]["load_factor"] == pytest.approx(1.5 / K.max())
    from ngcrack.solid.curve import CurveFront

    grown = CurveFront(res.scenes[1].cracks[0])
    old = np.array(f["points"])
    _, x1, _, _ = grown.coordinates(old)  # how far inside the new front each old point lies
    low, top = K < 0.96 * K.max(), K >= 0.98 * K.max()
    assert low.sum() > len(K) / 2 and top.sum() >= 2  # the test means something
    assert np.all(adv[low] == 0) and np.all(np.abs(x1[low]) < 0.005)
    assert np.all(np.abs(-x1[top] - 0.1) < 0.01)


@pytest.mark.slow
@pytest.mark.parametrize("shape", ["circle", "ellipse"])
def test_a_curve_crack_has_the_closed_form_K(shape):
    from scipy.special import ellipe

    a, b = (1.0, 1.0) if shape == "circle" else (1.0, 2 / 3)
    mesh = {"maxh": 5.0, "crack_h": 0.4, "front_h": 0.2} if shape == "circle" else {"maxh": 5.0, "crack_h": 0.3,
                                                                                   "front_h": 0.15}
    sol = nc.solve(scene_with({"shape": "curve", "points": circle(32, a, b)}, mesh=mesh))
    (f,) = sol.fronts
    phi = np.arctan2(f.points[:, 1] / b, f.points[:, 0] / a)
    exact = math.sqrt(math.pi * b) / ellipe(1 - b * b / (a * a)) * (np.sin(phi) ** 2 + (b / a) ** 2 * np.cos(phi) ** 2) ** 0.25
    # the disc on this mesh: 0.993-1.000 of Sneddon's; the ellipse shape at front_h 0.15: 0.983-1.018 of Irwin's
    assert np.max(np.abs(f.K_I / exact - 1)) < (0.01 if shape == "circle" else 0.02)


@pytest.mark.parametrize("where, reason", [("face", ""), ("crack", "crack: crack[0]'s front meets crack[1]")])
def test_a_front_reaching_a_face_breaks_through_and_one_reaching_another_crack_stops_the_run(where, reason):
    from types import SimpleNamespace

    from ngcrack.studies.growth.loop3d import _grown_scene

    d = coarse_penny()
    d["domain"] = {"box": [[-1.3, -4, -4], [4, 4, 4]]} if where == "face" else d["domain"]
    if where == "crack":
        d["crack"].append({"shape": "disc", "center": [1.0, 0, 0], "normal": [0, 0, 1], "radius": 0.5})
        d["crack"][0]["radius"] = 0.3  # 0.2 from the other in its plane: grown by 0.25, it runs into it
    scene = SolidScene.from_dict(d)
    angles = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    sol = SimpleNamespace(fronts=[SimpleNamespace(crack=0, angle=angles)])
    events = []
    new, why, _ = _grown_scene(scene, sol, None, [np.full(16, 0.25)], 0.25, True, 0, events)
    if where == "face":  # it crossed the face x = -1.3, held by a roller: no surface crack there (only free faces)
        assert new is None and not events and why.startswith("boundary: crack[0] nears face xmin"), why
        assert "no admissible crack" in why and "roller" in why, why
        return
    assert new is None and why.startswith(reason), why
