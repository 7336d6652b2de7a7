"""Loads that vary in space on 3D bodies, carried everywhere: closed forms, the error estimate, outputs, bad input.

Closed forms (a penny of radius a in a box of 6a, one mesh for all loads): under the
crack-face pressure p(r) = p0 (r / a)^2 the axisymmetric formula K_I = 2 / sqrt(pi a)
int_0^a p(r) r / sqrt(a^2 - r^2) dr gives K_I = (4/3) p0 sqrt(a / pi), 2/3 of the uniform
case's 2 p0 sqrt(a / pi); under p = p0 x / a with traction-free faces (no contact, so
that the closed half does not close) the penny's weight function (Tada's handbook, a
penny under an arbitrary pressure) gives K_I = (4/3) p0 sqrt(a / pi) cos(theta). Both are
asserted against K_I of the uniform pressure on the same mesh (its discretization error
cancels in the ratio): measured 1.1% (quadratic) and 1.9% (linear, of the uniform K) on
this coarse mesh at the default order (1).

The error estimate uses the applied loads: a uniform load given as a callable has the
estimate of the same load given as a number (to round-off), a crack-face pressure is load
data (an open pressurized penny's crack term is 7e-5 of eta^2, where -sigma_nn alone made
it 66% of eta^2), a traction linear over a face has no data term and a quadratic one a
data term that falls with the order. Bad varying loads are refused by field before meshing.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.fields import SceneError
from ngcrack.solid.scene import SolidScene

#: the coarse penny mesh of the closed-form checks (front_h 0.5a: 8 front points)
PENNY_MESH = {"maxh": 2.0, "crack_h": 0.8, "front_h": 0.5}


def _penny(p, mesh=None, traction=None) -> dict:
    d = {"name": "penny", "domain": {"box": [[-3, -3, -3], [3, 3, 3]]},
         "crack": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0, "pressure": p}],
         "material": {"E": 1000.0, "nu": 0.3}, "boundary": {"zmin": {"type": "clamped"}},
         "mesh": dict(mesh or PENNY_MESH)}
    if traction is not None:
        d["boundary"]["zmax"] = {"type": "traction", "value": traction}
    return d


@pytest.fixture(scope="module")
def pennies():
    from ngcrack.core.options import SolveOptions
    from ngcrack.core.pipeline import Pipeline
    from ngcrack.solid.stages import SOLID

    pipeline, out = Pipeline(), {}
    for name, p, model in (("uniform", 1.0, "contact"), ("quadratic", lambda x, y, z: x * x + y * y, "contact"),
                           ("linear", {"axis": [1, 0, 0], "table": [[-1, -1.0], [1, 1.0]]}, "free")):
        out[name] = SOLID.solve(pipeline, SolidScene.from_dict(_penny(p)), SolveOptions(crack_model=model))
    assert pipeline.counts["mesh"] == 1
    return out


def test_a_quadratic_pressure_gives_the_axisymmetric_closed_form(pennies):
    (u,), (q,) = pennies["uniform"].fronts, pennies["quadratic"].fronts
    assert np.abs(q.K_I / u.K_I / (2.0 / 3.0) - 1.0).max() < 0.03  # measured 1.1%
    assert np.abs(q.K_I / (4.0 / 3.0 / math.sqrt(math.pi)) - 1.0).max() < 0.06  # measured 4.9% (uniform: 5.8%)
    assert np.abs(q.K_II).max() < 0.01 * q.K_I.max() and np.abs(q.K_III).max() < 0.01 * q.K_I.max()


def test_a_linear_pressure_on_free_faces_gives_the_weight_function_closed_form(pennies):
    (u,), (f,) = pennies["uniform"].fronts, pennies["linear"].fronts
    cos = f.points[:, 0] / np.linalg.norm(f.points[:, :2], axis=1)
    assert np.abs(f.K_I / u.K_I - 2.0 / 3.0 * cos).max() < 0.03  # measured 1.9%
    assert np.min(f.K_I) < -0.5 * np.max(f.K_I)  # free faces: the negative half pulls (no contact)


def test_the_json_carries_the_applied_pressure_and_no_nan(pennies):
    for name, area_mean in (("uniform", 1.0), ("quadratic", 0.5), ("linear", 0.0)):
        sol = pennies[name]
        (crack,) = sol.to_json_dict()["cracks"]
        # int p dA over the meshed disc: p, p0 r^2 (mean 1/2), p0 x (mean 0); the disc's area to the mesh's accuracy
        assert crack["pressure_force"] == pytest.approx(area_mean * crack["area"], rel=1e-3, abs=1e-4 * crack["area"])
        json.dumps(sol.to_json_dict(), allow_nan=False)


ESTIMATE_MESH = {"maxh": 2.0, "crack_h": 0.7, "front_h": 0.5}


def _estimate(p, traction, order=1) -> dict:
    sol = nc.solve(SolidScene.from_dict(_penny(p, ESTIMATE_MESH, traction)), order=order, estimate=True)
    return sol.error_estimate, sol


@pytest.mark.slow
def test_a_uniform_load_as_a_callable_has_the_estimate_of_the_number():
    number, sol = _estimate(1.0, [0.3, 0.0, 0.5])
    call, _ = _estimate(lambda x, y, z: 1.0, lambda x, y, z: (0.3, 0.0, 0.5))
    assert call["total"] == pytest.approx(number["total"], rel=1e-10)  # measured 1e-14
    assert call["contact"] == pytest.approx(number["contact"], rel=1e-6, abs=1e-12 * number["total"] ** 2)
    # the pressure is data: the open penny's crack term is 7e-5 of eta^2 (with -sigma_nn alone: 66% of it)
    assert sol.contact.active.sum() == 0 and abs(number["contact"]) < 1e-3 * number["total"] ** 2
    assert number["data"] < 1e-10 * number["total"]  # a uniform traction's sigma_nn = g.n exactly
    record = sol.to_json_dict()["error_estimate"]
    assert record["total"] == number["total"] and record["data"] == number["data"]


def test_the_estimate_has_the_data_term_of_a_varying_traction():
    linear, _ = _estimate(1.0, {"axis": [1, 0, 0], "table": [[-3, 0, 0, 0.0], [3, 0, 0, 1.0]]})
    assert linear["data"] < 1e-10 * linear["total"]  # a linear g.n is in the normal-facet space
    quad, _ = _estimate(1.0, lambda x, y, z: (0.0, 0.0, 0.25 * x * x))
    assert 0.03 * quad["total"] < quad["data"] < 0.3 * quad["total"]  # measured 0.0050 of eta 0.065
    assert quad["total"] == pytest.approx(math.sqrt(quad["stress"] ** 2 + quad["contact"] + quad["data"] ** 2))


@pytest.mark.slow
def test_the_data_term_falls_with_the_order():
    quad = [_estimate(1.0, lambda x, y, z: (0.0, 0.0, 0.25 * x * x), order=k)[0] for k in (1, 2)]
    assert quad[1]["data"] < 0.05 * quad[0]["data"]  # measured 6.0e-5 against 0.0050


#: x = 1.125 is a plane of the traction's interpolation grid over the box [-3, 3] (33 points), not a probe point
GRID_PLANE = 1.125


@pytest.mark.parametrize("value, match", [
    (lambda x, y, z: [0, 0, math.nan if abs(x - GRID_PLANE) < 1e-9 else 1.0], r"boundary\.zmax\.value: the callable "
     r"returned \[0, 0, nan\] at \(x, y, z\) = \[1\.125, "),
    (lambda x, y, z: [0, 0, "a" if abs(x - GRID_PLANE) < 1e-9 else 1.0], r"boundary\.zmax\.value: the callable returned"),
    (lambda x, y, z: [0, 1.0], r"boundary\.zmax\.value: the callable returned .* must return 3 finite numbers"),
    (lambda x, y, z: [0, 0, 1, 0] if x > 1 else [0, 0, 1], r"boundary\.zmax\.value: the callable returned \[0, 0, 1, 0\]"),
    (lambda x, y, z: [0, 0, 1 / (x - GRID_PLANE)], r"boundary\.zmax\.value: the callable failed at .*ZeroDivisionError"),
    ({"axis": [1, 0, 0], "table": [[0, 0, 0, 1], [0, 0, 0, 2], [0, 0, 0, 3]]}, r"boundary\.zmax\.value\.table\[2\]: "
     r"a third row at s = 0"),
    ({"axis": [1, 0, 0], "table": [[0, 0, 0, 1], [1, 0, 0, float("nan")]]}, r"boundary\.zmax\.value\.table\[1\] = .*"
     r"finite numbers"),
    ({"axis": [1, 0, 0], "table": [[1, 0, 0, 1], [0.5, 0, 0, 2]]}, r"boundary\.zmax\.value\.table\[1\]: s = 0\.5 is "
     r"below"),
])
def test_bad_varying_tractions_are_refused_by_field_before_meshing(value, match):
    with pytest.raises(SceneError, match=match):
        SolidScene.from_dict(_penny(0.0, traction=value))


def test_bad_varying_pressures_are_refused_by_field_before_meshing():
    with pytest.raises(SceneError, match=r"crack\[0\]\.pressure: the callable returned nan"):
        SolidScene.from_dict(_penny(lambda x, y, z: math.nan if x * x + y * y > 0.9 else 1.0))
    with pytest.raises(SceneError, match=r"crack\[0\]\.pressure\.table\[1\] = "):
        SolidScene.from_dict(_penny({"axis": [1, 0, 0], "table": [[0, 1], [1, math.inf]]}))
    with pytest.raises(SceneError, match=r"crack\[0\]\.pressure\.table\[2\]: a third row"):
        SolidScene.from_dict(_penny({"axis": [1, 0, 0], "table": [[0, 1], [0, 2], [0, 3]]}))
    jump = SolidScene.from_dict(_penny({"axis": [1, 0, 0], "table": [[-1, 1], [0, 1], [0, 2], [1, 2]]}))
    assert jump.cracks[0].pressure.values(np.array([[-0.1, 0, 0], [0.1, 0, 0]]))[:, 0].tolist() == [1.0, 2.0]
    # a NaN met after the scene was built (the front's own evaluations) is refused by field, never a NaN result
    field = SolidScene.from_dict(_penny(lambda x, y, z: math.nan if abs(x - 0.3001) < 1e-4 else 1.0)).cracks[0].pressure
    with pytest.raises(SceneError, match=r"crack\[0\]\.pressure: the callable returned nan"):
        field.values(np.array([[0.3001, 0.0, 0.0]]))


def test_a_callable_pressure_follows_a_changed_crack():
    """The callable's grid covers the crack it was made for: a grown crack (3D growth re-validates it) gets a
    grid over itself, so the elements see the callable there, not the old grid's edge value."""
    import ngsolve as ngs

    scene = SolidScene.from_dict(_penny(lambda x, y, z: 1.0 + x))
    grown = dict(scene.cracks[0].to_dict(), radius=1.6)
    bigger = scene.with_(cracks=[SolidScene.from_dict(dict(_penny(0.0), crack=[grown])).cracks[0]])
    field = bigger.cracks[0].pressure
    assert field.fn is scene.cracks[0].pressure.fn and field.hi[0] > 1.6
    from netgen.occ import Box, OCCGeometry, Pnt

    mesh = ngs.Mesh(OCCGeometry(Box(Pnt(-2, -2, -1), Pnt(2, 2, 1))).GenerateMesh(maxh=1.0))
    # (1.5, 0, 0) is inside the bigger crack, outside the first one's grid: the callable's 2.5 (the old grid: 2.01)
    assert field.cf()(mesh(1.5, 0.0, 0.0)) == pytest.approx(2.5, abs=1e-9)
    assert scene.cracks[0].pressure.cf()(mesh(1.5, 0.0, 0.0)) < 2.1
    assert field.values(np.array([[1.5, 0.0, 0.0]]))[0, 0] == 2.5
    assert scene.with_(E=2000.0).cracks[0].pressure is scene.cracks[0].pressure  # an unchanged crack keeps its grid


