"""The crack QP (the paper's eq. 4.4) and its solvers.

    minimise 0.5 j^T S j - b^T j   subject to   G j >= 0

j holds the crack normal jumps in the jump space's own basis, S is the (dense, SPD)
Schur complement of the condensed system on them, and G maps j to the values that must
be non-negative: the identity for P0 jumps, the end-point values of each edge for P1
jumps. G is block diagonal and invertible, so the QP is posed in w = G j as a
bound-constrained QP and scaled before it is solved:

    w = D v,  D = diag(S_w)^{-1/2},  v = beta v',  beta = max |D b_w|

so that the scaled problem has unit diagonal and a unit right-hand side whatever E, the
load and the mesh size are, and a solver tolerance means the same in every case. Its
KKT conditions are v >= 0, mu = S v - b >= 0, v mu = 0 (mu: the scaled contact forces).

Solvers:

- "pdas" (the default): primal-dual active set, i.e. a semismooth Newton method on
  min(v, mu) = 0. Each step solves S on the inactive set (a dense Cholesky) and moves
  every index that violates v >= 0 or mu >= 0 to the other set. It converges in a few
  steps on the crack QPs and is exact to round-off; for the rare S on which the plain
  exchange cycles, the block principal pivoting safeguard of Judice and Pires is
  applied (after PDAS_BACKUP steps without fewer violations, exchange only the largest
  violating index, Murty's rule), which terminates for every SPD S.
- "uzawa": the paper's Uzawa iteration, i.e. projected gradient ascent on the
  multiplier of the saddle point (4.2); in the condensed form that is
  v <- max(0, v - rho (S v - b)) with the step rho = 2 / (lambda_min + lambda_max) of
  the scaled S (the fastest fixed step for the linear part; it contracts by
  (kappa - 1) / (kappa + 1) per step, kappa = cond(S)). qp_options: "max_iter",
  "tol" (scaled KKT residual at which it stops), "step" (a number overrides rho),
  "accelerate" (Nesterov's momentum with adaptive restarts and rho = 1 / lambda_max,
  about sqrt(kappa) steps instead of kappa; False, the default, is the paper's iteration).
- any QP solver that cvxpy knows: "clarabel", "osqp", "scs", ...; solver options are
  passed to cvxpy's Problem.solve unchanged.

Measured on crack QPs of the paper's scenes and griffith (m = 80-1838) and on random
SPD instances up to m = 2000, cond 1e8 (the source repository's QP benchmark): pdas reaches a
scaled KKT residual of 1e-15 in 1-16 steps and is the fastest everywhere (the
timings: BENCHMARKS.md, the crack QP solvers); clarabel reaches 1e-8 to
1e-11 on its own, osqp and scs 1e-5 to 1e-7 with their default tolerances; the plain
Uzawa iteration needs O(cond(S)) steps (3400-15000 on the small crack QPs, more than
20000 from cond 2e5 on), the accelerated one 250-1300.

After an approximate solver (uzawa, cvxpy) the answer is polished by active-set steps
started from the active set it found; this makes it exact to round-off, and the polish
is kept only if it satisfies the KKT conditions better. Every answer's KKT residuals
are checked, whoever produced it: above `kkt_tol` the solve raises ContactSolverError.

Warm starts: `initial_active` (the indices, or a boolean mask, of the constrained
values expected at zero) starts pdas from that active set; `initial_guess` (values of
w = G j) starts uzawa, and the cvxpy solvers that accept a starting point. Along a mesh
or nu sweep they halve the pdas steps, which saves milliseconds (measured):
`warm_start_data` maps a previous solution by crack position.
"""

from __future__ import annotations

import contextlib
import time
import warnings
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from .constraints import ACCEPT_KKT, ContactSolverError, _inverse_map, scaled_problem
from .csr import distinct
from .errors import InputError

