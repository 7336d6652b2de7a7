"""Coulomb friction on a 3D crack under `mpiexec -n 2` (and 3) against the serial 3D solve.

The distributed crack problem (ngcrack.distributed.solid_friction: Newton steps by projected
CG) and the serial one (ngcrack.core.sparse_friction: a semismooth Newton method with sparse LU)
solve the same discrete law at the same friction points. Asserted against the serial solve
on the same mesh in the same run: the normal jumps and the slips at every point to 1e-8 of
their largest, the same open / stick / slip sets, K_I, K_II, K_III to 1e-8 of their largest,
the Coulomb KKT residuals (cone, slip law, stationarity) at the Krylov tolerance.

Scenes: the inclined penny pressed shut (every point closed; at mu = 0.4 all but one slip,
at mu = 1.5 all stick) and the bent beam (half the crack open; at mu = 1 points stick and
slip on the closed half).
"""

from __future__ import annotations

import json
import textwrap

import numpy as np
import pytest
from test_mpi import _run, pytestmark  # noqa: F401  (the mpi4py skip)
from test_solid_friction_open import open_penny

from ngcrack.scenes.coarse3d import bent_penny, inclined_penny

RECORD = textwrap.dedent('''
    import json, sys
    import ngcrack as nc
    from ngcrack.solid.scene import SolidScene
    scene = SolidScene.from_dict(json.loads(open(sys.argv[2]).read()))
    sol = nc.solve(scene)  # under mpiexec -n 2, 3: the distributed 3D solve (None on ranks > 0); -n 1: the serial one
    if sol is not None:
        c = sol.contact
        out = dict(K=[[f.K_I.tolist(), f.K_II.tolist(), f.K_III.tolist()] for f in sol.fronts],
                   jumps=sol.normal_jumps().tolist(), slip=c.slip.tolist(), active=c.active.tolist(),
                   stick=c.stick.tolist(), on=(c.bound > 0).tolist(), kkt=sol.kkt, residuals=c.residuals,
                   info=sol.distributed)
        json.dump(out, open(sys.argv[1], "w"))
''')


def _record(tmp_path, scene: dict, n: int) -> dict:
    (tmp_path / "record.py").write_text(RECORD)
    (tmp_path / "scene.json").write_text(json.dumps(scene))
    out = tmp_path / f"out{n}.json"
    proc = _run([str(tmp_path / "record.py"), str(out), str(tmp_path / "scene.json")], n=n)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(out.read_text())


def _compare(tmp_path, scene: dict, n: int = 2, serial: bool = True) -> dict:
    """The distributed record over n ranks and, with `serial`, the serial one (-n 1, its own process) as *_serial."""
    r = _record(tmp_path, scene, n)
    if serial:
        r.update({f"{k}_serial": v for k, v in _record(tmp_path, scene, 1).items()})
    return r


def _bent(mu: float) -> dict:
    out = bent_penny()
    out["crack"][0]["friction"] = mu
    return out


def _relative(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    scale = np.max(np.abs(b))
    return float(np.max(np.abs(a - b)) / scale) if scale > 0 else float(np.max(np.abs(a)))


def check_equal_to_serial(r: dict, slip_scale: float | None = None) -> None:
    """The distributed answer equals the serial one (module docstring)."""
    assert _relative(r["K"], r["K_serial"]) <= 1e-8
    # the jumps' scale: the largest normal jump or slip (or, every point sticking, the frictionless slip's)
    jumps, slip = np.array(r["jumps"]), np.array(r["slip"])
    jumps_s, slip_s = np.array(r["jumps_serial"]), np.array(r["slip_serial"])
    scale = max(np.max(np.abs(jumps_s)), np.max(np.abs(slip_s)), slip_scale or 0.0)
    assert np.max(np.abs(jumps - jumps_s)) <= 1e-8 * scale and np.max(np.abs(slip - slip_s)) <= 1e-8 * scale
    assert r["active"] == r["active_serial"] and r["stick"] == r["stick_serial"] and r["on"] == r["on_serial"]
    # the Coulomb KKT residuals (relative to the largest normal force): cone and slip law at round-off,
    # stationarity at the Krylov tolerance (CG to 1e-12): measured 1.9e-11 to 1.5e-10
    assert r["residuals"]["cone"] <= 1e-14 and r["residuals"]["slip_law"] <= 1e-11, r["residuals"]
    assert max(r["kkt"].values()) <= 5e-10, r["kkt"]


def test_inclined_penny_under_friction_meets_the_coulomb_kkt(tmp_path):
    """mpiexec -n 2, the inclined penny shut at mu = 0.4 (509 tetrahedra), the distributed solve alone: its
    certificate from rank 0's serial system, the serial solve's sets (every point closed, one sticking, 80
    slipping; the serial comparison is the slow test below)."""
    r = _compare(tmp_path, inclined_penny(0.4), serial=False)
    assert all(r["active"]) and all(r["on"]) and sum(r["stick"]) == 1
    assert r["residuals"]["cone"] <= 1e-14 and r["residuals"]["slip_law"] <= 1e-11, r["residuals"]
    assert max(r["kkt"].values()) <= 5e-10, r["kkt"]  # stationarity at the Krylov tolerance: 4.1e-11 measured
    assert r["info"]["ranks"] == 2 and r["info"]["active_set_steps"] <= 20


@pytest.mark.slow
def test_inclined_penny_slipping_equals_serial(tmp_path):
    """The same against the serial solve."""
    check_equal_to_serial(_compare(tmp_path, inclined_penny(0.4)))


@pytest.mark.slow
def test_inclined_penny_sticking_equals_serial(tmp_path):
    """mu = 1.5 > tau / sigma_n = 1: every point sticks; the slips are zero (compared on the frictionless slip's
    scale, 1e-3 here)."""
    r = _compare(tmp_path, inclined_penny(1.5))
    assert all(r["stick"])
    check_equal_to_serial(r, slip_scale=1e-3)


@pytest.mark.slow
@pytest.mark.parametrize("n", [2, 3])
def test_bent_beam_stick_and_slip_equals_serial(tmp_path, n):
    """The bent beam at mu = 1: half the crack open, points sticking and slipping on the closed half."""
    r = _compare(tmp_path, _bent(1.0), n=n)
    check_equal_to_serial(r)
    stick, on = np.array(r["stick"]), np.array(r["on"])
    assert 0.3 < np.mean(r["active"]) < 0.7 and 0 < stick.sum() < on.sum()
    assert r["info"]["subdomains"] == n - 1


@pytest.mark.slow
def test_open_penny_with_friction_equals_serial(tmp_path):
    """The penny open everywhere with mu = 0.3 (no point closed): the distributed answer and its Coulomb residual
    equal the serial ones (2237 and 2281 before the residual was taken relative to the closed points' forces)."""
    r = _compare(tmp_path, open_penny(0.3))
    assert not any(r["active"]) and not any(r["on"])
    check_equal_to_serial(r)
    assert abs(r["kkt"]["friction"] - r["kkt_serial"]["friction"]) <= 1e-8
