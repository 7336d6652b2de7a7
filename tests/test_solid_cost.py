"""The cheaper 3D solve: the crack problems on the Schur complement of the crack's unknowns, and
the rate of K_I's error along the penny's front at the default mesh choices (BENCHMARKS section 21)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.sparse_contact import solve_contact
from ngcrack.core.sparse_friction import solve_friction
from ngcrack.scenes.coarse3d import inclined_penny
from ngcrack.solid.friction_points import friction_points
from ngcrack.solid.geometry import make_mesh
from ngcrack.solid.scene import SolidScene


@pytest.fixture(scope="module")
def tiny():
    """The closed inclined penny on its tiny mesh (509 tetrahedra), solved once without friction."""
    scene = SolidScene.from_dict(inclined_penny())
    smesh = make_mesh(scene)
    return nc.solve(scene, crack_mesh=smesh)


@pytest.mark.parametrize("load", [-1.0, 1.0])
def test_schur_and_sparse_active_sets_give_the_same_answer(tiny, load):
    """The active set on the dense Schur complement of the crack unknowns (one factorization) and
    the one with a sparse factorization per active set: the same closed points, jumps and forces."""
    system, G = tiny.system, tiny.G
    F = load * system.F  # the scene presses the faces shut; load -1 pulls them open
    a = solve_contact(system.K, F, system.contact, G, method="schur")
    b = solve_contact(system.K, F, system.contact, G, method="sparse")
    assert a.method == "schur" and b.method == "sparse" and a.factorizations == 1
    assert np.array_equal(a.active, b.active) and a.iterations == b.iterations
    assert (a.active.all() if load > 0 else not a.active.any())
    scale = np.max(np.abs(b.y))
    assert np.max(np.abs(a.y - b.y)) < 1e-10 * scale
    assert np.max(np.abs(a.lam - b.lam)) < 1e-9 * max(np.max(np.abs(b.lam)), 1e-300) or not b.active.any()
    assert all(v < 1e-12 for v in a.kkt.values()), a.kkt


@pytest.mark.slow
def test_reduced_and_sparse_coulomb_newton_give_the_same_answer(tiny):
    """Friction mu = 0.4 on the inclined penny: the semismooth Newton method on the crack's Schur
    complement and on the whole sparse system find the same slips, sets and certificate."""
    system, G = tiny.system, tiny.G
    points = friction_points(tiny.smesh, tiny.disc, system, [0.4])
    a = solve_friction(system.K, system.F, system.contact, G, points, method="schur")
    b = solve_friction(system.K, system.F, system.contact, G, points, method="sparse")
    assert np.array_equal(a.active, b.active) and np.array_equal(a.stick, b.stick)
    assert np.max(np.abs(a.slip - b.slip)) < 1e-9 * np.max(np.abs(b.slip))
    assert a.kkt["friction"] < 1e-10 and b.kkt["friction"] < 1e-10, (a.kkt, b.kkt)
    assert a.timings["reduced_unknowns"] < 0.2 * system.n  # the Newton steps see the crack's unknowns only


@pytest.mark.slow
def test_penny_K_I_error_falls_with_the_front_size_at_the_default_choices():
    """Order 1, the penny of side 20a at front_h = 0.4a and 0.2a (crack_h = 2 front_h; the body's size
    near the crack and the bump along the front of the defaults): K_I's worst error over the front
    points against Sneddon's. Measured (benchmarks/solid_cost.py): 2.14% and 0.61%, a rate of 1.8
    in front_h; the default penny (0.2a) within 1% at every point."""
    sneddon = 2.0 / math.sqrt(math.pi)
    worst = {}
    for h in (0.4, 0.2):
        sol = nc.solve("penny", front_h=h, crack_h=2 * h, maxh=5.0)
        worst[h] = float(np.max(np.abs(sol.fronts[0].K_I / sneddon - 1.0)))
    assert worst[0.2] < 0.01, worst
    assert math.log(worst[0.4] / worst[0.2]) / math.log(2.0) > 1.0, worst


# ------------------------------------------------------------------------------ accuracy=


@pytest.mark.parametrize("value", [0.0, -0.01, 0.003, 0.0049, 0.51, 1.0, float("nan"), float("inf"), "0.01", True])
def test_accuracy_outside_its_range_is_refused_by_name(value):
    from ngcrack.core.errors import InputError

    with pytest.raises(InputError, match=r"accuracy = .*\[0\.005, 0\.5\]"):
        nc.SolveOptions(accuracy=value)


def test_accuracy_is_refused_before_meshing(monkeypatch):
    """With front_h or crack_h (it sets them), and in 2D (adapt is its counterpart there): refused by name,
    and nothing is meshed."""
    from ngcrack.core.errors import InputError
    from ngcrack.planar import stages as planar_stages
    from ngcrack.solid import stages as solid_stages

    def no_mesh(*args, **kwargs):
        raise AssertionError("meshed before the refusal")

    monkeypatch.setattr(solid_stages, "make_mesh", no_mesh)
    monkeypatch.setattr(planar_stages.PlanarBody, "make_mesh", no_mesh)
    for size in ("front_h", "crack_h"):
        with pytest.raises(InputError, match=f"accuracy = 0.01 sets front_h and crack_h; give accuracy or {size}"):
            nc.solve("penny", accuracy=0.01, **{size: 0.3})
    with pytest.raises(InputError, match="accuracy: an option of 3D scenes only.*adapt"):
        nc.solve("griffith", accuracy=0.01)


@pytest.mark.parametrize("argv, fragment", [
    (["solve", "penny", "--accuracy", "0.004"], "--accuracy = 0.004: the relative error of K"),
    (["solve", "penny", "--accuracy", "0.02", "--front-h", "0.3"], "give accuracy or front_h, not both"),
    (["solve", "griffith", "--accuracy", "0.01"], "--accuracy: an option of 3D scenes only"),
])
def test_accuracy_on_the_command_line_is_refused_in_one_line(tmp_path, capsys, argv, fragment):
    from ngcrack.shell.cli import main

    out = tmp_path / "r.json"
    assert main(argv + ["--json", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert fragment in err and len(err.splitlines()) == 1 and not out.exists()


def test_accuracy_maps_to_smaller_sizes_monotonically():
    """A tighter accuracy never asks for a coarser mesh: front_h falls as accuracy^(1/1.19) (the measured rate of
    the worst front point's error), 0.005 gives the default sizes, and the coarse end stops at 0.15 of the crack's
    size; crack_h is twice front_h; the 3D options and the size guard see these sizes."""
    from ngcrack.solid import sizing
    from ngcrack.solid.options import solid_options
    from ngcrack.solid.scene import DEFAULT_FRONT_H_RTOL
    from ngcrack.solid.sizing import ACCURACY_RATE, accuracy_sizes, estimate_size

    scene = nc.scenes.load("penny")
    values = np.geomspace(0.5, 0.005, 25)
    sizes = [accuracy_sizes(scene, a) for a in values]
    h = np.array([s["front_h"] for s in sizes])
    assert np.all(np.diff(h) <= 0) and h[-1] < h[0]
    assert all(math.isclose(s["crack_h"], 2 * s["front_h"]) for s in sizes)
    assert math.isclose(accuracy_sizes(scene, 0.005)["front_h"], 0.2) and math.isclose(h[0], 0.3)
    assert sizing.ACCURACY_FRONT_H_RTOL == DEFAULT_FRONT_H_RTOL  # accuracy = 0.005 asks for the 3D defaults
    fine = accuracy_sizes(scene, 0.005)["front_h"] / accuracy_sizes(scene, 0.006)["front_h"]
    assert math.isclose(fine, (5 / 6) ** (1 / ACCURACY_RATE))
    opts = solid_options(nc.SolveOptions(accuracy=0.006), scene)
    assert math.isclose(opts["front_h"], 0.2 * 1.2 ** (1 / ACCURACY_RATE)) and math.isclose(opts["crack_h"], 2 * opts["front_h"])
    tets = [estimate_size(scene, maxh=5.0, **accuracy_sizes(scene, a)).tets for a in (0.008, 0.006, 0.005)]
    assert tets[0] < tets[1] < tets[2]


@pytest.mark.slow
def test_penny_K_within_the_accuracy_asked_for():
    """accuracy = 0.005, the tightest taken, on the penny of side 20a (the default sizes: front_h 0.2a, crack_h 0.4a;
    about 19 s of CPU): K_I within 0.5% of Sneddon's at every front point (measured 0.14%; 0.71% before the front
    integral's closed-form disc; the block's own correction to Sneddon's infinite body is of order (a / 10a)^3)."""
    sol = nc.solve("penny", accuracy=0.005)
    K = sol.fronts[0].K_I
    worst = float(np.max(np.abs(K / (2.0 / math.sqrt(math.pi)) - 1.0)))
    assert worst < 0.005, worst
