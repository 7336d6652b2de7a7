"""Growth options that were accepted and ignored (issue 43, item 7): refused by name before any solve, in Python and
on the command line (exit 2, one line naming the field, no output created or changed); and a GrowthResult prints
in a few lines (issue 40, item 5: `print(result)` dumped 430 kB of arrays).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.scenes import inclined_crack
from ngcrack.shell.cli import main
from ngcrack.studies.growth import loop


@pytest.fixture
def no_solve(monkeypatch):
    def refuse(*a, **k):
        raise AssertionError("grow solved before refusing its input")

    monkeypatch.setattr(loop, "solve_step", refuse)


#: (keywords of nc.grow, the field its one-line refusal starts with)
CASES = [
    ({"estimate": "yes"}, "estimate = 'yes'"), ({"estimate": 1}, "estimate = 1"), ({"estimate": None}, "estimate = None"),
    ({"frames": "no"}, "frames = 'no'"),
    ({"R": 0.5}, "R = 0.5: the load ratio of a fatigue cycle acts only with paris"), ({"R": "x"}, "R = 'x'"),
    ({"R": math.nan}, "R = nan"), ({"R": True}, "R = True"),
    ({"at_hole": 0.5}, "at_hole = 0.5: scene 'inclined-tension-30deg' has no hole"),
    ({"together": True}, "together = True"),
]


@pytest.mark.parametrize("kw, start", CASES, ids=[next(iter(kw)) + "=" + repr(v) for kw, _ in CASES
                                                   for v in kw.values()])
def test_ignored_option_refused_before_any_solve(no_solve, kw, start):
    scene = inclined_crack(angle=30.0, load=1.0)
    with pytest.raises(nc.InputError) as info:
        nc.grow(scene, da=0.1, steps=2, **kw)
    assert str(info.value).startswith(start) and "\n" not in str(info.value)


def test_the_accepted_values_still_run_the_checks_only(no_solve):
    """R = 0 without paris (the default), numpy's bool, at_hole 'stop' on a scene without holes: accepted (the
    monkeypatched solve is reached)."""
    for kw in ({"R": 0.0}, {"estimate": np.bool_(True)}, {"at_hole": "stop"}):
        with pytest.raises(AssertionError, match="grow solved"):
            nc.grow(inclined_crack(angle=30.0, load=1.0), da=0.1, steps=1, **kw)


@pytest.mark.parametrize("extra, fragment", [
    (["--at-hole", "0.5"], "at_hole = 0.5: scene 'griffith' has no hole"),
    (["--at-hole", "0.5", "--csv", "g.csv", "--png", "g.png"], "at_hole = 0.5"),
])
def test_at_hole_without_holes_on_the_command_line(tmp_path, monkeypatch, capsys, extra, fragment):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "old.json").write_text('{"kept": true}')
    code = main(["grow", "griffith", "--da", "0.05", "--steps", "1", "--json", "old.json", *extra])
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert code == 2 and len(err) == 1 and fragment in err[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.json"]
    assert (tmp_path / "old.json").read_text() == '{"kept": true}'


def test_a_growth_result_prints_in_a_few_lines():
    res = nc.grow("griffith", 0.05, 2, K_Ic=2.0, criterion="mts", maxh=0.5)
    text = repr(res)
    lines = text.splitlines()
    assert len(lines) == 4 and len(text) < 600, text
    assert lines[0] == "GrowthResult(scene='griffith', element='tdnns', criterion='mts', da=0.05, K_Ic 2)"
    lam = [s["load_factor"] for s in res.steps]
    assert lines[1] == f"  3 steps, 3 tip rows; load factor {lam[0]:.4g} at step 0, {lam[-1]:.4g} at the last"
    assert lines[2] == f"  stopped: {res.stopped}" and res.stopped == "steps: 2 of 2 steps done"
    x, y = res.steps[-1]["tips"][0]["x"], res.steps[-1]["tips"][0]["y"]
    assert x == pytest.approx(1.1, abs=1e-9) and lines[3] == f"  tips of the last step: 0,last at ({x:.4g}, {y:.4g})"
    assert str(res) == text
