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
