"""Unilateral contact on a sparse system: a primal-dual active set, no dense Schur complement.

The problem (any dimension: the solver sees a sparse matrix, a load and the indices of
the constrained unknowns, nothing of a mesh):

    minimise 0.5 y^T K y - F^T y   subject to   w = G y_c >= 0

with K sparse symmetric positive definite, c the constrained unknowns (the crack normal
jumps) and G the block-diagonal map from their coefficients to the constrained values
(None: the identity). In the variables x = T^{-1} y (x_c = w, the rest unchanged) the
constraints are bounds, x_c >= 0, and the KKT conditions read

    (K_w x - F_w)_c = lam >= 0,  x_c >= 0,  lam x_c = 0,  (K_w x - F_w)_r = 0,

K_w = T^T K T, F_w = T^T F. The primal-dual active set method (Hintermueller, Ito and
Kunisch: a semismooth Newton method) guesses the closed points A, solves K_w on the
other unknowns with x_A = 0 (one sparse factorization per active set), reads lam from
the residual and updates A = {i : lam_i - c_i x_i > 0} (c_i the diagonal of K_w) until A
repeats. Nothing of size m^2 (m the constrained unknowns) is ever formed: time and
memory are those of the sparse factorizations.

The answer is certified as in 2D (ngcrack.core.constraints): the contact forces are taken
from the residual of K y = F at the constrained rows (`discrete_contact_forces`), not
from the iteration, and the KKT residuals (max_penetration, max_tension,
complementarity) are relative to the largest jump and force.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..core.constraints import ContactSolverError, discrete_contact_forces, kkt_at_constraints
from ..core.csr import to_scipy
from ..core.schur import Factorization

#: at most this many active-set steps
MAX_ITERATIONS = 60


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


def _transform(K: sp.csr_matrix, F: np.ndarray, contact: np.ndarray, G) -> tuple[sp.csr_matrix, np.ndarray, sp.csr_matrix]:
    n = K.shape[0]
    if G is None:
        T = sp.identity(n, format="csr")
        return K, F, T
    from ..core.constraints import _inverse_map

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


def solve_contact(K: sp.spmatrix, F: np.ndarray, contact: np.ndarray, G=None, *, linear_solver: str = "auto",
                  active=None, max_iterations: int = MAX_ITERATIONS) -> ContactResult:
    """Solve the constrained problem (module docstring); `active`: an initial guess of the closed points."""
    t0 = time.perf_counter()
    K = sp.csr_matrix(K)
    contact = np.asarray(contact, dtype=int)
    n, m = K.shape[0], len(contact)
    Kw, Fw, T = _transform(K, F, contact, G)
    diag = Kw.diagonal()[contact]
    if np.any(diag <= 0):
        raise ContactSolverError("the crack unknowns' stiffness is not positive: a part of the body is not held")
    A = np.zeros(m, dtype=bool) if active is None else np.asarray(active, dtype=bool).copy()
    if A.shape != (m,):
        raise ValueError(f"active: a boolean array of {m} entries (one per constraint point) was expected")
    t_setup = time.perf_counter() - t0
    t_fact = 0.0
    x = np.zeros(n)
    seen = set()
    for it in range(1, max_iterations + 1):
        free = np.ones(n, dtype=bool)
        free[contact[A]] = False
        t1 = time.perf_counter()
        Kf = Kw[free][:, free]
        fac = Factorization(Kf, linear_solver)
        x[:] = 0.0
        x[free] = _refined(fac, Kf, Fw[free])
        t_fact += time.perf_counter() - t1
        lam = np.asarray(Kw[contact] @ x - Fw[contact])
        new = lam - diag * x[contact] > 0
        if np.array_equal(new, A):
            break
        key = new.tobytes()
        if key in seen:
            raise ContactSolverError(f"the active-set method cycles after {it} steps")
        seen.add(key)
        A = new
    else:
        raise ContactSolverError(f"the active-set method did not settle in {max_iterations} steps")
    y = T @ x
    w = x[contact]
    lam, bound = discrete_contact_forces(K, F, y, contact, G)
    kkt = kkt_at_constraints(w, lam, float(np.max(np.abs(w))) if m else 0.0, jump_scale=float(np.max(np.abs(y))),
                             force_scale=float(np.max(np.abs(F))), lam_bound=bound)
    timings = {"setup": t_setup, "factorizations": t_fact, "total": time.perf_counter() - t0}
    return ContactResult(y, w, lam, A, it, kkt, timings, factorizations=it)
