"""Coulomb friction on 3D crack faces: a sparse semismooth Newton method, no dense matrix.

The problem (dimension-free: a sparse matrix, a load, the normal constraints of
`sparse_contact.solve_contact` and the slip at friction points, nothing of a mesh):

    minimise 0.5 y'Ky - F'y + sum_q g_q |s_q|   subject to   w = G y_c >= 0,

s_q = B_q y the tangential jump at friction point q (a 2-vector in its crack's plane),
g_q = mu_q omega_q lam_f(q) the Coulomb bound in force units: mu the friction coefficient,
lam_f the normal contact force of the point's crack face (the sum of its constraints'
forces) and omega_q the point's share of that face. With lam_t,q the friction force at q
(the faces' tangential traction on the + side integrated against the point), the KKT
conditions read, besides those of frictionless contact,

    K y - F - (G'lam_n)_c + B'lam_t = 0,   |lam_t,q| <= g_q,   g_q s_q = |s_q| lam_t,q,

i.e. the friction force lies in the Coulomb cone (a second-order cone in 3D: the
tangential plane is 2D), the points inside it stick (s = 0), and where they slip the
force is on the cone's edge along the slip.

The method: a primal-dual active set / semismooth Newton method on the complementarity
function max(g, |xi|) lam_t - g xi = 0, xi = lam_t + c s (Hueber, Stadler and Wohlmuth
2008), with g updated from the current normal forces at every step. Each step fixes the
closed constraints (x_A = 0, as in `sparse_contact.solve_contact`), the sticking points (s_q = 0,
their forces the multipliers of a saddle-point system) and the slipping ones, whose
linearised law, taken along the predicted direction xi/|xi|,

    lam_t = g xi/|xi| + (c g / (|xi| - g)) (I - xi xi'/|xi|^2) s,

adds a 2x2 positive semidefinite block per point to K (the exact Jacobian at the
solution, where xi is along s). One sparse LU factorization per step (the saddle-point
matrix of K's free unknowns and the sticking points' constraints); nothing of size m^2.
The step's answer updates the sets: stick where |xi| <= g, slip elsewhere; closed where
lam_n - c_n w > 0. The sticking points' forces are the multipliers of their constraints,
not unique where those are redundant: of the forces that balance the step's residual the
step takes the nearest the cone (`coulomb.cone_forces`; the minimum-norm ones left the cone
near the smallest coefficient that holds every face, and about 20 points of the inclined
penny at mu = 2 then alternated between stick and slip without end). It ends when the sets
repeat and the slip law, the bound g = mu omega lam_f and the equations hold to round-off:
the outer loop (the bound's update, the test, the record, the failure) is
`coulomb.coulomb_loop`, shared by every frictional solve.

Reduced to the crack (`method` "schur", the default while the crack's normal and tangential
unknowns number at most constraints.SCHUR_MAX_M): one sparse factorization of K with those
unknowns last leaves their dense Schur complement S (MKL PARDISO's Schur option), the same
Newton method runs on S (each step a factorization of the small reduced matrix, not of the
body's), and the rest is recovered with one solve. The certificate is then computed on the
whole system. "sparse": every step factorizes the whole system.

The certificate is computed afterwards from the system itself: the normal forces from
the residual at the constraints (`constraints.discrete_contact_forces`), the friction
forces at the slipping points set to g s/|s| exactly (on the cone's edge), at the sticking
points the balancing forces nearest the cone (`sticking_forces`), and the
residual of every other equation (`stationarity`); `friction` in the KKT dictionary is the
largest of the cone's excess, the slip law's residual and the stationarity, each
relative to the largest normal force (and the largest slip).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from . import constraints
from .constraints import KKT_ZERO_RTOL, ContactSolverError, discrete_contact_forces, kkt_at_constraints
from .coulomb import STICK_RCOND, CoulombStep, cone_forces, coulomb_loop
from .schur import Factorization
from .sparse_contact import MAX_ITERATIONS, _transform

#: the slip law must hold to this fraction of the largest normal force at the end
NEWTON_RTOL = 1e-13
#: and the Coulomb bound g must have settled to this fraction (the normal forces come from a
#: residual, so they carry its round-off: a few 1e-13 of the largest)
BOUND_RTOL = 1e-11
#: the sticking points' constraint block: -delta, delta = this / c (iterated: module docstring)
STICK_REGULARIZATION = 1e-8
#: a sticking point stays stuck while its force exceeds the bound by at most this fraction of the largest
#: normal force (the round-off of the nearest-to-the-cone forces, `coulomb.cone_forces`, on the cone's edge)
CONE_SLACK = 1e-12
#: the most solves of the iterated regularisation per Newton step
MAX_REFINEMENTS = 30
#: the reduced ("schur") method corrects its load by the whole system's residual at most this many
#: times, until that residual at the crack's rows matches the reduced one to DEFECT_RTOL of the load
DEFECT_CORRECTIONS, DEFECT_RTOL = 3, 1e-15
#: c in xi = lam_t + c s, relative to the slip's stiffness scale (K's diagonal over B's rows)
COMPLEMENTARITY_SCALE = 1.0


@dataclass
class FrictionPoints:
    """Where the slip is measured: B maps y to the slips (2 rows per point, in its crack's
    plane basis); `face` is the point's crack face (its constraints are the face's rows of
    G: `face_rows`), `omega` its share of that face, `mu` the friction coefficient there."""

    B: sp.csr_matrix  # (2 q, n)
    face: np.ndarray  # (q,)
    omega: np.ndarray  # (q,)
    mu: np.ndarray  # (q,)
    face_rows: np.ndarray  # (faces, per): the constraint rows of each face
    where: np.ndarray | None = None  # (q, 3) the points in space
    basis: np.ndarray | None = None  # (q, 2, 3) each point's crack plane basis (e_a, e_b)
    crack: np.ndarray | None = None  # (q,) each point's crack


@dataclass
class FrictionResult:
    """The solution y and its certificate (`kkt` with the Coulomb residual under "friction")."""

    y: np.ndarray
    w: np.ndarray
    lam: np.ndarray  # normal contact forces at the constraints, from the residual
    active: np.ndarray  # closed constraints
    slip: np.ndarray  # (q, 2) the slip at the friction points
    lam_t: np.ndarray  # (q, 2) the friction forces at the friction points
    bound: np.ndarray  # (q,) the Coulomb bound mu omega lam_f at the end
    stick: np.ndarray  # (q,) the points that stick (with a positive bound)
    iterations: int
    kkt: dict
    residuals: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    factorizations: int = 0
    points: FrictionPoints | None = None  # where the slips and friction forces are (set by the caller)
    record: list = field(default_factory=list)  # the Newton steps (coulomb.coulomb_loop's record)


def coulomb_bound(points: FrictionPoints, lam: np.ndarray) -> np.ndarray:
    """g_q = mu omega lam_f: the Coulomb bound of every point from the normal forces `lam`."""
    face_force = np.maximum(lam[points.face_rows].sum(axis=1), 0.0)
    return points.mu * points.omega * face_force[points.face]


def coulomb_residuals(lam_n, w, slip, lam_t, bound, stationarity: float, jump_scale: float,
                      force_scale: float) -> dict:
    """The Coulomb law's relative residuals (module docstring): cone, slip law, stationarity."""
    L = float(np.max(lam_n, initial=0.0))
    L = L if L > 0.0 else (force_scale or 1.0)
    S = float(max(np.max(np.abs(w), initial=0.0), np.max(np.linalg.norm(slip, axis=1), initial=0.0)))
    S = S if S > KKT_ZERO_RTOL * jump_scale and S > 0.0 else (jump_scale or 1.0)
    norm_s = np.linalg.norm(slip, axis=1)
    cone = np.maximum(np.linalg.norm(lam_t, axis=1) - bound, 0.0)
    law = np.linalg.norm(bound[:, None] * slip - norm_s[:, None] * lam_t, axis=1)
    return {"cone": float(np.max(cone, initial=0.0) / L), "slip_law": float(np.max(law, initial=0.0) / (S * L)),
            "stationarity": float(stationarity / L)}


