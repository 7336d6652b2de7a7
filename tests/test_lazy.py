"""What a solve leaves for later: the error estimate is computed when first asked for.

A deferred estimate equals the one computed at once (also after the pipeline moved on
to other load values: the pending estimates are settled before the loads' Parameters
change), and the JSON result carries it exactly as before.
"""

from __future__ import annotations

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.shell.explorer import scaled_loads

SMALL = dict(maxh=4.0, tip_h=0.05)


def test_the_estimate_waits_until_asked_and_the_json_still_has_it():
    sol = nc.solve("griffith", **SMALL)
    assert sol.estimate_pending and "estimate" not in sol.timings
    d = sol.to_json_dict()
    assert not sol.estimate_pending
    assert d["error_estimate"]["relative"] == pytest.approx(sol.error_estimate.relative, rel=0, abs=0)
    assert 0 < sol.timings["estimate"]


def test_a_pending_estimate_survives_the_next_load_value():
    scene = nc.scenes.load("griffith")
    pipe, opts = nc.Pipeline(), nc.SolveOptions(**SMALL)
    sols = [pipe.run(scaled_loads(scene, p), opts) for p in (0.5, 1.0, 2.0)]
    assert pipe.counts["assemble"] == 1 and pipe.counts["load"] == 2
    assert [s.estimate_pending for s in sols] == [False, False, True]  # settled before each load change
    deferred = np.array([s.error_estimate.energy for s in sols])
    fresh = np.array([nc.solve(scaled_loads(scene, p), **SMALL).error_estimate.energy for p in (0.5, 1.0, 2.0)])
    np.testing.assert_allclose(deferred, fresh, rtol=1e-10)
    np.testing.assert_allclose(deferred / deferred[1], [0.5, 1.0, 2.0], rtol=1e-10)  # linear in the load


def test_setting_the_estimate_replaces_the_pending_one():
    sol = nc.solve("griffith", **SMALL)
    sol.error_estimate = None
    assert not sol.estimate_pending and sol.error_estimate is None