#: solvers reached without cvxpy
NATIVE_SOLVERS = ("pdas", "uzawa")
#: the default QP solver: the fastest that reaches a scaled KKT residual of 1e-8 (measured, module docstring)
DEFAULT_SOLVER = "pdas"
#: iteration cap of the primal-dual active set method
PDAS_MAX_ITER = 200
#: steps without fewer violations after which pdas exchanges one index only (Judice-Pires)
PDAS_BACKUP = 3
#: relative size below which a negative v or mu counts as zero in pdas (round-off level)
FEASIBILITY_RTOL = 1e-13
#: default iteration cap of the Uzawa iteration
UZAWA_MAX_ITER = 100_000
#: default stopping tolerance (scaled KKT residual) of the Uzawa iteration
UZAWA_TOL = 1e-10
#: Uzawa checks its KKT residual every this many steps
UZAWA_CHECK_EVERY = 25
#: scaled KKT residual below which an answer counts as exact
KKT_TOL = 1e-9
#: a value of the scaled problem (|b| = 1) at most this, relative to the largest, whose multiplier is
#: at least as large, is a contact value: it is set to exactly zero and the constraint is active. An
#: interior-point or ADMM solver stops a contact value at 1e-21..1e-12 instead of 0 (osqp 1.1 does); the
#: KKT check bounds v.mu, so such a value moves the answer by less than this times |S|
ACTIVE_RTOL = 1e-10
#: BLAS threads for the dense QP work. The matrices are m x m with m in the hundreds:
#: a second thread gains little, and on a busy machine the threads' synchronisation
#: made a 320-unknown pdas solve take up to 2 s instead of 0.02 s (measured)
QP_BLAS_THREADS = 1
#: the BLAS threads are limited only from this many constraints on: the limit costs about
#: 0.01-0.02 s the first time in a process (threadpoolctl inspects every loaded library),
#: a tenth of a small solve, while below this size the QP's dense work takes a few
#: milliseconds
QP_BLAS_LIMIT_FROM = 100


@lru_cache(maxsize=1)
def _threadpools():
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:  # pragma: no cover - threadpoolctl is a dependency
        return None
    return ThreadpoolController()


def _limited_blas(m: int):
    """A context in which BLAS uses QP_BLAS_THREADS threads for a QP of m constraints
    (no-op below QP_BLAS_LIMIT_FROM and without threadpoolctl)."""
    if m < QP_BLAS_LIMIT_FROM:
        return contextlib.nullcontext()
    pools = _threadpools()
    return pools.limit(limits=QP_BLAS_THREADS, user_api="blas") if pools is not None else contextlib.nullcontext()


@dataclass
class QPResult:
    """The answer of the crack QP.

    `j` are the normal jumps (jump-space basis), `w = G j` the constrained values,
    `multiplier` the Lagrange multipliers of w >= 0 (the contact forces, >= 0),
    `kkt` the scaled algebraic KKT residuals, `active` the indices with w = 0.
    `raw_kkt` are the residuals of the solver's own answer before any polish.
    """

    j: np.ndarray
    w: np.ndarray
    multiplier: np.ndarray
    active: np.ndarray
    solver: str
    iterations: int
    kkt: dict = field(default_factory=dict)
    time_s: float = 0.0
    raw_kkt: dict = field(default_factory=dict)
    #: where each constrained value sits: crack index and arc length s (for warm starts)
    crack: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    s: np.ndarray = field(default_factory=lambda: np.zeros(0))


#: up to this size spd_solve uses numpy's LU: a solve that needs no larger dense system
#: then does not load scipy.linalg and its own BLAS (BENCHMARKS.md, the start-up section)
SMALL_DENSE = 200


def spd_solve(M: np.ndarray, r: np.ndarray) -> np.ndarray:
    """M x = r for a symmetric M, positive definite up to round-off (Cholesky; a
    symmetric indefinite solve where Cholesky breaks down; numpy's LU up to SMALL_DENSE
    unknowns)."""
    if len(M) <= SMALL_DENSE:
        return np.linalg.solve(M, r)
    import scipy.linalg as sla

    try:
        return sla.cho_solve(sla.cho_factor(M, check_finite=False), r, check_finite=False)
    except np.linalg.LinAlgError:
        return sla.solve(M, r, assume_a="sym")


class ExchangeRule:
    """The active-set methods' safeguard, shared by the QP (`_pdas`) and the crack problem
    with friction (`friction._active_set`): which violating indices a step exchanges.

    Every violating index while the number of violations falls or has risen for at most
    PDAS_BACKUP steps; after that only the largest violating index (Murty's rule in the
    block principal pivoting of Judice and Pires, which terminates for every SPD matrix),
    until a step has fewer violations than the best so far.
    """

    def __init__(self, n: int):
        self.best, self.budget = n + 1, PDAS_BACKUP

    def __call__(self, bad: np.ndarray) -> np.ndarray:
        """The indices to exchange (a boolean mask) given the violating ones `bad`."""
        nbad = int(np.count_nonzero(bad))
        if nbad < self.best:
            self.best, self.budget = nbad, PDAS_BACKUP
            return bad
        if self.budget > 0:
            self.budget -= 1
            return bad
        one = np.zeros_like(bad)
        one[np.flatnonzero(bad)[-1]] = True
        return one


