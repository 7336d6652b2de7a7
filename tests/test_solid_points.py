"""3D point supports and point loads (ngcrack.solid.points, ngcrack.solid.point_means).

A box in tension on two opposite faces held by 3-2-1 points (a pin, three rollers: six
constraints on its rigid motions and nothing else) has the uniform stress to round-off and
zero reactions, with the mixed element and the displacement baseline; a force at a point is
balanced by the supports' reactions, forces and moments, to round-off. Every bad point is
refused by name before meshing.
"""

from __future__ import annotations

import copy

import ngsolve as ngs
import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.fields import SceneError
from ngcrack.solid.point_means import point_values
from ngcrack.solid.scene import SolidScene

#: a pin on the top face, a roller on the front face (y) and two on the bottom (z): statically determinate
SUPPORTS = [{"at": [1.0, 0.5, 0.5], "type": "pin", "width": 0.3},
            {"at": [1.5, 0.0, 0.0], "type": "roller", "width": 0.3},
            {"at": [1.5, 0.5, -0.5], "type": "roller", "width": 0.3},
            {"at": [1.0, 0.2, -0.5], "type": "roller", "width": 0.3}]


def _box(boundary=None, points=SUPPORTS, maxh=1.0) -> dict:
    return {"name": "box", "domain": {"box": [[0, 0, -0.5], [2, 1, 0.5]]}, "material": {"E": 100.0, "nu": 0.3},
            "boundary": {"xmin": {"type": "traction", "value": [-1.0, 0, 0]},
                         "xmax": {"type": "traction", "value": [1.0, 0, 0]}} if boundary is None else boundary,
            "point": copy.deepcopy(points), "mesh": {"maxh": maxh}}


def _stress_error(sol, exact) -> float:
    s, mesh = sol.disc.fields(sol.gf)["sigma"], sol.smesh.mesh
    return float(np.sqrt(ngs.Integrate(ngs.InnerProduct(s - exact, s - exact), mesh)
                         / ngs.Integrate(ngs.InnerProduct(exact, exact), mesh)))


@pytest.mark.parametrize("element", ["tdnns", "h1p2"])
def test_321_points_hold_a_free_box_in_tension_without_constraining_it(element):
    scene = SolidScene.from_dict(_box())
    sol = nc.solve(scene, element=element)
    exact = ngs.CF((1, 0, 0, 0, 0, 0, 0, 0, 0), dims=(3, 3))
    assert _stress_error(sol, exact) < 1e-9
    values = point_values(sol)
    for v in values.values():  # the load is in equilibrium: no reaction (the load's resultant on a face is 1)
        assert np.abs(v["force"]).max() < 1e-8
    # every patch's mean displacement is the exact field's at its centre: the uniform strain plus the rigid
    # motion t + w x p that the six constraints fix
    strain = np.array([1.0, -0.3, -0.3]) / 100.0
    rows, rhs = [], []
    for pc in scene.points:
        basis = np.hstack([np.eye(3), np.array([np.cross(e, pc.at) for e in np.eye(3)]).T])
        for d in pc.directions():
            rows.append(np.asarray(d) @ basis)
            rhs.append(-np.dot(d, strain * pc.at))
    t_w = np.linalg.solve(np.array(rows), np.array(rhs))
    for pc in scene.points:
        u = strain * pc.at + t_w[:3] + np.cross(t_w[3:], pc.at)
        assert np.abs(np.array(values[pc.label]["displacement"]) - u).max() < 1e-11


