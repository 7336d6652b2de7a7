"""Growth studies of 3D scenes: one planar growth per value, the same checks before any run as nc.grow's."""

from __future__ import annotations

import math

import pandas as pd
import pytest

import ngcrack as nc
from ngcrack.scenes.coarse3d import coarse_penny
from ngcrack.solid.scene import SolidScene
from ngcrack.studies.growth import grow_study
from ngcrack.studies.growth.study import STUDY_COLUMNS

#: a penny of radius 1 on a mesh coarse enough for a few seconds a solve
MESH = {"maxh": 5.0, "crack_h": 0.8, "front_h": 0.4}


def penny() -> SolidScene:
    d = coarse_penny()
    d["mesh"] = dict(MESH)
    return SolidScene.from_dict(d)


@pytest.mark.slow
def test_a_3d_study_over_K_Ic_scales_the_load_factor_exactly():
    """Quasi-static planar growth: the load factor is K_Ic / max K_eq, so doubling K_Ic doubles it to round-off,
    and the crack grows the same (every front point at K_Ic advances by da)."""
    table = grow_study(penny(), "K_Ic", [1.0, 2.0], da=0.1, steps=1)
    assert list(table.columns) == ["K_Ic", *STUDY_COLUMNS]
    one, two = table.iloc[0], table.iloc[1]
    assert two["lambda_first"] / one["lambda_first"] == pytest.approx(2.0, rel=1e-12)
    # lambda = K_Ic / K_max with Sneddon's K_I = 2 sigma sqrt(a / pi) (unit load): within this mesh's 3%
    assert one["lambda_first"] * 2.0 / math.sqrt(math.pi) == pytest.approx(1.0, abs=0.03)
    assert one["final_length"] == pytest.approx(two["final_length"], rel=1e-12)
    assert 1.0 < one["final_length"] <= 1.1 + 1e-9  # the equivalent radius: grown by at most da
    assert math.isnan(one["cycles"]) and one["steps"] == 1 and one["ndof"] > 0


@pytest.mark.slow
def test_a_3d_fatigue_study_counts_sneddons_cycles_and_resumes_from_its_file(tmp_path):
    """Paris fatigue: one step's cycles against Paris's law integrated with Sneddon's K at the grown size; the CSV
    keeps the row, and a rerun skips it."""
    C, m = 1e-3, 3.0
    out = tmp_path / "study.csv"
    table = grow_study(penny(), "nu", [0.3], da=0.1, steps=1, paris=(C, m), out=out)
    row = table.iloc[0]
    a = row["final_length"]
    k = C * (2.0 / math.sqrt(math.pi)) ** m
    closed = (a ** (1 - m / 2) - 1.0) / ((1 - m / 2) * k)
    assert abs(row["cycles"] / closed - 1) < 0.05  # coarse mesh: K within 3%, cubed
    saved = pd.read_csv(out)
    assert saved["cycles"].iloc[0] == pytest.approx(row["cycles"], rel=1e-12)
    again = grow_study(penny(), "nu", [0.3], da=0.1, steps=1, paris=(C, m), out=out)  # nothing left to run
    assert again["cycles"].iloc[0] == pytest.approx(row["cycles"], rel=1e-12)
    assert len(pd.read_csv(out)) == 1


@pytest.mark.parametrize("kw, field", [({"criterion": "mts"}, "criterion"), ({"r_c": 0.1}, "r_c"),
                                       ({"da": 0.6}, "da"), ({"paris": (1e-3, -1)}, "paris"),
                                       ({"front_h": -1.0}, "front_h")])
def test_a_3d_study_refuses_bad_input_by_name_before_any_run(monkeypatch, kw, field):
    from ngcrack.studies.growth import study

    def no_run(*args, **kwargs):
        raise AssertionError("a growth ran")

    monkeypatch.setattr(study, "_run_path", no_run)
    args = {"da": 0.1, "steps": 1, **kw}
    with pytest.raises(nc.InputError, match=field) as info:
        grow_study(penny(), "nu", [0.2, 0.3], **args)
    assert "\n" not in str(info.value)


def _no_solve_row(scene, da, steps, K_Ic, criterion, options) -> dict:
    return {"steps": 1, "final_length": 1.25, "lambda_first": 2.0, "lambda_last": 2.0, "lambda_max": 2.0,
            "cycles": math.nan, "stopped": "", "time_s": 0.0, "ndof": 7}


@pytest.mark.parametrize("header, field", [("nu,steps,final_length,lambda_first,lambda_last,lambda_max,stopped,time_s,ndof\n"
                                            "0.2,1,1.0,1.0,1.0,1.0,,0.1,5\n", "columns"),
                                           (f"nu,{','.join(STUDY_COLUMNS)}\n0.2,x,1,1,1,1,,,0.1,5\n", "line 2, column steps")])
def test_a_study_file_of_other_columns_or_bad_cells_is_refused_before_any_run(monkeypatch, tmp_path, header, field):
    """A rerun on a CSV written with another column set (or a bad cell) would append misaligned lines: refused."""
    from ngcrack.studies.growth import study

    monkeypatch.setattr(study, "_run_path", _no_solve_row)
    out = tmp_path / "study.csv"
    out.write_text(header)
    with pytest.raises(nc.InputError, match=field):
        grow_study(penny(), "nu", [0.2, 0.3], da=0.1, steps=1, out=out)
    assert out.read_text() == header


