"""Loads that vary in space on 3D bodies (ngcrack.solid.loads).

A box bent by tractions linear across its depth on its two ends, held by 3-2-1 points, has
the beam's stress sigma_xx = -M z / I exactly (TDNNS order 2 and H1-P2: the linear stress is in
their spaces); a penny opened by a pressure p0 + p1 x / a has K_I = 2 p0 sqrt(a / pi) +
(4/3) p1 sqrt(a / pi) cos(theta) (the penny's weight function integrated; checked by quadrature
against the uniform case) to the accuracy of the uniform case on the same mesh. Tables and
callables give the same CoefficientFunction for a linear field; bad fields are refused by name.
"""

from __future__ import annotations

import copy
import math

import ngsolve as ngs
import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.fields import SceneError
from ngcrack.solid.scene import SolidScene

SUPPORTS = [{"at": [1.0, 0.5, 0.5], "type": "pin", "width": 0.5},
            {"at": [1.5, 0.0, 0.0], "type": "roller", "width": 0.5},
            {"at": [1.5, 0.5, -0.5], "type": "roller", "width": 0.5},
            {"at": [1.0, 0.3, -0.5], "type": "roller", "width": 0.5}]


def _bent(xmin, xmax) -> dict:
    return {"name": "bent", "domain": {"box": [[0, 0, -0.5], [2, 1, 0.5]]}, "material": {"E": 100.0, "nu": 0.3},
            "boundary": {"xmin": {"type": "traction", "value": xmin}, "xmax": {"type": "traction", "value": xmax}},
            "point": copy.deepcopy(SUPPORTS), "mesh": {"maxh": 1.0}}


#: g_x = z on the left end and -z on the right: the moment of sigma_xx = -z
TABLES = ({"axis": [0, 0, 1], "table": [[-0.5, -0.5, 0, 0], [0.5, 0.5, 0, 0]]},
          {"axis": [0, 0, 1], "table": [[-0.5, 0.5, 0, 0], [0.5, -0.5, 0, 0]]})


@pytest.mark.parametrize("element, order", [("tdnns", 2), ("h1p2", None)])
def test_a_linear_traction_bends_a_box_as_beam_theory_says(element, order):
    scene = SolidScene.from_dict(_bent(*TABLES))
    sol = nc.solve(scene, element=element, order=order)
    s, mesh = sol.disc.fields(sol.gf)["sigma"], sol.smesh.mesh
    exact = ngs.CF((-ngs.z, 0, 0, 0, 0, 0, 0, 0, 0), dims=(3, 3))
    err = ngs.Integrate(ngs.InnerProduct(s - exact, s - exact), mesh) / ngs.Integrate(ngs.InnerProduct(exact, exact), mesh)
    assert math.sqrt(err) < 1e-9
    assert SolidScene.from_toml_string(scene.to_toml_string()) == scene


def test_tables_and_callables_give_the_same_field():
    table = SolidScene.from_dict(_bent(*TABLES))
    call = SolidScene.from_dict(_bent(lambda x, y, z: [z, 0.0, 0.0], lambda x, y, z: (-z, 0, 0)))
    mesh = ngs.Mesh(ngs.unit_cube.GenerateMesh(maxh=0.5))
    pts = [(0.1, 0.2, 0.3), (0.9, 0.4, 0.05), (0.5, 0.5, 0.45)]
    for label in ("xmin", "xmax"):
        a, b = table.tractions[label].value, call.tractions[label].value
        for p in pts:  # the callable's trilinear grid is exact for a linear field
            assert np.allclose(a.cf()(mesh(*p)), b.cf()(mesh(*p)), atol=1e-12, rtol=0)
        assert np.allclose(a.values(np.array(pts)), b.values(np.array(pts)), atol=1e-14)
    with pytest.raises(SceneError, match=r"boundary\.xmin\.value: a Python callable cannot be written"):
        call.to_toml_string()
    assert call.with_(E=200.0).tractions["xmin"].value is call.tractions["xmin"].value  # changed copies keep it