def solve_friction(K: sp.spmatrix, F: np.ndarray, contact: np.ndarray, G, points: FrictionPoints, *,
                   linear_solver: str = "auto", max_iterations: int = MAX_ITERATIONS, method: str = "auto",
                   _reduced: dict | None = None) -> FrictionResult:
    """Solve the frictional contact problem of the module docstring by the semismooth Newton method,
    on the Schur complement of the crack's unknowns (`method` "schur"; "auto": while they number at
    most constraints.SCHUR_MAX_M) or on the whole sparse system ("sparse")."""
    if method not in ("auto", "schur", "sparse"):
        raise ValueError(f"method = {method!r}: allowed values are auto, schur, sparse")
    crack = np.union1d(np.asarray(contact, dtype=int), np.unique(sp.csr_matrix(points.B).indices))
    if method == "schur" or (method == "auto" and len(crack) <= constraints.SCHUR_MAX_M):
        return _solve_reduced(K, F, np.asarray(contact, dtype=int), G, points, crack, linear_solver, max_iterations)
    t0 = time.perf_counter()
    K = sp.csr_matrix(K)
    contact = np.asarray(contact, dtype=int)
    n, m = K.shape[0], len(contact)
    nq = len(points.face)
    Kw, Fw, T = _transform(K, F, contact, G)
    B = sp.csr_matrix(points.B)  # B acts on the tangential unknowns only: B T = B
    diag = Kw.diagonal()[contact]
    if np.any(diag <= 0):
        raise ContactSolverError("the crack unknowns' stiffness is not positive: a part of the body is not held")
    if _reduced is not None:  # the whole system's scale (S's diagonal is smaller than K's)
        c = _reduced["c"]
    else:
        c = slip_stiffness(Kw, B)
    st = {"A": np.zeros(m, dtype=bool), "stick": np.zeros(nq, dtype=bool), "lam_t": np.zeros((nq, 2)),
          "x": np.zeros(n), "t_fact": 0.0}

    def step(g: np.ndarray) -> CoulombStep:
        """One semismooth Newton step with the bound g (module docstring); the sets move to the step's."""
        A, stick, lam_t, x = st["A"], st["stick"], st["lam_t"], st["x"]
        s = (B @ x).reshape(nq, 2)
        xi = lam_t + c * s
        nxi = np.linalg.norm(xi, axis=1)
        on = g > 0
        S_set = on & stick
        L_set = on & ~stick
        free = np.ones(n, dtype=bool)
        free[contact[A]] = False
        fidx = np.flatnonzero(free)
        # the slipping points' linearised law (Hueber, Stadler and Wohlmuth's, with the force
        # lt = g lam_t / max(g, |lam_t|) in the Jacobian; its component against xi dropped so that
        # M = (|xi| - g) I + lt d' stays invertible): lam_t = a + N s,
        # a = |xi| M^-1 lt, N = -c M^-1 (lt d' - g I), d = xi / |xi|
        d = np.zeros((nq, 2))
        d[L_set] = xi[L_set] / nxi[L_set, None]
        lt = g[:, None] * lam_t / np.maximum(g, np.linalg.norm(lam_t, axis=1))[:, None].clip(1e-300)
        lt -= np.minimum(np.sum(lt * d, axis=1), 0.0)[:, None] * d
        Minv = np.zeros((nq, 2, 2))
        Mq = (nxi - g)[L_set, None, None] * np.eye(2)[None] + lt[L_set, :, None] * d[L_set, None, :]
        Minv[L_set] = np.linalg.inv(Mq)
        a_q = np.zeros((nq, 2))
        a_q[L_set] = nxi[L_set, None] * np.einsum("qij,qj->qi", Minv[L_set], lt[L_set])
        Nblocks = np.zeros((nq, 2, 2))
        Nblocks[L_set] = -c * Minv[L_set] @ (lt[L_set, :, None] * d[L_set, None, :] - g[L_set, None, None] * np.eye(2))
        Nmat = sp.block_diag(list(Nblocks[L_set]), format="csr") if L_set.any() else None
        rowsL = np.flatnonzero(np.repeat(L_set, 2))
        rowsS = np.flatnonzero(np.repeat(S_set, 2))
        BL, BS = B[rowsL][:, fidx], B[rowsS][:, fidx]
        Kf = Kw[fidx][:, fidx]
        rhs = Fw[fidx].copy()
        if Nmat is not None:
            Kf = Kf + BL.T @ Nmat @ BL
            rhs -= BL.T @ a_q[L_set].ravel()
        ns = len(rowsS)
        t1 = time.perf_counter()
        if ns or Nmat is not None:
            # the sticking points' constraints B_S x = 0 may be redundant (more slips than jump
            # functions): the block is regularised, B_S x = delta (lam_t - lam_prev), and the
            # solve repeated from lam_prev = lam_t until B_S x = 0 to round-off (iterated
            # regularisation: the same factorization, the exact constrained x in the limit)
            delta = STICK_REGULARIZATION / c
            M = sp.bmat([[Kf, BS.T], [BS, -delta * sp.identity(ns)]], format="csr") if ns else sp.csr_matrix(Kf)
            fac = _DenseLU(M) if _reduced is not None else Factorization(M, linear_solver, definite=False)
            mult = np.zeros(ns)
            for _ in range(MAX_REFINEMENTS):
                sol = fac.solve(np.concatenate([rhs, -delta * mult]))
                x_f, new_mult = sol[:len(fidx)], sol[len(fidx):]
                moved = float(np.max(np.abs(new_mult - mult), initial=0.0))
                mult = new_mult
                if moved <= 1e-15 * max(float(np.max(np.abs(mult), initial=0.0)), 1e-300):
                    break
        else:
            fac = _DenseLU(Kf) if _reduced is not None else Factorization(sp.csr_matrix(Kf), linear_solver)
            x_f, mult = fac.solve(rhs), np.zeros(0)
        st["t_fact"] += time.perf_counter() - t1
        x[:] = 0.0
        x[fidx] = x_f
        s = (B @ x).reshape(nq, 2)
        new_lam_t = np.zeros((nq, 2))
        new_lam_t[L_set] = a_q[L_set] + np.einsum("qij,qj->qi", Nblocks[L_set], s[L_set])
        # normal forces at the constraints (the friction terms do not touch their rows)
        lam = np.asarray(Kw[contact] @ x - Fw[contact])
        new_A = lam - diag * x[contact] > 0
        # the bound from the closed constraints' forces: an open one's force is zero but for the
        # residual's round-off, which would switch its face's bound on and off from step to step
        new_g = coulomb_bound(points, np.where(new_A, lam, 0.0))
        new_lam_t[S_set] = mult.reshape(-1, 2)
        if ns and np.any(np.linalg.norm(new_lam_t[S_set], axis=1) > new_g[S_set] + CONE_SLACK * max(
                float(np.max(np.abs(lam), initial=0.0)), 1e-300)):
            # the sticking forces leave the cone: of those that balance the step's residual, the nearest it
            r_f = Kf @ x_f - rhs
            cols = np.unique(BS.indices)
            new_lam_t[S_set] = cone_forces(BS[:, cols].toarray().T, r_f[cols], new_g[S_set], start=mult)
        lam_t = new_lam_t
        xi = lam_t + c * s
        nxi = np.linalg.norm(xi, axis=1)
        scale = max(float(np.max(np.abs(lam), initial=0.0)), 1e-300)
        new_stick = nxi <= new_g + CONE_SLACK * scale
        # converged: the same sets, the bound settled, the slipping points' law on the cone's edge
        norm_s = np.linalg.norm(s, axis=1)
        law = np.zeros(nq)
        slipping = L_set & (norm_s > 0)
        law[slipping] = np.linalg.norm(lam_t[slipping] - g[slipping, None] * s[slipping] / norm_s[slipping, None],
                                       axis=1)
        changes = (np.count_nonzero(new_A != A) + np.count_nonzero((new_stick & (new_g > 0)) != S_set)
                   + np.count_nonzero((new_g > 0) != on))
        st.update(A=new_A, stick=new_stick, lam_t=lam_t, x=x)
        return CoulombStep(new_g, scale, int(changes), float(law.max(initial=0.0)) / scale)

    run = coulomb_loop(step, np.zeros(nq), max_steps=max_iterations, bound_rtol=BOUND_RTOL, law_rtol=NEWTON_RTOL,
                       what="the frictional contact (semismooth Newton)", unit="steps")
    A, stick, g, x, iterations = st["A"], st["stick"], run.bound, st["x"], run.steps
    result = certificate(K, F, T @ x, x[contact], contact, G, points, A, stick & (g > 0), g, iterations)
    result.timings = {"factorizations": st["t_fact"], "total": time.perf_counter() - t0}
    result.record = run.record
    return result


