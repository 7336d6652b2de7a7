"""Crack growth (ngcrack.studies.growth): the criteria against their closed forms, the loop against
closed forms and handbook values, wing cracks from a closed frictional crack, stops at the
boundary and before another crack, the JSON contract, the command, and bad input.

Measured (bdm, the scenes' default meshes): the MTS kink of the 45-degree crack in
tension is -53.12 degrees (closed form -53.13 for K_I = K_II); the centre-cracked strip's
load factor follows the handbook within 0.33% for a/b = 0.2..0.7 on an exactly straight
path; the wings of the 45-degree crack with mu = 0.3 start at lambda within 0.3% of
K_Ic / ((2/sqrt 3) K_II,eff), MTS 70.53 degrees, PLS 73.0 degrees.
"""

from __future__ import annotations

import io
import json
import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.scenes import inclined_crack
from ngcrack.scenes.handbook import centre_cracked_K, centre_cracked_strip
from ngcrack.shell.cli import main
from ngcrack.studies.growth import criteria, loop

MTS_EQUAL = math.degrees(2 * math.atan((1 - 3) / 4))  # K_I = K_II: 2 atan(-1/2) = -53.13 degrees
MTS_MODE_II = math.degrees(2 * math.atan(-math.sqrt(8) / 4))  # -70.53 degrees


# ------------------------------------------------------------------ criteria (no mesh)
def test_mts_closed_forms():
    assert MTS_EQUAL == pytest.approx(-53.1301, abs=1e-4)
    assert math.degrees(criteria.mts_angle(1.0, 1.0)) == pytest.approx(MTS_EQUAL, abs=1e-12)
    assert math.degrees(criteria.mts_angle(0.0, 1.0)) == pytest.approx(-70.5288, abs=1e-4)
    assert math.degrees(criteria.mts_angle(0.0, -2.0)) == pytest.approx(70.5288, abs=1e-4)  # K_II < 0: counter-clockwise
    assert criteria.mts_angle(3.0, 0.0) == 0.0 and criteria.mts_keq(3.0, 0.0) == 3.0
    assert criteria.mts_angle(0.0, 0.0) == 0.0 and criteria.mts_keq(0.0, 0.0) == 0.0
    assert criteria.mts_keq(0.0, 0.7) == pytest.approx(2 / math.sqrt(3) * 0.7, rel=1e-12)
    # the form 2 atan((K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)) where K_II != 0
    for k1, k2 in ((1.0, 0.3), (0.2, -1.0), (2.0, 1e-3), (0.0, 0.5)):
        textbook = 2 * math.atan((k1 - math.sqrt(k1 * k1 + 8 * k2 * k2)) / (4 * k2))
        assert criteria.mts_angle(k1, k2) == pytest.approx(textbook, abs=1e-12)


@pytest.mark.parametrize("k1, k2", [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.3, -0.8), (2.0, 0.05)])
def test_mts_angle_maximises_the_hoop_stress(k1, k2):
    """The MTS angle is where the hoop stress of the singular field is largest, and K_eq is its value."""
    theta = criteria.mts_angle(k1, k2)
    grid = np.linspace(-math.pi + 1e-6, math.pi - 1e-6, 200001)
    hoop = np.array([criteria.hoop_factor(t, k1, k2) for t in grid[::50]])
    best = grid[::50][np.argmax(hoop)]
    assert theta == pytest.approx(best, abs=2 * (grid[50] - grid[0]))
    h = 1e-6
    assert criteria.hoop_factor(theta, k1, k2) >= max(criteria.hoop_factor(theta + d, k1, k2) for d in (-h, h))
    assert criteria.mts_keq(k1, k2) == pytest.approx(hoop.max(), rel=1e-6)


def test_closed_faces_and_load_factor():
    assert criteria.effective_K_I(0.3, closed=True) == 0.0
    assert criteria.effective_K_I(-0.01, closed=False) == 0.0
    assert criteria.effective_K_I(0.3, closed=False) == 0.3
    assert criteria.load_factor(2.0, 0.5) == 4.0 and criteria.load_factor(2.0, 0.0) == math.inf
    # the secant step finds the root of a linear function at once, within its limit
    assert criteria.secant_angle(0.0, -1.0, 0.1, -0.5, limit=1.0) == pytest.approx(0.2)
    assert criteria.secant_angle(0.0, -1.0, 0.1, -0.5, limit=0.05) == pytest.approx(0.15)
    assert criteria.newton_angle(0.1, 0.3, 1.0, limit=1.0) == pytest.approx(0.1 - 0.3 / criteria.PLS_SLOPE)