def _inactive_solve(S: np.ndarray, b: np.ndarray, ina: np.ndarray) -> np.ndarray:
    """v with v = 0 on the active set and (S v)_I = b_I on the inactive set I."""
    v = np.zeros(len(b))
    if ina.any():
        idx = np.flatnonzero(ina)
        v[idx] = spd_solve(S[np.ix_(idx, idx)], b[idx])
    return v


def _pdas(S: np.ndarray, b: np.ndarray, active: np.ndarray | None = None,
          max_iter: int = PDAS_MAX_ITER) -> tuple[np.ndarray, int, bool]:
    """Primal-dual active set for min 0.5 v'Sv - b'v, v >= 0 (S SPD, unit diagonal).

    Block principal pivoting with the Judice-Pires backup rule (module docstring).
    Returns (v, steps, converged).
    """
    m = len(b)
    act = np.zeros(m, dtype=bool) if active is None else np.array(active, dtype=bool)
    exchange = ExchangeRule(m)
    v = np.zeros(m)
    for it in range(1, max_iter + 1):
        ina = ~act
        v = _inactive_solve(S, b, ina)
        mu = S @ v - b
        mu[ina] = 0.0
        tol_v = FEASIBILITY_RTOL * max(np.max(np.abs(v)), 1.0)
        tol_mu = FEASIBILITY_RTOL * max(np.max(np.abs(mu)), 1.0)
        bad = (ina & (v < -tol_v)) | (act & (mu < -tol_mu))
        if not bad.any():
            return v, it, True
        act ^= exchange(bad)
    return v, max_iter, False


def _extreme_eigenvalues(S: np.ndarray) -> tuple[float, float]:
    m = len(S)
    import scipy.linalg as sla

    lo = sla.eigh(S, eigvals_only=True, subset_by_index=[0, 0], check_finite=False)[0]
    hi = sla.eigh(S, eigvals_only=True, subset_by_index=[m - 1, m - 1], check_finite=False)[0]
    return float(lo), float(hi)


def _uzawa(S: np.ndarray, b: np.ndarray, v0: np.ndarray | None = None, max_iter: int = UZAWA_MAX_ITER,
           tol: float = UZAWA_TOL, step: float | None = None, accelerate: bool = False) -> tuple[np.ndarray, int, bool]:
    """Projected gradient on min 0.5 v'Sv - b'v, v >= 0 (the paper's Uzawa iteration).

    Returns (v, steps, reached tol).
    """
    if step is None:
        lo, hi = _extreme_eigenvalues(S)
        step = 1.0 / hi if accelerate else 2.0 / (lo + hi)
    v = np.zeros(len(b)) if v0 is None else np.maximum(np.asarray(v0, dtype=float), 0.0)
    y, t = v.copy(), 1.0
    for it in range(1, max_iter + 1):
        if accelerate:
            v_new = np.maximum(y - step * (S @ y - b), 0.0)
            t_new = 0.5 * (1.0 + np.sqrt(1.0 + 4.0 * t * t))
            if (v_new - v) @ (y - v_new) > 0.0:  # restart when the momentum goes uphill
                t_new, y = 1.0, v_new.copy()
            else:
                y = v_new + ((t - 1.0) / t_new) * (v_new - v)
            v, t = v_new, t_new
        else:
            v = np.maximum(v - step * (S @ v - b), 0.0)
        if it % UZAWA_CHECK_EVERY == 0 and _kkt_size(_scaled_kkt(S, b, v)) <= tol:
            return v, it, True
    return v, max_iter, _kkt_size(_scaled_kkt(S, b, v)) <= tol


def _scaled_kkt(S: np.ndarray, b: np.ndarray, v: np.ndarray) -> dict:
    """Residuals of v >= 0, mu = S v - b >= 0, v.mu = 0 in the scaled problem."""
    if not len(v):
        return {"primal": 0.0, "dual": 0.0, "complementarity": 0.0}
    mu = S @ v - b
    scale_v = max(np.max(np.abs(v)), 1.0)
    scale_mu = max(np.max(np.abs(mu)), 1.0)
    return {
        "primal": float(max(0.0, -v.min()) / scale_v),
        "dual": float(max(0.0, -mu.min()) / scale_mu),
        "complementarity": float(np.max(np.abs(v * mu)) / (scale_v * scale_mu)),
    }


def _kkt_size(k: dict) -> float:
    if not k:
        return 0.0
    vals = list(k.values())
    return float("inf") if any(not np.isfinite(x) for x in vals) else max(vals)


