"""Coulomb friction on the crack faces: the reduced crack problem and its solvers.

With friction the crack's tangential jumps stay in the reduced problem beside the
normal ones (`hybrid.condense(..., tangential=True)`): z = (zn, zt) in the jump spaces'
own bases, S the Schur complement of the condensed system on them, b its right-hand
side. Constraint points x_i (the QP's: edge mid points for P0 jumps, the p + 1
equispaced points of each edge for P_p jumps, the nodes of the displacement
baselines) carry the normal values wn = Gn zn and the tangential values wt = Gt zt,
and a quadrature weight omega_i (Newton-Cotes on each edge: the nodal quadrature of
the jump space). The Tresca problem with slip threshold g (stress units) is convex:

    minimise 0.5 z'Sz - b'z + sum_i g_i omega_i |wt_i|   subject to   wn >= 0.

Its multipliers at the constraint points are the contact forces lam_n = (dE/dwn) >= 0
(-sigma_n times the weight) and the friction forces lam_t = -(dE/dwt) (sigma_t times
the weight), E the quadratic energy: lam_t = g omega sign(wt) where the faces slip,
|lam_t| <= g omega where they stick (wt = 0). Coulomb takes g omega = mu lam_n: the
discrete Coulomb law at every constraint point is

    |lam_t| <= mu lam_n,   wt = 0 where |lam_t| < mu lam_n,   lam_t = mu lam_n sign(wt) where wt != 0.

Sign convention: [u] = u+ - u-, sigma_t = (sigma nu).t is the traction that the + side
exerts on the - face; it points along the slip [u].t. The friction traction on the
+ face, -sigma_t, opposes the slip.

Solvers (interchangeable, the same CrackProblem in, the same FrictionResult out):

- "pdas" (native): the problem is written in the point values w = (wn, wt), Jacobi
  scaled to a unit diagonal and a unit right-hand side as in `contact.py`
  (`constraints.scaled_problem`), and solved
  by a primal-dual active set (semismooth Newton) method: each step fixes which points
  are in contact, which stick and which slip in which direction, solves the linear
  system of that guess (dense), and exchanges every point whose guess is violated.
  Tresca steps solve symmetric systems (Cholesky).
- any cvxpy solver ("clarabel", ...): the Tresca problem above stated in cvxpy
  (`tresca_cvxpy`), then polished by the native steps from the sets it found.

Coulomb (`method`): "fixed-point" solves Tresca problems with g omega = mu lam_n of the
previous answer, each warm-started from the previous contact/stick/slip sets, until
the threshold changes by less than COULOMB_TOL relative to max lam_n; once two
successive answers have the same sets it tries one Newton step on the Coulomb law
itself (the slip rows read lam_t = mu lam_n sign(wt): a nonsymmetric linear solve),
which ends the iteration where all conditions hold. "newton" is that semismooth Newton
method on the Coulomb law from the first step (Hueber, Stadler, Wohlmuth 2008), with
nonsymmetric solves throughout. Either raises ContactSolverError when it does not
converge. The CrackProblem of a solve is built by `friction_setup.crack_problem`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .constraints import ACCEPT_KKT, ContactSolverError, _inverse_map, faces_closed, scaled_problem
from .contact import FEASIBILITY_RTOL, NATIVE_SOLVERS, PDAS_MAX_ITER, ExchangeRule, QPResult, _limited_blas, spd_solve
from .coulomb import CoulombStep, coulomb_loop
from .errors import InputError

#: how Coulomb friction is solved (module docstring)
FRICTION_METHODS = ("fixed-point", "newton")
#: the default: measured fewer dense solves and the same answers (BENCHMARKS.md, friction)
DEFAULT_FRICTION_METHOD = "fixed-point"
#: the Coulomb fixed point stops when the slip threshold mu lam_n changes by less than
#: this fraction of max lam_n (the Newton step usually ends it before, at round-off)
COULOMB_TOL = 1e-12
#: the most Tresca problems (or Newton steps) a Coulomb solve may take
COULOMB_MAX_ITER = 200
#: Newton-Cotes weights of the p + 1 equispaced points of an edge (times its length):
#: the nodal quadrature of P_p jumps, used for a Tresca threshold given in stress units
NEWTON_COTES = {0: (1.0,), 1: (0.5, 0.5), 2: (1 / 6, 4 / 6, 1 / 6), 3: (1 / 8, 3 / 8, 3 / 8, 1 / 8)}


# --------------------------------------------------------------------------- the problem


@dataclass
class CrackProblem:
    """The reduced crack problem (module docstring) as plain data.

    `S` ((nn + nt)^2, SPD) and `b` in z = (zn, zt); `Gn` (m x nn, invertible) maps zn
    to the normal values at the m constraint points, `Gt` (mt x nt, invertible) zt to
    the tangential values at the points `t_point` (mt indices into the m points; a
    point whose tangential jump is held at zero has none). `weights` (m) are the
    quadrature weights omega_i, `mu` (m) the Coulomb coefficients, `threshold` (m) a
    Tresca slip threshold g in stress units (None: Coulomb, g = mu times the contact
    pressure). `crack` and `s` say where each point sits (crack index, arc length).
    """

    S: np.ndarray
    b: np.ndarray
    Gn: np.ndarray
    Gt: np.ndarray
    t_point: np.ndarray
    weights: np.ndarray
    mu: np.ndarray
    threshold: np.ndarray | None = None
    crack: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    s: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def m(self) -> int:
        """The number of normal constraint values."""
        return self.Gn.shape[0]

    @property
    def nn(self) -> int:
        """The number of normal crack unknowns."""
        return self.Gn.shape[1]

    def point_form(self) -> _PointForm:
        """The problem in the scaled point values (module docstring)."""
        m, mt = self.m, len(self.t_point)
        if self.Gn.shape != (m, m) or self.Gt.shape != (mt, mt) or self.S.shape != (m + mt, m + mt):
            raise ValueError(f"CrackProblem: Gn {self.Gn.shape} and Gt {self.Gt.shape} must be square and S "
                             f"{self.S.shape} of their total size")
        import scipy.sparse as sp  # (a crack with friction only)

        from .csr import CSR

        blocks = []
        for G, k in ((self.Gn, m), (self.Gt, mt)):
            inv = _inverse_map(G, k) if k else None
            blocks.append(sp.identity(k, format="csr") if inv is None
                          else inv.to_scipy() if isinstance(inv, CSR) else sp.csr_matrix(inv))
        Ginv = sp.block_diag(blocks, format="csr")
        A, c, D = scaled_problem(self.S, self.b, Ginv)
        beta = float(np.max(np.abs(c))) if len(c) else 0.0
        p = np.asarray(self.t_point, dtype=int)
        return _PointForm(A=A, c=c / beta if beta > 0 else c, D=D, beta=beta, m=m, p=p, Ginv=Ginv,
                          mu_s=self.mu[p] * D[m:] / D[p])

    def scaled_threshold(self, pf: _PointForm) -> np.ndarray:
        """Tresca: tau_i = g omega D_t / beta at the tangential values (scaled units)."""
        p = pf.p
        return np.asarray(self.threshold, dtype=float)[p] * self.weights[p] * pf.D[pf.m:] / pf.beta


@dataclass
class _PointForm:
    A: np.ndarray
    c: np.ndarray
    D: np.ndarray
    beta: float
    m: int
    p: np.ndarray
    Ginv: object  # a scipy.sparse CSR matrix
    mu_s: np.ndarray  # mu scaled to the units of v: tau = mu_s * lam_n(scaled)


@dataclass
class FrictionResult(QPResult):
    """A QPResult (normal part: j, w, multiplier, active) plus the tangential part.

    `z` all reduced unknowns (zn, zt), `jt` the tangential unknowns zt, `wt` the
    tangential values at the points `t_point`, `lam_t` the friction forces there
    (sigma_t times the weight: along the slip), `slip` -1 / 0 / +1 (0: stick) per
    tangential value, `coulomb_iterations` the Tresca problems (or Newton steps)
    solved, `steps` the active-set steps in all, `kkt` the relative residuals
    (max_penetration, max_tension, complementarity, friction) at the constraint points.
    `problem` is the CrackProblem it solved (solve() keeps it: a new coefficient or a
    Tresca threshold is a new solve of the same problem, no new mesh or factorization).
    """

    z: np.ndarray = field(default_factory=lambda: np.zeros(0))
    jt: np.ndarray = field(default_factory=lambda: np.zeros(0))
    wt: np.ndarray = field(default_factory=lambda: np.zeros(0))
    lam_t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    slip: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    t_point: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    mu: np.ndarray = field(default_factory=lambda: np.zeros(0))
    coulomb_iterations: int = 0
    steps: int = 0
    method: str = ""
    problem: CrackProblem | None = None

    def point_states(self) -> np.ndarray:
        """open / stick / slip at every constraint point (constraints.faces_closed, as post.profile_states).

        Open where wn > 0; closed points stick where their tangential value is held
        (slip 0, or no tangential unknown) and the crack carries friction, else slip.
        """
        W = float(max(np.max(np.abs(self.w), initial=0.0), np.max(np.abs(self.wt), initial=0.0)))
        moving = np.zeros(len(self.w), dtype=bool)
        moving[self.t_point[self.slip != 0]] = True
        rough = np.zeros(len(self.w), dtype=bool)
        rough[self.t_point[self.mu > 0]] = True
        closed = np.where(rough & ~moving, "stick", "slip")
        return np.where(faces_closed(self.w, W), closed, "open")


# --------------------------------------------------------------------------- the native method


def _linear_step(pf: _PointForm, act: np.ndarray, slip: np.ndarray, tau: np.ndarray | None) -> np.ndarray:
    """v for one guess of the sets: v_n = 0 where in contact (act), v_t = 0 where stuck.

    Free rows: (A v - c)_n = 0 where not in contact; on slipping values (A v - c)_t =
    -s tau (Tresca, symmetric) or (A v - c)_t + s mu_s (A v - c)_n(p) = 0 (Coulomb,
    `tau` None: nonsymmetric).
    """
    A, c, m = pf.A, pf.c, pf.m
    free = np.concatenate([~act, slip != 0])
    F = np.flatnonzero(free)
    v = np.zeros(len(c))
    if not F.size:
        return v
    if tau is not None:
        r = c.copy()
        r[m:] -= slip * tau
        v[F] = spd_solve(A[np.ix_(F, F)], r[F])
        return v
    M = A[np.ix_(F, F)].copy()
    r = c[F].copy()
    rows = np.flatnonzero(F >= m)  # the slipping tangential rows of M
    i = F[rows] - m
    coef = slip[i] * pf.mu_s[i]
    M[rows] += coef[:, None] * A[np.ix_(pf.p[i], F)]
    r[rows] += coef * c[pf.p[i]]
    import scipy.linalg as sla  # (loaded by a solve with friction only)

    v[F] = sla.solve(M, r, check_finite=False)
    return v


def _active_set(pf: _PointForm, act: np.ndarray, slip: np.ndarray, tau: np.ndarray | None,
                max_iter: int = PDAS_MAX_ITER):
    """Primal-dual active set for Tresca (tau given) or Coulomb (tau None) in scaled point values.

    Returns (v, g = A v - c, act, slip, steps, converged). Which violations a step
    exchanges is contact.ExchangeRule's (the QP's safeguard), over the normal values
    followed by the tangential ones.
    """
    m = pf.m
    act, slip = act.copy(), slip.copy()
    exchange = ExchangeRule(len(pf.c))
    v = g = np.zeros(len(pf.c))
    for it in range(1, max_iter + 1):
        v = _linear_step(pf, act, slip, tau)
        g = pf.A @ v - pf.c
        lam = np.where(act, g[:m], 0.0)
        thr = tau if tau is not None else pf.mu_s * np.maximum(lam[pf.p], 0.0)
        y = -g[m:]  # friction forces (scaled): along the slip
        vn, vt = v[:m], v[m:]
        tol_v = FEASIBILITY_RTOL * max(np.max(np.abs(v)), 1.0)
        tol_g = FEASIBILITY_RTOL * max(np.max(np.abs(g)), 1.0)
        viol_n = np.where(act, -lam - tol_g, -vn - tol_v)
        stick = slip == 0
        viol_t = np.where(stick, np.abs(y) - thr - tol_g, -slip * vt - tol_v)
        bad = np.concatenate([viol_n > 0, viol_t > 0])
        if not bad.any():
            return v, g, act, slip, it, True
        flip = exchange(bad)
        bad_n, bad_t = flip[:m], flip[m:]
        act[bad_n] = ~act[bad_n]
        # a value that slips against its friction force sticks; a stuck value whose
        # force exceeds the threshold slips along that force (the semismooth Newton
        # step of wt - shrink(wt + c y, tau) = 0 in the limit c -> 0+; c = 1 lets the
        # slip direction of strongly coupled values flip back and forth)
        new = np.where(stick, np.sign(y), 0.0).astype(slip.dtype)
        slip[bad_t] = new[bad_t]
    return v, g, act, slip, max_iter, False


def _sets_from(pf: _PointForm, v: np.ndarray, tau: np.ndarray):
    """The contact / stick / slip sets an approximate answer v suggests."""
    m = pf.m
    g = pf.A @ v - pf.c
    act = g[:m] > v[:m]
    z = -g[m:] + v[m:]
    slip = np.where(np.abs(z) > tau, np.sign(z), 0.0).astype(np.int8)
    return act, slip


def tresca_cvxpy(pf: _PointForm, tau: np.ndarray, solver: str, options: dict | None = None) -> np.ndarray:
    """The Tresca problem in cvxpy, in the scaled point values v = (vn, vt):

        minimise 0.5 v'Av - c'v + sum_i tau_i |vt_i|   subject to   vn >= 0.
    """
    import cvxpy as cp

    name = solver.upper()
    if name not in cp.installed_solvers():
        raise InputError(f"qp_solver = {solver!r}: allowed values are pdas or an installed cvxpy solver: "
                          + ", ".join(s.lower() for s in cp.installed_solvers()))
    v = cp.Variable(len(pf.c))
    energy = 0.5 * cp.quad_form(v, cp.psd_wrap(pf.A)) - pf.c @ v
    problem = cp.Problem(cp.Minimize(energy + tau @ cp.abs(v[pf.m:])), [v[:pf.m] >= 0])
    try:
        problem.solve(solver=name, **dict(options or {}))
    except cp.error.SolverError as exc:
        raise ContactSolverError(f"qp_solver = {solver!r} failed on the Tresca problem: {exc}") from exc
    if problem.status not in ("optimal", "optimal_inaccurate") or v.value is None:
        raise ContactSolverError(f"qp_solver = {solver!r} returned status {problem.status!r} on the Tresca problem")
    return np.asarray(v.value, dtype=float)


# --------------------------------------------------------------------------- Coulomb


def coulomb_residual(wn, lam_n, wt, lam_t, t_point, bound) -> dict:
    """Relative residuals of the discrete contact and friction laws at the constraint points.

    W = max |w| over normal and tangential values, L = max lam_n (each absolute where
    zero): max_penetration = max(0, -min wn)/W, max_tension = max(0, -min lam_n)/L,
    complementarity = max |wn lam_n|/(W L), friction = the larger of
    max(0, |lam_t| - bound)/L and max |wt| |bound - sign(wt) lam_t|/(W L), with
    `bound` the slip threshold of each tangential value in force units (Coulomb:
    mu lam_n at its point `t_point`).
    """
    wn, lam_n, wt, lam_t, bound = (np.asarray(a, dtype=float) for a in (wn, lam_n, wt, lam_t, bound))
    W = float(max(np.max(np.abs(wn), initial=0.0), np.max(np.abs(wt), initial=0.0))) or 1.0
    L = float(np.max(lam_n, initial=0.0)) or 1.0
    friction = 0.0
    if len(wt):
        cone = np.max(np.maximum(0.0, np.abs(lam_t) - bound)) / L
        slide = np.max(np.abs(wt) * np.abs(bound - np.sign(wt) * lam_t)) / (W * L)
        friction = float(max(cone, slide))
    return {
        "max_penetration": float(max(0.0, -np.min(wn, initial=0.0)) / W),
        "max_tension": float(max(0.0, -np.min(lam_n, initial=0.0)) / L),
        "complementarity": float(np.max(np.abs(wn * lam_n), initial=0.0) / (W * L)),
        "friction": friction,
    }


def check_friction_solver(qp_solver: str, method: str) -> None:
    """The one check of how a crack problem with friction is solved: `method` one of
    FRICTION_METHODS; the Tresca steps by pdas or a cvxpy solver (not uzawa); newton only
    with pdas. `SolveOptions.check_for` calls it before any meshing, `solve_crack_problem`
    for a direct call."""
    if method not in FRICTION_METHODS:
        raise InputError(f"friction_method = {method!r}: allowed values are {', '.join(FRICTION_METHODS)}")
    if qp_solver in NATIVE_SOLVERS and qp_solver != "pdas":
        raise InputError(f"qp_solver = {qp_solver!r}: with friction the allowed values are pdas or a cvxpy solver")
    if qp_solver != "pdas" and method == "newton":
        raise InputError("friction_method = 'newton' is the native method: use qp_solver = 'pdas'")


def solve_crack_problem(problem: CrackProblem, solver: str = "pdas", solver_options: dict | None = None,
                        method: str = DEFAULT_FRICTION_METHOD, tol: float = COULOMB_TOL,
                        max_iter: int = COULOMB_MAX_ITER, kkt_tol: float = ACCEPT_KKT) -> FrictionResult:
    """Solve the Tresca (problem.threshold given) or Coulomb (None) crack problem.

    `solver` "pdas" (native) or a cvxpy solver for the Tresca steps (polished by the
    native steps); `method` "fixed-point" or "newton" for Coulomb (module docstring).
    Raises ContactSolverError if a solver fails, the Coulomb iteration does not
    converge in `max_iter` steps, or the answer's residuals exceed `kkt_tol`.
    """
    check_friction_solver(solver, method)
    if not (np.all(np.isfinite(problem.S)) and np.all(np.isfinite(problem.b))):
        raise ContactSolverError("the crack problem has non-finite entries (S or b): the linear system is singular")
    if np.any(problem.mu < 0) or not np.all(np.isfinite(problem.mu)):
        raise InputError("friction: the Coulomb coefficients must be finite numbers >= 0")
    with _limited_blas(len(problem.b)):
        return _solve(problem, solver, dict(solver_options or {}), method, tol, max_iter, kkt_tol)


def _solve(problem, solver, options, method, tol, max_iter, kkt_tol) -> FrictionResult:
    t0 = time.perf_counter()
    pf = problem.point_form()
    m, mt = pf.m, len(pf.p)
    act = np.zeros(m, dtype=bool)
    slip = np.ones(mt, dtype=np.int8)  # with tau = 0 the first step is the frictionless problem
    tresca = problem.threshold is not None
    raw = {}
    if pf.beta == 0.0:
        v, g, iters, steps = np.zeros(m + mt), np.zeros(m + mt), 0, 0
        act[:] = True
        slip[:] = 0
    elif tresca:
        tau = problem.scaled_threshold(pf)
        v, g, act, slip, steps, raw = _tresca(pf, tau, act, slip, solver, options)
        iters = 1
    elif method == "newton":
        tau0 = np.zeros(mt)
        v, g, act, slip, steps, _ = _tresca(pf, tau0, act, slip, "pdas", {})
        v, g, act, slip, s2, ok = _active_set(pf, act, slip, None, max_iter=max_iter)
        steps += s2
        iters = s2
        if not ok:
            raise ContactSolverError(f"friction_method = 'newton' did not converge in {max_iter} steps; "
                                     "try friction_method = 'fixed-point'")
    else:
        st = {"steps": 0, "prev": None}

        def tresca_step(tau: np.ndarray) -> CoulombStep:
            """A Tresca problem with the threshold tau, then the threshold mu lam_n of its answer; once two
            successive answers have the same sets, one Newton step on the Coulomb law itself (`final` if it
            holds)."""
            v, g, act, slip, s, raw = _tresca(pf, tau, st["act"], st["slip"], solver, options)
            st.update(v=v, g=g, act=act, slip=slip, raw=raw, steps=st["steps"] + s)
            lam = np.where(act, g[:m], 0.0)
            L = max(float(np.max(lam, initial=0.0)), np.finfo(float).tiny)
            tau_new = pf.mu_s * np.maximum(lam[pf.p], 0.0)
            if float(np.max(np.abs(tau_new - tau), initial=0.0)) / L <= tol:
                return CoulombStep(tau_new, L)
            sets, prev = (act.copy(), slip.copy()), st["prev"]
            st["prev"] = sets
            if prev is not None and np.array_equal(sets[0], prev[0]) and np.array_equal(sets[1], prev[1]):
                # the sets have settled: one Newton step on the Coulomb law itself
                vN, gN, aN, sN, _, ok = _active_set(pf, act, slip, None, max_iter=1)
                st["steps"] += 1
                if ok:
                    st.update(v=vN, g=gN, act=aN, slip=sN)
                    return CoulombStep(tau_new, L, final=True)
            return CoulombStep(tau_new, L)

        st.update(act=act, slip=slip)
        run = coulomb_loop(tresca_step, np.zeros(mt), max_steps=max_iter, bound_rtol=tol, what="the Coulomb fixed point",
                           unit="Tresca problems", hint="; try friction_method = 'newton' or a smaller friction coefficient")
        v, g, act, slip, raw, steps, iters = st["v"], st["g"], st["act"], st["slip"], st["raw"], st["steps"], run.steps
    return _result(problem, pf, v, g, act, slip, solver, iters, steps, method if not tresca else "tresca",
                   raw, kkt_tol, time.perf_counter() - t0)


def _tresca(pf, tau, act, slip, solver, options):
    """One Tresca problem: native active set (warm-started) or cvxpy then native polish."""
    raw = {}
    if solver != "pdas":
        v0 = tresca_cvxpy(pf, tau, solver, options)
        if not np.all(np.isfinite(v0)):
            raise ContactSolverError(f"qp_solver = {solver!r} returned non-finite values")
        act, slip = _sets_from(pf, v0, tau)
        raw = _scaled_residual(pf, v0, tau)
    v, g, act, slip, steps, ok = _active_set(pf, act, slip, tau)
    if not ok:
        raise ContactSolverError(f"the active-set method did not converge on the Tresca problem in {PDAS_MAX_ITER} "
                                 "steps; try qp_solver = 'clarabel'")
    return v, g, act, slip, steps, raw


def _scaled_residual(pf, v, tau) -> dict:
    """Residuals of an approximate Tresca answer v (scaled units, for the record)."""
    m = pf.m
    g = pf.A @ v - pf.c
    vn, gn, vt, y = v[:m], g[:m], v[m:], -g[m:]
    s = max(np.max(np.abs(v)), 1.0) * max(np.max(np.abs(g)), 1.0)
    return {"primal": float(max(0.0, -np.min(vn, initial=0.0))),
            "dual": float(max(0.0, -np.min(gn, initial=0.0))),
            "complementarity": float(np.max(np.abs(vn * gn), initial=0.0) / s),
            "friction": float(max(np.max(np.maximum(0.0, np.abs(y) - tau), initial=0.0),
                                  np.max(np.abs(vt) * np.abs(tau - np.sign(vt) * y), initial=0.0)))}


def _result(problem, pf, v, g, act, slip, solver, iters, steps, method, raw, kkt_tol, elapsed) -> FrictionResult:
    m = pf.m
    v = v.copy()
    v[:m] = np.maximum(v[:m], 0.0)
    v[:m][act] = 0.0
    v[m:][slip == 0] = 0.0
    x = pf.beta * pf.D * v
    lam_n = np.where(act, pf.beta * g[:m] / pf.D[:m], 0.0)
    lam_t = -pf.beta * g[m:] / pf.D[m:]
    wn, wt = x[:m], x[m:]
    z = pf.Ginv @ x
    if problem.threshold is None:
        bound = problem.mu[pf.p] * lam_n[pf.p]
    else:  # Tresca: the threshold g omega in force units
        bound = np.asarray(problem.threshold, dtype=float)[pf.p] * problem.weights[pf.p]
    kkt = coulomb_residual(wn, lam_n, wt, lam_t, pf.p, bound)
    if not all(np.isfinite(list(kkt.values()))) or not np.all(np.isfinite(z)):
        raise ContactSolverError(f"qp_solver = {solver!r}: non-finite values in the friction answer")
    if max(kkt.values()) > kkt_tol:
        raise ContactSolverError(f"qp_solver = {solver!r}: the friction answer violates its conditions (residuals {kkt})")
    nn = problem.nn
    return FrictionResult(
        j=z[:nn], w=wn, multiplier=lam_n, active=np.flatnonzero(act), solver=solver, iterations=iters,
        kkt=kkt, time_s=elapsed, raw_kkt=raw, crack=problem.crack, s=problem.s,
        z=z, jt=z[nn:], wt=wt, lam_t=lam_t, slip=slip.astype(int), t_point=pf.p, mu=problem.mu[pf.p],
        coulomb_iterations=iters, steps=steps, method=method, problem=problem,
    )