def test_the_explorer_scales_varying_tractions_with_its_load():
    from ngcrack.shell.explorer.solid_view import SolidExplorer

    for value in ({"axis": [1, 0, 0], "table": [[-3, 0, 0, 0.0], [3, 0, 0, 0.6]]}, lambda x, y, z: [0, 0, 0.1 * (x + 3)]):
        scene = SolidScene.from_dict(_penny(lambda x, y, z: 1.0 + 0.5 * x, traction=value))
        made = SolidExplorer(scene, solve_now=False, load=2.0).make_scene()
        g = made.tractions["zmax"].value.values(np.array([[3.0, 0.0, 3.0], [0.0, 1.0, 3.0]]))
        assert np.allclose(g, [[0, 0, 1.2], [0, 0, 0.6]], atol=1e-14, rtol=0)
        assert made.cracks[0].pressure.fn is scene.cracks[0].pressure.fn


def test_a_table_pressure_keeps_its_origin_on_a_moved_crack_and_in_the_file():
    scene = SolidScene.from_dict(_penny({"axis": [1, 0, 0], "table": [[-1, 0.0], [1, 2.0]]}))
    # the grown crack's dict takes the crack's field itself, as 3D growth's does (studies.growth.fronts3d)
    moved = dict(scene.cracks[0].to_dict(), center=[0.5, 0.0, 0.0], radius=1.2, pressure=scene.cracks[0].pressure)
    other = SolidScene.from_dict(dict(_penny(0.0), crack=[moved]))
    assert other.cracks[0].pressure.given_origin and not scene.cracks[0].pressure.given_origin
    again = SolidScene.from_toml_string(other.with_(E=2000.0).to_toml_string())
    pts = np.array([[0.0, 0.0, 0.0], [1.4, 0.3, 0.0]])
    for s in (other, again):  # p = 1 + x about the first crack's centre, not the moved one's
        assert s.cracks[0].pressure.values(pts)[:, 0].tolist() == [1.0, 2.0]