# ------------------------------------------------------------------------- bad input
@pytest.fixture
def no_solve(monkeypatch):
    def refuse(*a, **k):
        raise AssertionError("grow solved before refusing its input")

    monkeypatch.setattr(loop, "solve_step", refuse)


@pytest.mark.parametrize("kw, field", [
    ({"K_Ic": 0.0}, "K_Ic"), ({"K_Ic": -1.0}, "K_Ic"), ({"K_Ic": math.nan}, "K_Ic"), ({"K_Ic": math.inf}, "K_Ic"),
    ({"K_Ic": True}, "K_Ic"), ({"da": 0.0}, "da"), ({"da": -0.1}, "da"), ({"da": 2.9}, "da"), ({"da": math.nan}, "da"),
    ({"steps": 0}, "steps"), ({"steps": loop.MAX_STEPS + 1}, "steps"), ({"steps": 2.5}, "steps"),
    ({"criterion": "maxG"}, "criterion"), ({"warm_start": None}, "warm_start"), ({"together": 1.5}, "together"),
])
def test_bad_input_refused_before_any_solve(no_solve, kw, field):
    scene = inclined_crack(angle=30.0, load=1.0)  # diameter 28.3: da at most 2.83
    args = {"da": 0.1, "steps": 2, **kw}
    with pytest.raises(ValueError, match=rf"^{field}"):
        nc.grow(scene, **args)


def test_scene_without_a_tip_refused(no_solve):
    scene = nc.scenes.load("paper-1")  # its crack runs through the whole width
    with pytest.raises(ValueError, match="no crack tip inside the body"):
        nc.grow(scene, da=0.1, steps=1)


def test_bad_solve_option_refused_before_meshing():
    with pytest.raises(ValueError, match="^element"):
        nc.grow(inclined_crack(), da=0.1, steps=1, element="q2")


# ----------------------------------------------------------------- inclined crack, tension
@pytest.fixture(scope="module")
def tension_mts():
    return nc.grow(inclined_crack(angle=45.0, load=1.0), da=0.1, steps=1, K_Ic=1.0, criterion="mts")


def test_kink_of_the_45_degree_crack_in_tension(tension_mts):
    """K_I = K_II: both tips kink by the MTS closed form -53.13 degrees (within 1 degree), and grow together."""
    df = tension_mts.table
    first = df[df.step == 0]
    assert len(first) == 2 and first.grew.all()
    assert np.allclose(first.K_I / first.K_II, 1.0, atol=0.01)
    assert np.all(np.abs(first.kink_deg - MTS_EQUAL) < 1.0), first.kink_deg.tolist()
    # the kink from the computed K is the closed form's
    for r in first.itertuples():
        assert r.kink_deg == pytest.approx(math.degrees(criteria.mts_angle(r.K_I, r.K_II)), abs=1e-9)
        assert r.tip_load_factor == pytest.approx(1.0 / criteria.mts_keq(r.K_I, r.K_II), rel=1e-9)
    # the new segments point where the kink says: tangent at 45 degrees turned by the kink
    for c_end, sign in (("last", 1), ("first", -1)):
        r = first[first.end == c_end].iloc[0]
        pts = np.asarray(tension_mts.final_scene.cracks[0].points)
        seg = pts[-1] - pts[-2] if c_end == "last" else pts[0] - pts[1]
        expected = math.radians(45.0 if sign > 0 else -135.0) + math.radians(r.kink_deg)
        assert np.allclose(seg, 0.1 * np.array([math.cos(expected), math.sin(expected)]), atol=1e-12)
    # after the kink the crack is nearly in mode I, normal to the load (kink of a few degrees)
    assert np.all(np.abs(df[df.step == 1].kink_deg) < 4.0)


