"""3D Coulomb friction near and at full stick, and the one outer Coulomb loop of every frictional solve.

The penny at 60 degrees to a compression (sigma_n = 0.25, tau = 0.433 on its plane: the continuum sticks for
mu > tau / sigma_n = 1.73) on the tiny mesh of the serial friction tests (box 4a, 509-ish tetrahedra). Near the
smallest coefficient that holds every face the sticking forces that balance the residual are not unique and
their minimum-norm member leaves the cone: the semismooth Newton method used to cycle there (at mu = 1.8-2.4 on
this mesh, at mu = 2 on the standard 20a box of BENCHMARKS); it now picks the member nearest the cone
(`core.coulomb.cone_forces`). On this coarse mesh the discrete Coulomb problem sticks everywhere from mu
between 2.0 and 2.2 (1.997 on the 20a box at the default sizes), so mu = 2.3 is its full stick.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.constraints import ContactSolverError
from ngcrack.core.coulomb import CoulombStep, cone_forces, coulomb_loop
from ngcrack.scenes.coarse3d import inclined_penny
from ngcrack.solid.geometry import make_mesh
from ngcrack.solid.scene import SolidScene


def _scene(mu: float) -> SolidScene:
    d = inclined_penny(mu)
    th = math.radians(60.0)
    d["crack"][0]["normal"] = [math.sin(th), 0.0, math.cos(th)]
    return SolidScene.from_dict(d)


@pytest.fixture(scope="module")
def free():
    """The frictionless solve of the 60 degree penny on the tiny mesh (the mesh shared by the frictional ones)."""
    smesh = make_mesh(_scene(0.0))
    return nc.solve(_scene(0.0), crack_mesh=smesh)


def test_full_stick_near_the_critical_coefficient(free):
    """mu = 2.3: every friction point sticks, the slips vanish to round-off and the certificate is round-off."""
    sol = nc.solve(_scene(2.3), crack_mesh=free.smesh)
    res = sol.contact
    assert res.active.all() and res.stick.all()
    s0 = np.max(np.abs(sol.contact.points.B @ free.y))
    assert np.max(np.abs(res.slip)) < 1e-13 * s0, np.max(np.abs(res.slip)) / s0
    assert all(v < 1e-13 for v in sol.kkt.values()), sol.kkt
    # the shear modes: no jump, but the front integral's face friction term (solid.face_friction: each face's
    # point forces spread as a uniform traction) leaves 0.03-0.06 of the frictionless values (measured)
    for name in ("K_II", "K_III"):
        k0, k = np.abs(getattr(free.fronts[0], name)).max(), np.abs(getattr(sol.fronts[0], name)).max()
        assert k < 0.1 * k0, (name, k / k0)


def test_mu_2_converges_with_a_round_off_certificate(free):
    """mu = 2 on the tiny mesh: a few points near the front slip (its critical coefficient is above 2), the
    rest stick; the Newton method settles and the Coulomb law holds to round-off."""
    sol = nc.solve(_scene(2.0), crack_mesh=free.smesh)
    res = sol.contact
    assert res.active.all() and 0.8 * len(res.stick) < np.count_nonzero(res.stick) < len(res.stick)
    assert all(v < 1e-10 for v in sol.kkt.values()), sol.kkt
    assert res.record and res.record[-1]["changes"] == 0 and len(res.record) == res.iterations


def test_cone_forces_picks_a_balancing_member_inside_the_cone():
    """Two points share one constraint (A = [1 0 1 0]: their x forces sum to 1): the minimum-norm split (0.5,
    0.5) leaves the first point's small cone; the nearest member inside the cones puts 0.2 and 0.8."""
    A = np.array([[1.0, 0.0, 1.0, 0.0]])
    lam = cone_forces(A, np.array([-1.0]), np.array([0.2, 2.0]))
    assert abs(lam[:, 0].sum() - 1.0) < 1e-14 and np.linalg.norm(lam[0]) <= 0.2 + 1e-14, lam
    assert np.all(np.linalg.norm(lam, axis=1) <= np.array([0.2, 2.0]) + 1e-14)


def test_coulomb_loop_stops_on_the_bound_and_reports_failure():
    """The shared outer loop: a contraction g -> 0.5 g + 1 settles at 2 to the bound's tolerance; a step that
    keeps changing sets raises ContactSolverError naming the iteration."""
    run = coulomb_loop(lambda g: CoulombStep(0.5 * g + 1.0, 1.0), np.zeros(3), max_steps=100, bound_rtol=1e-12)
    assert np.max(np.abs(run.bound - 2.0)) < 4e-12 and run.steps == len(run.record) and run.steps < 50
    with pytest.raises(ContactSolverError, match="toy iteration did not converge in 5 steps"):
        coulomb_loop(lambda g: CoulombStep(g, 1.0, changes=1), np.zeros(1), max_steps=5, bound_rtol=1e-12,
                     what="the toy iteration")


@pytest.mark.parametrize("module", ["core/friction.py", "core/sparse_friction.py", "distributed/friction.py",
                                    "distributed/solid_friction.py"])
def test_every_frictional_solve_runs_the_shared_outer_loop(module):
    """The four Coulomb solves (2D and 3D, serial and distributed) each call `coulomb_loop` once and keep no
    outer loop of their own (no `while True`, no loop over a step count around their inner step)."""
    import ast
    import pathlib

    tree = ast.parse((pathlib.Path(nc.__file__).parent / module).read_text())
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and getattr(n.func, "id", None) == "coulomb_loop"]
    assert len(calls) == 1, module
    endless = [n for n in ast.walk(tree) if isinstance(n, ast.While) and isinstance(n.test, ast.Constant) and n.test.value]
    assert not endless, module
