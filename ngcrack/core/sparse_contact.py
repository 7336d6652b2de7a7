"""Unilateral contact on a sparse system: a primal-dual active set on the crack unknowns' Schur complement.

The problem (any dimension: the solver sees a sparse matrix, a load and the indices of
the constrained unknowns, nothing of a mesh):

    minimise 0.5 y^T K y - F^T y   subject to   w = G y_c >= 0

with K sparse symmetric positive definite, c the constrained unknowns (the crack normal
jumps) and G the block-diagonal map from their coefficients to the constrained values
(None: the identity). In the variables x = T^{-1} y (x_c = w, the rest unchanged) the
constraints are bounds, x_c >= 0, and the KKT conditions read

    (K_w x - F_w)_c = lam >= 0,  x_c >= 0,  lam x_c = 0,  (K_w x - F_w)_r = 0,

K_w = T^T K T, F_w = T^T F. The primal-dual active set method (Hintermueller, Ito and
Kunisch: a semismooth Newton method) guesses the closed points A, solves with x_A = 0,
reads lam from the residual and updates A = {i : lam_i - c_i x_i > 0} (c the diagonal of
the matrix) until A repeats. Two ways (`method`):

- "schur" (the default while m <= constraints.SCHUR_MAX_M): one sparse factorization of K with the
  crack unknowns last, which leaves the dense Schur complement S = K_cc - K_cr K_rr^-1 K_rc
  on them (MKL PARDISO's Schur option, `ngcrack.core.schur.schur_complement`); the active set
  is found by the crack QP's solver on S (`ngcrack.core.contact.solve_qp`: pdas, or uzawa or a
  cvxpy solver polished by pdas), the one solver of the dense strategy in every dimension;
  the answer y is then solved on the whole system with the closed values held at zero
  (iterative refinement through the partial factorization and S) and the active set checked
  on it by the primal-dual rule below (a step more where the two disagree). An active-set
  change costs a small dense solve, not a refactorization; the sparse factorization is the
  one any linear solve of the body needs (timed apart as "factorize").
- "sparse": one sparse factorization of K_w's free unknowns per active set, nothing of
  size m^2 formed (for m above constraints.SCHUR_MAX_M, where S would not fit).

The answer is certified as in 2D (ngcrack.core.constraints): the contact forces are taken
from the residual of K y = F at the constrained rows (`discrete_contact_forces`), not
from the iteration, and the KKT residuals (max_penetration, max_tension,
complementarity) are relative to the largest jump and force.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from . import constraints
from .constraints import ContactSolverError, discrete_contact_forces, kkt_at_constraints
from .csr import to_scipy
from .errors import InputError
from .schur import Factorization

#: at most this many active-set steps
MAX_ITERATIONS = 60
#: the contact solve's methods (module docstring)
METHODS = ("auto", "schur", "sparse")
#: iterative refinement steps of the "schur" method's solves (at most)
REFINEMENTS = 4


@dataclass
class ContactResult:
    """The solution y of the constrained problem and its certificate."""

    y: np.ndarray
    w: np.ndarray  # constrained values (normal jumps at the constraint points)
    lam: np.ndarray  # contact forces at the constraint points, from the residual
    active: np.ndarray  # closed constraint points
    iterations: int
    kkt: dict
    timings: dict = field(default_factory=dict)
    factorizations: int = 0
    method: str = "sparse"  # "schur" or "sparse" (module docstring)


def _transform(K: sp.csr_matrix, F: np.ndarray, contact: np.ndarray, G) -> tuple[sp.csr_matrix, np.ndarray, sp.csr_matrix]:
    n = K.shape[0]
    if G is None:
        T = sp.identity(n, format="csr")
        return K, F, T
    from .constraints import _inverse_map

    Ginv = _inverse_map(G, len(contact))
    Ginv = sp.csr_matrix(to_scipy(Ginv)) if Ginv is not None else sp.identity(len(contact), format="csr")
    rest = np.setdiff1d(np.arange(n), contact)
    Ic = sp.csr_matrix((np.ones(len(rest)), (rest, rest)), shape=(n, n))
    P = sp.csr_matrix((np.ones(len(contact)), (contact, np.arange(len(contact)))), shape=(n, len(contact)))
    T = (Ic + P @ Ginv @ P.T).tocsr()
    Kw = (T.T @ K @ T).tocsr()
    return Kw, T.T @ F, T


def _refined(fac: Factorization, K: sp.csr_matrix, b: np.ndarray, steps: int = 3) -> np.ndarray:
    """K^{-1} b with up to `steps` steps of iterative refinement while the residual falls: a
    stiff body (nu near 1/2: lambda/mu in the thousands) leaves the direct solve's residual
    far above round-off, and the certificate reads the contact forces from that residual."""
    x = fac.solve(b)
    r = b - K @ x
    norm = np.linalg.norm(r)
    for _ in range(steps):
        if norm == 0.0:
            break
        dx = fac.solve(r)
        r_new = b - K @ (x + dx)
        norm_new = np.linalg.norm(r_new)
        if not norm_new < 0.5 * norm:
            break
        x, r, norm = x + dx, r_new, norm_new
    return x


def _initial(active, m: int) -> np.ndarray:
    A = np.zeros(m, dtype=bool) if active is None else np.asarray(active, dtype=bool).copy()
    if A.shape != (m,):
        raise ValueError(f"active: a boolean array of {m} entries (one per constraint point) was expected")
    return A


def _inverse(G, m: int) -> sp.csr_matrix:
    """G^-1 as a scipy CSR matrix (the identity for G None)."""
    if G is None:
        return sp.identity(m, format="csr")
    from .constraints import _inverse_map

    Ginv = _inverse_map(G, m)
    return sp.csr_matrix(to_scipy(Ginv)) if Ginv is not None else sp.identity(m, format="csr")


class _BlockSolver:
    """Solves with the constrained system in the variables x (x_c = w = G y_c, the rest y_r), the
    crack's closed values held at zero, through the partial factorization of K_rr and the dense
    Schur complement in w, S_w = G^-T S G^-1 (the "schur" method). K itself is not transformed:
    only its crack rows K_cr and the small G^-1 are (no copy of the body's matrix is made)."""

    def __init__(self, K: sp.csr_matrix, F: np.ndarray, contact: np.ndarray, rest: np.ndarray, data, Ginv):
        self.K, self.F, self.contact, self.rest, self.data, self.Ginv = K, F, contact, rest, data, Ginv
        self.K_cr = K[contact][:, rest].tocsr()
        self.K_rc = self.K_cr.T.tocsr()
        GS = np.asarray((Ginv.T @ data.S).T)  # S G^-1 (S symmetric)
        self.S = np.asarray(Ginv.T @ GS)
        self.S = 0.5 * (self.S + self.S.T)

    def solve(self, r_r: np.ndarray, r_c: np.ndarray, free: np.ndarray, chol) -> tuple[np.ndarray, np.ndarray]:
        """(d_r, d_c) with the free rows of the constrained system solved for the residual (r_r, r_c)."""
        import scipy.linalg as la

        fac = self.data.factorization
        z = fac.solve(r_r)
        d_c = np.zeros(len(self.contact))
        if free.any():
            d_c[free] = la.cho_solve(chol, (r_c - self.Ginv.T @ (self.K_cr @ z))[free])
            z = z - fac.solve(self.K_rc @ (self.Ginv @ d_c))
        return z, d_c

    def residual(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """F - K y at the rest's rows and, in w's rows, G^-T (F - K y)_c."""
        r = self.F - self.K @ y
        return r[self.rest], np.asarray(self.Ginv.T @ r[self.contact])

    def refined(self, A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(y, w) with the closed values w_A = 0 solving the other rows, refined (up to REFINEMENTS
        steps while the residual halves): the dense S of a stiff body (nu near 1/2) carries the
        partial factorization's rounding, and the certificate reads the forces from the residual
        (as `_refined` for the sparse method)."""
        import scipy.linalg as la

        free = ~A
        chol = la.cho_factor(self.S[np.ix_(free, free)]) if free.any() else None
        n, m = len(self.F), len(self.contact)
        y, w = np.zeros(n), np.zeros(m)
        r_r, r_c = self.F[self.rest].copy(), np.asarray(self.Ginv.T @ self.F[self.contact])
        norm = np.inf
        for _ in range(REFINEMENTS + 1):
            d_r, d_c = self.solve(r_r, r_c, free, chol)
            y_new, w_new = y.copy(), w + d_c
            y_new[self.rest] += d_r
            y_new[self.contact] = self.Ginv @ w_new
            nr_r, nr_c = self.residual(y_new)
            norm_new = math.hypot(np.linalg.norm(nr_r), np.linalg.norm(nr_c[free]))
            if not norm_new < 0.5 * norm:
                break
            y, w, r_r, r_c, norm = y_new, w_new, nr_r, nr_c, norm_new
            if norm == 0.0:
                break
        return y, w


def _solve_schur(K, F, contact, G, A, linear_solver: str, max_iterations: int, t0: float, qp_solver: str = "pdas",
                 qp_options: dict | None = None) -> ContactResult:
    """The "schur" method (module docstring): one partial factorization, the crack QP on S, the answer on the whole system."""
    from .contact import solve_qp
    from .schur import schur_complement

    n = K.shape[0]
    rest = np.setdiff1d(np.arange(n), contact)
    t1 = time.perf_counter()
    data = schur_complement(K, F, rest, contact, linear_solver=linear_solver)
    t2 = time.perf_counter()
    block = _BlockSolver(K, F, contact, rest, data, _inverse(G, len(contact)))
    c = np.diag(block.S).copy()
    if np.any(c <= 0):
        raise ContactSolverError("the crack unknowns' stiffness is not positive: a part of the body is not held")
    qp = solve_qp(data.S, data.b, G=G, solver=qp_solver, solver_options=qp_options, initial_active=A if A.any() else None)
    A = np.zeros(len(contact), dtype=bool)
    A[qp.active] = True

    def step(A):  # the QP's active set checked on the whole system's answer
        y, w = block.refined(A)
        lam = -block.residual(y)[1]
        return lam - c * w > 0, (y, w)

    A, it, (y, w) = _settle(A, step, max_iterations)
    t3 = time.perf_counter()
    lam, kkt = certificate(K, F, y, w, contact, G)
    t4 = time.perf_counter()
    timings = {"setup": t1 - t0, "factorize": t2 - t1, "factorizations": t2 - t1, "active_set": t3 - t2,
               "certificate": t4 - t3, "total": t4 - t0}
    return ContactResult(y, w, lam, A, qp.iterations + it - 1, kkt, timings, factorizations=1, method="schur")


def _settle(A: np.ndarray, step, max_iterations: int):
    """Iterate the active set A <- step(A)[0] until it is fixed: (A, the steps taken, the last step's
    answer). ContactSolverError when a set comes back (a cycle) or after max_iterations steps."""
    seen = set()
    for it in range(1, max_iterations + 1):
        new, answer = step(A)
        if np.array_equal(new, A):
            return A, it, answer
        key = new.tobytes()
        if key in seen:
            raise ContactSolverError(f"the active-set method cycles after {it} steps")
        seen.add(key)
        A = new
    raise ContactSolverError(f"the active-set method did not settle in {max_iterations} steps")


def certificate(K, F, y, w, contact, G) -> tuple[np.ndarray, dict]:
    """The contact forces read from the whole system's residual and the KKT residuals of an answer y
    with constraint values w (any strategy's: dense, sparse, or the distributed Krylov one gathered on
    rank 0): relative to its largest jump, displacement and load."""
    lam, bound = discrete_contact_forces(K, F, y, contact, G)
    kkt = kkt_at_constraints(w, lam, float(np.max(np.abs(w))) if len(w) else 0.0, jump_scale=float(np.max(np.abs(y))),
                             force_scale=float(np.max(np.abs(F))), lam_bound=bound)
    return lam, kkt


def solve_contact(K: sp.spmatrix, F: np.ndarray, contact: np.ndarray, G=None, *, linear_solver: str = "auto",
                  active=None, max_iterations: int = MAX_ITERATIONS, method: str = "auto", qp_solver: str = "pdas",
                  qp_options: dict | None = None) -> ContactResult:
    """Solve the constrained problem (module docstring); `active`: an initial guess of the closed points;
    `method`: "schur", "sparse" or "auto" (schur up to constraints.SCHUR_MAX_M constrained unknowns); `qp_solver` and
    `qp_options`: the crack QP's solver of the "schur" method (`ngcrack.core.contact.solve_qp`)."""
    if method not in METHODS:
        raise ValueError(f"method = {method!r}: allowed values are {', '.join(METHODS)}")
    t0 = time.perf_counter()
    K = sp.csr_matrix(K)
    contact = np.asarray(contact, dtype=int)
    n, m = K.shape[0], len(contact)
    A = _initial(active, m)
    if method == "schur" or (method == "auto" and 0 < m <= constraints.SCHUR_MAX_M):
        return _solve_schur(K, F, contact, G, A, linear_solver, max_iterations, t0, qp_solver, qp_options)
    if qp_solver != "pdas":
        raise InputError(f"qp_solver = {qp_solver!r}: this crack has {m} constrained unknowns, more than the "
                         f"{constraints.SCHUR_MAX_M} whose Schur complement a QP solver is given; above that the "
                         "sparse active set solves the contact (allowed value: pdas)")
    Kw, Fw, T = _transform(K, F, contact, G)
    diag = Kw.diagonal()[contact]
    if np.any(diag <= 0):
        raise ContactSolverError("the crack unknowns' stiffness is not positive: a part of the body is not held")
    t_setup = time.perf_counter() - t0
    t_fact = 0.0

    def step(A):  # one factorization of the free block per active set
        nonlocal t_fact
        free = np.ones(n, dtype=bool)
        free[contact[A]] = False
        t1 = time.perf_counter()
        Kf = Kw[free][:, free]
        x = np.zeros(n)
        x[free] = _refined(Factorization(Kf, linear_solver), Kf, Fw[free])
        t_fact += time.perf_counter() - t1
        lam = np.asarray(Kw[contact] @ x - Fw[contact])
        return lam - diag * x[contact] > 0, x

    A, it, x = _settle(A, step, max_iterations)
    y = T @ x
    w = x[contact]
    lam, kkt = certificate(K, F, y, w, contact, G)
    timings = {"setup": t_setup, "factorizations": t_fact, "total": time.perf_counter() - t0}
    return ContactResult(y, w, lam, A, it, kkt, timings, factorizations=it, method="sparse")