def test_json_contract(tension_mts):
    d = tension_mts.to_json_dict()
    assert list(d) == ["scene", "element", "criterion", "da", "K_Ic", "stopped", "steps", "cracks"]
    assert d["criterion"] == "mts" and d["da"] == 0.1 and d["K_Ic"] == 1.0 and d["element"] == nc.SolveOptions().element
    assert d["stopped"].startswith("steps")
    assert [s["step"] for s in d["steps"]] == [0, 1]
    for s in d["steps"]:
        assert list(s) == ["step", "load_factor", "ndof", "time_s", "kkt", "error_estimate", "tips", "force",
                           "displacement"]
        for t in s["tips"]:
            assert list(t) == ["crack", "end", "x", "y", "K_I", "K_II", "G", "K_eq", "kink_deg", "grew", "T", "stopped"]
        assert max(s["kkt"].values()) < 1e-8
        assert s["error_estimate"] is None  # computed only with estimate=True
    assert [t["grew"] for t in d["steps"][0]["tips"]] == [True, True]
    assert [t["grew"] for t in d["steps"][1]["tips"]] == [False, False]
    assert len(d["cracks"][0]["points"]) == 4
    json.dumps(d, allow_nan=False)


def test_error_estimate_per_step_when_asked():
    """grow(..., estimate=True): each step's relative estimate, step 0's equal to a fresh solve's
    (with growth's path grading)."""
    from ngcrack.studies.growth.checks import GROWTH_PATH_GRADING
    scene = inclined_crack(angle=45.0, load=1.0)
    res = nc.grow(scene, da=0.1, steps=1, K_Ic=1.0, criterion="mts", estimate=True)
    ests = [s["error_estimate"] for s in res.to_json_dict()["steps"]]
    assert len(ests) == 2 and all(0.0 < e < 1.0 for e in ests)
    assert ests[0] == pytest.approx(nc.solve(scene, path_grading=GROWTH_PATH_GRADING).error_estimate.relative, rel=1e-9)


def test_pure_mode_II_kink():
    """A closed frictionless crack at -45 degrees under compression: K_I taken as 0, MTS -70.53 degrees."""
    res = nc.grow(inclined_crack(angle=-45.0, load=-1.0), da=0.1, steps=1, criterion="mts")
    first = res.table[res.table.step == 0]
    assert first.closed.all()
    assert np.all(first.K_II > 0)
    assert np.all(np.abs(first.kink_deg - MTS_MODE_II) < 1.0)
    assert res.steps[0]["load_factor"] == 1.0  # without K_Ic, relative to the first step
    assert res.K_Ic is None


# ------------------------------------------------------------------ centre-cracked strip
def test_centre_crack_grows_straight_and_follows_the_handbook():
    """The crack stays on the symmetry line exactly and lambda(a) = K_Ic / K_handbook(a) within 1%."""
    b = 1.0
    res = nc.grow(centre_cracked_strip(a_over_b=0.2, b=b), da=0.1, steps=5, K_Ic=1.0)
    df = res.table
    assert len(df) == 6 and df.grew.iloc[:-1].all()
    assert np.max(np.abs(np.asarray(res.paths[0])[:, 1])) <= 1e-6 * b
    assert np.allclose(df.x, np.linspace(0.2, 0.7, 6), atol=1e-12)
    handbook = np.array([1.0 / centre_cracked_K(a / b, b=b) for a in df.x])
    err = df.load_factor.to_numpy() / handbook - 1
    assert np.all(np.abs(err) < 0.01), err
    assert np.all(np.diff(df.load_factor) < 0)  # unstable growth in tension: lambda falls


# ------------------------------------------------------------------------ wing cracks
WING_MU = 0.3


@pytest.fixture(scope="module")
def wings():
    scene = inclined_crack(angle=45.0, load=-1.0).with_(friction=WING_MU)
    return scene, nc.grow(scene, da=0.1, steps=4, K_Ic=1.0, maxh=2.0)


def _wing_segments(scene, result, n):
    """(main, wings, distance to the main crack's ends) of the crack samples of step n's profile
    (main: on the original segment)."""
    p0, p1 = (np.asarray(p) for p in scene.cracks[0].points)
    L = np.linalg.norm(p1 - p0)
    t = (p1 - p0) / L
    prof = result.profiles[n][0]
    xy = np.column_stack([prof.x, prof.y]) - p0
    s = xy @ t
    off = np.abs(xy @ np.array([-t[1], t[0]]))
    main = (off < 1e-9) & (s > 0) & (s < L)
    return main, ~main, np.minimum(s, L - s)


