"""The crack QP and its solvers (contact.py).

What is checked, and against what:
- every QP path (pdas, the paper's Uzawa iteration plain and accelerated, cvxpy with
  clarabel, osqp, scs) gives the known solution to 1e-8 on random SPD instances built
  from a chosen solution: active, inactive and weakly active (v = mu = 0) indices, with
  cond(S) from 1e2 to 1e8, with G = I and with a block-diagonal G like the P1 map;
- every path gives the same crack jumps to 1e-8 on the paper's scenes (maxh 0.1);
- failure modes: a cvxpy status other than optimal, NaN values, a non-finite S, a pdas
  that runs out of steps all raise ContactSolverError naming the solver;
- warm starts: the exact active set makes pdas converge in one step; a Solution from a
  coarser mesh carried over by crack position; the same answer with and without.

Run with `-s` to see the measured numbers (lines starting with "[contact]").
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest
from test_schur import system

import ngcrack.scenes as scenes
from ngcrack.core import contact
from ngcrack.core.contact import ContactSolverError, QPResult, solve_qp, warm_start_data
from ngcrack.core.hybrid import reduce_to_contact
from ngcrack.core.solve import solve
from ngcrack.planar.post import endpoint_map

#: every path agrees with the known (or reference) solution to this, relative to its size
AGREE_RTOL = 1e-8
#: the QP paths: (name, solver, options)
PATHS = [
    ("pdas", "pdas", {}),
    ("uzawa", "uzawa", {}),
    ("uzawa-accelerated", "uzawa", {"accelerate": True}),
    ("clarabel", "clarabel", {}),
    ("osqp", "osqp", {"eps_abs": 1e-10, "eps_rel": 1e-10, "max_iter": 100_000}),
    ("scs", "scs", {"eps_abs": 1e-10, "eps_rel": 1e-10}),
]
IDS = [p[0] for p in PATHS]


def report(*args):
    print("[contact]", *args)


def known_instance(m: int, cond: float, n_active: int, n_weak: int, seed: int, multipliers: bool = False):
    """(S, b, v[, mu]): S SPD with eigenvalues 1..cond, v the solution of min 0.5 v'Sv - b'v, v >= 0.

    n_active indices have v = 0 < mu, n_weak have v = mu = 0 (weakly active), the rest
    v > 0 = mu; b = S v - mu.
    """
    rng = np.random.default_rng(seed)
    Q, _ = np.linalg.qr(rng.standard_normal((m, m)))
    S = (Q * np.logspace(0.0, np.log10(cond), m)) @ Q.T
    S = 0.5 * (S + S.T)
    idx = rng.permutation(m)
    active, free = idx[:n_active], idx[n_active + n_weak:]
    v = np.zeros(m)
    v[free] = rng.uniform(0.5, 2.0, len(free))
    Sv = S @ v
    mu = np.zeros(m)
    mu[active] = rng.uniform(0.5, 2.0, len(active)) * np.abs(Sv).max()
    return (S, Sv - mu, v, mu) if multipliers else (S, Sv - mu, v)


def block_map(m: int) -> np.ndarray:
    """A block-diagonal G with 2x2 blocks like the P1 end-point map (invertible)."""
    G = np.eye(m)
    for k in range(0, m - 1, 2):
        G[k:k + 2, k:k + 2] = [[0.75, 0.25], [0.25, 0.75]] if k % 4 else [[1.0, 0.3], [-0.2, 1.0]]
    return G


def run(S, b, G, solver, options, **kw) -> QPResult:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "optimal_inaccurate" answers are polished and checked
        return solve_qp(S, b, G=G, solver=solver, solver_options=options, **kw)


@pytest.mark.parametrize("cond", [1e2, 1e5, 1e8])
@pytest.mark.parametrize("use_g", [False, True], ids=["G=I", "G=P1"])
@pytest.mark.parametrize("name, solver, options", PATHS, ids=IDS)
def test_known_solution(name, solver, options, cond, use_g):
    S_w, b_w, w_ref, mu_ref = known_instance(40, cond, 12, 4, seed=int(np.log10(cond)), multipliers=True)
    if use_g:  # the same QP in j with w = G j: S = G' S_w G, b = G' b_w
        G = block_map(40)
        S, b = G.T @ S_w @ G, G.T @ b_w
    else:
        G, S, b = None, S_w, b_w
    r = run(S, b, G, solver, options)
    err = np.abs(r.w - w_ref).max() / np.abs(w_ref).max()
    report(f"{name} cond {cond:.0e} {'G=P1' if use_g else 'G=I'}: |w - w*| {err:.1e}, raw KKT "
           f"{max(r.raw_kkt.values()):.1e}, KKT {max(r.kkt.values()):.1e}, {r.iterations} steps")
    assert err <= AGREE_RTOL
    assert max(r.kkt.values()) <= contact.KKT_TOL
    # the weakly active and active indices end at w = 0, the multipliers are >= 0 up to
    # round-off (a weakly active index has a zero multiplier of either sign)
    assert np.all(r.w >= 0) and r.multiplier.min() >= -contact.KKT_TOL * np.abs(r.multiplier).max()
    # the strictly active set is found exactly; a weakly active index may end at round-off
    # above zero
    strict = set(np.flatnonzero(mu_ref > 0))
    assert strict <= set(r.active) <= set(np.flatnonzero(w_ref == 0))


def test_contact_values_a_solver_stops_short_of_zero_are_active(monkeypatch):
    # an interior-point or ADMM solver may stop a contact value at 1e-21 instead of 0 (osqp 1.1.3
    # did at 6 of 12): without the polish the active set still holds every strictly active index
    S, b, v_ref, mu_ref = known_instance(40, 1e4, 12, 4, seed=7, multipliers=True)
    short = v_ref.copy()
    short[mu_ref > 0] = 1e-21 * np.abs(v_ref).max()
    D = 1.0 / np.sqrt(np.diag(S))  # the solver sees the Jacobi-scaled problem with |b| = 1: v = w / (beta D)
    monkeypatch.setattr(contact, "_cvxpy_solve", lambda *a, **k: short / (np.abs(D * b).max() * D))
    r = solve_qp(S, b, solver="clarabel", polish=False)
    assert set(r.active) == set(np.flatnonzero(v_ref == 0))
    assert np.all(r.w[r.active] == 0.0) and max(r.kkt.values()) <= contact.KKT_TOL


@functools.cache
def scene_qp(scene: str, element: str):
    sysm = system(scene, element)
    red = reduce_to_contact(sysm)
    disc = sysm.disc
    G = endpoint_map(disc.fes.components[disc.jn], disc.crack_mesh, disc.facet_order)
    return red.S, red.b, G


@pytest.mark.parametrize("scene", ["paper-1", "paper-2"])
@pytest.mark.parametrize("element", ["peers", "bdm"])
def test_paper_scenes_all_paths_agree(scene, element):
    S, b, G = scene_qp(scene, element)
    ref = run(S, b, G, "pdas", {})
    errs = {}
    for name, solver, options in PATHS[1:]:
        r = run(S, b, G, solver, options)
        errs[name] = float(np.abs(r.j - ref.j).max() / max(np.abs(ref.j).max(), 1e-300))
    report(f"{scene} {element} (m={len(b)}, {len(ref.active)} active): max rel |j - j_pdas| {errs}")
    assert max(errs.values()) <= AGREE_RTOL


# ------------------------------------------------------------------------- failure modes


class _FakeProblem:
    """Stands in for cvxpy.Problem: solve() leaves a chosen status and value."""

    status_to_set = "infeasible"
    value_to_set = None

    def __init__(self, objective, constraints):
        self.variable = objective.args[0].variables()[0]
        self.status = None

    def solve(self, **kwargs):
        self.status = self.status_to_set
        # save_value: what cvxpy itself uses to store a solver's answer (no validation)
        self.variable.save_value(self.value_to_set(self.variable.shape[0]) if self.value_to_set else None)


@pytest.mark.parametrize("status", ["infeasible", "unbounded", "solver_error", "infeasible_inaccurate"])
def test_cvxpy_bad_status_raises_naming_solver(monkeypatch, status):
    import cvxpy as cp

    monkeypatch.setattr(_FakeProblem, "status_to_set", status)
    monkeypatch.setattr(cp, "Problem", _FakeProblem)
    S, b, _ = known_instance(6, 10.0, 2, 0, seed=3)
    with pytest.raises(ContactSolverError, match="osqp") as info:
        solve_qp(S, b, solver="osqp")
    assert status in str(info.value)


def test_cvxpy_nan_raises_naming_solver(monkeypatch):
    import cvxpy as cp

    monkeypatch.setattr(_FakeProblem, "status_to_set", "optimal")
    monkeypatch.setattr(_FakeProblem, "value_to_set", staticmethod(lambda n: np.full(n, np.nan)))
    monkeypatch.setattr(cp, "Problem", _FakeProblem)
    S, b, _ = known_instance(6, 10.0, 2, 0, seed=3)
    with pytest.raises(ContactSolverError, match="clarabel.*non-finite"):
        solve_qp(S, b, solver="clarabel")


def test_cvxpy_solver_exception_raises_naming_solver(monkeypatch):
    import cvxpy as cp

    def boom(self, **kwargs):
        raise cp.error.SolverError("numerical trouble")

    monkeypatch.setattr(cp.Problem, "solve", boom)
    S, b, _ = known_instance(6, 10.0, 2, 0, seed=3)
    with pytest.raises(ContactSolverError, match="scs.*numerical trouble"):
        solve_qp(S, b, solver="scs")


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_data_raise(bad):
    S, b, _ = known_instance(6, 10.0, 2, 0, seed=3)
    S[1, 2] = S[2, 1] = bad
    with pytest.raises(ContactSolverError, match="non-finite"):
        solve_qp(S, b)
    S, b, _ = known_instance(6, 10.0, 2, 0, seed=3)
    b[0] = bad
    with pytest.raises(ContactSolverError, match="non-finite"):
        solve_qp(S, b, solver="clarabel")


def test_pdas_out_of_steps_raises():
    S, b, _ = known_instance(30, 1e4, 10, 0, seed=4)
    with pytest.raises(ContactSolverError, match="pdas"):
        solve_qp(S, b, solver="pdas", solver_options={"max_iter": 1})


def test_uzawa_without_polish_is_checked():
    """Uzawa stopped early and not polished: the KKT check refuses the answer."""
    S, b, _ = known_instance(30, 1e4, 10, 0, seed=4)
    with pytest.raises(ContactSolverError, match="uzawa.*KKT"):
        solve_qp(S, b, solver="uzawa", solver_options={"max_iter": 10}, polish=False, kkt_tol=1e-8)


def test_bad_qp_options_refused():
    S, b, _ = known_instance(6, 10.0, 2, 0, seed=3)
    with pytest.raises(ValueError, match="max_iter"):
        solve_qp(S, b, solver="pdas", solver_options={"tolerance": 1})
    with pytest.raises(ValueError, match="accelerate"):
        solve_qp(S, b, solver="uzawa", solver_options={"momentum": 1})
    with pytest.raises(ValueError, match="initial_active"):
        solve_qp(S, b, initial_active=np.ones(3, dtype=bool))


# ------------------------------------------------------------------------------ warm starts


def test_pdas_warm_start_from_exact_active_set_takes_one_step():
    S, b, v = known_instance(60, 1e5, 20, 0, seed=5)
    cold = solve_qp(S, b)
    warm = solve_qp(S, b, initial_active=np.flatnonzero(v == 0))
    report(f"pdas steps: cold {cold.iterations}, warm (exact active set) {warm.iterations}")
    assert warm.iterations == 1 < cold.iterations
    assert np.abs(warm.w - cold.w).max() <= 1e-12 * np.abs(cold.w).max()


def test_warm_start_maps_by_crack_position():
    old = QPResult(j=np.zeros(4), w=np.array([0.0, 0.0, 1.0, 2.0]), multiplier=np.zeros(4), active=np.array([0, 1]),
                   solver="pdas", iterations=1, crack=np.array([0, 0, 0, 0]), s=np.array([0.1, 0.3, 0.5, 0.7]))
    active, guess = warm_start_data(old, np.zeros(6, dtype=int), np.array([0.0, 0.15, 0.25, 0.45, 0.62, 0.9]))
    assert active.tolist() == [True, True, True, False, False, False]
    assert guess.tolist() == [0.0, 0.0, 0.0, 1.0, 2.0, 2.0]
    # an explicit active set passes through, None means a cold start
    mask, none = warm_start_data(np.array([1]), np.zeros(3, dtype=int), np.zeros(3))
    assert mask.tolist() == [False, True, False] and none is None
    assert warm_start_data(None, np.zeros(3, dtype=int), np.zeros(3)) == (None, None)


@pytest.mark.parametrize("element", ["peers", "bdm"])
def test_solve_warm_start_across_meshes(element):
    scene = scenes.load("paper-1")
    coarse = solve(scene, element, maxh=0.2)
    cold = solve(scene, element, maxh=0.1)
    warm = solve(scene, element, maxh=0.1, warm_start=coarse)
    diff = np.abs(warm.qp.j - cold.qp.j).max() / np.abs(cold.qp.j).max()
    report(f"paper-1 {element}: pdas steps cold {cold.qp.iterations}, warm from maxh 0.2 {warm.qp.iterations}; "
           f"rel diff {diff:.1e}")
    assert diff <= 1e-12
    assert warm.qp.iterations < cold.qp.iterations
    assert len(warm.qp.s) == len(warm.qp.w) and np.all(warm.qp.s >= 0) and np.all(warm.qp.s <= 4.0 + 1e-12)
