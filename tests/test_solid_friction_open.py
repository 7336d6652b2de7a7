"""Coulomb friction on a 3D crack that opens everywhere (issue 43, item 3, in 3D): the Coulomb law's residual is
relative to the closed points' normal forces, none here, so to the load's scale (1.9e-11, the sparse LU solve's
stationarity). Before, it was relative to the largest normal force read from the residual at the open points,
round-off (1.5e-14): the serial solve reported a friction KKT residual of 1935 (2281 on a finer mesh, 2237 under
mpiexec -n 2) with exit 0. The distributed solve's certificate is the same function (tests/test_mpi_solid_friction.py).
"""

from __future__ import annotations

import copy

import numpy as np

from ngcrack.scenes.coarse3d import coarse_penny
from ngcrack.solid.scene import SolidScene
from ngcrack.solid.solve import solve_solid


def open_penny(mu: float) -> dict:
    """The coarse penny under tension (open everywhere) on a coarser mesh (maxh 5, crack_h 0.8, front_h 0.4)."""
    d = copy.deepcopy(coarse_penny())
    d["crack"][0]["friction"] = mu
    d["mesh"] = {"maxh": 5.0, "crack_h": 0.8, "front_h": 0.4}
    return d


def test_friction_on_an_open_crack_changes_nothing_and_its_kkt_is_round_off():
    rough, smooth = (solve_solid(SolidScene.from_dict(open_penny(mu))) for mu in (0.3, 0.0))
    assert not np.any(rough.contact.active)
    assert max(rough.kkt.values()) <= 1e-10, rough.kkt  # the sparse LU solve's stationarity: 1.9e-11 measured
    K, K0 = (np.array([[f.K_I, f.K_II, f.K_III] for f in s.fronts]) for s in (rough, smooth))
    assert np.max(np.abs(K - K0)) <= 1e-10 * np.max(np.abs(K0))
