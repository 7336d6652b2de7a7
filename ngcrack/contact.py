"""The crack QP (the paper's eq. 4.4) and its solvers.

    minimise 0.5 j^T S j - b^T j   subject to   G j >= 0

j holds the crack normal jumps in the jump space's own basis, S is the (dense, SPD)
Schur complement of the condensed system on them, and G maps j to the values that must
be non-negative: the identity for P0 jumps, the end-point values of each edge for P1
jumps. G is block diagonal and invertible, so the QP is posed in w = G j as a
bound-constrained QP and scaled before it is solved:

    w = D v,  D = diag(S_w)^{-1/2},  v = beta v',  beta = max |D b_w|

so that the scaled problem has unit diagonal and a unit right-hand side whatever E, the
load and the mesh size are, and a solver tolerance means the same in every case.

Solvers: any QP solver that cvxpy knows ("clarabel" is the default; "osqp", "scs", ...),
and "pdas", a primal-dual active set method (exact to round-off when it converges).
After a cvxpy solve the answer is polished by one active-set solve on the active set
it found, which makes it exact to round-off; the polish is kept only if it satisfies
the KKT conditions better.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla

#: solvers reached without cvxpy
NATIVE_SOLVERS = ("pdas",)
#: iteration cap of the primal-dual active set method
PDAS_MAX_ITER = 200
#: scaled KKT residual below which an answer counts as exact
KKT_TOL = 1e-9


class ContactSolverError(RuntimeError):
    """The QP solver failed or returned an answer that violates the KKT conditions."""


@dataclass
class QPResult:
    """The answer of the crack QP.

    `j` are the normal jumps (jump-space basis), `w = G j` the constrained values,
    `multiplier` the Lagrange multipliers of w >= 0 (the contact forces, >= 0),
    `kkt` the scaled algebraic KKT residuals, `active` the indices with w = 0.
    """

    j: np.ndarray
    w: np.ndarray
    multiplier: np.ndarray
    active: np.ndarray
    solver: str
    iterations: int
    kkt: dict = field(default_factory=dict)
    time_s: float = 0.0


def _pdas(S: np.ndarray, b: np.ndarray, active: np.ndarray | None = None) -> tuple[np.ndarray, int, bool]:
    """Primal-dual active set for min 0.5 v'Sv - b'v, v >= 0 (S SPD, unit diagonal)."""
    m = len(b)
    act = np.zeros(m, dtype=bool) if active is None else active.copy()
    v = np.zeros(m)
    for it in range(1, PDAS_MAX_ITER + 1):
        ina = ~act
        v = np.zeros(m)
        if ina.any():
            v[ina] = sla.solve(S[np.ix_(ina, ina)], b[ina], assume_a="pos")
        mu = S @ v - b
        mu[ina] = 0.0
        new = mu - v > 0.0
        if np.array_equal(new, act):
            return v, it, True
        act = new
    return v, PDAS_MAX_ITER, False


def _scaled_kkt(S: np.ndarray, b: np.ndarray, v: np.ndarray) -> dict:
    """Residuals of v >= 0, mu = S v - b >= 0, v.mu = 0 in the scaled problem."""
    mu = S @ v - b
    scale_v = max(np.max(np.abs(v)), 1.0) if len(v) else 1.0
    scale_mu = max(np.max(np.abs(mu)), 1.0) if len(v) else 1.0
    if not len(v):
        return {"primal": 0.0, "dual": 0.0, "complementarity": 0.0}
    return {
        "primal": float(max(0.0, -v.min()) / scale_v),
        "dual": float(max(0.0, -mu.min()) / scale_mu),
        "complementarity": float(np.max(np.abs(v * mu)) / (scale_v * scale_mu)),
    }


def _kkt_size(k: dict) -> float:
    return max(k.values()) if k else 0.0


def _cvxpy_solve(S: np.ndarray, b: np.ndarray, solver: str, options: dict) -> np.ndarray:
    import cvxpy as cp

    name = solver.upper()
    if name not in cp.installed_solvers():
        raise ValueError(
            f"qp_solver = {solver!r}: allowed values are {', '.join(NATIVE_SOLVERS)} or an installed cvxpy solver: "
            + ", ".join(s.lower() for s in cp.installed_solvers())
        )
    v = cp.Variable(len(b))
    problem = cp.Problem(cp.Minimize(0.5 * cp.quad_form(v, cp.psd_wrap(S)) - b @ v), [v >= 0])
    try:
        problem.solve(solver=name, **dict(options))
    except cp.error.SolverError as exc:
        raise ContactSolverError(f"qp_solver = {solver!r} failed on the crack QP: {exc}") from exc
    if problem.status not in ("optimal", "optimal_inaccurate") or v.value is None:
        raise ContactSolverError(f"qp_solver = {solver!r} returned status {problem.status!r} on the crack QP")
    if problem.status == "optimal_inaccurate":
        warnings.warn(f"qp_solver = {solver!r} reports an inaccurate answer; it is polished and checked", stacklevel=3)
    return np.asarray(v.value, dtype=float)


def solve_qp(
    S: np.ndarray,
    b: np.ndarray,
    G: np.ndarray | None = None,
    solver: str = "clarabel",
    solver_options: dict | None = None,
    polish: bool = True,
    kkt_tol: float = 1e-6,
) -> QPResult:
    """Solve min 0.5 j'Sj - b'j subject to G j >= 0 (G square and invertible, or None = I).

    `solver_options` are passed to cvxpy's `Problem.solve` unchanged. Raises
    ContactSolverError if the answer's scaled KKT residual exceeds `kkt_tol`.
    """
    t0 = time.perf_counter()
    m = len(b)
    if not (np.all(np.isfinite(S)) and np.all(np.isfinite(b))):
        raise ContactSolverError("the crack QP has non-finite entries (S or b): the linear system is singular or the data are not finite")
    if m == 0:
        z = np.zeros(0)
        return QPResult(z, z, z, np.zeros(0, dtype=int), solver, 0, _scaled_kkt(S, b, z), 0.0)
    Ginv = np.eye(m) if G is None else np.linalg.inv(G)
    S_w = Ginv.T @ S @ Ginv
    b_w = Ginv.T @ b
    diag = np.diag(S_w)
    if np.any(diag <= 0.0):
        raise ContactSolverError("the crack Schur complement is not positive definite: a part of the body is not held")
    D = 1.0 / np.sqrt(diag)
    S_s = D[:, None] * S_w * D[None, :]
    S_s = 0.5 * (S_s + S_s.T)
    b_s = D * b_w
    beta = float(np.max(np.abs(b_s)))
    if beta == 0.0:
        z = np.zeros(m)
        return QPResult(z, z, z, np.arange(m), solver, 0, _scaled_kkt(S_s, b_s, z), time.perf_counter() - t0)
    b_s = b_s / beta
    if solver == "pdas":
        v, iters, ok = _pdas(S_s, b_s)
        if not ok:
            raise ContactSolverError(f"qp_solver = 'pdas' did not converge in {PDAS_MAX_ITER} iterations; try qp_solver = 'clarabel'")
    else:
        v = _cvxpy_solve(S_s, b_s, solver, solver_options or {})
        iters = 1
        if polish:
            mu = S_s @ v - b_s
            vp, it2, ok = _pdas(S_s, b_s, active=mu > v)
            if ok and _kkt_size(_scaled_kkt(S_s, b_s, vp)) <= _kkt_size(_scaled_kkt(S_s, b_s, v)):
                v, iters = vp, 1 + it2
    kkt = _scaled_kkt(S_s, b_s, v)
    if not np.all(np.isfinite(v)):
        raise ContactSolverError(f"qp_solver = {solver!r} returned non-finite values")
    if _kkt_size(kkt) > kkt_tol:
        raise ContactSolverError(f"qp_solver = {solver!r}: the answer violates the KKT conditions (scaled residuals {kkt})")
    v = np.maximum(v, 0.0)  # remove round-off below zero on the active set
    w = beta * D * v
    mult = beta * (S_s @ v - b_s) / D  # multipliers of w >= 0 in the unscaled problem
    mult[v > 0] = 0.0
    j = Ginv @ w
    return QPResult(
        j=j,
        w=w,
        multiplier=mult,
        active=np.flatnonzero(v == 0.0),
        solver=solver,
        iterations=iters,
        kkt=kkt,
        time_s=time.perf_counter() - t0,
    )
