"""The crack problem's strategies against each other on the same problem (ngcrack.core.crack_problem).

One problem, posed once, solved by the dense strategy (the Schur complement and the crack QP
on it) and by the sparse one (the active set on the factorized system, forced by lowering the
dense strategy's threshold to 0): the fracture parameters agree to 1e-10 (measured 5.6e-12 in
2D, 1.2e-12 in 3D), the active sets are the same, both answers' KKT residuals are round-off;
in 2D (paper-2: 4 of its 40 constraint values closed) and in 3D (the bent coarse penny, half
closed, and the inclined penny pressed shut with Coulomb friction 0.3). The crack unknowns agree
to 1e-10 in 3D and to 1e-7 in 2D (measured 7.3e-9): the 2D dense strategy takes the QP's j on S
as it is, where the 3D one solves the answer again on the whole system (refined), and S carries
the partial factorization's rounding. The choice rule is by size and ranks, not by dimension.
"""

from __future__ import annotations

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core import constraints
from ngcrack.core.crack_problem import STRATEGIES, ContactProblem, choose_strategy, solve
from ngcrack.core.errors import InputError
from ngcrack.scenes.coarse3d import bent_penny, inclined_penny
from ngcrack.solid.scene import SolidScene
from ngcrack.solid.solve import solve_solid

#: the strategies' answers on the same problem agree to this (relative to the largest value)
AGREE = 1e-10
#: the 2D crack unknowns agree to this (module docstring)
AGREE_2D_JUMPS = 1e-7
#: and each answer's KKT residuals are at most this
KKT_ROUND_OFF = 1e-10


def _rel(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.max(np.abs(a - b)) / max(float(np.max(np.abs(a))), 1e-300))


def test_the_choice_is_by_size_and_ranks():
    m = constraints.SCHUR_MAX_M
    assert [choose_strategy(n) for n in (1, m, m + 1)] == ["dense", "dense", "sparse"]
    assert choose_strategy(10, ranks=2) == choose_strategy(m + 1, ranks=4) == "krylov"
    assert choose_strategy(m + 1, frictional_on_schur=True) == "dense"  # the 2D problem with friction is posed on S
    assert len(STRATEGIES) == 3


def test_krylov_and_unknown_strategies_are_refused_by_name():
    problem = ContactProblem(K=np.eye(2), F=np.ones(2), contact=np.array([1]))
    with pytest.raises(InputError, match="mpiexec"):
        solve(problem, "krylov")
    with pytest.raises(InputError, match="dense, sparse, krylov"):
        solve(problem, "cholesky")


def test_dense_and_sparse_agree_in_2d(monkeypatch):
    scene = nc.scenes.load("paper-2")
    dense = nc.solve(scene)
    monkeypatch.setattr(constraints, "SCHUR_MAX_M", 0)
    sparse = nc.solve(scene)
    assert sparse.qp.solver == "sparse active set" and dense.qp.solver == "pdas"
    m = len(dense.qp.j)  # the sparse strategy forms no dense Schur complement (its m^2 entries)
    assert sparse.backend.largest_dense == 0 and dense.backend.largest_dense == m * m
    assert 0 < len(dense.qp.active) < m and np.array_equal(dense.qp.active, sparse.qp.active)
    assert _rel(dense.qp.j, sparse.qp.j) <= AGREE_2D_JUMPS
    K = [np.array([[t.K_I, t.K_II] for t in s.tips]) for s in (dense, sparse)]
    assert _rel(*K) <= AGREE
    assert max(max(s.kkt.values()) for s in (dense, sparse)) <= KKT_ROUND_OFF


@pytest.mark.parametrize("scene", [bent_penny(), inclined_penny(0.3)], ids=["bent-penny", "friction-0.3"])
def test_dense_and_sparse_agree_in_3d(monkeypatch, scene):
    scene = SolidScene.from_dict(scene)
    dense = solve_solid(scene)
    monkeypatch.setattr(constraints, "SCHUR_MAX_M", 0)
    sparse = solve_solid(scene)
    # the dense strategy factorizes once with the crack unknowns last ("factorize"), the sparse one per step
    assert "factorize" in dense.contact.timings and "factorize" not in sparse.contact.timings
    assert np.any(dense.contact.active) and np.array_equal(dense.contact.active, sparse.contact.active)
    assert np.max(np.abs(dense.normal_jumps() - sparse.normal_jumps())) <= AGREE * np.max(np.abs(dense.y))
    K = [np.array([[f.K_I, f.K_II, f.K_III] for f in s.fronts]).ravel() for s in (dense, sparse)]
    assert _rel(*K) <= AGREE
    assert max(max(s.kkt.values()) for s in (dense, sparse)) <= KKT_ROUND_OFF


def test_a_cvxpy_solver_on_the_3d_schur_complement_gives_the_native_answer(monkeypatch):
    """The dense strategy takes any QP solver in 3D as in 2D: clarabel on the bent penny's crack QP (half
    closed) ends, after the native polish, with the same closed points and K as pdas; above the dense
    strategy's size the QP solver has no problem to solve and is refused by name."""
    scene = SolidScene.from_dict(bent_penny())
    native = solve_solid(scene)
    other = solve_solid(scene, qp_solver="clarabel")
    assert 0 < native.contact.active.sum() < len(native.contact.active)
    assert np.array_equal(native.contact.active, other.contact.active)
    K = [np.array([[f.K_I, f.K_II, f.K_III] for f in s.fronts]).ravel() for s in (native, other)]
    assert _rel(*K) <= AGREE
    assert max(other.kkt.values()) <= KKT_ROUND_OFF
    monkeypatch.setattr(constraints, "SCHUR_MAX_M", 0)
    with pytest.raises(InputError, match="qp_solver = 'clarabel'.*allowed value: pdas"):
        solve_solid(scene, qp_solver="clarabel")
    with pytest.raises(InputError, match="qp_solver = 'nope': allowed values are pdas"):
        solve_solid(scene, qp_solver="nope")