def slip_stiffness(Kw: sp.csr_matrix, B: sp.csr_matrix) -> float:
    """c in xi = lam_t + c s: K's diagonal on the slip's unknowns over B's rows (times COMPLEMENTARITY_SCALE)."""
    cols = np.unique(B.indices)
    row_sq = np.asarray(B.multiply(B).sum(axis=1)).ravel()
    c = float(np.median(Kw.diagonal()[cols]) / max(np.median(row_sq[row_sq > 0]), 1e-300)) if len(cols) else 1.0
    return c * COMPLEMENTARITY_SCALE


class _DenseLU:
    """A dense LU factorization with solves (the reduced method's small matrices)."""

    def __init__(self, M):
        import scipy.linalg as la

        self._lu = la.lu_factor(M.toarray() if sp.issparse(M) else np.asarray(M), check_finite=False)

    def solve(self, b: np.ndarray) -> np.ndarray:
        import scipy.linalg as la

        return la.lu_solve(self._lu, b, check_finite=False)


def _solve_reduced(K, F, contact, G, points: FrictionPoints, crack: np.ndarray, linear_solver: str,
                   max_iterations: int) -> FrictionResult:
    """The "schur" method (module docstring): the Newton method on S of the crack's unknowns `crack`
    (the normal jumps and the slips' unknowns), the rest recovered, the certificate on the whole system."""
    import dataclasses

    from .schur import schur_complement

    t0 = time.perf_counter()
    K = sp.csr_matrix(K)
    n = K.shape[0]
    rest = np.setdiff1d(np.arange(n), crack)
    data = schur_complement(K, F, rest, crack, linear_solver=linear_solver)
    t1 = time.perf_counter()
    at = np.searchsorted(crack, contact)
    c = slip_stiffness(K, sp.csr_matrix(points.B))  # T leaves the slip's unknowns alone: K_w's diagonal there is K's
    reduced = dataclasses.replace(points, B=sp.csr_matrix(points.B)[:, crack])
    K_rc = K[rest][:, crack]
    K_c = K[crack]
    b = data.b.copy()
    S = sp.csr_matrix(data.S)
    scale = float(np.max(np.abs(F))) or 1.0
    newton = 0.0
    for _ in range(DEFECT_CORRECTIONS + 1):
        t = time.perf_counter()
        inner = solve_friction(S, b, at, G, reduced, linear_solver=linear_solver, max_iterations=max_iterations,
                               method="sparse", _reduced={"c": c})
        newton += time.perf_counter() - t
        y = np.zeros(n)
        y[crack] = inner.y
        y[rest] = data.x0 - data.factorization.solve(K_rc @ inner.y)
        r = F[rest] - K[rest] @ y  # one step of iterative refinement of the rest (the crack's unknowns held)
        y[rest] += data.factorization.solve(r)
        # defect correction: S and b carry the partial factorization's rounding; the crack rows'
        # residual of the whole system is the reduced problem's once b absorbs the difference
        defect = (K_c @ y - F[crack]) - (S @ inner.y - b)
        if np.max(np.abs(defect)) <= DEFECT_RTOL * scale:
            break
        b -= defect
    t2 = time.perf_counter()
    result = certificate(K, F, y, inner.w, contact, G, points, inner.active, inner.stick, inner.bound, inner.iterations)
    result.record = inner.record
    result.timings = {"factorize": t1 - t0, "newton": newton, "recover": t2 - t1 - newton, "factorizations": t1 - t0,
                      "reduced_unknowns": float(len(crack)), "total": time.perf_counter() - t0}
    return result