def test_wings_start_at_the_mode_II_angle_and_load(wings):
    scene, res = wings
    cf = nc.scenes.inclined_closed_form(scene)
    K_II_eff = (abs(cf["tau"]) - WING_MU * abs(cf["sigma_n"])) * math.sqrt(math.pi)
    first = res.table[res.table.step == 0]
    assert first.closed.all() and first.grew.all()
    expected = 1.0 / (2 / math.sqrt(3) * K_II_eff)
    assert res.steps[0]["load_factor"] == pytest.approx(expected, rel=0.02)
    # MTS from the computed K: the pure mode II angle (K_II < 0 here: counter-clockwise)
    for r in first.itertuples():
        assert math.degrees(criteria.mts_angle(0.0, r.K_II)) == pytest.approx(-MTS_MODE_II, abs=2.0)
        # PLS (the default) kinks a little more than MTS: 73.0 degrees measured
        assert 1.0 < r.kink_deg - (-MTS_MODE_II) < 5.0


def test_wings_grow_stably_towards_the_compression_axis_open_with_the_main_crack_closed(wings):
    scene, res = wings
    lam = res.load_factors()
    assert np.all(np.diff(lam) > 0), lam  # stable: more load for every step
    pts = np.asarray(res.final_scene.cracks[0].points)
    wing = pts[-6:]  # the last end's wing: 4 segments after the kink point
    angles_from_axis = [abs(math.degrees(math.atan2(d[0], d[1]))) for d in np.diff(wing[1:], axis=0)]
    assert np.all(np.diff(angles_from_axis) < 0), angles_from_axis  # turning towards the y axis
    kinks = res.table[res.table.step.between(1, 3)].kink_deg
    assert np.all(kinks < 0) and np.all(kinks > -10)  # smooth: no zig-zag
    for n, step in enumerate(res.steps):
        assert max(step["kkt"].values()) < 1e-8
        main, wing_mask, to_kink = _wing_segments(scene, res, n)
        prof = res.profiles[n][0]
        state = np.asarray(prof.state)
        # the main crack stays closed and slides; only its edge at each kink (within one crack_h
        # of it) opens with the wing's mouth, by 1-4% of the largest opening (measured)
        near = to_kink < scene.crack_h
        assert np.all(state[main & ~near] == "slip")
        assert np.all(prof.normal_jump[main & near] < 0.05 * np.max(prof.normal_jump, initial=0.0) + 1e-300)
        if n:
            assert np.all(state[wing_mask] == "open")


# ---------------------------------------------------------------------- stops
def _clamped_strip(crack_end_x):
    return nc.Scene(name="clamped-strip", polygon=((0, 0), (2, 0), (2, 1), (0, 1)),
                    labels=("bottom", "right", "top", "left"), cracks=({"points": [[0, 0.5], [crack_end_x, 0.5]]},),
                    material={"E": 1000.0, "nu": 0.3},
                    boundary={"bottom": {"type": "clamped"}, "top": {"type": "displacement", "value": [0, 0.01]}},
                    maxh=0.25, tip_h=0.01, crack_h=0.05)


def test_tip_reaching_the_boundary_cuts_through():
    res = nc.grow(_clamped_strip(1.8), da=0.15, steps=3)
    assert res.stopped.startswith("cut through") and "2 pieces" in res.stopped
    assert len(res.scenes) == 2  # both pieces are held: the grown scene is a valid one, kept
    assert len(res.steps) == 1 and res.steps[0]["tips"][0]["grew"]
    assert res.paths[0][-1] == pytest.approx([2.0, 0.5], abs=1e-12)
    assert res.events[0][1] == "0,last" and "boundary" in res.events[0][2]


def test_tip_that_would_cross_another_crack_stops():
    scene = _clamped_strip(1.0).with_(cracks=({"points": [[0, 0.5], [1.0, 0.5]]},
                                              {"points": [[1.1, 0.3], [1.1, 0.7]]}))
    res = nc.grow(scene, da=0.15, steps=1, maxh=0.5)
    assert "0,last" in res.frozen and "would cross crack 1" in res.frozen["0,last"]
    assert np.allclose(res.paths[0], [[0, 0.5], [1.0, 0.5]])


