"""Conjugate gradients on NGSolve's parallel vectors, projected onto a subspace, with BDDC.

The condensed facet system of a crack problem is K y = F with K = sign * A (A the
assembled, statically condensed matrix: a ParallelMatrix under MPI). The crack
problem's steps solve it with some constraint values held at zero: y in the range of
a projector P that is symmetric and acts on each rank's own entries (the Dirichlet
dofs and, per crack edge, the active constraint values). CG on P K P with the
preconditioner P C P (C = sign * BDDC(A)) stays in that range and converges as CG on
the constrained problem. Every inner product is NGSolve's (reduced over the ranks).
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

_DEBUG = bool(os.environ.get("NGCRACK_MPI_DEBUG"))

#: relative residual (preconditioned norm) at which CG stops; the answers agree with the
#: direct serial solve to about this tolerance times the condition of the constrained system
TOL = 1e-12
#: CG steps before giving up
MAX_STEPS = 2000


class KrylovError(RuntimeError):
    """CG did not reach its tolerance."""


@dataclass
class Operator:
    """K = sign * A and its preconditioner on NGSolve vectors: C = sign * (A's preconditioner) for an NGSolve
    matrix `C`, `C.apply` (an approximate inverse of K itself, subdomains.py) otherwise."""

    A: ngs.BaseMatrix
    C: object
    sign: float
    #: seconds spent in `pcg` with this operator
    seconds: float = 0.0
    #: relative residuals whose first CG step each `pcg` records on its way to its tolerance
    marks: tuple = (1e-8,)
    #: per `pcg` call: {mark: the first step at or below it} (BENCHMARKS: steps to 1e-8 and to 1e-12 in one solve)
    reached: list = field(default_factory=list)
    #: the exchange of shared unknowns among the ranks (exchange.py), made at the first `cumulate`
    exchange: object = None

    def apply(self, x: ngs.BaseVector, out: ngs.BaseVector) -> None:
        """out = K x; x cumulated (a ParallelMatrix would cumulate a distributed x through NGSolve's exchange)."""
        self.cumulate(x)
        out.data = self.A * x
        out.data *= self.sign

    def cumulate(self, vec: ngs.BaseVector) -> None:
        """`vec.Cumulate()` for a vector of K's unknowns, by mpi4py (exchange.py: NGSolve's own is not reliable on a
        rank with two or more neighbours); collective."""
        if vec.GetParallelStatus() != ngs.PARALLEL_STATUS.DISTRIBUTED:
            return
        if self.exchange is None:
            from .exchange import Exchange

            self.exchange = Exchange(getattr(self.A, "row_pardofs", None))
        self.exchange.cumulate(vec)

    def precondition(self, r: ngs.BaseVector, out: ngs.BaseVector) -> None:
        if hasattr(self.C, "apply"):
            self.C.apply(r, out)
            return
        out.SetParallelStatus(ngs.PARALLEL_STATUS.CUMULATED)  # NGSolve's inverses cumulate their output first
        out.data = self.C * r
        out.data *= self.sign


def pcg(op: Operator, rhs: ngs.BaseVector, x: ngs.BaseVector, project, tol: float = TOL,
        max_steps: int = MAX_STEPS) -> int:
    """`_pcg`, its time added to op.seconds."""
    t0 = time.perf_counter()
    try:
        return _pcg(op, rhs, x, project, tol, max_steps)
    finally:
        op.seconds += time.perf_counter() - t0


def _pcg(op: Operator, rhs: ngs.BaseVector, x: ngs.BaseVector, project, tol: float, max_steps: int) -> int:
    """Solve P K P x = P rhs for x in range(P), starting from P x; returns the CG steps.

    `project(v)` applies P to v in place (each rank its own entries: P must be the same
    on the entries two ranks share). Stops when the preconditioned residual norm is `tol`
    times the larger of its first value and the right-hand side's.
    """
    project(x)
    reached: dict = {}
    op.reached.append(reached)
    r, z, p, q = (x.CreateVector() for _ in range(4))
    _distributed(r, rhs)
    project(r)
    op.precondition(r, z)
    project(z)
    rz_rhs = abs(ngs.InnerProduct(r, z))
    op.apply(x, q)
    _distributed(r, rhs)
    r.data -= q
    project(r)
    op.precondition(r, z)
    project(z)
    p.data = z
    rz = ngs.InnerProduct(r, z)
    # relative to the larger of the first residual and the right-hand side: a warm start close to
    # the answer is not asked for a further reduction below round-off
    rz0 = max(abs(rz), rz_rhs)
    if abs(rz) <= tol * tol * rz0:
        reached.update((m, 0) for m in op.marks if abs(rz) <= m * m * rz0)
        return 0
    for step in range(1, max_steps + 1):
        op.apply(p, q)
        project(q)
        pq = ngs.InnerProduct(p, q)
        if pq <= 0.0:
            raise KrylovError(f"CG: the constrained system is not positive definite (p.Kp = {pq:.3e} at step {step})")
        alpha = rz / pq
        x.data += alpha * p
        r.data -= alpha * q
        op.precondition(r, z)
        project(z)
        rz_new = ngs.InnerProduct(r, z)
        for m in op.marks:
            if m not in reached and abs(rz_new) <= m * m * rz0:
                reached[m] = step
        if _DEBUG and step % 20 == 0:
            print(f"cg step {step}: {abs(rz_new) / rz0:.3e}", flush=True)
        if abs(rz_new) <= tol * tol * rz0:
            return step
        p.data *= rz_new / rz
        p.data += z
        rz = rz_new
    raise KrylovError(f"CG: no convergence to {tol:g} in {max_steps} steps (residual ratio {abs(rz) / rz0:.1e})")


def _distributed(r: ngs.BaseVector, rhs: ngs.BaseVector) -> None:
    """r = rhs, distributed: the residual stays distributed like K's products, so that no sum of a cumulated and a
    distributed vector makes NGSolve cumulate one through its own exchange (exchange.py; Distribute is local)."""
    r.data = rhs
    if r.GetParallelStatus() == ngs.PARALLEL_STATUS.CUMULATED:
        r.Distribute()


def held_rows(blocks, ndof: int):
    """Sparse rows over `ndof` dofs stacked from (rows, their columns' dofs) blocks."""
    parts = []
    for rows, dofs in blocks:
        M = sp.coo_matrix(rows)
        parts.append(sp.csr_matrix((M.data, (M.row, np.asarray(dofs, dtype=int)[M.col])), shape=(rows.shape[0], ndof)))
    return sp.vstack(parts).tocsr() if parts else sp.csr_matrix((0, ndof))


def hold(op: Operator, sets) -> None:
    """Tell the preconditioner the held values' rows (`sets.held()`) where it takes them into its local solves
    (collective)."""
    if hasattr(op.C, "hold") and hasattr(sets, "held"):
        op.C.hold(sets.held())


def condensed_rhs(disc, loads, free, prescribed=None):
    """(rhs, x): the sign-flipped right-hand side of the condensed system, with the prescribed values moved to it,
    and those values (zero on the unknowns `free`; collective: NGSolve's distributed vectors). `prescribed`: the
    prescribed values per local dof, made on rank 0's serial mesh (planar.py); None: interpolated here by NGSolve
    (GridFunction.Set, which sums through NGSolve's own exchange: exchange.py)."""
    import ngsolve as ngs

    fes, a, f = disc.fes, disc.a, disc.f
    fmod = f.vec.CreateVector()
    fmod.data = f.vec
    fmod.data += a.harmonic_extension_trans * fmod
    x = f.vec.CreateVector()
    x[:] = 0.0
    if loads.displacement:  # prescribed values: moved to the right-hand side
        if prescribed is not None:
            x.FV().NumPy()[:] = prescribed
        else:
            gD = ngs.GridFunction(fes)
            disc.boundary_values(gD, loads)
            x.data = gD.vec
        x.FV().NumPy()[free] = 0.0
    rhs = fmod.CreateVector()
    rhs.data = fmod - a.mat * x
    rhs.data *= disc.sign
    return rhs, x