def _penny(p) -> dict:
    return {"name": "penny", "domain": {"box": [[-3, -3, -3], [3, 3, 3]]},
            "crack": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0, "pressure": p}],
            "material": {"E": 1000.0, "nu": 0.3}, "boundary": {"zmin": {"type": "clamped"}},
            "mesh": {"maxh": 1.5, "crack_h": 0.6, "front_h": 0.3}}


@pytest.mark.slow
def test_a_linear_pressure_on_a_penny_gives_its_closed_form_K():
    from ngcrack.core.options import SolveOptions
    from ngcrack.core.pipeline import Pipeline
    from ngcrack.solid.stages import SOLID

    pipeline, unit = Pipeline(), 2.0 * math.sqrt(1.0 / math.pi)  # one mesh; K in units of the uniform case's
    errors = []
    for p, p1 in ((1.0, 0.0), ({"axis": [1, 0, 0], "table": [[-1, 0.0], [1, 2.0]]}, 1.0)):
        sol = SOLID.solve(pipeline, SolidScene.from_dict(_penny(p)), SolveOptions())
        (front,) = sol.fronts
        cos = front.points[:, 0] / np.linalg.norm(front.points[:, :2], axis=1)
        ref = unit + 4.0 / 3.0 * p1 * math.sqrt(1.0 / math.pi) * cos
        errors.append(np.abs(front.K_I - ref).max() / unit)
    assert pipeline.counts["mesh"] == 1
    # measured (front_h = 0.3a, box 6a): 2.2% uniform, 1.8% linear
    assert errors[0] < 0.03 and errors[1] < errors[0] + 0.005, errors


@pytest.mark.parametrize("value, match", [
    ({"axis": [0, 0, 1]}, r"boundary\.xmin\.value\.table: missing"),
    ({"axis": [0, 0, 1], "table": [[0, 1, 0, 0]]}, r"boundary\.xmin\.value\.table = .*2 or more rows"),
    ({"axis": [0, 0, 1], "table": [[1, 1, 0, 0], [0, 1, 0, 0]]}, r"boundary\.xmin\.value\.table\[1\]: s = 0 is below"),
    ({"axis": [0, 0, 0], "table": [[0, 1, 0, 0], [1, 1, 0, 0]]}, r"boundary\.xmin\.value\.axis = .*nonzero direction"),
    ({"axis": [0, 0, 1], "table": [[0, 1], [1, 1]]}, r"boundary\.xmin\.value\.table\[0\] = .*\[s, gx, gy, gz\]"),
    (lambda x, y, z: 1 / 0, r"boundary\.xmin\.value: the callable failed at .*ZeroDivisionError"),
    (lambda x, y, z: [float("nan"), 0, 0], r"boundary\.xmin\.value: the callable returned"),
    ({"axis": [0, 0, 1], "table": [[0, 1e200, 0, 0], [1, 1, 0, 0]]}, r"boundary\.xmin\.value"),
])
def test_bad_tractions_are_refused_by_name(value, match):
    with pytest.raises(SceneError, match=match):
        SolidScene.from_dict(_bent(value, TABLES[1]))


def test_bad_pressures_are_refused_by_name():
    with pytest.raises(SceneError, match=r"crack\[0\]\.pressure\.axis = .*along the crack's normal"):
        SolidScene.from_dict(_penny({"axis": [0, 0, 1], "table": [[0, 1], [1, 2]]}))
    with pytest.raises(SceneError, match=r"crack\[0\]\.pressure: the callable returned"):
        SolidScene.from_dict(_penny(lambda x, y, z: [1, 2]))
    with pytest.raises(SceneError, match=r"crack\[0\]\.pressure = 'high'"):
        SolidScene.from_dict(_penny("high"))
    scene = SolidScene.from_dict(_penny({"axis": [1, 1, 0], "table": [[-1, 0.0], [1, 2.0]]}))
    assert scene.cracks[0].pressure.values(np.array([[0.5, 0.5, 0.0]]))[0, 0] == pytest.approx(1 + math.sqrt(0.5))