def test_tip_that_reaches_a_hole_joins_it():
    """The hole-crack plate with the crack pointed at the hole: the near tip joins the hole (its end on
    the circle, the reason kept, no tip there any more); the far tip grows on."""
    scene = nc.scenes.load("hole-crack").with_(cracks=[nc.Crack(points=((12.6, 10.0), (15.0, 10.0)))])
    res = nc.grow(scene, da=0.25, steps=3, K_Ic=1.0, criterion="mts", maxh=2.0)
    assert "reached hole[0]" in res.frozen["0,first"] and "joined it" in res.frozen["0,first"]
    near = np.asarray(res.paths[0][0])
    assert np.hypot(*(near - (10.0, 10.0))) == pytest.approx(2.0, abs=1e-12)
    assert res.scenes[-1].hole_joins() == [(0, 0, 0)]
    assert res.paths[0][-1][0] > 15.0 + 0.5 * 0.25  # the far tip grew on once the near one had joined the hole


# ---------------------------------------------------------------------- command
def test_grow_command(tmp_path, capsys):
    out = tmp_path / "g.json"
    code = main(["grow", "griffith", "--da", "0.05", "--steps", "1", "--K-Ic", "2", "--criterion", "mts",
                 "--maxh", "0.5", "--json", str(out), "--csv", str(tmp_path / "g.csv"), "--vtk", str(tmp_path / "g")])
    assert code == 0
    # ParaView: one body and one crack file per step and their collection
    import meshio

    pvd = (tmp_path / "g.pvd").read_text()
    assert pvd.count("<DataSet") == 4 and "g_0001.vtu" in pvd
    cracks = [meshio.read(tmp_path / f"g_{n:04d}_cracks.vtu") for n in (0, 1)]
    openings = [float(np.max(c.cell_data["opening"][0])) for c in cracks]
    assert min(openings) > 0 and openings[1] > openings[0]  # the crack opens, and more once it is longer
    d = json.loads(out.read_text())
    assert d["K_Ic"] == 2.0 and d["criterion"] == "mts" and len(d["steps"]) == 2
    import pandas as pd

    table = pd.read_csv(tmp_path / "g.csv")
    assert list(table.columns[:5]) == ["step", "crack", "end", "x", "y"]
    assert np.allclose(table.K_eq, [t["K_eq"] for s in d["steps"] for t in s["tips"]])
    code = main(["grow", "griffith", "--da", "0.05", "--steps", "1", "--criterion", "maxG", "--json",
                 str(tmp_path / "bad.json")])
    assert code == 2 and "criterion" in capsys.readouterr().err and not (tmp_path / "bad.json").exists()


# ------------------------------------------------------------------ PLS against MTS (slow)
@pytest.mark.slow
def test_pls_against_mts_on_the_same_cases():
    """Tension at 45 degrees: the first kinks agree within 1 degree (PLS accepts the MTS trial:
    K_II at the new tip 2.4% of K_eq, measured). Wings (mu = 0.3): PLS kinks 2.5 degrees more
    at the start (73.0 against 70.5) and then turns smoothly (kinks of one sign, below 5 degrees),
    while explicit MTS from the same K zig-zags: kinks alternate in sign and grow beyond 20 degrees."""
    tension = inclined_crack(angle=45.0, load=1.0)
    kinks = {c: nc.grow(tension, da=0.1, steps=1, K_Ic=1.0, criterion=c).table for c in ("mts", "pls")}
    first = {c: t[t.step == 0].kink_deg.to_numpy() for c, t in kinks.items()}
    assert np.all(np.abs(first["pls"] - first["mts"]) < 1.0)
    scene = inclined_crack(angle=45.0, load=-1.0).with_(friction=WING_MU)
    runs = {c: nc.grow(scene, da=0.1, steps=6, K_Ic=1.0, criterion=c, maxh=2.0, frames=False) for c in ("mts", "pls")}
    last = {c: r.table[r.table.end == "last"].kink_deg.to_numpy() for c, r in runs.items()}
    assert last["pls"][0] - last["mts"][0] == pytest.approx(2.5, abs=1.5)
    assert np.all(last["pls"][1:6] < 0) and np.all(last["pls"][1:6] > -5.0)
    signs = np.sign(last["mts"][1:6])
    assert np.all(signs[1:] == -signs[:-1]) and np.max(np.abs(last["mts"][1:6])) > 20.0
    # both grow stably; after 6 steps lambda is 3.40 (PLS) and 2.88 (MTS), measured: the
    # zig-zag's mean path turns less towards the compression axis
    for r in runs.values():
        assert np.all(np.diff(r.load_factors()) > 0)
    assert runs["mts"].load_factors()[-1] < runs["pls"].load_factors()[-1]