def _cvxpy_solve(S: np.ndarray, b: np.ndarray, solver: str, options: dict, v0: np.ndarray | None = None) -> np.ndarray:
    import cvxpy as cp

    name = solver.upper()
    if name not in cp.installed_solvers():
        raise InputError(
            f"qp_solver = {solver!r}: allowed values are {', '.join(NATIVE_SOLVERS)} or an installed cvxpy solver: "
            + ", ".join(s.lower() for s in cp.installed_solvers())
        )
    v = cp.Variable(len(b))
    problem = cp.Problem(cp.Minimize(0.5 * cp.quad_form(v, cp.psd_wrap(S)) - b @ v), [v >= 0])
    kwargs = dict(options)
    if v0 is not None:
        v.value = np.maximum(v0, 0.0)
        kwargs.setdefault("warm_start", True)
    try:
        problem.solve(solver=name, **kwargs)
    except cp.error.SolverError as exc:
        raise ContactSolverError(f"qp_solver = {solver!r} failed on the crack QP: {exc}") from exc
    if problem.status not in ("optimal", "optimal_inaccurate") or v.value is None:
        raise ContactSolverError(f"qp_solver = {solver!r} returned status {problem.status!r} on the crack QP")
    out = np.asarray(v.value, dtype=float)
    if not np.all(np.isfinite(out)):
        raise ContactSolverError(f"qp_solver = {solver!r} returned non-finite values on the crack QP")
    if problem.status == "optimal_inaccurate":
        warnings.warn(f"qp_solver = {solver!r} reports an inaccurate answer; it is polished and checked", stacklevel=3)
    return out


def _mask(active, m: int) -> np.ndarray | None:
    """A boolean mask of length m from indices or a mask (None stays None)."""
    if active is None:
        return None
    a = np.asarray(active)
    if a.dtype == bool:
        if a.shape != (m,):
            raise InputError(f"initial_active: a mask of length {m} (the number of crack constraints) was expected, got shape {a.shape}")
        return a.copy()
    mask = np.zeros(m, dtype=bool)
    idx = a.astype(int)
    if idx.size and (idx.min() < 0 or idx.max() >= m):
        raise InputError(f"initial_active: indices must lie in [0, {m})")
    mask[idx] = True
    return mask


def solve_qp(
    S: np.ndarray,
    b: np.ndarray,
    G: np.ndarray | None = None,
    solver: str = DEFAULT_SOLVER,
    solver_options: dict | None = None,
    polish: bool = True,
    kkt_tol: float = ACCEPT_KKT,
    initial_active=None,
    initial_guess: np.ndarray | None = None,
) -> QPResult:
    """Solve min 0.5 j'Sj - b'j subject to G j >= 0 (G square and invertible, or None = I).

    `solver` is "pdas" (default), "uzawa" or a cvxpy solver; `solver_options` go to
    cvxpy's `Problem.solve` (or to uzawa: max_iter, tol, step, accelerate) unchanged.
    `initial_active` / `initial_guess`: warm starts (module docstring), in the indices
    and units of w = G j. Raises ContactSolverError if the answer's scaled KKT residual
    exceeds `kkt_tol`, the solver fails, or S and b are not finite. The dense work runs
    with QP_BLAS_THREADS BLAS threads.
    """
    with _limited_blas(len(b)):
        return _solve_qp(S, b, G, solver, solver_options, polish, kkt_tol, initial_active, initial_guess)


