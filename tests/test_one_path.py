"""One path for every body: one Scene type, one SolveOptions, one Solution with fronts, one sweep entry.

What is checked, and against what:
- every built-in scene is an `nc.Scene` whose `dimension` its kind gives (2 or 3), and reading its
  TOML text back through `nc.Scene` gives the same scene (both kinds);
- `nc.solve` returns an `nc.Solution` in 2D and 3D; a 2D solution's fronts are its tips (the same
  K_I, K_II, G to the last digit), a 3D one's the fronts along the crack;
- what a body cannot take is refused with InputError naming the field, before any meshing (the
  mesh stage is replaced by one that fails the test), in 3D and in 2D alike;
- `nc.sweep` of a 3D scene gives one row per front size, its finest the reference (err_K_I NaN)
  and the coarser rows' err_K the largest K difference along the front over the finest's K.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.scenes import coarse3d


def test_every_built_in_scene_is_a_scene_and_reads_back_through_scene():
    for name in nc.scenes.names():
        s = nc.scenes.load(name)
        assert isinstance(s, nc.Scene) and s.dimension in (2, 3)
        back = nc.Scene.from_toml_string(s.to_toml_string())
        assert type(back) is type(s) and back.to_dict() == s.to_dict()
    assert nc.scenes.load("penny").dimension == 3 and nc.scenes.load("griffith").dimension == 2


def test_scene_from_fields_is_planar():
    s = nc.Scene(name="square", polygon=[(0, 0), (1, 0), (1, 1), (0, 1)], material={"E": 1.0, "nu": 0.3},
                 boundary={"e0": {"type": "clamped"}})
    assert isinstance(s, nc.Scene) and s.dimension == 2 and s == s.with_()


@pytest.fixture(scope="module")
def planar():
    return nc.solve("griffith", maxh=4.0)


@pytest.fixture(scope="module")
def solid():
    return nc.solve(nc.Scene.from_dict(coarse3d.inclined_penny()))


def test_a_2d_solution_has_its_tips_as_fronts_of_one_point(planar):
    assert isinstance(planar, nc.Solution) and planar.dimension == 2
    assert len(planar.fronts) == len(planar.tips) >= 1
    for front, tip in zip(planar.fronts, planar.tips):
        assert isinstance(front, nc.Front)
        assert front.points.shape == (1, 2) and tuple(front.points[0]) == (tip.x, tip.y)
        assert (front.K_I[0], front.K_II[0], front.G[0], front.K_III[0]) == (tip.K_I, tip.K_II, tip.G, 0.0)
        assert front.label == tip.label
    assert planar.contact is planar.qp


def test_a_3d_solution_has_the_same_names(solid):
    assert isinstance(solid, nc.Solution) and solid.dimension == 3 and solid.crack_mesh is solid.smesh
    (front,) = solid.fronts
    assert front.points.shape[1] == 3 and len(front.K_I) == len(front.points) >= 8
    assert np.all(np.isfinite(front.K_II)) and np.all(np.isfinite(front.K_III))
    record = solid.to_json_dict()
    assert record["fronts"][0]["K_I"] == list(front.K_I) and set(record["ndof"]) == {"total", "global", "contact"}


@pytest.fixture
def no_meshing(monkeypatch):
    """Any mesh stage reached fails the test: refusals must come before it."""
    from ngcrack.core import pipeline

    def refuse(*args, **kwargs):
        raise AssertionError("meshed before the options were checked")

    monkeypatch.setattr(pipeline.Pipeline, "mesh", refuse)


@pytest.mark.parametrize(("options", "field"), [
    ({"grading": 5.0}, "grading = 5.0: must lie in"),
    ({"linear_solver": "bogus"}, "linear_solver = 'bogus': allowed values"),
    ({"front_points": -3}, "front_points = -3: must be a whole number"),
    ({"order": True}, "order = True"),
    ({"element": "bdm"}, "element = 'bdm': allowed values in 3D"),
    ({"crack_model": "bonded"}, "crack_model = 'bonded': allowed values in 3D"),
    ({"tip_h": 0.1}, "tip_h: an option of 2D scenes only"),
    ({"hp": 2}, "hp: an option of 2D scenes only"),
    ({"estimate": "yes"}, "estimate = 'yes'"),
    ({"preconditioner": "bddc"}, "preconditioner = 'bddc': the distributed solve's option"),
])
def test_3d_options_are_refused_by_name_before_meshing(no_meshing, options, field):
    with pytest.raises(nc.InputError, match=field):
        nc.solve("penny", **options)


@pytest.mark.parametrize(("options", "field"), [
    ({"front_h": 0.1}, "front_h: an option of 3D scenes only"),
    ({"front_points": 5}, "front_points: an option of 3D scenes only"),
    ({"fronts": False}, "fronts: an option of 3D scenes only"),
    ({"grading": 0.0}, "grading = 0.0: must lie in"),
])
def test_2d_options_of_the_other_body_are_refused_by_name_before_meshing(no_meshing, options, field):
    with pytest.raises(nc.InputError, match=field):
        nc.solve("griffith", **options)


def test_the_2d_estimate_is_computed_when_asked_and_never_when_refused():
    asked = nc.solve("griffith", maxh=4.0, estimate=True)
    assert not asked.estimate_pending and asked.timings["estimate"] > 0.0
    lazy = nc.solve("griffith", maxh=4.0)
    assert lazy.estimate_pending and lazy.error_estimate.energy == pytest.approx(asked.error_estimate.energy, rel=1e-12)
    never = nc.solve("griffith", maxh=4.0, estimate=False)
    assert never.error_estimate is None and "estimate = False" in never.no_estimate


def test_a_3d_sweep_gives_one_row_per_front_size_against_the_finest():
    pytest.importorskip("pandas")
    scene = nc.Scene.from_dict(coarse3d.inclined_penny())
    sizes = [0.7, 0.5]
    df = nc.sweep(scene, front_h=sizes, solve_options={"crack_h": 1.0})
    assert list(df.front_h) == sorted(sizes, reverse=True) and list(df.reference) == [False, True]
    assert math.isnan(df.err_K.iloc[-1]) and 0.0 < df.err_K.iloc[0] < 0.5  # closed and sliding: K_II, K_III
    assert df.err_K_I.iloc[0] <= df.err_K.iloc[0]
    assert all(df.ndof_total > 0) and all(df.K_I_max >= df.K_I_min)
    with pytest.raises(nc.InputError, match="maxh: a sweep argument of 2D scenes"):
        nc.sweep(scene, maxh=[0.5], front_h=sizes)
    with pytest.raises(nc.InputError, match="front_h: the size axis of 3D scenes"):
        nc.sweep("griffith", front_h=[0.5])


def test_a_3d_solve_writes_its_outputs_together_or_not_at_all(tmp_path, monkeypatch, capsys):
    """The JSON record and the ParaView files of `ngcrack solve` on a 3D scene are staged together: a
    failure while the VTK files are written leaves the old JSON as it was and no new file."""
    from pathlib import Path

    from ngcrack.shell.cli import main
    from ngcrack.solid.output import SolidSolution

    scene = tmp_path / "tiny.toml"
    scene.write_text(nc.Scene.from_dict(coarse3d.inclined_penny()).to_toml_string())
    old = tmp_path / "out.json"
    old.write_text("old")

    def broken(self, path, subdivision=0):  # a writer that fails half-way, its first file written
        Path(str(path) + ".vtu").write_text("half")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(SolidSolution, "save_vtk", broken)
    code = main(["solve", str(scene), "--json", str(old), "--vtk", str(tmp_path / "v")])
    err = capsys.readouterr().err
    assert code == 2 and "--vtk" in err and "nothing was written" in err
    assert old.read_text() == "old" and sorted(p.name for p in tmp_path.iterdir()) == ["out.json", "tiny.toml"]


def test_the_command_line_skips_the_estimate_when_told(tmp_path, capsys):
    import json

    from ngcrack.shell.cli import main

    out = tmp_path / "g.json"
    assert main(["solve", "griffith", "--maxh", "4", "--no-estimate", "--json", str(out)]) == 0
    record = json.loads(out.read_text())
    assert "error_estimate" not in record and record["tips"]
    assert "error estimate" not in capsys.readouterr().out
    assert main(["solve", "griffith", "--maxh", "4", "--no-estimate", "--adapt", "0.1"]) == 2
    assert "--no-estimate = False: adapt refines" in capsys.readouterr().err


def _penny(change):
    d = coarse3d.coarse_penny()
    change(d)
    return d


@pytest.mark.parametrize(("change", "field"), [
    (lambda d: d["crack"][0].update(radius=1e-300), r"crack\[0\]: its smallest size 1e-300"),
    (lambda d: d["crack"].__setitem__(0, {"shape": "ellipse", "center": [0, 0, 0], "normal": [0, 0, 1],
                                          "semi_axes": [1.0, 1e-9], "major_axis": [1, 0, 0]}), r"crack\[0\]: its smallest size 1e-09"),
    (lambda d: d["material"].update(E=1e300), r"material.E = 1e\+300: out of range"),
    (lambda d: d["boundary"]["zmax"].update(value=[0, 0, 1e300]), "boundary.zmax.value = .0, 0, 1e.300.: out of range"),
    (lambda d: d.update(load={"body_force": [0, 0, 1e300]}), "load.body_force = .0, 0, 1e.300.: out of range"),
])
def test_3d_scene_values_beyond_double_precision_are_refused_when_the_scene_is_read(change, field):
    with pytest.raises(nc.SceneError, match=field):
        nc.Scene.from_dict(_penny(change))
