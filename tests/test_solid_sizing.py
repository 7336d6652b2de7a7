"""The 3D size guard (ngcrack.solid.sizing, issue 43 item 2): tetrahedra, unknowns and memory estimated before
meshing, against netgen's meshes and the measured solves; one-line refusals naming the size, before any meshing.
"""

from __future__ import annotations

import copy

import pytest

import ngcrack as nc
from ngcrack.core.errors import InputError
from ngcrack.scenes.coarse3d import bent_penny, coarse_penny, inclined_penny
from ngcrack.solid import sizing
from ngcrack.solid.scene import SolidScene


def _scene(d: dict, **mesh) -> SolidScene:
    d = copy.deepcopy(d)
    d["mesh"] = {**d.get("mesh", {}), **mesh}
    return SolidScene.from_dict(d)


def _ellipse() -> dict:
    d = coarse_penny()
    d["crack"] = [{"shape": "ellipse", "center": [0, 0, 0], "normal": [0, 0, 1], "semi_axes": [1.0, 0.5],
                   "major_axis": [1, 0, 0]}]
    return d


def _cylinder() -> dict:
    d = coarse_penny()
    d["domain"] = {"cylinder": {"center": [0, 0, 0], "axis": [0, 0, 1], "radius": 3.0, "height": 6.0}}
    d["boundary"] = {"bottom": {"type": "clamped"}, "top": {"type": "traction", "value": [0.0, 0.0, 1.0]}}
    return d


#: (scene, mesh sizes, netgen's tetrahedra; measured with the body's size near the cracks, BENCHMARKS.md "3D memory,
#: the ellipse in 3 GB and the accuracy option")
MESHES = [
    (coarse_penny, dict(maxh=5.0, crack_h=0.6, front_h=0.3, grading=0.3), 4595),
    (coarse_penny, dict(maxh=5.0, crack_h=0.4, front_h=0.2, grading=0.3), 8553),
    (coarse_penny, dict(maxh=5.0, crack_h=0.2, front_h=0.1, grading=0.3), 15700),
    (coarse_penny, dict(maxh=5.0, crack_h=0.4, front_h=0.05, grading=0.3), 25463),
    (coarse_penny, dict(maxh=5.0, crack_h=0.4, front_h=0.2, grading=0.5), 6474),
    (coarse_penny, dict(maxh=5.0, crack_h=0.4, front_h=0.2, grading=0.2), 19612),
    (bent_penny, dict(maxh=1.0, crack_h=0.3, front_h=0.15, grading=0.3), 5999),
    (_ellipse, dict(maxh=5.0, crack_h=0.2, front_h=0.1, grading=0.3), 21706),
    (_ellipse, dict(maxh=5.0, crack_h=0.25, front_h=0.09, grading=0.3), 13628),
    (_cylinder, dict(maxh=1.0, crack_h=0.3, front_h=0.1, grading=0.3), 9966),
]


@pytest.mark.parametrize("make, sizes, tets", MESHES)
def test_estimate_against_netgen(make, sizes, tets):
    ratio = sizing.estimate_tets(_scene(make(), **sizes)) / tets
    lo, hi = sizing.ESTIMATE_SPREAD
    assert lo <= ratio <= hi, ratio


def test_estimate_against_a_mesh_and_its_unknowns():
    """The inclined penny meshed now (509 tetrahedra when measured) and its TDNNS unknowns: within the spread; the
    built-in penny's unknowns per tetrahedron (order 1 at front_h 0.2a: 415,172 on 8,553, BENCHMARKS.md section 21) too."""
    from ngcrack.core.pipeline import Pipeline
    from ngcrack.solid.geometry import make_mesh
    from ngcrack.solid.solve import check_options

    scene = SolidScene.from_dict(inclined_penny())
    smesh = make_mesh(scene)
    est = sizing.estimate_size(scene)
    lo, hi = sizing.ESTIMATE_SPREAD
    assert lo <= est.tets / smesh.mesh.ne <= hi
    disc, _ = Pipeline().discretization(scene, smesh, {**check_options({}), **scene.mesh_sizes()})
    assert lo <= est.unknowns / disc.fes.ndof <= hi
    assert sizing.UNKNOWNS_PER_TET[("tdnns", 1)] == pytest.approx(415172 / 8553, rel=0.02)


@pytest.fixture
def no_mesh(monkeypatch):
    from ngcrack.solid import geometry

    def refuse(*a, **k):
        raise AssertionError("meshed before refusing")

    monkeypatch.setattr(geometry, "occ_geometry", refuse)


#: (keywords of check_size on the built-in penny, the start of the one-line refusal, a fragment of it)
REFUSED = [
    (dict(front_h=0.005), "front_h = 0.005: scene 'penny', element 'tdnns' would need about 2e+05 tetrahedra, "
     "9.81e+06 unknowns", "exceeds the default ceiling of 5000000 unknowns; use a larger front_h"),
    (dict(max_dof=1000), "crack_h = 0.4: scene 'penny'", "exceeds max_dof of 1000 unknowns"),
    (dict(crack_h=0.001, front_h=0.001), "crack_h = 0.001: scene 'penny'", "use a larger crack_h"),
    (dict(maxh=0.05), "maxh = 0.05: scene 'penny'", "use a larger maxh"),
    (dict(grading=5), "grading = 5: must lie in (0, 1]", "netgen gives up"),
    (dict(grading=1e-4), "front_h = 0.2", "tetrahedra"),
    (dict(maxh=1e-300), "maxh = 1e-300: below the smallest mesh size", "give maxh >= 3.46e-05"),
    (dict(front_h=float("nan")), "front_h = nan: must be a finite number > 0", ""),
    (dict(front_h=True), "front_h = True: must be a finite number > 0", ""),
    (dict(max_dof=2.5), "max_dof = 2.5", "whole number"),
]


@pytest.mark.parametrize("kw, start, fragment", REFUSED, ids=[repr(c[0]) for c in REFUSED])
def test_refused_in_one_line_before_meshing(no_mesh, kw, start, fragment):
    with pytest.raises(InputError) as info:
        sizing.check_size(nc.scenes.load("penny"), **kw)
    text = str(info.value)
    assert text.startswith(start) and fragment in text and "\n" not in text, text


def test_accepted_and_the_memory_limit(no_mesh, monkeypatch):
    penny = nc.scenes.load("penny")
    est = sizing.check_size(penny, max_dof=10 ** 8, front_h=0.005)  # an explicit ceiling: the caller takes it on
    assert est.culprit == "front_h" and est.unknowns == pytest.approx(9.81e6, rel=0.01)
    monkeypatch.setattr(sizing, "available_memory", lambda: 2e9)
    monkeypatch.setattr(sizing, "memory_limits", lambda: {"machine": 2e9})
    with pytest.raises(InputError, match=r"^crack_h = 0.4: .* 1.88 GB of memory; this machine has 2 GB available"):
        sizing.check_size(penny)  # the built-in penny: 1.15e4 tetrahedra (netgen 8,553), 5.6e5 unknowns (415,172)