def test_a_study_writes_no_nan_and_a_header_to_an_empty_file(monkeypatch, tmp_path):
    from ngcrack.studies.growth import study

    monkeypatch.setattr(study, "_run_path", _no_solve_row)
    out = tmp_path / "study.csv"
    out.touch()
    grow_study(penny(), "nu", [0.3], da=0.1, steps=1, out=out)
    assert out.read_text() == f"nu,{','.join(STUDY_COLUMNS)}\n0.3,1,1.25,2.0,2.0,2.0,,,0.0,7\n"
    again = grow_study(penny(), "nu", [0.3], da=0.1, steps=1, out=out)  # read back: the empty cell is NaN
    assert math.isnan(again["cycles"].iloc[0]) and again["ndof"].iloc[0] == 7


def _scene_function(radius=1.0):
    d = coarse_penny()
    d["mesh"] = dict(MESH)
    d["crack"][0]["radius"] = 1.0 / 0.0 if radius == 2.0 else radius
    return SolidScene.from_dict(d)


@pytest.mark.parametrize("call, message", [
    (lambda: grow_study(_scene_function, "depth", [1.0], da=0.1, steps=1), "parameter = 'depth': not a keyword of the "
     "scene function; allowed: radius, K_Ic"),
    (lambda: grow_study(_scene_function, "radius", [2.0], da=0.1, steps=1), "scene: the scene function failed at "
     "radius = 2.0 \\(ZeroDivisionError"),
    (lambda: grow_study(5, "nu", [0.3], da=0.1, steps=1), "scene = 5: must be a Scene"),
    (lambda: grow_study(penny(), "nu", 0.3, da=0.1, steps=1), "values = 0.3: must be a list"),
    (lambda: grow_study(penny(), "nu", [0.3], da=0.1, steps=1, out=5), "out = 5: must be None or the path"),
    (lambda: grow_study(penny(), "nu", [0.3], da=0.1, steps=1, out="."), "out = '.': is a directory"),
    (lambda: grow_study(penny(), "nu", [0.3], da=0.1, steps=1, frames=True), "frames = True: a growth study keeps no frames"),
    (lambda: grow_study(penny(), "nu", [0.3], da=0.1, steps=1, progress=5), "progress = 5: must be None or a callable")])
def test_a_study_refuses_a_bad_scene_function_values_or_out_by_name(monkeypatch, call, message):
    from ngcrack.studies.growth import study

    monkeypatch.setattr(study, "_run_path", _no_solve_row)
    with pytest.raises(nc.InputError, match=message):
        call()


def test_a_scene_functions_K_Ic_study_calls_the_function_with_its_defaults(monkeypatch):
    from ngcrack.studies.growth import study

    monkeypatch.setattr(study, "_run_path", _no_solve_row)
    assert list(grow_study(_scene_function, "K_Ic", [1.0, 2.0], da=0.1, steps=1)["K_Ic"]) == [1.0, 2.0]


@pytest.mark.parametrize("scene, value, message", [
    ("griffith", False, "corrector = False: an option of 3D growth \\(Heun's step of surface cracks\\); scene 'griffith' is 2D"),
    ("surface-crack", "yes", "corrector = 'yes': must be True \\(surface cracks grow by Heun's predictor-corrector step")])
def test_a_study_checks_the_corrector_as_grow_does(monkeypatch, scene, value, message):
    from ngcrack.studies.growth import study

    monkeypatch.setattr(study, "_run_path", _no_solve_row)
    with pytest.raises(nc.InputError, match=message):
        grow_study(scene, "nu", [0.3], da=0.1, steps=1, corrector=value)
    with pytest.raises(nc.InputError, match=message):
        nc.grow(scene, da=0.1, steps=1, corrector=value)


def test_a_study_on_worker_processes_refuses_a_scene_it_cannot_send_before_any_run(monkeypatch):
    from ngcrack.studies.growth import study

    monkeypatch.setattr(study, "_run_path", _no_solve_row)
    with pytest.raises(nc.InputError, match="pressure = <function .*: the scene cannot be sent to a worker process "
                                            ".*module-level functions, or jobs=1"):
        grow_study(penny(), "pressure", [lambda x, y, z: 1.0], da=0.1, steps=1, jobs=2)


def test_a_study_refuses_a_value_whose_first_mesh_is_too_large_before_any_run(monkeypatch):
    """The size guard of each path's first solve runs with the checks: no path grows before a later value fails it."""
    from ngcrack.studies.growth import study

    ran = []
    monkeypatch.setattr(study, "_run_path", lambda *args: ran.append(args) or _no_solve_row(*args))
    with pytest.raises(nc.InputError, match="front_h = 0.001: scene 'penny-coarse', element 'tdnns' would need about "
                                            "9.79e\\+05 tetrahedra.*exceeds the default ceiling of 5000000 unknowns"):
        grow_study(penny(), "front_h", [0.4, 0.001], da=0.1, steps=1)
    assert ran == []
