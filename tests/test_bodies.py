"""Properties that hold whatever the body: one test body each, the planar and the solid scenes as data.

What is checked, and against what (scikit-fem's pattern: the cases are data, the property is written once):
- a crack that the load opens everywhere gives the same answer with unilateral contact as with
  traction-free faces (the contact code is the identity there): K along the fronts equal to 1e-10;
- on a crack the load closes, the discrete Signorini conditions hold to round-off (KKT <= 1e-12) and
  K_I is reported as 0 at the closed front points;
- the problem is linear in the load while the contact state does not change: scaling every load by
  2.5 on a closed crack scales K_II (2D) or K_II, K_III (3D) by 2.5 to 1e-9;
- the JSON record of either body carries the shared keys with the same meaning.
"""

from __future__ import annotations

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.scenes import coarse3d

#: the bodies: a scene the load opens, one it closes (and shears), and the solve options of each
BODIES = {
    "planar": {"open": lambda: nc.scenes.load("griffith"), "closed": lambda: nc.scenes.load("inclined-compression"),
               "options": {"maxh": 4.0}, "shear": ("K_II",)},
    "solid": {"open": lambda: nc.Scene.from_dict(coarse3d.inclined_penny()).with_(nu=0.3),
              "closed": lambda: nc.Scene.from_dict(coarse3d.inclined_penny()),
              "options": {}, "shear": ("K_II", "K_III")},
}
#: the keys of the `solve --json` record every body writes, with the same meaning
SHARED_KEYS = {"scene", "element", "maxh", "nu", "E", "ndof", "time_s", "kkt", "cracks"}


def _open(body: str):
    scene = BODIES[body]["open"]()
    if body == "solid":  # the inclined penny under tension instead of compression: every face opens
        d = coarse3d.inclined_penny()
        for cond in d["boundary"].values():
            if cond.get("type") == "traction":
                cond["value"] = [-v for v in cond["value"]]
        scene = nc.Scene.from_dict(d)
    return scene


def _K(sol, mode: str) -> np.ndarray:
    return np.concatenate([np.atleast_1d(getattr(f, mode)) for f in sol.fronts])


@pytest.mark.parametrize("body", list(BODIES))
def test_an_open_crack_is_the_same_with_contact_as_with_free_faces(body):
    scene, options = _open(body), BODIES[body]["options"]
    contact = nc.solve(scene, **options)
    free = nc.solve(scene, crack_model="free", **options)
    assert contact.fronts and not any(np.any(f.closed) for f in contact.fronts)
    for mode in ("K_I", "K_II", "G"):
        a, b = _K(contact, mode), _K(free, mode)
        assert np.max(np.abs(a - b)) <= 1e-10 * np.max(np.abs(_K(free, "K_I")))


@pytest.mark.parametrize("body", list(BODIES))
def test_a_closed_crack_meets_the_signorini_conditions_to_round_off(body):
    sol = nc.solve(BODIES[body]["closed"](), **BODIES[body]["options"])
    assert max(sol.kkt.values()) <= 1e-12
    closed = np.concatenate([np.atleast_1d(f.closed) for f in sol.fronts])
    assert closed.all() and np.all(_K(sol, "K_I") == 0.0)
    assert np.max(np.abs(np.concatenate([_K(sol, m) for m in BODIES[body]["shear"]]))) > 0.0


@pytest.mark.parametrize("body", list(BODIES))
def test_the_answer_is_linear_in_the_load_while_the_contact_state_holds(body):
    scene = BODIES[body]["closed"]()
    sol = nc.solve(scene, **BODIES[body]["options"])
    if body == "planar":
        scaled = scene.scaled(load=2.5)
    else:
        d = scene.to_dict()
        for cond in d["boundary"].values():
            if cond.get("type") == "traction":
                cond["value"] = [2.5 * v for v in cond["value"]]
        scaled = nc.Scene.from_dict(d)
    big = nc.solve(scaled, **BODIES[body]["options"])
    for mode in BODIES[body]["shear"]:
        a, b = _K(sol, mode), _K(big, mode)
        assert np.max(np.abs(b - 2.5 * a)) <= 1e-9 * np.max(np.abs(b))


@pytest.mark.parametrize("body", list(BODIES))
def test_the_json_record_has_the_shared_keys(body):
    record = nc.solve(_open(body), **BODIES[body]["options"]).to_json_dict()
    assert SHARED_KEYS <= set(record)
    assert set(record["ndof"]) == {"total", "global", "contact"} and record["ndof"]["contact"] > 0
    assert {"total", "mesh", "assemble", "linear", "contact"} <= set(record["time_s"])
    assert set(record["kkt"]) >= {"max_penetration", "max_tension", "complementarity"}
