"""The inclined-crack scene family against its closed forms (frictionless contact)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.scenes import inclined_closed_form, inclined_crack

#: relative L2 error of the sliding profile at the scene's default mesh (measured:
#: bdm 0.19%, tdnns 0.62%, peers 3.2%); the bands let a regression show
SLIDE_BANDS = {"bdm": 0.005, "tdnns": 0.01, "peers": 0.045}


def test_builtin_scene_is_the_function_default():
    assert nc.scenes.load("inclined-compression") == inclined_crack()


def test_closed_form_values():
    cf = inclined_closed_form(inclined_crack(angle=30.0, load=-2.0))
    assert cf["sigma_n"] == pytest.approx(-1.5)
    assert cf["tau"] == pytest.approx(-2.0 * math.sin(math.pi / 6) * math.cos(math.pi / 6))
    assert cf["K_I"] == 0.0


def test_bad_angle_named():
    with pytest.raises(ValueError, match="angle"):
        inclined_crack(angle=95.0)


@pytest.mark.parametrize("element", sorted(SLIDE_BANDS))
def test_closed_crack_slides_as_closed_form(element):
    scene = inclined_crack()
    cf = inclined_closed_form(scene)
    sol = nc.solve(scene, element=element)
    prof = sol.crack_profiles()[0]
    s = prof.s - 1.0
    exact = 4 * (1 - 0.3 ** 2) / 1000.0 * cf["tau"] * np.sqrt(np.clip(1 - s ** 2, 0, None))
    err = np.linalg.norm(prof.tangential_jump - exact) / np.linalg.norm(exact)
    assert err < SLIDE_BANDS[element]
    assert np.max(np.abs(prof.normal_jump)) <= 1e-12 * np.max(np.abs(exact))
    assert np.mean(prof.normal_stress) == pytest.approx(cf["sigma_n"], rel=0.01)
