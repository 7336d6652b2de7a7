"""The explorer (`nc.Explorer`, `nc.explore`) without a browser: the model's caches against fresh solves, what
each change redoes (counted calls), failures shown as one line, the widget's wiring.

Cached answers must equal a fresh `nc.solve` of the same scene to round-off: the model
runs the library's own solve with its caches standing in for the expensive stages.
"""

from __future__ import annotations

import numpy as np
import pytest

import ngcrack as nc
import ngcrack.core.schur
import ngcrack.planar.elements
from ngcrack.scenes import SCENE_FUNCTIONS
from ngcrack.shell import explorer as ex

#: cached against fresh answers: relative difference of the solution vector and profiles
ROUNDOFF = 1e-10
#: a coarse teaching mesh keeps these tests fast (about 1e4 unknowns)
MAXH = 2.0


def _relative(a, b, floor: float = 0.0) -> float:
    """|a - b| / max(|b|, floor sqrt(len b)): relative, or relative to a scale where b is ~0."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.linalg.norm(a - b) / max(np.linalg.norm(b), floor * np.sqrt(b.size), 1e-300))


def _same_answer(cached, fresh) -> float:
    """The largest relative difference over the solution vector and the crack profiles
    (the tractions of an open crack are round-off: relative to the body's stress scale)."""
    from ngcrack.planar.post import field_scales

    assert cached.ndof == fresh.ndof
    u_scale, sigma_scale = field_scales(fresh.crack_mesh, fresh.u, fresh.sigma)
    diffs = [_relative(cached.gf.vec.FV().NumPy(), fresh.gf.vec.FV().NumPy())]
    for p, q in zip(cached.crack_profiles(), fresh.crack_profiles()):
        for k, scale in (("normal_jump", u_scale), ("tangential_jump", u_scale), ("normal_stress", sigma_scale),
                         ("shear_stress", sigma_scale)):
            diffs.append(_relative(getattr(p, k), getattr(q, k), scale))
    return max(diffs)


def _fresh(study):
    return nc.solve(study.scene, element=study.state["element"], maxh=study.state["maxh"],
                    crack_model=study.state["crack_model"])


@pytest.fixture
def factorizations(monkeypatch):
    """Counts every sparse factorization and Schur complement formed, and every element assembly."""
    counts = {"factorization": 0, "pardiso": 0, "schur_complement": 0, "build": 0}

    def counting(name, fn):
        def wrapped(*args, **kwargs):
            counts[name] += 1
            return fn(*args, **kwargs)
        return wrapped

    monkeypatch.setattr(ngcrack.core.schur.Factorization, "__init__",
                        counting("factorization", ngcrack.core.schur.Factorization.__init__))
    monkeypatch.setattr(ngcrack.core.schur._Pardiso, "__init__", counting("pardiso", ngcrack.core.schur._Pardiso.__init__))
    monkeypatch.setattr(ngcrack.core.hybrid, "schur_complement", counting("schur_complement", ngcrack.core.hybrid.schur_complement))
    monkeypatch.setattr(ngcrack.planar.elements, "build", counting("build", ngcrack.planar.elements.build))
    return counts


def test_load_change_reuses_factorization_and_matches_fresh_solve(factorizations):
    study = nc.Explorer("inclined-crack", maxh=MAXH)
    assert study.error is None, study.error
    before = dict(factorizations)
    first = study.solution
    # compression -> tension: the crack opens, the contact zone changes completely
    sol = study.update(load=-1.0, load_angle=10.0)
    assert study.error is None, study.error
    assert factorizations == before, "a load change must not re-assemble, re-factorize or re-form S"
    assert study.counts["load"] == 1 and study.counts["factorize"] == 1 and study.counts["mesh"] == 1
    assert "one solve (factorization and S reused)" in study.redone
    assert sol.crack_mesh is first.crack_mesh and sol.disc is first.disc
    assert ex.contact_length(first) > 0.99 * study.readouts()["crack_length"]  # closed under compression
    assert ex.contact_length(sol) == 0.0  # open under tension
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF


def test_material_change_reassembles_on_the_same_mesh(factorizations):
    study = nc.Explorer("inclined-crack", maxh=MAXH)
    mesh = study.solution.crack_mesh
    sol = study.update(nu=0.45, E=2000.0)
    assert study.error is None, study.error
    assert sol.crack_mesh is mesh and study.counts["mesh"] == 1
    assert study.counts["assemble"] == 2 and study.counts["factorize"] == 2
    assert factorizations["build"] == 2
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF
    # a load change after the material change uses the new factorization
    n = dict(factorizations)
    sol = study.update(load=0.5)
    assert factorizations == n
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF


def test_geometry_and_mesh_changes_remesh():
    study = nc.Explorer("cracked-beam", maxh=0.5)
    sol = study.update(angle=20.0, center_x=1.5)
    assert study.error is None and study.counts["mesh"] == 2 and "mesh" in study.redone
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF
    ndof = sol.ndof["total"]
    study.update(maxh=0.15)
    assert study.counts["mesh"] == 3 and study.solution.maxh == 0.15 and study.solution.ndof["total"] > ndof


def test_crack_model_change_keeps_the_assembly_and_matches():
    study = nc.Explorer("griffith-plate", maxh=MAXH, load=-1.0)  # compression: closed
    assert ex.contact_length(study.solution) > 0
    sol = study.update(crack_model="free")
    assert study.counts["assemble"] == 1 and study.counts["factorize"] == 2
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF
    # free faces interpenetrate under compression: the KKT residual says so
    assert study.readouts()["kkt"] > 0.1
    sol = study.update(crack_model="contact", load=-0.5)
    assert study.counts["factorize"] == 2, "the contact reduction of the first solve is reused"
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF
    assert study.readouts()["kkt"] < 1e-8


def test_griffith_plate_opens_as_the_closed_form():
    """The teaching Griffith plate (a = 1, plate 10 a wide) against the infinite plate:
    the finite width raises the opening by about sqrt(sec(pi a / W)) - 1 = 2.5%."""
    study = nc.Explorer("griffith-plate")
    p = study.solution.crack_profiles()[0]
    mat = study.scene.material
    s = p.s - 1.0
    exact = 4 * 1.0 * (1 - mat.nu ** 2) / mat.E * np.sqrt(1 - s ** 2)
    ratio = p.normal_jump.max() / exact.max()
    assert 1.0 < ratio < 1.05
    # reversed load: closed everywhere, the pressure is the remote stress
    study.update(load=-1.0)
    p = study.solution.crack_profiles()[0]
    assert np.max(np.abs(p.normal_jump)) < 1e-12
    assert np.allclose(p.normal_stress, -1.0, rtol=0.05)


def test_bad_combinations_show_one_line_and_keep_the_last_answer():
    """A refused combination: one plain sentence naming the control and what to do (no
    exception's name), the technical line as its detail, and the controls back on the
    values of the answer shown, so that the next change starts from values that work."""
    study = nc.Explorer("inclined-crack", maxh=MAXH)
    good, before = study.solution, dict(study.state)
    assert study.update(nu=0.5) is not None  # bdm takes nu = 1/2
    at_half = dict(study.state)
    assert study.update(element="h1p1") is None
    assert study.error.startswith("The displacement element h1p1 cannot take Poisson's ratio 1/2") \
        and "pick bdm, peers or tdnns" in study.error and "\n" not in study.error
    assert study.error_detail.startswith("material.nu = 0.5") and study.refused == ("element",)
    assert study.state == at_half and study.state["element"] == "bdm"  # the menu goes back to bdm
    assert study.update(nu=0.3) is not None and study.error is None and study.error_detail is None
    assert study.update(center_x=4.0) is not None
    assert study.update(half_length=2.5) is None  # in range, but the crack leaves the plate
    assert study.error == ("The crack would leave the plate with this crack half length: move the crack centre back "
                           "towards the middle or shorten the crack.")
    assert study.error_detail.startswith("crack[0].points[1]") and "outside domain.polygon" in study.error_detail
    assert study.state["half_length"] == before["half_length"] and study.state["center_x"] == 4.0
    assert study.update(E=50.0) is not None and study.error is None  # later changes work at once
    for text in (study.error or "",):
        assert "Error:" not in text
    assert study.update(colour="red") is None and study.error.startswith("There is no control called colour")
    assert "unknown control colour" in study.error_detail
    assert study.update(field="pressure") is None and "field (stress shown) = 'pressure'" in study.error_detail
    assert study.error == "'pressure' is not a choice for the stress shown: pick one of sigma_nu, von_mises."
    assert study.update(maxh=-1.0) is None and study.error.startswith("The mesh size -1 is out of range")
    assert study.update(maxh=MAXH, field="von_mises") is not None and study.error is None
    assert good is not study.solution


def test_a_bad_start_keeps_the_values_so_that_they_can_be_repaired():
    w = nc.Explorer("cracked-beam", maxh=0.5, center_y=0.95, angle=40)
    assert w.solution is None and w.error.startswith("The crack would leave the plate")
    assert w.update(center_y=0.9) is None and w.state["center_y"] == 0.9  # no good values to go back to
    assert w.update(angle=0.0) is not None and w.error is None and w.state["center_y"] == 0.9


def test_held_scales_depend_on_the_controls_not_on_their_history():
    """"hold for load changes": the scales are those of the reference load (factor 1, angle
    0, contact) for the current material, element, mesh and geometry, whatever the order
    of the changes (the history of the issue: E = 1234 at load 0.55, then load 1, E = 1000)."""
    a = nc.Explorer("inclined-crack", maxh=MAXH)
    ref = a.reference_scales("sigma_nu")
    assert a.update(load=0.55) is not None and a.reference_scales("sigma_nu") == ref  # a load change keeps them
    a.update(E=1234.0)
    a.update(load=1.0)
    a.update(E=1000.0)
    assert a.reference_scales("sigma_nu") == ref
    a.update(load=-1.0, crack_model="free", load_angle=30.0)
    assert a.reference_scales("sigma_nu") == ref
    b = nc.Explorer("inclined-crack", maxh=MAXH, E=1000.0, load=-0.5)  # (a solve at the reference load)
    assert b.reference_scales("sigma_nu") == pytest.approx(ref, rel=1e-9)
    c = nc.Explorer("inclined-crack", maxh=MAXH, load=0.4)  # (L = 0.4 > 0: the answer scaled by 1/L, no solve)
    runs = dict(c.counts)
    assert c.reference_scales("sigma_nu") == pytest.approx(ref, rel=1e-6) and c.counts == runs
    # they follow the material and the geometry: stresses do not depend on E, displacements do
    a.update(E=100.0)
    soft = a.reference_scales("sigma_nu")
    assert soft["clim"] == pytest.approx(ref["clim"], rel=1e-6)
    assert soft["scale"] == pytest.approx(ref["scale"] / 10.0, rel=1e-6)
    a.update(E=1000.0, angle=60.0)
    assert a.reference_scales("sigma_nu")["clim"] != pytest.approx(ref["clim"], rel=1e-3)
    # the colour limit is a level of the body, not the tip's peak: the area-weighted 98th percentile
    from ngcrack.planar.plots import element_displacements
    from ngcrack.shell.explorer.fields import CLIM_PERCENTILE, stress_values

    sol = nc.Explorer("inclined-crack", maxh=MAXH, load=1.0).solution
    corners, _ = element_displacements(sol)
    vals = np.abs(stress_values(sol, "sigma_nu"))
    a_, b_ = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    area = 0.5 * np.abs(a_[:, 0] * b_[:, 1] - a_[:, 1] * b_[:, 0])
    clim = ref["clim"]
    share = area[vals <= clim].sum() / area.sum()
    assert CLIM_PERCENTILE / 100 - 0.01 <= share <= CLIM_PERCENTILE / 100 + 0.01
    assert vals.max() > 1.5 * clim  # the tip's peak is beyond the colour bar (clipped and marked)


def test_tips_are_named_by_where_they_are():
    from ngcrack.shell.explorer.messages import tip_names

    tips = [{"crack": 0, "end": "first", "x": 1.0, "y": 0.2}, {"crack": 0, "end": "last", "x": -1.0, "y": -0.2}]
    assert tip_names(tips) == ["right tip", "left tip"]
    steep = [{"crack": 0, "end": "first", "x": 0.1, "y": -1.0}, {"crack": 0, "end": "last", "x": 0.0, "y": 1.0}]
    assert tip_names(steep) == ["lower tip", "upper tip"]
    two = tips + [{"crack": 1, "end": "first", "x": 3.0, "y": 0.0}, {"crack": 1, "end": "last", "x": 4.0, "y": 0.0}]
    assert tip_names(two) == ["crack 1, right tip", "crack 1, left tip", "crack 2, left tip", "crack 2, right tip"]


def test_out_of_range_values_are_refused_not_clamped_nor_kept():
    """A value out of its control's range is refused with one line naming the control
    and the range; the model keeps its previous value (and answer)."""
    study = nc.Explorer("inclined-crack", maxh=MAXH)
    good, before = study.solution, dict(study.state)
    for change, text in [({"nu": 0.7}, "nu (Poisson's ratio) = 0.7 refused: allowed from 0 to 0.5"),
                         ({"E": -1000.0}, "E (Young's modulus) = -1000 refused: allowed from 10 to 1e+05"),
                         ({"maxh": 0.0}, "maxh (mesh size) = 0 refused: allowed from "),
                         ({"load": 3.0}, "load (load factor) = 3 refused: allowed from -2 to 2"),
                         ({"angle": 100.0}, "angle (crack angle) = 100 refused: allowed from -80 to 80"),
                         ({"nu": "abc"}, "nu (Poisson's ratio) = 'abc': a number from 0 to 0.5"),
                         ({"load": 0.5, "nu": 0.7}, "nu (Poisson's ratio) = 0.7 refused")]:
        assert study.update(**change) is None
        assert study.error_detail.startswith(text) and "\n" not in study.error, study.error_detail
        assert "Error" not in study.error and study.error.endswith(".")
        assert study.state == before and study.solution is good
    study.update(nu=0.7)
    assert study.error == "The Poisson's ratio 0.7 is out of range: choose a value from 0 to 0.5."
    # the finest mesh offered stays below the unknowns the widget allows (sizing's estimate)
    from ngcrack.planar.sizing import estimate_size
    from ngcrack.shell.explorer.controls import MAX_UNKNOWNS

    low = study.ranges["maxh"].low
    assert estimate_size(study.make_scene(), "bdm", maxh=low).unknowns <= 1.01 * MAX_UNKNOWNS
    assert estimate_size(study.make_scene(), "bdm", maxh=0.9 * low).unknowns > MAX_UNKNOWNS


@pytest.mark.parametrize("kwargs,text", [
    ({"maxh": 0}, "maxh (mesh size) = 0 refused: it must be a number > 0"),
    ({"E": -1000}, "E (Young's modulus) = -1000 refused: it must be a number > 0"),
    ({"element": "q2"}, "element = 'q2': allowed values are peers, bdm, tdnns, h1p1, h1p2"),
    ({"nu": 0.7}, "nu (Poisson's ratio) = 0.7 refused: allowed from 0 to 0.5"),
    ({"crack_model": "glued"}, "crack_model (crack model) = 'glued': allowed values are contact, free, bonded"),
    ({"angle": 90}, "angle (crack angle) = 90 refused: allowed from -80 to 80"),
])
def test_construction_refuses_bad_arguments_before_any_widget(kwargs, text):
    with pytest.raises(ValueError) as info:
        nc.explore("inclined-crack", **kwargs)
    assert str(info.value) == text or str(info.value).startswith(text), str(info.value)
    assert "\n" not in str(info.value)


def test_unknown_scene_lists_scene_functions_and_built_in_scenes():
    with pytest.raises(ValueError) as info:
        nc.explore("inclined")
    msg = str(info.value)
    assert msg.startswith("scene = 'inclined'")
    for name in list(SCENE_FUNCTIONS) + nc.scenes.names():
        assert name in msg


def test_controls_follow_the_scene_and_the_installed_ngcrack():
    study = nc.Explorer("inclined-crack", maxh=MAXH)
    geo = {p.name for p in SCENE_FUNCTIONS["inclined-crack"].geometry()}
    assert geo == {"angle", "half_length", "center_x", "center_y"} and geo <= set(study.controls())
    assert "friction" in study.controls()
    fixed = nc.Explorer(nc.scenes.load("griffith"), solve_now=False)
    assert not geo & set(fixed.controls())
    with pytest.raises(ValueError, match="scene = 3"):
        nc.Explorer(3)
    with pytest.raises(ValueError, match="unknown control"):
        nc.Explorer("griffith", size=3, solve_now=False)


def test_scaled_loads_turn_and_scale_every_load_vector():
    scene = nc.scenes.load("paper-2")
    turned = ex.scaled_loads(scene, load=-2.0, load_angle=90.0)
    assert np.allclose(turned.body_force, (-2.0, 0.0), atol=1e-15)  # (0, -1) turned by 90 degrees, times -2
    incl = SCENE_FUNCTIONS["inclined-crack"]()
    top = ex.scaled_loads(incl, load=0.5, load_angle=-90.0).boundary["top"].value
    assert np.allclose(top, (-0.5, 0.0), atol=1e-15)


def test_scene_functions_and_listing(capsys):
    for name, fn in SCENE_FUNCTIONS.items():
        scene = fn()
        assert scene.cracks and fn.signature().startswith(name + "(")
        for p in fn.parameters:
            assert p.low <= p.default <= p.high and p.kind in ("geometry", "load")
    with pytest.raises(ValueError, match="unknown parameter"):
        SCENE_FUNCTIONS["griffith-plate"](angle=3)
    with pytest.raises(ValueError, match="scene function"):
        nc.scenes.scene_function("nope")
    from ngcrack.shell.cli import main

    assert main(["scenes"]) == 0
    out = capsys.readouterr().out
    for name in SCENE_FUNCTIONS:
        assert name in out
    assert "angle = 30  [-80, 80]  geometry" in out


def test_widget_wiring_and_failures_without_a_browser():
    pytest.importorskip("ipywidgets")
    w = nc.explore("inclined-crack", maxh=MAXH)
    png = w.image.value
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and w.status.value == ""
    assert "unknowns" in w.readout.value and "contact check (KKT residual)" in w.readout.value
    assert "<abbr title='contact check: how far the answer is" in w.readout.value  # the glossary, on hover
    assert "<abbr title='a crack tip, named by where it is" in w.readout.value and "left tip (" in w.readout.value
    w.controls["load"].value = -1.0
    assert w.image.value != png and w.study.counts["factorize"] == 1
    w.controls["element"].value = "h1p1"
    good = w.image.value
    nu = w.model.state["nu"]
    w.controls["nu"].value = 0.5  # nu = 1/2 with a displacement baseline: refused, the slider goes back
    assert "Poisson's ratio 1/2 (incompressible) needs a mixed element" in w.status.value and w.image.value == good
    assert "Error" not in w.status.value.split("details:")[0] and "details: material.nu = 0.5" in w.status.value
    assert w.controls["nu"].value == w.typed["nu"].value == w.model.state["nu"] == nu
    w.controls["element"].value = "bdm"  # the widget keeps working
    assert w.status.value == "" and w.image.value != good
    w.controls["center_x"].value = 4.0
    assert w.status.value == ""
    w.controls["half_length"].value = 2.5  # the crack leaves the plate
    assert "The crack would leave the plate" in w.status.value and "back to the figure's value" in w.status.value
    assert w.controls["half_length"].value == w.model.state["half_length"] == 1.0
    w.controls["half_length"].value = 0.75
    assert w.status.value == ""
    w.controls["field"].value = "von_mises"
    assert w.study.redone == ["figure"] and w.latency > 0
    # a bad start: the message and no figure, then a good value gives one
    w = nc.explore("cracked-beam", maxh=0.5, center_y=0.95, angle=40)
    assert "The crack would leave the plate" in w.status.value and "No answer yet" in w.status.value
    assert w.image.value == b""
    w.controls["angle"].value = 0.0
    assert w.status.value == "" and w.image.value[:4] == b"\x89PNG"


class _WithTipsAndStates:
    """A solution seen with fracture parameters and friction states (as the library may add them)."""

    def __init__(self, sol):
        from types import SimpleNamespace

        self._sol = sol
        p = sol.crack_profiles()[0]
        fields = {k: getattr(p, k) for k in p.__dataclass_fields__}
        fields["state"] = np.where(np.arange(len(p.s)) < len(p.s) // 2, "stick", "slip")  # replaces the real one
        self._profiles = [SimpleNamespace(**fields)]
        self.tips = [{"crack": 0, "end": end, "x": float(x), "y": float(y), "K_I": 0.0, "K_II": 1.2, "G": 0.0}
                     for end, (x, y) in (("first", (p.x[0], p.y[0])), ("last", (p.x[-1], p.y[-1])))]

    def crack_profiles(self):
        return self._profiles

    def __getattr__(self, name):
        return getattr(self._sol, name)


def test_figure_draws_tips_and_stick_slip_states_where_present():
    study = nc.Explorer("inclined-crack", maxh=MAXH)
    drawing = ex.Drawing()
    plain = drawing.render(study.solution)
    richer = drawing.render(_WithTipsAndStates(study.solution))
    again = drawing.render(study.solution)
    assert plain[:4] == richer[:4] == b"\x89PNG" and richer != plain
    assert again == plain, "a redraw of the same solution must give the same image (nothing left over)"
    for field in ex.FIELDS:
        vals = ex.stress_values(study.solution, field)
        assert np.all(np.isfinite(vals)) and len(vals) == len(study.solution.crack_mesh.triangles)
    # uniaxial compression p = -1 far from the crack: von Mises of (0, -1, 0) with sigma_zz = nu p
    vm = ex.stress_values(study.solution, "von_mises")
    nu = study.scene.material.nu
    assert abs(np.median(vm) - np.sqrt(1 - nu + nu ** 2)) < 0.05


def test_webgui_view_is_optional():
    pytest.importorskip("ipywidgets")
    w = nc.explore("griffith-plate", maxh=MAXH, webgui=True)
    assert w.webgui is not None and w.status.value == ""
    w._draw_webgui(True)  # outside a notebook the 3D view has nowhere to go, but must not raise
    w._draw_webgui(False)


@pytest.mark.parametrize("element", ["peers", "bdm", "tdnns", "h1p1", "h1p2"])
def test_load_change_matches_fresh_solve_for_every_element(element):
    """paper-1 (body force, a through crack partly in contact) on a coarse mesh, the load turned."""
    study = nc.Explorer("paper-1", element, maxh=0.25)
    assert study.error is None, study.error
    sol = study.update(load=1.5, load_angle=-30.0)
    assert study.error is None and study.counts["factorize"] == 1 and study.counts["load"] == 1
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF


def test_prescribed_displacements_follow_the_load():
    """A displacement boundary condition is a load too: scaled and turned through the Parameters."""
    scene = nc.Scene(name="pulled", polygon=((0, 0), (2, 0), (2, 1), (0, 1)), labels=("bottom", "right", "top", "left"),
                     cracks=({"points": [[0.5, 0.5], [1.5, 0.5]]},), material={"E": 100.0, "nu": 0.3},
                     boundary={"left": {"type": "clamped"}, "right": {"type": "displacement", "value": [0.01, 0.0]}},
                     maxh=0.25)
    study = nc.Explorer(scene, "bdm")
    sol = study.update(load=-2.0, load_angle=90.0)  # (0.01, 0) -> (0, -0.02)
    assert study.error is None and study.counts["factorize"] == 1
    assert np.allclose(study.scene.boundary["right"].value, (0.0, -0.02), atol=1e-15)
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF


def test_friction_change_keeps_the_assembly_and_matches(factorizations):
    """The inclined crack (30 degrees) under uniaxial compression: the faces carry
    tau = sin 30 cos 30 = 0.433 and sigma_n = -cos^2 30 = -0.75 of the remote stress, so
    they stick for mu >= tan 30 = 0.577 and slip below, where Coulomb's law leaves the
    driving shear tau - mu |sigma_n|: K_II scales by 1 - mu cot 30 (0.480 at mu = 0.3)."""
    study = nc.Explorer("inclined-crack", maxh=MAXH)
    K_II = [t.K_II for t in study.solution.tips]
    assert len(K_II) == 2
    build = factorizations["build"]
    sol = study.update(friction=0.6)
    assert study.error is None, study.error
    assert factorizations["build"] == build and study.counts["assemble"] == 1
    assert study.counts["factorize"] == 2  # the tangential jumps join the crack unknowns once
    assert all(set(p.state) == {"stick"} for p in sol.crack_profiles())
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF
    n = dict(factorizations)
    sol = study.update(friction=0.3)
    assert factorizations == n and "one solve (factorization and S reused)" in study.redone
    assert all(set(p.state) == {"slip"} for p in sol.crack_profiles())
    assert sol.kkt["friction"] < 1e-8
    ratio = 1 - 0.3 / np.tan(np.radians(30.0))
    for k, tip in zip(K_II, sol.tips):
        assert abs(tip.K_II / k - ratio) < 0.02 * ratio
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF
    png = ex.Drawing().render(sol)  # the real states and tips drawn
    assert png[:4] == b"\x89PNG"
    n = dict(factorizations)  # (the fresh solves count too)
    sol = study.update(load=1.5, load_angle=10.0, friction=0.6)  # partly stuck, partly slipping
    assert factorizations == n and study.error is None
    assert {"stick", "slip"} <= set(np.concatenate([p.state for p in sol.crack_profiles()]))
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF
    n = dict(factorizations)
    sol = study.update(friction=0.0)  # back to the frictionless reduction of the first solve
    assert factorizations == n and study.counts["factorize"] == 2
    assert _same_answer(sol, _fresh(study)) < ROUNDOFF


def test_a_stage_with_other_arguments_runs_for_real():
    """The caches are keyed by each stage's arguments: another linear solver or Schur
    method is a new factorization, another mesh size a new mesh, never a stale answer."""
    study = nc.Explorer("griffith-plate", maxh=MAXH)
    study.solve_options["linear_solver"] = "superlu"
    sol = study.update(load=0.5)
    assert study.counts["factorize"] == 2 and study.counts["assemble"] == 1
    assert sol.options["linear_solver"] == "superlu"
    study.solve_options["schur"] = "columns"
    sol = study.update(load=0.7)
    assert study.counts["factorize"] == 3 and sol.options["schur"] == "columns"
    fresh = nc.solve(study.scene, element="bdm", maxh=MAXH, linear_solver="superlu", schur="columns")
    assert _same_answer(sol, fresh) < ROUNDOFF
    study.solve_options["tip_h"] = 0.2
    study.update()
    assert study.counts["mesh"] == 2 and study.counts["assemble"] == 2


def test_former_names_still_work():
    """`nc.Study` (the model's former name) warns and is an Explorer; `ngcrack.interactive` warns and re-exports."""
    import importlib
    import sys

    sys.modules.pop("ngcrack.interactive", None)
    with pytest.warns(DeprecationWarning, match="ngcrack.shell.explorer"):
        old = importlib.import_module("ngcrack.interactive")

    with pytest.warns(DeprecationWarning, match="nc.Explorer"):
        model = nc.Study("griffith", solve_now=False)
    assert isinstance(model, nc.Explorer) and old.Study is nc.Study
    assert old.Drawing is ex.Drawing and old.scaled_loads is ex.scaled_loads and old.explore is nc.explore
    pytest.importorskip("ipywidgets")
    assert old.Explorer is ex.ExplorerWidget


@pytest.mark.parametrize("element,crack_model", [("peers", "contact"), ("bdm", "contact"), ("tdnns", "bonded"),
                                                 ("h1p1", "contact"), ("h1p2", "free")])
def test_estimate_sums_in_numpy_as_ngsolve_integrates(monkeypatch, element, crack_model):
    """The estimate's element integrals are sums over NGSolve's own quadrature points in
    numpy, with the fields evaluated in their own element (no point search): the same
    numbers to 1e-12 (tdnns 1e-10) as NGSolve's element-wise Integrate over the same integrands with
    the point search (the path kept for curved meshes). paper-1: a body force, a clamped
    edge, a crack partly in contact."""
    from ngcrack.core.pipeline import scene_loads
    from ngcrack.planar import estimate as est
    from ngcrack.planar import local_fields

    model = nc.Explorer("paper-1", element, maxh=0.2, crack_model=crack_model)
    sol, loads = model.solution, scene_loads(model.scene)
    fast = est.estimate(sol, loads, crack_model)
    again = est.estimate(sol, loads, crack_model)  # the mesh's topology and quadrature kept
    monkeypatch.setattr(est, "_quadrature", lambda cmesh, top: None)
    monkeypatch.setattr(local_fields, "_element_mesh_points", lambda cmesh, top, lam: None)
    monkeypatch.setattr(est, "_topology", est._Topology.build)
    slow = est.estimate(sol, loads, crack_model)
    # tdnns: its displacement is post-processed by a local solve per triangle from u at the
    # same points found by the point search, and averaged: round-off of |u| over h, 1e-11
    tol = 1e-10 if element == "tdnns" else 1e-12
    assert np.max(np.abs(fast.eta - slow.eta)) <= tol * np.max(slow.eta)
    assert np.array_equal(fast.eta, again.eta)
    assert abs(fast.energy - slow.energy) <= tol * slow.energy
    assert abs(fast.relative - slow.relative) <= tol * slow.relative
    for k, v in slow.terms.items():
        assert abs(fast.terms[k] - v) <= tol * max(abs(v), slow.energy ** 2)
    assert fast.notes == slow.notes and fast.min_jump == pytest.approx(slow.min_jump, rel=1e-12, abs=1e-300)


def test_widget_refuses_typed_values_and_stays_equal_to_the_model():
    pytest.importorskip("ipywidgets")
    w = nc.explore("inclined-crack", maxh=MAXH)
    png, nu = w.image.value, w.model.state["nu"]
    for name, value, text in [("nu", 0.7, "nu (Poisson's ratio) = 0.7 refused: allowed from 0 to 0.5"),
                              ("E", -1000.0, "E (Young's modulus) = -1000 refused"),
                              ("maxh", 0.0, "maxh (mesh size) = 0 refused: allowed from"),
                              ("angle", 95.0, "angle (crack angle) = 95 refused: allowed from -80 to 80")]:
        before = dict(w.model.state)
        w.typed[name].value = value
        assert text in w.status.value, w.status.value
        assert w.model.state == before and w.image.value == png
        shown = before[name] if before[name] is not None else w.model.start_maxh
        assert w.typed[name].value == shown and w.controls[name].value == pytest.approx(shown, rel=1e-12)
    assert w.model.state["nu"] == nu
    w.typed["nu"].value = 0.35  # a typed value in range is taken, and the slider follows
    assert w.status.value == "" and w.model.state["nu"] == 0.35 and w.controls["nu"].value == 0.35
    w.controls["load"].value = -1.0  # and a slider value, the box follows
    assert w.typed["load"].value == -1.0 == w.model.state["load"]
    import json

    data = json.loads(w.data.value.replace("&amp;", "&"))
    assert data["state"]["nu"] == data["controls"]["nu"] == data["typed"]["nu"] == 0.35


def test_figure_faces_show_gap_overlap_and_closure():
    """Tension opens the inclined crack (a gap between the drawn faces), crack model
    free under compression makes the faces pass through each other (an overlap),
    contact under compression keeps them closed: read off the figure's data, the faces'
    openings drawn against the solution's own jumps."""
    pytest.importorskip("ipywidgets")
    w = nc.explore("inclined-crack", maxh=MAXH)
    d = w.drawing.data
    assert d["max_gap"] == 0.0 and d["max_overlap"] == 0.0  # compression, contact: closed
    jn = lambda: np.concatenate([p.normal_jump for p in w.model.solution.crack_profiles()])  # noqa: E731
    w.controls["crack_model"].value = "free"
    d = w.drawing.data
    assert d["max_gap"] == 0.0 and d["max_overlap"] > 0.0
    r = w.model.readouts()
    assert r["contact_length"] == 0.0 and r["overlap_length"] == pytest.approx(r["crack_length"], rel=1e-12)
    assert "faces pass through each other" in w.readout.value
    assert d["max_overlap"] == pytest.approx(-jn().min(), rel=0.1)  # the faces' vertices vs the edge mid points
    for f in d["faces"]:  # the drawn faces: the + face moved by its displacement, the overlap is on the figure
        plus, minus = np.asarray(f["plus"]), np.asarray(f["minus"])
        nu = w.model.solution.crack_mesh.cracks[f["crack"]].normal[0]
        assert np.min((plus - minus) @ nu) == pytest.approx(-d["max_overlap"] * d["magnification"], rel=1e-9)
    w.controls["crack_model"].value = "contact"
    w.controls["load"].value = -1.0
    d = w.drawing.data
    assert d["max_overlap"] == 0.0 and d["max_gap"] == pytest.approx(jn().max(), rel=0.1)
    # no slip shading where nothing moves
    w.controls["load"].value = 0.0
    assert w.drawing.data["shaded"] == [] and w.drawing.data["max_gap"] == 0.0


def test_scales_are_held_while_the_load_changes():
    pytest.importorskip("ipywidgets")
    w = nc.explore("inclined-crack", maxh=MAXH)
    first = dict(w.drawing.data)
    w.controls["load"].value = 0.5  # auto: held
    d = w.drawing.data
    assert d["held"] and d["clim"] == first["clim"] and d["magnification"] == first["magnification"]
    assert d["jump_lim"] == first["jump_lim"]
    w.controls["angle"].value = 60.0  # a new geometry: the reference load's scales of the new geometry
    assert w.drawing.data["clim"][1] == w.model.reference_scales()["clim"] != first["clim"][1]
    fitted = dict(w.drawing.data)
    w.controls["scales"].value = "hold"
    w.controls["angle"].value = 30.0  # held across a geometry change too
    assert w.drawing.data["clim"] == fitted["clim"] and w.drawing.data["magnification"] == fitted["magnification"]
    w.controls["scales"].value = "fit"
    w.controls["load"].value = 1.0
    assert w.drawing.data["held"] is False and w.drawing.data["clim"] != fitted["clim"]
    w.controls["magnification"].value = 50.0  # a fixed magnification
    assert w.drawing.data["magnification"] == 50.0 and w.model.redone == ["figure"]
    # the time split adds up: the model's update plus the drawing
    w.controls["load"].value = 0.8
    r = w.model.readouts()
    assert sum(w.timing.values()) == pytest.approx(r["latency_s"] + w.timing["drawing"] + w.timing.get("scales", 0.0),
                                                   rel=1e-9, abs=1e-12)
    # K values tied to their tips, three significant digits
    tips = w.drawing.data["tips"]
    assert len(tips) == 2 and tips[0].startswith(("left tip (", "right tip (")) and "K_I = " in tips[0]
    assert "K_II = " in tips[1] and {t.split(" (")[0] for t in tips} == {"left tip", "right tip"}
    K_II = w.model.solution.tips[0].K_II
    assert f"K_II = {K_II:#.3g}".rstrip(".") in tips[0]


def test_webgui_field_is_the_figure_field():
    """The webgui's stress is the figure's: sigma_nu, and von Mises in plane strain (the scene's)."""
    from ngcrack.shell.explorer.widget import webgui_field

    study = nc.Explorer("inclined-crack", maxh=MAXH)
    sol = study.solution
    cent = sol.crack_mesh.centroids
    for field in ex.FIELDS:
        cf, name = webgui_field(sol, field)
        vals = np.asarray(cf(sol.mesh(cent[:, 0], cent[:, 1]))).reshape(-1)
        assert np.allclose(vals, ex.stress_values(sol, field), rtol=1e-12, atol=1e-12 * np.abs(vals).max())
    assert sol.scene.material.plane == "strain" and "plane strain" in webgui_field(sol, "von_mises")[1]
    # plane stress: sigma_zz = 0, as the figure
    stress = nc.Explorer(nc.scenes.load("griffith").with_(plane="stress"), maxh=MAXH).solution
    cent = stress.crack_mesh.centroids
    cf, name = webgui_field(stress, "von_mises")
    vals = np.asarray(cf(stress.mesh(cent[:, 0], cent[:, 1]))).reshape(-1)
    assert "plane stress" in name and np.allclose(vals, ex.stress_values(stress, "von_mises"), rtol=1e-12)


def test_a_closed_tip_shows_K_I_zero_by_the_one_state_rule():
    """Under compression the inclined crack is closed at both tips (the state of the crack
    sample nearest each tip, the rule the growth loop uses): K_I is shown as 0, not as the
    method's small error about zero; in tension the computed K_I is shown."""
    from ngcrack.shell.explorer.fields import tip_closed

    study = nc.Explorer("inclined-crack", maxh=MAXH)
    d = ex.Drawing()
    d.render(study.solution)
    sol = study.solution
    assert all(tip_closed(sol, t) for t in sol.tips) and max(abs(t.K_I) for t in sol.tips) < 0.05
    assert all("K_I = 0 (faces closed)" in t for t in d.data["tips"])
    study.update(load=-1.0)
    d.render(study.solution)
    assert not any(tip_closed(study.solution, t) for t in study.solution.tips)
    assert all(f"K_I = {t.K_I:#.3g}".rstrip(".") in s for t, s in zip(study.solution.tips, d.data["tips"]))


def test_webgui_view_draws_the_figures_deformation_faces_and_limits():
    """The 3D view's deformation is the figure's, to round-off (each triangle's affine map
    through its corners' displacements); the crack faces are lines; the colours are fixed
    at the figure's limits, not the tip's peak."""
    from ngcrack.planar.plots import element_displacements
    from ngcrack.shell.explorer.webgui import deformation_cf, webgui_scene

    sol = nc.Explorer("inclined-crack", maxh=MAXH, load=-1.0).solution
    corners, disp = element_displacements(sol)
    c = corners.mean(axis=1)
    pts = (0.8 * corners + 0.2 * c[:, None, :]).reshape(-1, 2)
    vals = np.asarray(deformation_cf(sol, 2.0)(sol.mesh(pts[:, 0], pts[:, 1]))).reshape(-1, 3)
    expected = 2.0 * (0.8 * disp + 0.2 * disp.mean(axis=1)[:, None, :]).reshape(-1, 2)
    assert np.max(np.abs(vals[:, :2] - expected)) <= 1e-12 * np.max(np.abs(expected)) and np.all(vals[:, 2] == 0)
    kw = webgui_scene(sol, 100.0, (-0.9, 0.9), "sigma_nu")
    (lines,) = kw["objects"]
    n_edges = sum(len(cr) for cr in sol.crack_mesh.cracks)
    assert lines["type"] == "lines" and len(lines["position"]) == 2 * n_edges * 6  # two faces, a point pair an edge
    assert kw["settings"]["Colormap"] == {"autoscale": False, "min": -0.9, "max": 0.9, "ncolors": 24}
    assert kw["caption"].startswith("sigma_nu: colours from -0.9 to 0.9") and "× 100" in kw["caption"]


def test_robust_colour_limits_clip_a_peak_on_small_triangles():
    """The solve figure's colour limits: area-weighted percentiles, so that a singular peak
    on many tiny triangles (a tip's refinement) is clipped instead of setting the scale."""
    from ngcrack.planar.plots import robust_limits

    body = np.linspace(0.5, 1.5, 1000)  # the plate: 1000 values of area 1
    peak = np.full(5000, 40.0)  # the tip: 5000 values of area 1e-6
    values, area = np.r_[body, peak], np.r_[np.ones(1000), np.full(5000, 1e-6)]
    lo, hi = robust_limits(values, weights=area)
    assert lo == pytest.approx(0.51, abs=0.002) and hi == pytest.approx(1.49, abs=0.002)
    assert robust_limits(values)[1] == 40.0  # counted alone, the peak would set the scale
    assert robust_limits(np.r_[-body, body], weights=np.ones(2000)) == pytest.approx((-1.481, 1.481), abs=0.001)


def test_free_faces_keep_their_negative_K_I():
    """Crack model free under compression: the faces pass through each other, no contact
    closes them, and the figure shows the computed (negative) K_I, not 0."""
    study = nc.Explorer("inclined-crack", maxh=MAXH, crack_model="free")
    d = ex.Drawing()
    d.render(study.solution)
    assert all(t.K_I < -0.1 for t in study.solution.tips)
    assert all("faces closed" not in t and f"K_I = {s.K_I:#.3g}".rstrip(".") in t
               for s, t in zip(study.solution.tips, d.data["tips"]))
    assert d.data["peak_clipped"] and "peak" in d.colorbar.ax.get_ylabel()
