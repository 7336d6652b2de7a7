"""The Python entries accept what the command line accepts and refuse the rest before any work, naming the field.

What is checked, and against what:
- `nc.grow` takes a built-in scene's name as `nc.solve` does, and refuses None, a progress that
  is not callable, friction on cracks without contact and a da below what the tip mesh resolves,
  each with an InputError naming the field, before the first solve (the solve is replaced by one
  that fails the test if it is reached);
- `Scene.from_toml` of a directory, a missing file and a binary file: one InputError naming the file;
- `nc.solve(hp=...)` on a scene without a crack tip inside the body is refused naming hp, before
  any meshing, as `ngcrack solve --hp` is; hp = 0 stays allowed;
- a tip stopped by a hole keeps its reason in its rows (table, CSV and JSON) and no load factor
  is written as infinity.
"""

from __future__ import annotations

import json
import math

import pytest

import ngcrack as nc
from ngcrack import InputError
from ngcrack.studies.growth import loop

SCENE = "inclined-compression"
FAST = {"maxh": 2.0, "criterion": "mts"}


@pytest.fixture
def no_solve(monkeypatch):
    def reached(*args, **kwargs):
        raise AssertionError("a solve ran before the input was refused")

    monkeypatch.setattr(loop, "solve_step", reached)


@pytest.mark.parametrize("scene, changes, fragment", [
    (None, {}, "scene = None: must be a Scene"),
    (3.5, {}, "scene = 3.5: must be a Scene"),
    ("nosuch", {}, "scene = 'nosuch'"),
    (SCENE, {"progress": "abc"}, "progress = 'abc': must be None or a callable"),
    (SCENE, {"da": 1e-6}, "da = 1e-06: must be at least 0.1 of the mesh size at the crack tips (0.005)"),
    (SCENE, {"da": 1e-9}, "da = 1e-09: must be at least"),
    ("friction", {"crack_model": "free"}, "crack_model = 'free': the scene's cracks have friction 0.3"),
    ("friction", {"crack_model": "bonded"}, "crack_model = 'bonded'"),
], ids=["None", "number", "unknown-name", "progress", "da-1e-6", "da-1e-9", "friction-free", "friction-bonded"])
def test_grow_refuses_before_any_solve(no_solve, scene, changes, fragment):
    if scene == "friction":
        scene = nc.scenes.load(SCENE).with_(friction=0.3)
    args = {"da": 0.2, "steps": 1, **FAST, **changes}
    with pytest.raises(InputError) as err:
        nc.grow(scene, **args)
    assert fragment in str(err.value)


def test_grow_takes_a_scene_name_as_solve_does():
    by_name = nc.grow(SCENE, da=0.2, steps=1, frames=False, **FAST)
    by_scene = nc.grow(nc.scenes.load(SCENE), da=0.2, steps=1, frames=False, **FAST)
    assert by_name.scene == by_scene.scene
    assert by_name.table["K_I"].tolist() == by_scene.table["K_I"].tolist()  # the same run, to the bit


def test_solve_refuses_hp_without_a_tip_before_meshing(monkeypatch):
    from ngcrack.core import pipeline

    def reached(*args, **kwargs):
        raise AssertionError("meshing ran before the input was refused")

    monkeypatch.setattr(pipeline.Pipeline, "mesh", reached)
    with pytest.raises(InputError) as err:
        nc.solve("no-crack", hp=2)
    assert "hp = 2: scene 'no-crack' has no crack tip inside the body" in str(err.value)
    monkeypatch.undo()
    sol = nc.solve("no-crack", hp=0, maxh=0.5)
    assert sol.tips == [] and math.isfinite(sol.ndof["total"])


@pytest.mark.parametrize("what", ["directory", "missing", "binary"])
def test_from_toml_names_the_file(tmp_path, what):
    path = {"directory": tmp_path, "missing": tmp_path / "nosuch.toml", "binary": tmp_path / "b.toml"}[what]
    if what == "binary":
        path.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(InputError) as err:
        nc.Scene.from_toml(path)
    message = str(err.value)
    assert message.startswith(f"scene file {str(path)!r}: ")
    assert {"directory": "is a directory", "missing": "does not exist", "binary": "not a UTF-8 text file"}[what] \
        in message


def test_a_tip_stopped_by_a_hole_says_why_and_no_load_factor_is_infinite(tmp_path):
    """hole-crack: the crack's first tip lies 0.5 from the hole; a segment of 0.6 enters it, so the
    tip joins the hole's edge (its row says so) and is no tip afterwards; the other tip never meets it."""
    res = nc.grow("hole-crack", da=0.6, steps=1, K_Ic=1.0, frames=False, **FAST)
    df = res.table
    first = df[(df["end"] == "first")]
    assert len(first) == 1 and "joined it" in first["stopped"].iloc[0]
    last = df[(df["end"] == "last")]
    assert (last["stopped"] == "").all()
    assert df["load_factor"].notna().all() and df["tip_load_factor"].notna().all()
    csv = tmp_path / "g.csv"
    df.to_csv(csv, index=False)
    assert "inf" not in csv.read_text()
    data = json.loads(json.dumps(res.to_json_dict()))
    tips = {t["end"]: t for t in data["steps"][0]["tips"]}
    assert "hole" in tips["first"]["stopped"] and tips["last"]["stopped"] == ""
    assert all(s["load_factor"] is None or math.isfinite(s["load_factor"]) for s in data["steps"])