def _solve_qp(S, b, G, solver, solver_options, polish, kkt_tol, initial_active, initial_guess) -> QPResult:
    t0 = time.perf_counter()
    S = np.asarray(S, dtype=float)
    b = np.asarray(b, dtype=float)
    m = len(b)
    if not (np.all(np.isfinite(S)) and np.all(np.isfinite(b))):
        raise ContactSolverError("the crack QP has non-finite entries (S or b): the linear system is singular or the data are not finite")
    options = dict(solver_options or {})
    if m == 0:
        z = np.zeros(0)
        return QPResult(z, z, z, np.zeros(0, dtype=int), solver, 0, _scaled_kkt(S, b, z), 0.0)
    Ginv = _inverse_map(G, m)
    S_s, b_s, D = scaled_problem(S, b, Ginv)
    beta = float(np.max(np.abs(b_s)))
    if beta == 0.0:
        z = np.zeros(m)
        return QPResult(z, z, z, np.arange(m), solver, 0, _scaled_kkt(S_s, b_s, z), time.perf_counter() - t0)
    b_s = b_s / beta
    act0 = _mask(initial_active, m)
    v0 = None
    if initial_guess is not None:
        v0 = np.asarray(initial_guess, dtype=float) / (beta * D)
        if v0.shape != (m,) or not np.all(np.isfinite(v0)):
            raise InputError(f"initial_guess: {m} finite values (w = G j) were expected")
    if solver == "pdas":
        max_iter = int(options.pop("max_iter", PDAS_MAX_ITER))
        if options:
            raise InputError(f"qp_options for 'pdas': allowed keys are max_iter, not {', '.join(options)}")
        if act0 is None and v0 is not None:
            act0 = v0 <= 0.0
        v, iters, ok = _pdas(S_s, b_s, active=act0, max_iter=max_iter)
        if not ok:
            raise ContactSolverError(f"qp_solver = 'pdas' did not converge in {max_iter} iterations; try qp_solver = 'clarabel'")
        raw = _scaled_kkt(S_s, b_s, v)
    else:
        if solver == "uzawa":
            allowed = {"max_iter", "tol", "step", "accelerate"}
            if set(options) - allowed:
                raise InputError(f"qp_options for 'uzawa': allowed keys are {', '.join(sorted(allowed))}")
            v, iters, _ = _uzawa(S_s, b_s, v0=v0, **options)
        else:
            v = _cvxpy_solve(S_s, b_s, solver, options, v0=v0)
            iters = 1
        if not np.all(np.isfinite(v)):
            raise ContactSolverError(f"qp_solver = {solver!r} returned non-finite values")
        raw = _scaled_kkt(S_s, b_s, v)
        if polish:
            mu = S_s @ v - b_s
            vp, it2, ok = _pdas(S_s, b_s, active=mu > v)
            if ok and _kkt_size(_scaled_kkt(S_s, b_s, vp)) <= _kkt_size(raw):
                v, iters = vp, iters + it2
    kkt = _scaled_kkt(S_s, b_s, v)
    if not np.all(np.isfinite(v)):
        raise ContactSolverError(f"qp_solver = {solver!r} returned non-finite values")
    if _kkt_size(kkt) > kkt_tol:
        raise ContactSolverError(f"qp_solver = {solver!r}: the answer violates the KKT conditions (scaled residuals {kkt})")
    v = np.maximum(v, 0.0)  # remove round-off below zero on the active set
    mu = S_s @ v - b_s
    v[(v <= ACTIVE_RTOL * max(float(v.max()), 1.0)) & (mu >= v)] = 0.0  # a solver's stop short of zero
    kkt = _scaled_kkt(S_s, b_s, v)
    w = beta * D * v
    mult = beta * (S_s @ v - b_s) / D  # multipliers of w >= 0 in the unscaled problem
    mult[v > 0] = 0.0
    j = w if Ginv is None else Ginv @ w
    return QPResult(
        j=j,
        w=w,
        multiplier=mult,
        active=np.flatnonzero(v == 0.0),
        solver=solver,
        iterations=iters,
        kkt=kkt,
        time_s=time.perf_counter() - t0,
        raw_kkt=raw,
    )


# ----------------------------------------------------------------------------- warm starts


def warm_start_data(previous, crack: np.ndarray, s: np.ndarray) -> tuple[np.ndarray | None, np.ndarray | None]:
    """(initial_active, initial_guess) for a QP whose constrained values sit at (crack, s).

    `previous` is None, an earlier Solution or QPResult (its contact state is carried
    over by crack position: each new value takes the state and the value w of the
    nearest old value on the same crack; meshes may differ), or an explicit active set
    (indices or a boolean mask in the new QP's numbering).
    """
    if previous is None:
        return None, None
    qp = getattr(previous, "qp", previous)
    if qp is None:  # a previous solve without a QP (no crack, or another crack model)
        return None, None
    if not isinstance(qp, QPResult):
        return _mask(previous, len(s)), None
    if not len(qp.s):
        raise InputError("warm_start: the previous QP result carries no crack positions (use a Solution from solve())")
    old_active = np.zeros(len(qp.w), dtype=bool)
    old_active[qp.active] = True
    active = np.zeros(len(s), dtype=bool)
    guess = np.zeros(len(s))
    for k in distinct(crack):
        new = np.flatnonzero(crack == k)
        old = np.flatnonzero(qp.crack == k)
        if not len(old):
            continue
        order = old[np.argsort(qp.s[old])]
        pos = np.searchsorted(qp.s[order], s[new])
        lo = order[np.clip(pos - 1, 0, len(order) - 1)]
        hi = order[np.clip(pos, 0, len(order) - 1)]
        nearest = np.where(np.abs(qp.s[lo] - s[new]) <= np.abs(qp.s[hi] - s[new]), lo, hi)
        active[new] = old_active[nearest]
        guess[new] = qp.w[nearest]
    return active, guess