def test_figures_and_animation(tension_mts, tmp_path):
    """The figure of the paths and load factors, and one GIF frame per step; writing them
    leaves pyplot's backend and figures alone (a notebook's later figures still show)."""
    import matplotlib
    import matplotlib.pyplot as plt
    from PIL import Image

    before = matplotlib.get_backend()
    plt.switch_backend("svg")  # (a backend that is not Agg: a switch to Agg would show)
    try:
        tension_mts.plot(tmp_path / "paths.png")
        tension_mts.animate(tmp_path / "growth.gif")
        assert matplotlib.get_backend() == "svg" and plt.get_fignums() == []
    finally:
        plt.switch_backend(before)
    assert Image.open(tmp_path / "paths.png").size[0] > 1000
    gif = Image.open(tmp_path / "growth.gif")
    assert gif.n_frames == len(tension_mts.steps) == 2
    frame = tension_mts.frames[1]
    assert frame["corners"].shape == frame["disp"].shape and frame["corners"].dtype == np.float32
    # the crack in tension is open: its two faces apart at every open sample
    face = frame["faces"][0]
    assert np.mean(face["open"]) > 0.9
    assert np.all(np.linalg.norm(face["plus"] - face["minus"], axis=1)[face["open"]] > 0)


def test_growth_view_shows_each_step_with_its_numbers(tension_mts):
    """The widget's step view: a picture per step and a readout that quotes the table."""
    from PIL import Image

    from ngcrack.shell.explorer.growth_view import explore_growth, render_step, step_readout

    for n in range(len(tension_mts.steps)):
        png = render_step(tension_mts, n)
        assert Image.open(io.BytesIO(png)).size[0] >= 700
        text = step_readout(tension_mts, n)
        row = tension_mts.table[tension_mts.table["step"] == n].iloc[0]
        assert f"K_I = {row['K_I']:.4g}" in text and f"K_II = {row['K_II']:.4g}" in text
        assert "left tip (" in text and "right tip (" in text and "tip 0," not in text
    pytest.importorskip("ipywidgets")
    view = explore_growth(tension_mts)
    (slider, box), status, image, readout = view.children[0].children, *view.children[1:]
    first = image.value
    slider.value = 1
    assert image.value != first and "step 1 of 1" in readout.value and status.value == "" and box.value == 1
    box.value = 99  # a typed step out of range: refused in one red line, the box back to the step shown
    assert "Step 99 is out of range: choose a step from 0 to 1." in status.value and "#b00020" in status.value
    assert box.value == slider.value == 1
    box.value = 0
    assert slider.value == 0 and image.value == first
    with pytest.raises(ValueError, match="result"):
        explore_growth("not a result")


def test_growth_frames_draw_kinks_and_the_body_without_rigid_motion(tension_mts):
    """A step's frame: the kink of each tip written on it (the table's angle), the drawn
    displacement free of rigid motion, the whole body inset where the view is a zoom."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from ngcrack.studies.growth.figures import _minus_rigid, draw_frame, without_rigid_motion

    fig = Figure()
    FigureCanvasAgg(fig)
    drawn = draw_frame(fig.add_subplot(), tension_mts, 0)
    kinks = tension_mts.table.query("step == 0").kink_deg
    assert sorted(drawn["kinks"]) == sorted(f"kink {k:+.1f}°" for k in kinks)
    assert all(abs(k + 53.13) < 3.0 for k in kinks)  # MTS at 45 degrees in tension: 2 arctan(-1/2)
    f = tension_mts.frames[0]
    rest = _minus_rigid(f["corners"], f["disp"], drawn["rigid"])
    a, _, w = without_rigid_motion(f["corners"], rest)  # nothing rigid is left in what is drawn
    scale = float(np.max(np.abs(rest)))
    assert np.max(np.abs(a)) < 1e-6 * scale and abs(w) * tension_mts.scene.diameter < 1e-6 * scale
    # a rigid motion alone is taken out to round-off
    pts = f["corners"].reshape(-1, 2).astype(float)
    rigid = np.array([0.3, -0.2]) + 1e-3 * np.stack([-(pts[:, 1] - 1.0), pts[:, 0] - 2.0], axis=1)
    assert np.max(np.abs(_minus_rigid(pts, rigid, without_rigid_motion(pts, rigid)))) < 1e-12
    assert drawn["zoom"]


def test_load_factor_panel_marks_tips_off_the_scale():
    """A closed tip that does not grow (load factor 1e5) is marked at the top, not plotted,
    and the scale is the growing tip's."""
    from types import SimpleNamespace

    import pandas as pd
    from matplotlib.figure import Figure

    from ngcrack.studies.growth.figures import draw_load_factors

    rows = [{"step": n, "crack": 0, "end": end, "x": x, "y": 0.0, "tip_load_factor": lam, "load_factor": 0.8 + 0.1 * n,
             "crack_length": 2.0 + 0.1 * n, "grew": end == "last", "closed": end == "first"}
            for n in range(3) for end, x, lam in (("first", -1.0, 1e5), ("last", 1.0, 0.8 + 0.1 * n))]
    tips = [{"crack": 0, "end": "first", "x": -1.0, "y": 0.0}, {"crack": 0, "end": "last", "x": 1.0, "y": 0.0}]
    res = SimpleNamespace(table=pd.DataFrame(rows), steps=[{"tips": tips}] * 3, K_Ic=1.0,
                          scene=SimpleNamespace(units=None))
    out = draw_load_factors(Figure().add_subplot(), res, step=1)
    assert out["off_scale"] == [(0, "left tip"), (1, "left tip"), (2, "left tip")]
    assert out["ylim"] == pytest.approx((0.0, 1.2 * 1.0)) and out["tips"] == ["left tip", "right tip"]


