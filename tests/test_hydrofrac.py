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
from ngcrack.studies.hydrofrac.result import STEP_KEYS, TIP_KEYS

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
    assert list(data) == ["scene", "element", "rate", "K_Ic", "stopped", "steps", "cracks"]
    assert [list(s) for s in data["steps"]] == [list(STEP_KEYS) + ["tips"]] * 2
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
