"""The 3D displacement baselines h1p1/h1p2 and crack-face pressure in 3D, on coarse meshes.

Every figure fails on a wrong answer: bad element/order combinations refused before
meshing; on a clamped cube h1p2 agrees with TDNNS at nu = 0.3 and h1p1 locks at
nu = 0.4999 while TDNNS does not; the penny under tension with h1p2 against Sneddon
and against TDNNS on the same mesh; a pressurized penny with no remote load against
the penny under tension (the same crack problem: the uniform field is exact in P2, so
the jumps agree to round-off) and against Sneddon's K_I = 2 p sqrt(a / pi).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_solid import PENNY, clamped_cube  # the coarse penny and the clamped cube of the 3D tests

import ngcrack as nc
from ngcrack.solid.scene import SolidScene

K_SNEDDON = 2.0 / math.sqrt(math.pi)


def pressurized() -> SolidScene:
    import copy

    d = copy.deepcopy(PENNY)
    del d["boundary"]["zmax"]
    d["crack"][0]["pressure"] = 1.0
    return SolidScene.from_dict(d)


def test_bad_element_and_order_are_refused_before_meshing():
    s = SolidScene.from_dict(PENNY)
    for kw, field in ((dict(element="h1p2", order=3), "order = 3: element .h1p2. has a fixed order"),
                      (dict(element="h1p1", order=2), "order = 2: element .h1p1. has a fixed order"),
                      (dict(element="h1p3"), "element = 'h1p3'"), (dict(element="bdm"), "2D only")):
        with pytest.raises(nc.InputError, match=field):
            nc.solve(s, **kw)
    cyl = dict(PENNY, domain={"cylinder": {"center": [0, 0, 0], "axis": [0, 0, 1], "radius": 5.0, "height": 20.0}},
               boundary={"bottom": {"type": "clamped"}, "side": {"type": "roller"}})
    with pytest.raises(nc.InputError, match="boundary.side.type"):
        nc.solve(SolidScene.from_dict(cyl), element="h1p2")
    with pytest.raises(nc.SceneError, match=r"crack\[0\].pressure"):
        SolidScene.from_dict(dict(PENNY, crack=[dict(PENNY["crack"][0], pressure="high")]))
    assert pressurized().cracks[0].pressure == 1.0
    assert nc.Scene.from_toml_string(pressurized().to_toml_string()) == pressurized()
    assert s.with_(pressure=2.0).cracks[0].pressure == 2.0


@pytest.fixture(scope="module")
def cube():
    return clamped_cube(0.3)


def test_h1p1_locks_at_nu_04999_where_tdnns_does_not(cube):
    scene, smesh = cube
    tip = smesh.mesh(1.0, 0.5, 0.5)

    def uz(nu, element, order):
        return nc.solve(scene.with_(nu=nu), crack_mesh=smesh, element=element, order=order).u(tip)[2]

    # nu = 0.3: h1p2 and TDNNS agree (measured 0.1%); h1p1 is 14% stiff on this mesh
    t1 = uz(0.3, "tdnns", 1)
    assert abs(uz(0.3, "h1p2", 2) / t1 - 1.0) < 0.01
    assert 0.8 < uz(0.3, "h1p1", 1) / t1 < 0.9
    # nu = 0.4999 (the converged tip displacement is 0.1% above its nu = 0.3 value): TDNNS
    # moves by 1%, h1p2 loses 12% and h1p1 46% (measured 0.99, 0.88 and 0.54 of TDNNS at 0.3)
    assert abs(uz(0.4999, "tdnns", 1) / t1 - 1.0) < 0.02
    assert 0.8 < uz(0.4999, "h1p2", 2) / t1 < 0.93
    assert uz(0.4999, "h1p1", 1) / t1 < 0.6


@pytest.fixture(scope="module")
def penny_mesh():
    from ngcrack.solid.geometry import make_mesh

    s = SolidScene.from_dict(PENNY)
    return s, make_mesh(s)


@pytest.fixture(scope="module")
def tension(penny_mesh):
    scene, smesh = penny_mesh
    return nc.solve(scene, crack_mesh=smesh, element="h1p2")


def test_h1p2_penny_under_tension_follows_sneddon(tension):
    sol = tension
    w, pts = sol.normal_jumps(), sol.disc.constraint_points
    r = np.linalg.norm(pts[:, :2], axis=1)
    centre = r < 0.3
    sneddon = 8 * (1 - 0.09) / (math.pi * 1000.0) * np.sqrt(1 - r[centre] ** 2)
    # measured on this mesh: opening 0.973-0.978 of Sneddon's (TDNNS order 1: 0.979-0.994)
    assert np.all(np.abs(w[centre] / sneddon - 1.0) < 0.04), w[centre] / sneddon
    assert all(v < 1e-12 for v in sol.kkt.values()) and not sol.contact.active.any()
    (front,) = sol.fronts
    # measured: K_I 0.967-0.983 of Sneddon's (TDNNS order 1 on this mesh: 0.988-1.008)
    assert np.all(np.abs(front.K_I / K_SNEDDON - 1.0) < 0.05), front.K_I / K_SNEDDON
    assert np.all(np.abs(front.K_II) < 0.02 * K_SNEDDON) and np.all(np.abs(front.K_III) < 0.02 * K_SNEDDON)
    summary = sol.crack_summaries()[0]
    assert summary["closed_fraction"] == 0.0 and 0.0 < summary["max_sliding"] < 0.05 * summary["max_opening"]
    points, tris, data = sol.crack_arrays()
    assert tris.shape == (len(sol.smesh.cracks[0].elements), 3) and np.all(data["opening"] >= 0.0)
    assert sol.to_json_dict()["element"] == "h1p2"


def test_pressurized_penny_is_the_tension_problem(penny_mesh, tension):
    scene, smesh = penny_mesh
    sol = nc.solve(pressurized(), crack_mesh=smesh, element="h1p2")
    w, w_t = sol.normal_jumps(), tension.normal_jumps()
    # remote tension p = the uncracked body's uniform stress (exact in P2) + pressure p on the faces
    assert np.max(np.abs(w - w_t)) < 1e-10 * np.max(w_t)
    assert all(v < 1e-12 for v in sol.kkt.values())
    (front,) = sol.fronts
    (ref,) = tension.fronts
    # the pressure's face term in the interaction integral: K_I as under tension
    assert np.all(np.abs(front.K_I / K_SNEDDON - 1.0) < 0.05), front.K_I / K_SNEDDON
    # measured: 0.963-0.992 of Sneddon, within 2.5% of the tension case point by point (TDNNS order 1:
    # 0.986-1.011 against 0.988-1.008 under tension)
    assert np.max(np.abs(front.K_I / ref.K_I - 1.0)) < 0.04, front.K_I / ref.K_I


def test_h1p1_penny_closes_under_compression_and_the_faces_carry_the_load(penny_mesh, tmp_path):
    import copy

    import meshio

    scene, smesh = penny_mesh
    d = copy.deepcopy(PENNY)
    d["boundary"]["zmax"]["value"] = [0.0, 0.0, -1.0]
    # P1: jn >= 0 at the vertices is jn >= 0 everywhere. (P2 with jn >= 0 at vertices and edge mid
    # points leaves 25 of 1100 mid points open by 4e-7, 2e-4 of the tension case's opening: the
    # nodal P2 constraint allows a little interpenetration between the nodes, as TDNNS order 2.)
    sol = nc.solve(SolidScene.from_dict(d), crack_mesh=smesh, element="h1p1")
    assert sol.contact.active.all() and sol.crack_summaries()[0]["closed_fraction"] == 1.0
    assert max(sol.kkt.values()) < 1e-12
    # closed frictionless faces under uniaxial compression: the uncracked body's uniform field, so
    # the contact pressure is the applied p = 1 (measured: within 0.4%; not round-off, as P1
    # on the tetrahedra curved to second order at the front does not hold a linear field exactly)
    _, _, data = sol.crack_arrays()
    on = data["closed"] > 0  # a corner on the front has no jump unknown: pressure 0 there
    assert on.sum() > 0.5 * len(on) and np.max(np.abs(data["contact_pressure"][on] - 1.0)) < 1e-2
    assert np.all(data["contact_pressure"][~on] == 0.0)
    assert np.all(sol.fronts[0].K_I == 0.0)
    files = sol.save_vtk(tmp_path / "penny")
    cracks = meshio.read(files[1])
    assert set(cracks.point_data) == {"opening", "sliding", "closed", "contact_pressure"}


def test_webgui_scene_colours_the_crack_faces_by_the_opening(tension):
    import ngsolve as ngs

    from ngcrack.solid.view import webgui_scene

    with pytest.raises(nc.InputError, match="quantity"):
        webgui_scene(tension, "stress")
    mesh = tension.smesh.mesh
    rule = ngs.IntegrationRule(ngs.TRIG, 2)
    mp = mesh.MapToAllElements(rule, ngs.BND).reshape(mesh.GetNE(ngs.BND), -1)[tension.smesh.cracks[0].elements].ravel()
    for quantity, top in (("opening", tension.crack_summaries()[0]["max_opening"]),
                          ("sliding", tension.crack_summaries()[0]["max_sliding"])):
        scene = webgui_scene(tension, quantity, body=quantity == "sliding")
        v = np.asarray(scene.cf(mp)).ravel()
        # the colour on the crack faces is the quantity: within 5% of its largest value at the constraint points
        assert v.min() >= -1e-12 and abs(v.max() / top - 1.0) < 0.05, (quantity, v.max(), top)
        assert scene.kwargs["max"] == pytest.approx(top)
    data = webgui_scene(tension).draw(show=False).GetData()
    assert data["funcmax"] == pytest.approx(tension.crack_summaries()[0]["max_opening"])


@pytest.mark.slow
def test_tdnns_pressurized_penny_is_the_tension_problem(penny_mesh):
    scene, smesh = penny_mesh
    sol = nc.solve(pressurized(), crack_mesh=smesh)
    ref = nc.solve(scene, crack_mesh=smesh)
    w, w_t = sol.normal_jumps(), ref.normal_jumps()
    # measured 6e-4: the uniform stress is not in TDNNS's space on the tetrahedra curved at the front
    assert np.max(np.abs(w - w_t)) < 2e-3 * np.max(w_t)
    assert max(sol.kkt.values()) < 1e-12
    (front,), (front_t,) = sol.fronts, ref.fronts
    # measured: 0.986-1.011 of Sneddon's 2 p sqrt(a / pi), against 0.988-1.008 under tension
    assert np.all(np.abs(front.K_I / K_SNEDDON - 1.0) < 0.04), front.K_I / K_SNEDDON
    assert np.max(np.abs(front.K_I / front_t.K_I - 1.0)) < 0.03, front.K_I / front_t.K_I