def sticking_forces(B: sp.csr_matrix, r: np.ndarray, stick: np.ndarray, g: np.ndarray | None = None) -> np.ndarray:
    """The sticking points' friction forces (|stick|, 2) that balance the residual `r` (the other forces in it):
    B_S' lam = -r on B_S's columns. B_S's rows are redundant (module docstring of `solid.friction_points`), so
    the forces are not unique: of them, the nearest the cones |lam_q| <= g_q (`coulomb.cone_forces`; without
    `g`, or when they lie in it, the minimum-norm ones). Both are defined by y alone, the same from any
    method that finds y."""
    rows = np.flatnonzero(np.repeat(stick, 2))
    if not len(rows):
        return np.zeros((0, 2))
    BS = B[rows]
    cols = np.unique(BS.indices)
    lam = np.linalg.lstsq(BS[:, cols].toarray().T, -r[cols], rcond=STICK_RCOND)[0].reshape(-1, 2)
    bound = None if g is None else np.asarray(g, dtype=float)[stick]
    if bound is not None and np.any(np.linalg.norm(lam, axis=1) > bound * (1 + CONE_SLACK)):
        return cone_forces(BS[:, cols].toarray().T, r[cols], bound, start=lam)
    return lam


def certificate(K: sp.spmatrix, F: np.ndarray, y: np.ndarray, w: np.ndarray, contact: np.ndarray, G,
                points: FrictionPoints, active: np.ndarray, stick: np.ndarray, g: np.ndarray,
                iterations: int) -> FrictionResult:
    """The certificate of an answer y (module docstring): `w` its constraint values, `active`, `stick` and `g`
    the sets and Coulomb bound of the method's last step; the normal forces are read from the residual, the
    sticking points' friction forces too (`sticking_forces`)."""
    K = sp.csr_matrix(K)
    B = sp.csr_matrix(points.B)
    nq, m = len(points.face), len(contact)
    lam, lam_bound = discrete_contact_forces(K, F, y, contact, G)
    # the bound from the closed constraints' forces (an open one's is round-off: as in the iteration)
    bound = coulomb_bound(points, np.where(active, lam, 0.0))
    s = (B @ y).reshape(nq, 2)
    norm_s = np.linalg.norm(s, axis=1)
    # the certificate's friction forces: on the cone's edge along the slip where the points slip, and where
    # they stick the forces that balance the residual nearest the cone (`sticking_forces`)
    cert_t = np.zeros((nq, 2))
    slipping = (g > 0) & ~stick & (norm_s > 0)
    held = (g > 0) & ~slipping  # sticking, or slipping without a slip
    cert_t[slipping] = bound[slipping, None] * s[slipping] / norm_s[slipping, None]
    r = K @ y - F + B.T @ cert_t.ravel()
    cert_t[held] = sticking_forces(B, r, held, bound)
    r += B.T @ np.where(held[:, None], cert_t, 0.0).ravel()
    r[contact] = 0.0
    # less its rounding-error bound (as the normal forces': constraints.discrete_contact_forces)
    nnz = np.diff(K.indptr) + np.diff(sp.csc_matrix(B).indptr) + 2
    u = np.finfo(float).eps / 2
    rounding = nnz * u / (1 - nnz * u) * (abs(K) @ np.abs(y) + np.abs(F) + abs(B).T @ np.abs(cert_t.ravel()))
    stationarity = float(np.max(np.maximum(np.abs(r) - rounding, 0.0)))
    force_scale = float(np.max(np.abs(F))) or 1.0
    # relative to the closed constraints' forces (an open one's is round-off: on a crack open everywhere its largest,
    # 1e-14, made the residual 2e3)
    residuals = coulomb_residuals(np.where(active, lam, 0.0), w, s, cert_t, bound, stationarity,
                                  float(np.max(np.abs(y))), force_scale)
    kkt = kkt_at_constraints(w, lam, float(np.max(np.abs(w))) if m else 0.0, jump_scale=float(np.max(np.abs(y))),
                             force_scale=float(np.max(np.abs(F))), friction=max(residuals.values()), lam_bound=lam_bound)
    return FrictionResult(y, w, lam, active, s, cert_t, bound, stick & (g > 0), iterations, kkt, residuals,
                          factorizations=iterations)
