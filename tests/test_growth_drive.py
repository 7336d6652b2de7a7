"""Growth driven by round-off (issue 43, item 6): a tip whose K_eq is the discretization's noise on the load's
scale (growth/drive.py) neither grows nor kinks, and a run where no tip is driven stops saying so.

The scene: the three-point-bend beam with its force reversed (pulling the midspan up): the crack's faces are
pressed together (K_I = 0) and K_II = 0 by symmetry; computed, K_II is 1e-5 to 1e-2 of sigma_rms sqrt(pi a)
depending on the element and the mesh. Before, the lone tip was grown with its load scaled by 1e3 to 1e4 and a
kink of +-88 degrees.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import ngcrack as nc
from ngcrack.shell.cli import main
from ngcrack.studies.growth import drive, loop


@pytest.fixture(scope="module")
def reversed_bend(tmp_path_factory) -> Path:
    text = (Path(nc.scenes.__file__).parent / "three-point-bend.toml").read_text()
    assert text.count("value = [0.0, -1.0]") == 1
    path = tmp_path_factory.mktemp("bend") / "reversed-bend.toml"
    path.write_text(text.replace("value = [0.0, -1.0]", "value = [0.0, 1.0]"))
    return path


@pytest.mark.parametrize("element", ["tdnns", "h1p1"])
def test_the_reversed_three_point_bend_does_not_grow(reversed_bend, tmp_path, capsys, element):
    """tdnns: noise 9e-5 of the load's scale, below the floor 1e-3; h1p1: noise 2.0e-3 of the load's scale, above the
    floor and below 0.2 times its error estimate (0.27)."""
    out = tmp_path / "g.json"
    code = main(["grow", str(reversed_bend), "--da", "0.1", "--steps", "3", "--maxh", "0.5", "--element", element,
                 "--json", str(out)])
    assert code == 0
    lines = capsys.readouterr().out.splitlines()
    stop = [ln for ln in lines if "stopped:" in ln]
    assert len(stop) == 1 and stop[0].startswith("three-point-bend: 1 steps, stopped: no tip can grow: tip 0,last: "
                                                 "no driving force: K_eq = "), lines
    assert "the load neither opens nor shears the crack there" in stop[0]
    data = json.loads(out.read_text())
    assert len(data["steps"]) == 1 and data["steps"][0]["load_factor"] is None
    tip = data["steps"][0]["tips"][0]
    assert tip["kink_deg"] == 0.0 and tip["grew"] is False and tip["K_I"] == 0.0
    assert 0.0 < tip["K_eq"] < 0.2 * 1.6  # noise, well below 0.2 of the load's scale (1.6 to 1.7 here)
    assert data["cracks"][0]["points"] == [[4.5, 0.0], [4.5, 0.8]]  # no segment added


def test_noise_against_the_load_scale_forward_and_reversed(reversed_bend):
    """The same beam: forward, K_eq is 2.3 times sigma_rms sqrt(pi a) and the tip is driven; reversed, K_eq is
    below 1e-3 of it (the floor) and the tip is not."""
    for scene, driven in ((nc.scenes.load("three-point-bend"), True), (nc.Scene.from_toml(reversed_bend), False)):
        sol = nc.solve(scene, maxh=0.5)
        values = loop.tip_values(sol)
        k_load = drive.stress_rms(sol) * math.sqrt(math.pi * 0.8)
        ratio = values[0]["K_eq"] / k_load
        reasons = drive.noise_reasons(sol, scene, values)
        if driven:
            assert ratio == pytest.approx(2.34, rel=0.02) and reasons == {}
        else:
            assert ratio < drive.DRIVE_NOISE_FLOOR and list(reasons) == ["0,last"]


def test_stress_rms_of_uniform_tension():
    """sigma_rms of the uncracked plate under uniaxial stress s is s (the only stress component)."""
    scene = nc.scenes.load("griffith")
    sol = nc.solve(scene, maxh=0.5, crack_model="bonded")  # bonded faces: the plate without its crack
    sigma = max(abs(bc.value[1]) for bc in scene.boundary.values() if bc.type == "traction")
    assert drive.stress_rms(sol) == pytest.approx(sigma, rel=1e-6)
