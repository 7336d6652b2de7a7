"""Hydraulic fracture, toughness-dominated: KGD's closed form, the in-situ stress, the contract.

KGD (plane strain, uniform pressure, no leak-off): l(t) = 0.4302 (E' Q0 t / K_Ic)^(2/3),
p = K_Ic / sqrt(pi l), w0 = 4 p l / E', checked at every step with l 20 mesh sizes at
the tips in a body 40 l0 wide (its own effect on l measured below 0.3% here; the
built-in `kgd` scene is 200 l0 wide). Under a uniform in-situ compression sigma across
the crack the pressure at propagation is sigma more, and the volume the same (exact
superposition on the same mesh, through the contact search).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

import ngcrack as nc
from ngcrack.planar.scene import Scene
from ngcrack.shell.cli import main
from ngcrack.studies.hydrofrac.result import FLUID_KEYS, STEP_KEYS, TIP_KEYS

E, NU, Q0, K_IC = 30e9, 0.25, 1e-4, 1e6
E_PRIME = E / (1 - NU**2)
MESH = dict(maxh=8.0, tip_h=0.05, crack_h=0.1)


def kgd_body(width: float, sigma: float = 0.0) -> Scene:
    """A square of side 2 width with a crack (-1, 0)-(1, 0); rollers on the left and bottom
    edges, the top edge loaded by -sigma normal to the crack (an in-situ compression)."""
    boundary = {"left": {"type": "roller"}, "bottom": {"type": "roller"},
                "top": {"type": "traction", "value": [0.0, -sigma]}}
    return Scene(name="kgd-test", polygon=[[-width, -width], [width, -width], [width, width], [-width, width]],
                 labels=["bottom", "right", "top", "left"], cracks=[{"points": [[-1, 0], [1, 0]]}],
                 material={"E": E, "nu": NU}, boundary=boundary)


def kgd(t: float) -> tuple[float, float, float]:
    l = 0.4302 * (E_PRIME * Q0 * t / K_IC) ** (2 / 3)
    p = K_IC / math.sqrt(math.pi * l)
    return l, p, 4 * p * l / E_PRIME


def test_kgd_closed_form_at_every_step():
    result = nc.hydrofrac(kgd_body(40.0), rate=Q0, K_Ic=K_IC, da=0.1, steps=3, **MESH)
    assert result.stopped.startswith("steps")
    for step in result.steps:
        l, p, w0 = kgd(step["time"])
        assert abs(step["half_length"] / l - 1) < 0.01
        assert abs(step["pressure"] / p - 1) < 0.01
        assert abs(step["opening_at_injection"] / w0 - 1) < 0.01
        assert abs(step["volume"] / (Q0 * step["time"]) - 1) < 1e-12
        for tip in step["tips"]:
            assert abs(tip["K_I"] / K_IC - 1) < 1e-3 and tip["kink_deg"] == 0.0
    assert np.allclose(result.final.cracks[0].points, [[-1.3, 0.0], [1.3, 0.0]], rtol=0, atol=1e-12)
    shown = repr(result).splitlines()  # a few lines, never the profiles
    assert len(shown) == 3 and shown[1].startswith("  4 steps: half-length 1 -> 1.3") and len(repr(result)) < 400


def test_in_situ_compression_adds_to_the_pressure():
    sigma = 2e5
    free = nc.hydrofrac(kgd_body(20.0), rate=Q0, K_Ic=K_IC, da=0.1, steps=1, **MESH)
    held = nc.hydrofrac(kgd_body(20.0, sigma), rate=Q0, K_Ic=K_IC, da=0.1, steps=1, **MESH)
    for a, b in zip(free.steps, held.steps):
        assert abs((b["pressure"] - sigma) / a["pressure"] - 1) < 1e-6
        assert abs(b["volume"] / a["volume"] - 1) < 1e-6
        assert b["kkt"] < 1e-10


def test_json_contract_and_bad_options(tmp_path):
    out = tmp_path / "h.json"
    bad = [["--rate", "0"], ["--K-Ic", "-1"], ["--steps", "0"], ["--crack", "2"], ["--da", "1e4"],
           ["--injection", "5", "5"]]
    base = {"--rate": ["1e-4"], "--K-Ic": ["1e6"], "--da": ["0.1"], "--steps": ["1"]}
    for change in bad:
        args = dict(base)
        args[change[0]] = change[1:]
        argv = ["hydrofrac", "kgd", "--json", str(out)] + [x for k, v in args.items() for x in [k] + v]
        assert main(argv) == 2
        assert not out.exists()
    assert main(["hydrofrac", "kgd", "--rate", "1e-4", "--K-Ic", "1e6", "--da", "0.1", "--steps", "1",
                 "--json", str(out), "--csv", str(tmp_path / "h.csv"), "--gif", str(tmp_path / "h.gif")]) == 0
    from PIL import Image

    with Image.open(tmp_path / "h.gif") as gif:
        assert gif.n_frames == 2  # one frame per step
    table = pd.read_csv(tmp_path / "h.csv")
    assert len(table) == 4 and set(table["end"]) == {"first", "last"}
    data = json.loads(out.read_text())
    assert list(data) == ["scene", "element", "rate", "K_Ic", "stopped", "steps", "cracks", "model", "viscosity",
                          "leakoff", "K_m"]
    assert data["model"] == "toughness" and data["K_m"] is None and data["viscosity"] is None
    assert [list(s) for s in data["steps"]] == [list(STEP_KEYS) + list(FLUID_KEYS) + ["tips"]] * 2
    assert all(s["efficiency"] == 1.0 and list(s["profile"]) == ["s", "opening", "pressure"] for s in data["steps"])
    assert all(list(t) == list(TIP_KEYS) for s in data["steps"] for t in s["tips"])
    assert len(data["cracks"]) == 1
    assert np.allclose(data["cracks"][0]["points"], [[-1.1, 0.0], [1.1, 0.0]], rtol=0, atol=1e-12)
    l, p, w0 = kgd(data["steps"][0]["time"])
    assert abs(data["steps"][0]["pressure"] / p - 1) < 0.01


@pytest.mark.parametrize("kwargs, words", [
    (dict(rate=float("nan")), "rate"), (dict(K_Ic=0.0), "K_Ic"), (dict(steps=2.5), "steps"),
    (dict(crack=1), "crack"), (dict(crack_mesh=None), "crack_mesh"),
])
def test_bad_arguments_refused_by_name(kwargs, words):
    args = dict(rate=Q0, K_Ic=K_IC, da=0.1, steps=1)
    args.update(kwargs)
    with pytest.raises(nc.InputError, match=words):
        nc.hydrofrac(kgd_body(20.0), **args)


@pytest.mark.parametrize("scene, change, words", [
    ("kgd", ["--da", "1e-9"], "da"),  # below a quarter of the tip mesh size (time would run backwards)
    ("kgd", ["--crack-model", "bonded"], "crack_model"),
    ("kgd", ["--K-Ic", "1e300"], "K_Ic"),  # a pressure of 1e289 E'
    ("penny", ["--injection", "0", "0"], "injection"),  # 3D: a radial fracture is fed at the disc's centre
])
def test_hostile_cli_values_refused_before_work(tmp_path, capsys, scene, change, words):
    """One line naming the field, exit 2, an existing output left as it was."""
    out = tmp_path / "h.json"
    out.write_text("old")
    args = {"--rate": ["1e-4"], "--K-Ic": ["1e6"], "--da": ["0.1"], "--steps": ["1"]}
    if change:
        args[change[0]] = change[1:]
    argv = ["hydrofrac", scene, "--json", str(out)] + [x for k, v in args.items() for x in [k] + v]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1
    assert out.read_text() == "old" and sorted(p.name for p in tmp_path.iterdir()) == ["h.json"]


def test_progress_checked_before_the_first_step():
    with pytest.raises(nc.InputError, match="progress"):
        nc.hydrofrac(kgd_body(20.0), rate=Q0, K_Ic=K_IC, da=0.1, steps=1, progress="x", **MESH)


def test_small_da_refused_with_its_bound():
    """da below MIN_DA_TIP_FRACTION of tip_h = 0.05: the bound 0.0125 is named."""
    with pytest.raises(nc.InputError, match=r"da = 0.01: must be a number in \[0.0125, "):
        nc.hydrofrac(kgd_body(20.0), rate=Q0, K_Ic=K_IC, da=0.01, steps=1, **MESH)


@pytest.mark.slow
def test_kgd_geos_values_at_ten_seconds():
    """The built-in kgd scene grown to l = 4.5 m: at t = 10 s GEOS's closed-form values
    l = 4.335 m, p = 0.2710 MPa, w0 = 146.8 um (measured: 4.328 m, 0.2711 MPa, 146.9 um)."""
    result = nc.hydrofrac("kgd", rate=Q0, K_Ic=K_IC, da=0.1, steps=35)
    t = np.array([s["time"] for s in result.steps])
    assert t[0] < 10.0 < t[-1]
    at = {k: float(np.interp(10.0, t, [s[k] for s in result.steps]))
          for k in ("half_length", "pressure", "opening_at_injection")}
    assert abs(at["half_length"] / 4.335 - 1) < 0.01
    assert abs(at["pressure"] / 0.2710e6 - 1) < 0.01
    assert abs(at["opening_at_injection"] / 146.8e-6 - 1) < 0.01


def test_interrupted_run_keeps_the_finished_steps(tmp_path):
    """SIGTERM after a step: exit 128 + 15, the finished steps written, marked interrupted."""
    import shutil
    import signal
    import subprocess

    out = tmp_path / "h.json"
    proc = subprocess.Popen([shutil.which("ngcrack"), "hydrofrac", "kgd", "--rate", "1e-4", "--K-Ic", "1e6",
                             "--da", "0.1", "--steps", "50", "--json", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in proc.stdout:
        if line.startswith("step 1:"):
            proc.send_signal(signal.SIGTERM)
            break
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + signal.SIGTERM, err
    data = json.loads(out.read_text())
    assert data["stopped"].startswith("interrupted: SIGTERM") and len(data["steps"]) >= 2


def barrier_slab(crack) -> Scene:
    """A slab [-10, 10] x [-2, 2], clamped at its ends, compressed across the crack by
    S1 = 1 MPa on its top and bottom faces except over 2.5 < x < 4.5, where S2 = 5 MPa (a band
    of higher in-situ stress on the right of the crack only)."""
    s1, s2 = 1e6, 5e6
    top = [[10, 2], [4.5, 2], [2.5, 2], [-10, 2]]
    bottom = [[-10, -2], [2.5, -2], [4.5, -2], [10, -2]]
    labels = ["bot-l", "blayer", "bot-r", "right", "top-r", "layer", "top-l", "left"]
    load = {lab: {"type": "traction", "value": [0.0, (s2 if "layer" in lab else s1) * (-1 if lab.startswith(("top", "layer")) else 1)]}
            for lab in labels if lab not in ("left", "right")}
    return Scene(name="barrier", polygon=bottom + top, labels=labels, cracks=[] if crack is None else [{"points": crack}],
                 material={"E": E, "nu": NU}, boundary={"left": {"type": "clamped"}, "right": {"type": "clamped"}, **load})


def test_stress_barrier_arrests_the_tip_facing_it():
    """The right tip faces the band: it stays (K_I 0.81-0.85 K_Ic, measured), the left one runs at K_Ic;
    the fluid pressure is above the in-situ compression across the crack wherever it is open."""
    mesh = dict(maxh=1.0, tip_h=0.04, crack_h=0.08)
    run = nc.hydrofrac(barrier_slab([[-1, 0], [1, 0]]), rate=Q0, K_Ic=K_IC, da=0.3, steps=3, **mesh)
    uncracked = nc.solve(barrier_slab(None), **mesh)
    m = uncracked.crack_mesh.mesh
    for n, step in enumerate(run.steps):
        first, last = step["tips"]
        assert first["advanced"] and not last["advanced"]
        assert abs(math.hypot(first["K_I"], first["K_II"]) / K_IC - 1) < 1e-2
        assert 0.75 < last["K_I"] / K_IC < 0.9
        assert last["x"] == 1.0 and abs(first["x"] + 1.0 + 0.3 * n) < 1e-2
        prof = run.frames[n]
        opening = np.asarray(prof["opening"])
        open_ = opening > 1e-9 * opening.max()
        in_situ = np.array([-uncracked.sigma(m(x, y))[3] for x, y in zip(prof["x"], prof["y"])])
        assert open_.mean() > 0.9 and np.all(step["pressure"] > in_situ[open_])
    assert run.final.cracks[0].points[-1] == (1.0, 0.0)
