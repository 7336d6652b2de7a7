"""3D Coulomb friction near and at full stick, and the one outer Coulomb loop of every frictional solve.

The penny at 60 degrees to a compression (sigma_n = 0.25, tau = 0.433 on its plane: the continuum sticks for
mu > tau / sigma_n = 1.73) on the tiny mesh of the serial friction tests (box 4a, 509-ish tetrahedra). Near the
smallest coefficient that holds every face the sticking forces that balance the residual are not unique and
their minimum-norm member leaves the cone: the semismooth Newton method used to cycle there (at mu = 1.8-2.4 on
this mesh, at mu = 2 on the standard 20a box of BENCHMARKS); it now picks the member nearest the cone
(`core.coulomb.cone_forces`). On this coarse mesh the discrete Coulomb problem sticks everywhere from mu
between 2.0 and 2.2 (1.997 on the 20a box at the default sizes), so mu = 2.3 is its full stick.

Sticking faces carry no shear singularity: K_II = K_III = 0 up to the front integral's own error. The integral's
face friction term (`solid.face_friction`) takes the faces' mean traction out as a uniform shear whose K (zero in
the continuum) it subtracts, so that a uniform face traction is extracted exactly (the patch test below); what a
sticking crack keeps is the extraction's error on the remaining uniform stress (normal and in-plane), which the
frictionless K of the closed crack carries too.
"""

from __future__ import annotations

import dataclasses
import math

import ngsolve as ngs
import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.constraints import ContactSolverError
from ngcrack.core.coulomb import CoulombStep, cone_forces, coulomb_loop
from ngcrack.scenes.coarse3d import inclined_penny
from ngcrack.solid import face_friction
from ngcrack.solid.front import front_parameters
from ngcrack.solid.geometry import make_mesh
from ngcrack.solid.scene import SolidScene

#: the inclination of the crack's normal to the compression (degrees), and the compression
ANGLE, LOAD = 60.0, 1.0


def _scene(mu: float) -> SolidScene:
    d = inclined_penny(mu)
    th = math.radians(ANGLE)
    d["crack"][0]["normal"] = [math.sin(th), 0.0, math.cos(th)]
    return SolidScene.from_dict(d)


def _shear_modes(sol) -> np.ndarray:
    """(points, 2): K_II, K_III along the front."""
    return np.column_stack([sol.fronts[0].K_II, sol.fronts[0].K_III]) if sol.fronts else None


def _front(sol) -> np.ndarray:
    """K_II, K_III of the front integral run again on `sol` (the current face term)."""
    f = front_parameters(sol)[0]
    return np.column_stack([f.K_II, f.K_III])


@pytest.fixture(scope="module")
def stick(free):
    """mu = 2.3 on the tiny mesh: every friction point sticks."""
    return nc.solve(_scene(2.3), crack_mesh=free.smesh)


@pytest.fixture(scope="module")
def free():
    """The frictionless solve of the 60 degree penny on the tiny mesh (the mesh shared by the frictional ones)."""
    smesh = make_mesh(_scene(0.0))
    return nc.solve(_scene(0.0), crack_mesh=smesh)


def test_full_stick_near_the_critical_coefficient(free, stick):
    """mu = 2.3: every friction point sticks, the slips vanish to round-off and the certificate is round-off; the
    shear modes vanish to the extraction's error on the uniform stress left beside the sticking traction."""
    res = stick.contact
    assert res.active.all() and res.stick.all()
    s0 = np.max(np.abs(stick.contact.points.B @ free.y))
    assert np.max(np.abs(res.slip)) < 1e-13 * s0, np.max(np.abs(res.slip)) / s0
    assert all(v < 1e-13 for v in stick.kkt.values()), stick.kkt
    # K_II, K_III over the frictionless ones: measured 0.0113 and 0.0094 (0.061 and 0.089 with each face's point
    # forces spread over it and the face rule alone: `face_friction.CONSISTENT = False`)
    k0 = np.abs(_shear_modes(free)).max(axis=0)
    ratio = np.abs(_shear_modes(stick)).max(axis=0) / k0
    assert np.all(ratio < 0.02), ratio
    # what is left is the front integral's error on the remote uniform stress less its shear on the crack (K = 0 in
    # the continuum, no shear traction on the faces; 0.0108 and 0.0060 of K0): measured within 0.0037 (K_II) and
    # 0.0055 (K_III) of K0 at every front point, the sticking field's own departure from the uniform one
    n = stick.smesh.cracks[0].normal
    s_remote = np.diag([0.0, 0.0, -LOAD])
    t = s_remote @ n - (n @ s_remote @ n) * n
    rest = _front(face_friction.uniform_stress_solution(stick, s_remote - np.outer(t, n) - np.outer(n, t)))
    assert np.all(np.abs(_shear_modes(stick) - rest) < 0.01 * k0), np.abs(_shear_modes(stick) - rest).max(axis=0) / k0