def test_a_point_force_is_balanced_by_the_reactions():
    force = [0.3, 0.1, -0.2]
    scene = SolidScene.from_dict(_box(boundary={}, points=SUPPORTS + [
        {"at": [2.0, 0.5, 0.1], "type": "force", "value": force, "width": 0.3}]))
    sol = nc.solve(scene, element="h1p2")
    values = point_values(sol)
    assert values["point4"]["force"] == tuple(force)
    total = np.sum([v["force"] for v in values.values()], axis=0)
    moment = np.sum([np.cross(pc.at, values[pc.label]["force"]) for pc in scene.points], axis=0)
    assert np.abs(total).max() < 1e-12 and np.abs(moment).max() < 1e-12
    # the pin carries the force's x component alone (the only x support)
    assert values["point0"]["force"][0] == pytest.approx(-0.3, abs=1e-12)
    record = sol.to_json_dict()  # the JSON record and the report carry them
    assert record["points"]["point4"]["force"] == force and record["points"]["point0"]["type"] == "pin"
    assert any(line.startswith("point0 (pin): force [-0.3") for line in sol.report_lines(record))


def test_points_count_in_the_rigid_motion_check_and_round_trip():
    scene = SolidScene.from_dict(_box())
    assert [pc.face for pc in scene.points] == ["zmax", "ymin", "zmin", "zmin"]
    assert SolidScene.from_toml_string(scene.to_toml_string()) == scene
    pts = copy.deepcopy(SUPPORTS)
    del pts[0]["width"]
    assert SolidScene.from_dict(_box(points=pts)).points[0].width == 0.5  # half of maxh, as in 2D
    with pytest.raises(SceneError, match="leave 1 rigid motion"):
        SolidScene.from_dict(_box(points=SUPPORTS[:3]))


@pytest.mark.parametrize("change, match", [
    ({"at": [1.0, 0.5, 0.2]}, r"point\[0\]\.at = .*not on the body's boundary"),
    ({"type": "hinge"}, r"point\[0\]\.type = 'hinge': allowed types are force, pin, roller"),
    ({"width": 1.2}, r"point\[0\]\.width = 1\.2: the patch .* does not fit on face 'zmax'"),
    ({"value": [1, 0, 0]}, r"point\[0\]\.value = .*takes no value"),
    ({"at": [1.0, 0.5, 0.5], "label": "xmin"}, r"point\[0\]\.label = 'xmin': already a label"),
    ({"colour": 1}, r"point\[0\]"),
])
def test_bad_points_are_refused_by_name(change, match):
    pts = copy.deepcopy(SUPPORTS)
    pts[0].update(change)
    with pytest.raises(SceneError, match=match):
        SolidScene.from_dict(_box(points=pts))


def test_overlaps_faces_and_cylinders_refused_by_name():
    pts = copy.deepcopy(SUPPORTS) + [{"at": [1.1, 0.5, 0.5], "type": "force", "value": [0, 0, 1]}]
    with pytest.raises(SceneError, match=r"point\[4\]\.at = .*overlaps the patch of point\[0\]"):
        SolidScene.from_dict(_box(points=pts))
    with pytest.raises(SceneError, match=r"boundary\.point0: the patch of a point"):
        SolidScene.from_dict(_box(boundary={"point0": {"type": "clamped"}}))
    with pytest.raises(SceneError, match=r"point\[0\]\.at = .*on face 'zmax', which is clamped"):
        SolidScene.from_dict(_box(boundary={"zmax": {"type": "clamped"}}))
    cyl = {"name": "c", "domain": {"cylinder": {"center": [0, 0, 0], "axis": [0, 0, 1], "radius": 1, "height": 2}},
           "material": {"E": 1.0, "nu": 0.3}, "boundary": {"bottom": {"type": "clamped"}},
           "point": [{"at": [1.0, 0.0, 0.0], "type": "force", "value": [1, 0, 0]}]}
    with pytest.raises(SceneError, match=r"point\[0\]\.at = .*on the cylinder's side, a curved face"):
        SolidScene.from_dict(cyl)
    cyl["point"][0]["at"] = [0.5, 0.0, 1.0]
    assert SolidScene.from_dict(cyl).points[0].face == "top"


def test_points_are_refused_by_the_distributed_solve_by_name():
    from ngcrack.core.errors import InputError
    from ngcrack.distributed.solid import check_supported

    with pytest.raises(InputError, match=r"point\[0\]: point supports are solved serially"):
        check_supported(SolidScene.from_dict(_box()), {"element": "tdnns"}, size=2)
