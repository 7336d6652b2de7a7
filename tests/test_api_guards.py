"""The Python API refuses bad values by name before any work, as the command line does.

Each case of the table is a call a user may make with a wrong value; it must raise a
ValueError (InputError or SceneError) whose message names the field, before any mesh
is made (the cases run in well under a second each: no solve happens).
"""

from __future__ import annotations

import pytest

import ngcrack as nc
from ngcrack.core.pipeline import Pipeline


@pytest.fixture(scope="module")
def penny():
    return nc.scenes.load("penny")


def _penny_crack(penny, **changes):
    return [dict(penny.cracks[0].to_dict(), **changes)]


CASES = [
    ("3D replace: radius 1e-300", lambda p: p.replace(cracks=_penny_crack(p, radius=1e-300)), r"crack\[0\]: its smallest size 1e-300"),
    ("3D replace: E 1e300", lambda p: p.replace(material={"E": 1e300, "nu": 0.3}), r"material\.E = 1e\+300"),
    ("3D replace: traction 1e300", lambda p: p.replace(boundary={**p.boundary, "zmax": {"type": "traction", "value": [0, 0, 1e300]}}),
     r"boundary\.zmax\.value"),
    ("3D replace: ellipse axis 1e-9", lambda p: p.replace(cracks=[{"shape": "ellipse", "center": [0, 0, 0], "normal": [0, 0, 1],
                                                                    "semi_axes": [1.0, 1e-9], "major_axis": [1, 0, 0]}]),
     r"crack\[0\]: its smallest size 1e-09"),
    ("3D replace: unknown field", lambda p: p.replace(colour="red"), r"colour: not a field of a 3D scene"),
    ("3D solve: maxh 1e-300", lambda p: nc.solve(p, maxh=1e-300), r"maxh = 1e-300"),
    ("3D solve: order True", lambda p: nc.solve(p, order=True), r"order = True"),
    ("3D solve: front_points 0", lambda p: nc.solve(p, front_points=0), r"front_points"),
    ("crack volume of a scene", lambda p: nc.crack_volume(nc.scenes.load("griffith"), [0]), r"sol = PlanarScene: must be a solution"),
    ("volume 1e300", lambda p: nc.solve_volume("griffith", volume=1e300), r"volume = 1e\+300"),
    ("negative volume", lambda p: nc.solve_volume("griffith", volume=-1.0), r"volume = -1\.0: must be >= 0"),
    ("grow: R without paris", lambda p: nc.grow("griffith", 0.1, 2, R=0.5), r"R = 0\.5"),
    ("grow: estimate 'yes'", lambda p: nc.grow("griffith", 0.1, 2, estimate="yes"), r"estimate = 'yes'"),
    ("hydrofrac: progress 'x'", lambda p: nc.hydrofrac("kgd", rate=1e-4, K_Ic=1e6, da=0.5, steps=2, progress="x"),
     r"progress = 'x'"),
]


@pytest.mark.parametrize("call, message", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_a_bad_value_is_refused_by_name_before_any_mesh(penny, monkeypatch, call, message):
    def no_mesh(*args, **kwargs):
        raise AssertionError("a mesh was made before the refusal")

    monkeypatch.setattr(Pipeline, "mesh", no_mesh)
    with pytest.raises(ValueError, match=message):
        call(penny)


def test_a_3d_replace_keeps_what_it_does_not_change(penny):
    """replace() rebuilds the scene through the same checks; unchanged fields give an equal scene."""
    assert penny.replace() == penny
    assert penny.replace(cracks=penny.cracks, maxh=3.0) == penny.with_(maxh=3.0)
    moved = penny.replace(cracks=_penny_crack(penny, radius=2.0))
    assert moved.cracks[0].radius == 2.0 and moved.material == penny.material