def test_a_uniform_face_traction_is_extracted_exactly(stick):
    """The patch test of the face term: a uniform shear s = tau n + n tau with the point forces of its own traction
    tau at the friction points has K_II = K_III = 0 to round-off (the face rule alone leaves 6-9% of the K of its
    domain integral: the face term before its uniform part was taken out)."""
    res, faces = stick.contact, stick.smesh.cracks[0]
    pts = res.points
    n = faces.normal
    tau = np.array([0.3, 0.7, -0.2])
    tau -= (tau @ n) * n
    # each face's point forces: its traction times its area, shared by the points' weights (sum 1 on a face)
    mesh = stick.smesh.mesh
    rule = ngs.IntegrationRule(ngs.TRIG, face_friction.QUADRATURE_ORDER)
    k = len(rule.weights)
    mp = mesh.MapToAllElements(rule, ngs.BND).reshape(mesh.GetNE(ngs.BND), k)[faces.elements].ravel()
    jac = np.asarray(ngs.specialcf.JacobianMatrix(3, 2)(mp)).reshape(-1, 3, 2)
    area = (np.linalg.norm(np.cross(jac[:, :, 0], jac[:, :, 1]), axis=1) * np.tile(np.array(rule.weights), len(faces.elements)))
    area = area.reshape(-1, k).sum(axis=1)
    lam_t = (pts.omega * area[pts.face])[:, None] * np.einsum("qij,j->qi", pts.basis, tau)
    uniform = face_friction.uniform_stress_solution(stick, np.outer(tau, n) + np.outer(n, tau))
    uniform = dataclasses.replace(uniform, contact=dataclasses.replace(res, lam_t=lam_t))
    scale = np.abs(_front(dataclasses.replace(uniform, contact=None))).max()  # its domain integral alone
    assert np.abs(_front(uniform)).max() < 1e-12 * scale, np.abs(_front(uniform)).max() / scale
    face_friction.CONSISTENT = False
    try:
        before = np.abs(_front(uniform)).max() / scale
    finally:
        face_friction.CONSISTENT = True
    assert before > 0.02, before


def test_slipping_faces_cut_the_shear_modes_by_the_driving_shear(free):
    """mu = 0.4: every point slips; the shear modes are (tau - mu sigma_n) / tau = 0.769 of the frictionless ones
    (the friction traction is the bound's, uniform up to the box's effect on sigma_n). Measured 0.788 and 0.789 with
    the front integral's rule of order 8 on closed fronts (0.766 and 0.778 at order 6; 0.775 and 0.800 with the term
    before: `face_friction.CONSISTENT = False`): on this mesh of 509-ish tetrahedra the rule moves the ratio by 2%."""
    sol = nc.solve(_scene(0.4), crack_mesh=free.smesh)
    assert not sol.contact.stick.any()
    th = math.radians(ANGLE)
    driving = 1.0 - 0.4 * math.cos(th) ** 2 / (math.sin(th) * math.cos(th))
    ratio = np.abs(_shear_modes(sol)).max(axis=0) / np.abs(_shear_modes(free)).max(axis=0)
    assert np.all(np.abs(ratio - driving) < 0.025), (ratio, driving)


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
