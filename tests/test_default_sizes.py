"""Mesh sizes a scene does not give: derived from its shortest crack, graded.

Rule (sizing.default_mesh_sizes): when neither the scene's [mesh] nor the caller gives
maxh, crack_h or tip_h, maxh = diameter / 10, crack_h = L / 40 and tip_h = L / 400 with L
the shortest crack's length, grading 0.2 unless the scene gives one.
"""

import math

import pytest

import ngcrack as nc
from ngcrack import scenes
from ngcrack.planar import sizing
from ngcrack.planar.geometry import make_mesh

NO_SIZES = dict(maxh=None, tip_h=None, crack_h=None, grading=None)
#: K_I / (p sqrt(pi a)) of the 40 x 40 plate (rollers left and bottom, crack length 2),
#: converged: bdm at maxh 0.5, crack_h 0.02, tip_h 0.002 (380k unknowns) gives 1.0012,
#: and 1.0011 at crack_h 0.01, tip_h 0.001
PLATE40_K = 1.0012
#: the same for the built-in griffith (half of a 20 x 20 plate): the finite plate's value
GRIFFITH_K = 1.00936


def plate40():
    """The 40 x 40 plate with a crack of length 2 under tension 1, without a [mesh] section."""
    return scenes.griffith_plate(plate=20.0).with_(**NO_SIZES)


def test_the_rule_and_its_description():
    s = plate40()
    d = sizing.default_mesh_sizes(s)
    assert d["maxh"] == pytest.approx(s.diameter / 10, rel=1e-14)
    assert (d["crack_h"], d["tip_h"], d["grading"]) == (pytest.approx(2 / 40), pytest.approx(2 / 400), 0.2)
    assert sizing.mesh_sizes(s) == (pytest.approx(d["maxh"]), d["tip_h"], d["crack_h"], 0.2)
    line = sizing.describe_mesh_sizes(s)
    assert "crack_h 0.05" in line and "tip_h 0.005" in line and "shortest crack" in line
    # any size given, by the scene or the caller, turns the rule off (uniform meshes stay uniform)
    assert sizing.mesh_sizes(s, maxh=1.0)[1:3] == (None, None)
    assert sizing.mesh_sizes(s.with_(maxh=1.0))[1:3] == (None, None)
    assert "given" in sizing.describe_mesh_sizes(s, maxh=1.0)
    # no crack: only maxh
    assert sizing.default_mesh_sizes(scenes.load("no-crack").with_(maxh=None))["tip_h"] is None


def test_sizes_come_from_the_shortest_crack_and_every_crack_gets_20_edges():
    s = scenes.load("two-cracks").with_(**NO_SIZES)
    L = min(c.length for c in s.cracks)
    cm = make_mesh(s)
    assert (cm.crack_h, cm.tip_h) == (pytest.approx(L / 40), pytest.approx(L / 400))
    assert min(len(c) for c in cm.cracks) >= 20


@pytest.mark.parametrize("element", ["bdm", "tdnns"])
def test_plate_40_with_crack_2_gets_graded_sizes_and_K_within_1_percent(element):
    """Before: maxh = diameter/10 = 5.7, one crack edge. Now: >= 20 edges (55 measured) and
    K_I within 1% of the plate's converged value (bdm -0.1%, tdnns +0.1% measured)."""
    sol = nc.solve(plate40(), element=element)
    assert all(len(c) >= 20 for c in sol.crack_mesh.cracks)
    assert len(sol.tips) == 2
    for tip in sol.tips:
        assert tip.K_I / math.sqrt(math.pi) == pytest.approx(PLATE40_K, rel=0.01)


@pytest.mark.parametrize("element", ["bdm", "tdnns"])
def test_griffith_without_mesh_section_K_within_1_percent(element):
    """The built-in griffith with its [mesh] removed: K_I = 1.00936 p sqrt(pi a) (the finite
    plate's value) to 1% (bdm -0.17%, tdnns +0.02% measured)."""
    sol = nc.solve(scenes.load("griffith").with_(**NO_SIZES), element=element)
    assert len(sol.crack_mesh.cracks[0]) >= 20
    (tip,) = sol.tips
    assert tip.K_I / math.sqrt(math.pi) == pytest.approx(GRIFFITH_K, rel=0.01)
    assert sol.crack_mesh.tip_h == pytest.approx(1 / 400) and sol.crack_mesh.grading == 0.2
