"""Crack paths as they are grown (ngcrack.studies.growth): the kinked-crack relations against their
closed forms (no mesh), no kink where the new tip is not in the state the criterion
assumes (the zig-zag of an edge crack under compression with friction), and the cost
of PLS steps.

Measured (tdnns, the scene's default mesh): the zig-zag scene below kinked -47, +54,
+50, -69, -69, +79 degrees before (a closed new tip accepted; the previous kink carried
over at a tip with K_II = 0); now -7.9, +1.6, +0.03, -0.03 degrees at load factors 11.7,
17.8, 21.1, 28.6, then the tip's faces close straight ahead (K_I falls from 0.115 to
0.038 as it runs into the compressed ligament) and the run stops with that reason.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.scenes.handbook import centre_cracked_K, centre_cracked_strip
from ngcrack.shell.cli import main
from ngcrack.studies.growth import criteria, fatigue, holes

MODE_II_PLS_EXACT = 77.3  # Amestoy and Leblond's exact PLS angle under pure mode II (degrees)


# ------------------------------------------------------------------ kinked-crack relations (no mesh)
def test_kink_factors_at_zero_and_their_parity():
    assert criteria.kink_factors(0.0) == pytest.approx((1.0, 0.0, 0.0, 1.0), abs=1e-15)
    for t in (0.1, 0.5, 1.2):
        f, g = criteria.kink_factors(t), criteria.kink_factors(-t)
        assert (f[0], f[3]) == pytest.approx((g[0], g[3]), rel=1e-14)  # F_11, F_22 even
        assert (f[1], f[2]) == pytest.approx((-g[1], -g[2]), rel=1e-14)  # F_12, F_21 odd


def test_kink_factors_agree_with_cotterell_rice_to_first_order():
    """Both are the singular field's stresses to first order in theta: k_1 = K_I - 3/2 theta K_II,
    k_2 = K_II + theta K_I / 2; F_11 agrees to second order (1 - 3 theta^2 / 8); the difference is O(theta^2)."""
    h = 1e-5
    for fun in (criteria.kink_factors, criteria.cotterell_rice):
        d = (np.array(fun(h)) - np.array(fun(-h))) / (2 * h)
        assert d[1] == pytest.approx(-1.5, abs=1e-8) and d[2] == pytest.approx(0.5, abs=1e-8)
        assert (fun(h)[0] - 1) / h ** 2 == pytest.approx(-3 / 8, abs=1e-4)
    for t in (0.01, 0.02, 0.04):
        diff = np.max(np.abs(np.array(criteria.kink_factors(t)) - np.array(criteria.cotterell_rice(t))))
        assert diff < 0.2 * t ** 2


@pytest.mark.parametrize("k1, k2", [(1.0, 0.3), (0.2, -1.0), (2.0, 1e-3), (0.0, 0.5), (1.0, 1.0)])
def test_cotterell_rice_k2_vanishes_at_the_mts_angle(k1, k2):
    """First order: sigma_rt = 0 where sigma_tt is largest, so k_2 = 0 exactly at the MTS angle."""
    f = criteria.cotterell_rice(criteria.mts_angle(k1, k2))
    assert f[2] * k1 + f[3] * k2 == pytest.approx(0.0, abs=1e-14)
    assert f[0] * k1 + f[1] * k2 == pytest.approx(criteria.mts_keq(k1, k2), rel=1e-12)


def test_pls_kink_angle():
    mode_II = math.degrees(criteria.pls_kink_angle(0.0, 1.0))
    assert abs(abs(mode_II) - MODE_II_PLS_EXACT) < 1.0 and mode_II < 0  # K_II > 0: clockwise
    assert criteria.pls_kink_angle(0.0, -1.0) == pytest.approx(-criteria.pls_kink_angle(0.0, 1.0), rel=1e-12)
    assert criteria.pls_kink_angle(1.0, 0.0) == 0.0
    for k1, k2 in ((1.0, 0.3), (1.0, 1.0), (0.5, -2.0)):
        t = criteria.pls_kink_angle(k1, k2)
        k1_new, k2_new = criteria.kinked_K(k1, k2, t)
        assert k2_new == pytest.approx(0.0, abs=1e-12) and k1_new > 0
        assert abs(t) > abs(criteria.mts_angle(k1, k2))  # PLS kinks a little more than MTS
    # small K_II / K_I: -2 K_II / K_I, the first-order angle
    assert criteria.pls_kink_angle(1.0, 1e-4) == pytest.approx(-2e-4, rel=1e-6)


def test_predictor_carries_only_a_smooth_path_s_kink():
    """A grown tip's previous kink is carried over only where it is a path's curvature (a few
    degrees): after a large kink the K at the tip says where to go (here straight on)."""
    small, large = math.radians(3.0), math.radians(-68.7)
    assert criteria.pls_predictor(1.0, 0.0, small) == pytest.approx(small)
    assert criteria.pls_predictor(0.118, -0.0002, large) == pytest.approx(criteria.pls_kink_angle(0.118, -0.0002))
    assert abs(criteria.pls_predictor(0.118, -0.0002, large)) < math.radians(0.5)
    # the K_II left at the tip corrects the carried kink by the measured slope
    assert criteria.pls_predictor(1.0, 0.1, small, slope=2.0) == pytest.approx(small - 0.05)


# ------------------------------------------------------------------ the zig-zag scene
def zigzag_scene():
    """A plate with a hole, a closed inclined crack beside it and an edge crack from the bottom,
    under compression with friction 0.3 on both cracks."""
    return nc.Scene(name="zigzag", polygon=((0, 0), (10, 0), (10, 4), (0, 4)), labels=("bottom", "right", "top", "left"),
                    holes=[{"center": [5, 2], "radius": 0.6, "label": "hole"}],
                    cracks=({"points": [[6.0, 2.0], [7.0, 2.3]], "friction": 0.3},
                            {"points": [[3.0, 0.0], [3.0, 1.0]], "friction": 0.3}),
                    material={"E": 1000.0, "nu": 0.3},
                    boundary={"bottom": {"type": "roller"}, "left": {"type": "roller"},
                              "top": {"type": "traction", "value": [0, -1]}})


@pytest.fixture(scope="module")
def zigzag():
    # the path at crack_h all along: where the tip closes is a threshold (with growth's graded path its
    # K_I at step 5 is 2e-4 of step 1's, open by a hair, and PLS's K_II/K_I means nothing there)
    return nc.grow(zigzag_scene(), da=0.15, steps=6, K_Ic=2.0, path_grading=None)


def test_zigzag_scene_grows_smoothly_then_stops_where_its_tip_closes(zigzag):
    res = zigzag
    df = res.table
    edge = df[(df.crack == 1) & (df.end == "last")]
    grown = edge[edge.grew]
    kinks = grown.kink_deg.to_numpy()
    assert len(kinks) >= 3
    assert abs(kinks[0]) < 15.0  # the first kink: K_I = 0.115, K_II = 0.081 at the tip
    assert np.all(np.abs(kinks[1:]) < 3.0), kinks  # then a smooth path: no zig-zag
    # every tip the path grew to was open (the state PLS assumes) and PLS held there
    after = edge[edge.step >= 1]
    assert not after.closed.any() and np.all(after.K_I > 0)
    assert np.all(np.abs(after.K_II) < 0.05 * after.K_I), after[["K_I", "K_II"]]
    # the closed inclined crack has no driving force: it never grows
    assert not df[df.crack == 0].grew.any()
    assert res.stopped.startswith("no tip can grow") and "close" in res.frozen["1,last"], res.stopped
    lam = res.load_factors()
    assert np.all(np.diff(lam[np.isfinite(lam)]) > 0)  # arrest: more load for every step


# ------------------------------------------------------------------ to failure
def test_a_crack_that_cuts_a_piece_loose_ends_the_run_with_its_last_segment():
    """An edge crack across a strip clamped at the bottom and pulled by a traction on the top:
    the segment that reaches the far edge leaves the top piece held by nothing. The run ends
    cleanly ("cut through"), the last segment in the paths and the JSON, no error."""
    scene = nc.Scene(name="pulled-strip", polygon=((0, 0), (2, 0), (2, 1), (0, 1)), labels=("bottom", "right", "top", "left"),
                     cracks=({"points": [[0, 0.5], [1.8, 0.5]]},), material={"E": 1000.0, "nu": 0.3},
                     boundary={"bottom": {"type": "clamped"}, "top": {"type": "traction", "value": [0, 1.0]}},
                     maxh=0.25, tip_h=0.01, crack_h=0.05)
    res = nc.grow(scene, da=0.15, steps=3, K_Ic=1.0)
    assert res.stopped.startswith("cut through") and "2 pieces" in res.stopped, res.stopped
    assert len(res.steps) == 1 and res.steps[0]["tips"][0]["grew"]
    assert len(res.scenes) == 1  # the cut scene is no valid scene (a piece held by nothing): not kept
    end = res.paths[0][-1]
    assert end[0] == pytest.approx(2.0, abs=1e-12) and abs(end[1] - 0.5) < 0.01  # on the far edge
    d = res.to_json_dict()
    assert d["cracks"][0]["points"][-1] == pytest.approx(end.tolist(), abs=1e-12)
    assert d["stopped"] == res.stopped
    assert res.events[0][1] == "0,last"


# ------------------------------------------------------------------ fatigue
PARIS_C, PARIS_M = 1e-3, 3.0


def _handbook_life(a0, a1, b=1.0, R=0.0):
    from scipy.integrate import quad

    return quad(lambda a: 1.0 / (PARIS_C * ((1 - R) * centre_cracked_K(a / b, b=b)) ** PARIS_M), a0, a1)[0]


def test_step_cycles_integrates_the_paris_law():
    """Exact for a power law K ~ L^p (any p); within 0.1% of the handbook life of the
    centre-cracked strip from a = 0.2 to 0.6 with its K at steps of 0.05 (no mesh)."""
    for p in (0.5, 1.3):
        L = np.array([0.3, 0.35, 0.4])
        K = 2.0 * L ** p
        exact = (L[2] ** (1 - PARIS_M * p) - L[1] ** (1 - PARIS_M * p)) / (1 - PARIS_M * p) / (PARIS_C * 2.0 ** PARIS_M)
        assert fatigue.step_cycles(L, K, PARIS_C, PARIS_M) == pytest.approx(exact, rel=1e-12)
        assert fatigue.step_cycles(L[1:], K[1:], PARIS_C, PARIS_M) == pytest.approx(exact, rel=1e-12)
    a = np.linspace(0.2, 0.6, 9)
    K = [centre_cracked_K(x) for x in a]
    life = sum(fatigue.step_cycles(a[max(i - 1, 0):i + 2], K[max(i - 1, 0):i + 2], PARIS_C, PARIS_M) for i in range(8))
    assert life == pytest.approx(_handbook_life(0.2, 0.6), rel=1e-3)
    # R: Delta K = (1 - R) K_max, so the life grows by (1 - R)^-m; R < 0 counts K_max only
    one = fatigue.step_cycles(a[:2], K[:2], PARIS_C, PARIS_M)
    assert fatigue.step_cycles(a[:2], K[:2], PARIS_C, PARIS_M, R=0.5) == pytest.approx(one * 2 ** PARIS_M, rel=1e-12)
    assert fatigue.step_cycles(a[:2], K[:2], PARIS_C, PARIS_M, R=-1.0) == pytest.approx(one, rel=1e-12)


@pytest.mark.parametrize("kw, field", [({"paris": (1e-3,)}, "paris"), ({"paris": (1e-3, -3)}, "paris"),
                                       ({"paris": "fast"}, "paris"), ({"paris": (1e-3, 3), "R": 1.0}, "R")])
def test_bad_fatigue_input_refused_before_any_solve(kw, field):
    with pytest.raises(nc.InputError, match=f"^{field} = "):
        nc.grow(centre_cracked_strip(a_over_b=0.2), da=0.05, steps=1, **kw)


def test_fatigue_life_of_the_centre_cracked_strip():
    """From a/b = 0.2 to 0.6 by da = 0.05: the cycles within 1% of integrating the handbook K; the
    run stops where K_max reaches K_Ic (set between the handbook K at a = 0.55 and 0.6)."""
    K_Ic = 0.5 * (centre_cracked_K(0.55) + centre_cracked_K(0.6))
    res = nc.grow(centre_cracked_strip(a_over_b=0.2), da=0.05, steps=20, K_Ic=K_Ic, paris=(PARIS_C, PARIS_M))
    df = res.table
    assert np.allclose(df.x, np.linspace(0.2, 0.6, 9), atol=1e-12)
    assert df.cycles.iloc[0] == 0.0 and np.all(np.diff(df.cycles) > 0)
    life = df.cycles.iloc[-1]
    handbook = _handbook_life(0.2, 0.6)
    assert abs(life / handbook - 1) < 0.01, (life, handbook)
    assert res.stopped.startswith("fracture: K_max") and len(res.steps) == 9
    assert (df.load_factor == 1.0).all()  # the cycle's maximum load is the scene's
    steps = res.to_json_dict()["steps"]
    assert [s["cycles"] for s in steps] == pytest.approx(df.cycles.tolist(), rel=1e-12)


def test_closest_approach_to_each_hole_is_reported(zigzag):
    """The inclined crack starts at (6, 2), 1 from the centre of the hole of radius 0.6: 0.4 exactly."""
    (h,) = zigzag.holes
    assert h["label"] == "hole" and h["crack"] == 0
    assert h["distance"] == pytest.approx(0.4, abs=1e-12) and h["point"] == pytest.approx([6.0, 2.0], abs=1e-12)
    assert zigzag.to_json_dict()["holes"] == [h]
    assert "closest approach to hole: 0.4" in zigzag.summary()


# ------------------------------------------------------------------ cracks and holes
def _hole_crack():
    """The hole-crack plate (hole of radius 2 at (10, 10), tension along y) with the crack pointed at the hole."""
    return nc.scenes.load("hole-crack").with_(cracks=[nc.Crack(points=((12.6, 10.0), (15.0, 10.0)))])


def test_bad_at_hole_refused_before_any_solve(tmp_path, capsys):
    for bad in ("go", -1.0, True, 100.0):
        with pytest.raises(nc.InputError, match="^at_hole = "):
            nc.grow(_hole_crack(), da=0.25, steps=1, at_hole=bad)
    out = tmp_path / "bad.json"
    code = main(["grow", "hole-crack", "--da", "0.25", "--steps", "1", "--at-hole", "go", "--json", str(out)])
    assert code == 2 and "at_hole" in capsys.readouterr().err and not out.exists()


def test_a_crack_through_a_hole_leaves_it_where_the_hoop_stress_is_largest():
    """at_hole=1.0: the tip that reaches the hole joins it (the crack ends on the circle itself, that end
    no tip any more); a new crack of length 1 starts on the far side of the hole's edge, radially, where
    Kirsch's hoop stress is largest (3p at (8, 10), the arriving tip's side left out), and grows on."""
    scene = _hole_crack()
    res = nc.grow(scene, da=0.25, steps=3, K_Ic=1.0, criterion="mts", maxh=2.0, at_hole=1.0)
    near = res.paths[0][0]
    assert np.hypot(*(near - (10.0, 10.0))) == pytest.approx(2.0, abs=1e-12)  # on the circle, not its polygon
    assert "reached hole[0]" in res.frozen["0,first"] and "joined it" in res.frozen["0,first"]
    assert len(res.paths) == 2
    start, end = res.paths[1][0], res.paths[1][-1]
    assert np.hypot(*(start - (10.0, 10.0))) == pytest.approx(2.0, abs=1e-12)  # starts on the hole's edge
    direction = math.degrees(math.atan2(*(end - start)[::-1]))
    assert abs(abs(direction) - 180.0) < 2.0  # radial, to the left: the far side's largest hoop stress
    assert any("crack 1 leaves hole[0]" in what for _, _, what in res.events)
    h = res.holes[0]
    assert h["distance"] == pytest.approx(0.0, abs=1e-12) and h["crack"] == 0
    assert [t for t in res.scenes[-1].tip_points()] == [(0, tuple(res.paths[0][-1])), (1, tuple(end))]
    # the hoop stress the new crack left from, against Kirsch's 3p (the crack beside it changes it a little)
    phi, hoop = holes.hoop_stress(nc.solve(res.scenes[1], maxh=2.0), scene.holes[0])
    away = np.abs(np.angle(np.exp(1j * phi))) > holes.ARRIVAL_SECTOR
    assert phi[np.argmax(np.where(away, hoop, -np.inf))] == pytest.approx(math.pi, abs=0.02)
    assert hoop[np.argmin(np.abs(phi - math.pi))] == pytest.approx(3.0, rel=0.15)
