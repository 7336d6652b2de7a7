"""The Coulomb law's shared pieces: the outer iteration of every frictional solve, and the sticking
forces inside the cone.

The outer iteration (`coulomb_loop`). Every Coulomb solve of the package (2D on the Schur complement,
`friction`; 3D on the crack's Schur complement or the sparse system, `sparse_friction`; both over MPI
ranks, `ngcrack.distributed.friction` and `.solid_friction`) iterates on the Coulomb bound g = mu lam_n:
an inner step of its own (a Tresca problem solved exactly, or one semismooth Newton step on its data)
with the bound of the previous step, then the bound from the step's normal forces. The loop, its
convergence test (no set changes, the bound settled, the slip law held), its stopping and error
report and its record of the steps are this module's, the same for all.

Sticking forces (`cone_forces`). Where friction points stick, their forces lam (2 per point, in
the crack's plane) are the multipliers of the constraints B_S y = 0: they balance the residual
r of the other forces, A lam = -r with A = B_S' on B_S's columns. B_S's rows are redundant
(more slips than jump functions: `solid.friction_points`), so the balancing forces form an
affine family lam_0 + N z (N a basis of A's null space). The minimum-norm member is one choice,
not the Coulomb law's: the law asks for a member inside the cone |lam_q| <= g_q, and on a
sticking crack whose friction coefficient is close to the smallest that holds it, the
minimum-norm forces leave the cone where another member fits (the inclined penny of BENCHMARKS,
mu = 2: the minimum-norm forces need mu = 2.45 at the worst point, the cone's best member
1.997). `cone_forces` picks the member nearest the cone: it minimises

    f(z) = 0.5 sum_q dist(lam_q(z), disc of radius g_q)^2,

a convex, once differentiable function, by a Newton method on its generalised Hessian
N' (I - P') N (P' the derivative of the projection onto the disc: g/|lam| (I - d d') outside,
I inside) with a Levenberg term and a backtracking line search on f. f = 0 at its minimum
when a member fits in the cone; otherwise the points left outside are the ones that must slip.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: singular values of the sticking rows below this fraction of the largest are their redundancy
STICK_RCOND = 1e-10
#: the cone's distance counts as zero below this fraction of the largest bound (f's minimum found)
CONE_RTOL = 1e-14
#: Newton steps of the nearest-to-the-cone choice
CONE_MAX_STEPS = 50


def balancing_family(A: np.ndarray, r: np.ndarray, rcond: float = STICK_RCOND) -> tuple[np.ndarray, np.ndarray]:
    """(lam_0, N): a solution of A lam = -r and an orthonormal basis N of A's null space (a QR factorization
    of A' with column pivoting: its diagonal below `rcond` of the largest is A's redundancy)."""
    import scipy.linalg as sla

    if A.size == 0:
        return np.zeros(A.shape[1]), np.eye(A.shape[1])
    Q, R, perm = sla.qr(A.T, mode="full", pivoting=True, check_finite=False)
    diag = np.abs(np.diag(R))
    rank = int(np.sum(diag > rcond * diag[0])) if len(diag) and diag[0] > 0 else 0
    # A' P = Q R: lam = Q_1 R_11^-T (-r)[P] on the independent columns P[:rank]
    lam0 = Q[:, :rank] @ sla.solve_triangular(R[:rank, :rank], -r[perm[:rank]], trans="T", check_finite=False)
    return lam0, Q[:, rank:]


def _excess(lam: np.ndarray, g: np.ndarray):
    """Per point: lam - P(lam) (P the projection onto the disc of radius g) and |lam|."""
    norm = np.linalg.norm(lam, axis=1)
    out = np.maximum(norm - g, 0.0)
    e = lam * (out / np.maximum(norm, 1e-300))[:, None]
    return e, norm


def cone_forces(A: np.ndarray, r: np.ndarray, g: np.ndarray, start: np.ndarray | None = None) -> np.ndarray:
    """The sticking forces (len(g), 2) that balance `r` (A lam = -r, A = B_S' on B_S's columns) nearest
    the cones |lam_q| <= g_q (module docstring); `start` a guess (e.g. the last step's forces)."""
    lam0, N = balancing_family(A, r)
    ns = len(g)
    if start is not None and N.shape[1]:
        z = N.T @ (np.asarray(start, dtype=float).ravel() - lam0)
    else:
        z = np.zeros(N.shape[1])
    if not N.shape[1] or not ns:
        return lam0.reshape(ns, 2)
    tol = CONE_RTOL * max(float(np.max(g, initial=0.0)), 1e-300)

    def f(z):
        lam = (lam0 + N @ z).reshape(ns, 2)
        e, norm = _excess(lam, g)
        return 0.5 * float(np.sum(e * e)), lam, e, norm

    val, lam, e, norm = f(z)
    for _ in range(CONE_MAX_STEPS):
        if np.sqrt(2 * val) <= tol:
            break
        grad = N.T @ e.ravel()
        out = norm > g
        d = lam[out] / norm[out, None]
        blocks = np.zeros((ns, 2, 2))
        ratio = g[out] / norm[out]
        blocks[out] = np.eye(2)[None] * (1 - ratio)[:, None, None] + ratio[:, None, None] * d[:, :, None] * d[:, None, :]
        rows = np.flatnonzero(np.repeat(out, 2))
        Nb = N[rows]
        D = np.zeros((len(rows), len(rows)))
        for k in range(int(out.sum())):
            D[2 * k:2 * k + 2, 2 * k:2 * k + 2] = blocks[out][k]
        H = Nb.T @ D @ Nb
        H[np.diag_indices_from(H)] += 1e-12 * max(float(np.trace(H)), 1e-300) / len(H) + 1e-300
        step = -np.linalg.solve(H, grad)
        t = 1.0
        while True:
            new = f(z + t * step)
            if new[0] <= val - 1e-4 * t * float(grad @ -step) or t < 1e-10:
                break
            t *= 0.5
        if new[0] >= val:
            break
        z = z + t * step
        val, lam, e, norm = new
    return lam


# --------------------------------------------------------------------------- the outer loop


@dataclass
class CoulombStep:
    """What one inner step of a Coulomb solve reports to `coulomb_loop`: the bound its normal forces give
    (the next step's), the largest normal force (the bound's change is measured against it), the set changes
    it proposes, the slip law's residual relative to the largest normal force, and `final` when the step has
    ended the iteration itself (the 2D fixed point's Newton finish)."""

    bound: np.ndarray
    scale: float
    changes: int = 0
    law: float = 0.0
    final: bool = False


@dataclass
class CoulombRun:
    """The loop's end: the bound the last step used, that step's report and every step's record
    (set changes, the bound's relative change, the slip law)."""

    bound: np.ndarray
    last: CoulombStep
    record: list = field(default_factory=list)

    @property
    def steps(self) -> int:
        return len(self.record)


def coulomb_loop(step, bound, *, max_steps: int, bound_rtol: float, law_rtol: float = math.inf,
                 what: str = "the Coulomb iteration", unit: str = "steps", hint: str = "", reduce_max=None) -> CoulombRun:
    """The outer Coulomb iteration every frictional solve shares (2D and 3D, serial and over MPI ranks).

    `step(bound)` is the solve's own inner step (a Tresca problem solved exactly, or one semismooth Newton
    step) with the Coulomb bound mu lam_n of the previous step (`bound`: the first one given); it returns a
    CoulombStep. The iteration ends when a step changes no set, moves the bound by at most `bound_rtol`
    of the largest normal force and leaves the slip law within `law_rtol` (or reports `final`); after
    `max_steps` without that it raises ContactSolverError naming `what`, the last step's record and `hint`.
    Every rank of a distributed solve calls it with a step whose report is the same on every rank (reduced
    over them) and `reduce_max` the largest of a number over the ranks (the bound's change: each rank
    holds its own points' bound), so that all stop together."""
    from .constraints import ContactSolverError

    record = []
    for k in range(1, max_steps + 1):
        out = step(bound)
        moved = float(np.max(np.abs(np.asarray(out.bound) - np.asarray(bound)), initial=0.0))
        moved = (reduce_max(moved) if reduce_max is not None else moved) / max(out.scale, 1e-300)
        record.append({"step": k, "changes": int(out.changes), "bound_change": moved, "law": float(out.law)})
        if out.final or (out.changes == 0 and moved <= bound_rtol and out.law <= law_rtol):
            return CoulombRun(bound, out, record)
        bound = out.bound
    last = record[-1] if record else {"changes": 0, "bound_change": 0.0, "law": 0.0}
    raise ContactSolverError(f"{what} did not converge in {max_steps} {unit} (the last: {last['changes']} set changes, "
                             f"the Coulomb bound still moves by {last['bound_change']:.1e} of the largest normal force, "
                             f"the slip law's residual {last['law']:.1e}){hint}")