# ---------------------------------------------------------------------- studies
def test_growth_study_of_friction_resumes(tmp_path, monkeypatch):
    """One path per friction coefficient; the wings start at lambda = K_Ic / ((2/sqrt 3) K_II,eff(mu)),
    and a rerun with one more value runs only that one."""
    from ngcrack.studies.growth import study

    scene = inclined_crack(angle=45.0, load=-1.0, maxh=2.0, tip_h=0.01)
    out = tmp_path / "study.csv"
    table = study.grow_study(scene, "friction", [0.0], da=0.1, steps=1, K_Ic=1.0, out=out)
    assert list(table.columns) == ["friction", *study.STUDY_COLUMNS]
    expected = [1.0 / (2 / math.sqrt(3) * 0.5 * (1 - mu) * math.sqrt(math.pi)) for mu in (0.0, 0.3)]
    calls = []
    real = study._run_path

    def counting(scene, *args):
        calls.append(scene.cracks[0].friction)
        return real(scene, *args)

    monkeypatch.setattr(study, "_run_path", counting)
    again = study.grow_study(scene, "friction", [0.0, 0.3], da=0.1, steps=1, K_Ic=1.0, out=out)
    assert calls == [0.3]
    assert again.lambda_first[0] == pytest.approx(table.lambda_first[0], rel=1e-12) and len(again) == 2
    assert np.allclose(again.lambda_first, expected, rtol=0.02)
    assert np.all(again.lambda_last > again.lambda_first) and np.all(again.steps == 1)
    assert len(out.read_text().strip().splitlines()) == 3  # header and two paths


@pytest.mark.slow
def test_growth_study_on_worker_processes_gives_the_serial_rows():
    scene = inclined_crack(angle=45.0, load=-1.0, maxh=2.0, tip_h=0.01)
    from ngcrack.studies.growth import grow_study

    serial = grow_study(scene, "friction", [0.0, 0.3], da=0.1, steps=1, K_Ic=1.0)
    parallel = grow_study(scene, "friction", [0.0, 0.3], da=0.1, steps=1, K_Ic=1.0, jobs=2)
    for col in ("final_length", "lambda_first", "lambda_last"):
        assert np.allclose(serial[col], parallel[col], rtol=1e-10)
    assert list(serial.stopped) == list(parallel.stopped)


def test_a_failing_later_solve_stops_the_run_keeping_its_steps(monkeypatch):
    real, count = loop.solve_step, []

    def once(scene, previous, options):
        count.append(1)
        if len(count) > 1:
            raise nc.SolveError("the condensed system is singular")
        return real(scene, previous, options)

    monkeypatch.setattr(loop, "solve_step", once)
    res = nc.grow(_clamped_strip(1.0), da=0.1, steps=3, maxh=0.5)
    assert res.stopped.startswith("solve:") and "singular" in res.stopped
    assert len(res.steps) == 1 and res.final_scene is res.scene
