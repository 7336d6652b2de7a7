"""The crack's mesh size graded from the tips (path_sizes.py), the block inverse of the
constraint maps (constraints.py), and what both do to a growth run: the graded path against
the path meshed at crack_h (kinks, load factors, tips), friction KKT residuals, unknowns.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.constraints import _compute_inverse_map, _sparse_inverse
from ngcrack.core.errors import InputError
from ngcrack.planar.geometry import make_mesh
from ngcrack.planar.path_sizes import (
    PATH_H_CAP,
    PathGrading,
    check_path_grading,
    grading_points,
    segment_sizes,
    segment_tip_distance,
)


def test_segment_sizes_grow_with_the_distance_from_the_tip_and_are_capped():
    tips = np.array([[0.0, 0.0]])
    a = np.array([[1.0, -1.0], [3.0, 4.0], [100.0, 0.0], [-1.0, 0.5]])
    b = np.array([[1.0, 1.0], [3.0, 5.0], [101.0, 0.0], [1.0, 0.5]])
    d = segment_tip_distance(tips, a, b)
    assert np.allclose(d, [1.0, 5.0, 100.0, 0.5], rtol=0, atol=1e-15)
    h = segment_sizes(tips, a, b, 0.05, PathGrading(0.1), maxh=1.0)
    assert np.allclose(h, [0.15, min(0.55, PATH_H_CAP * 0.05), PATH_H_CAP * 0.05, 0.1], rtol=0, atol=1e-15)
    assert np.all(segment_sizes(tips, a, b, 0.05, PathGrading(0.1), maxh=0.12) <= 0.12)
    # no grading, no tip: crack_h everywhere; segments on a fine polyline keep crack_h
    assert np.all(segment_sizes(tips, a, b, 0.05, None, maxh=1.0) == 0.05)
    assert np.all(segment_sizes(np.zeros((0, 2)), a, b, 0.05, PathGrading(0.1), maxh=1.0) == 0.05)
    fine = (((3.0, 0.0), (3.0, 10.0)),)
    h = segment_sizes(tips, a, b, 0.05, PathGrading(0.1, fine), maxh=1.0, fine=fine, tol=1e-12)
    assert h[1] == 0.05 and h[0] == pytest.approx(0.15)


@pytest.mark.parametrize("value", [0.0, -0.1, 1.5, float("nan"), "0.1", True])
def test_bad_path_grading_refused_naming_the_field(value):
    with pytest.raises(InputError, match="path_grading"):
        check_path_grading(value)
    with pytest.raises(InputError, match="path_grading"):
        nc.SolveOptions(path_grading=value)


def test_grow_refuses_a_bad_path_grading_before_any_solve(monkeypatch):
    from ngcrack.studies.growth import loop

    monkeypatch.setattr(loop, "solve_step", lambda *a: pytest.fail("solved"))
    with pytest.raises(InputError, match="path_grading"):
        nc.grow("inclined-compression", da=0.1, steps=1, path_grading=5.0)


def test_plain_mesh_unchanged_and_graded_crack_coarser_away_from_the_tips():
    """path_grading None is the mesh as before (the same points, bitwise); graded, a long crack
    has fewer triangles, and its edges next to the tips are as fine as before."""
    scene = nc.scenes.load("inclined-compression")
    pts = [(-2.0 + 0.2 * i, 0.02 * (i % 2)) for i in range(21)]  # a long zig-zag path, like a grown one
    scene = scene.with_(cracks=[nc.Crack(pts)])
    plain, again = make_mesh(scene), make_mesh(scene, path_grading=None)
    assert np.array_equal(plain.points, again.points) and np.array_equal(plain.triangles, again.triangles)
    graded = make_mesh(scene, path_grading=0.2)
    assert len(graded.triangles) < 0.9 * len(plain.triangles)
    for cm in (plain, graded):
        c = cm.cracks[0]
        near = np.minimum(np.hypot(*(c.mid - pts[0]).T), np.hypot(*(c.mid - pts[-1]).T)) < 0.1
        assert c.length[near].max() <= 1.01 * scene.crack_h


def _permuted_blocks(rng, sizes):
    m = sum(sizes)
    G = np.zeros((m, m))
    k = 0
    for s in sizes:
        G[k:k + s, k:k + s] = rng.normal(size=(s, s)) + 3 * np.eye(s)
        k += s
    return G[rng.permutation(m)][:, rng.permutation(m)]


def test_block_inverse_of_a_permuted_block_diagonal_map():
    """Blocks whose rows and columns are numbered apart (the tangential map of friction) are
    found as blocks: the inverse is sparse and equals the dense one to round-off."""
    rng = np.random.default_rng(3)
    for sizes in ([2] * 60, [1, 2, 3] * 20, [2] * 59 + [1, 1]):
        G = _permuted_blocks(rng, sizes)
        inv = _sparse_inverse(G)
        assert not isinstance(inv, np.ndarray) and inv.nnz == sum(s * s for s in sizes)
        assert np.abs(inv.toarray() @ G - np.eye(len(G))).max() < 1e-12
    chain = np.diag(np.full(50, 2.0)) + np.diag(np.ones(49), 1)  # one block of 50
    assert np.abs(_sparse_inverse(chain).toarray() @ chain - np.eye(50)).max() < 1e-12
    G = np.eye(4)
    G[1, 1] = 0.0  # singular: numpy's error, as before
    with pytest.raises(np.linalg.LinAlgError):
        _compute_inverse_map(np.kron(np.eye(30), G), 120)


def test_grading_points_are_the_crack_ends():
    cracks = [np.array([(-1.0, 1.0), (0.0, 0.0), (1.0, 0.0)]), np.array([(5.0, 5.0), (6.0, 5.0)])]
    assert grading_points(cracks).tolist() == [[-1.0, 1.0], [1.0, 0.0], [5.0, 5.0], [6.0, 5.0]]


# ------------------------------------------------------------------ growth: graded path against the path at crack_h
STEPS, DA = 4, 0.25


@pytest.fixture(scope="module")
def both_runs():
    scene = nc.scenes.load("inclined-compression").with_(friction=0.3)
    kw = dict(da=DA, steps=STEPS, K_Ic=2.0, frames=False)
    return scene, nc.grow(scene, **kw), nc.grow(scene, path_grading=None, **kw)


def test_graded_path_follows_the_path_at_crack_h_with_fewer_unknowns(both_runs):
    """The teaching scene's wings, 4 steps of 0.25: the same kinks (within 0.5 degrees: PLS keeps a
    kink within 1.5 degrees of its angle) and load factors (0.3%), tips 1e-3 apart, fewer unknowns."""
    scene, graded, uniform = both_runs
    a, b = graded.table, uniform.table
    both = a.merge(b, on=["step", "crack", "end"], suffixes=("", "_u"))
    assert len(both) == 2 * (STEPS + 1)
    grown = both[both.kink_deg.notna()]
    assert np.abs(grown.kink_deg - grown.kink_deg_u).max() < 0.5
    assert np.abs(both.load_factor / both.load_factor_u - 1).max() < 3e-3
    last = both[both.step == STEPS]
    assert np.hypot(last.x - last.x_u, last.y - last.y_u).max() < 1e-3 * DA * STEPS
    ndof = a.groupby("step").ndof.first().to_numpy(), b.groupby("step").ndof.first().to_numpy()
    assert ndof[0][-1] - ndof[0][0] < 0.6 * (ndof[1][-1] - ndof[1][0])
    assert a.kkt.max() < 1e-10  # the friction problem solved exactly by the Newton method (largest residual)


def test_graded_mesh_of_a_grown_scene_gives_the_same_K(both_runs):
    """The last grown scene of the run at crack_h, meshed graded: K_I within 0.5%, K_II within 1% of K_I
    (measured 0.34% and 0.81%; 1% of K_I in K_II is 0.4 degrees of PLS kink at dK_II/dtheta = 1.5 K_I)."""
    scene, graded, uniform = both_runs
    last = uniform.scenes[-1]
    fine, coarse = nc.solve(last), nc.solve(last, path_grading=0.1)
    assert coarse.ndof["total"] < fine.ndof["total"]
    for s, t in zip(fine.tips, coarse.tips):
        assert abs(t.K_I - s.K_I) < 5e-3 * s.K_I and abs(t.K_II - s.K_II) < 1e-2 * s.K_I


def test_grow_command_path_grading(tmp_path, capsys):
    """`ngcrack grow --path-grading`: a bad rate refused before any work (exit 2, naming the field);
    none meshes the path at crack_h: step 0 is the plain solve's mesh."""
    from ngcrack.shell.cli import main

    out = tmp_path / "bad.json"
    code = main(["grow", "griffith", "--da", "0.05", "--steps", "1", "--path-grading", "2", "--json", str(out)])
    assert code == 2 and "path_grading" in capsys.readouterr().err and not out.exists()
    out = tmp_path / "g.json"
    code = main(["grow", "griffith", "--da", "0.05", "--steps", "1", "--K-Ic", "2", "--criterion", "mts", "--maxh", "0.5",
                 "--path-grading", "none", "--json", str(out)])
    assert code == 0
    ndof = json.loads(out.read_text())["steps"][0]["ndof"]
    assert ndof == nc.solve("griffith", maxh=0.5).ndof["total"]
