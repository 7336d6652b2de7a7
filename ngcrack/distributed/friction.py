"""Coulomb friction in the distributed solve: contact, stick and slip sets on each rank's crack edges.

The serial law (friction.py): at every constraint point i the normal value wn = Gn jn,
the tangential value wt = Gt jt (jt the tangential jump unknowns), the contact force
lam_n = dE/dwn and the friction force lam_t = -dE/dwt (E the quadratic energy of the
sign-flipped system K y = F), with

    wn >= 0, lam_n >= 0, wn lam_n = 0;   |lam_t| <= mu lam_n,
    wt = 0 where |lam_t| < mu lam_n,     lam_t = mu lam_n sign(wt) where wt != 0.

Distributed, each step holds the contact points' wn and the sticking points' wt at zero
(projections of the crack edges' unknowns, as for the frictionless crack) and puts the
slipping points' forces lam_t = tau s (tau = mu lam_n of the previous step, s the slip
direction) on the right-hand side: a symmetric positive definite constrained problem,
solved by CG with BDDC. The sets are then updated from the answer (a contact point leaves
where lam_n < 0, a gap point enters where wn < 0; a sticking point slips where
|lam_t| > tau, along lam_t; a slipping point sticks where wt runs against s) and tau
from lam_n: a fixed point on the Coulomb threshold combined with the active-set steps,
stopped when no rank changes a set and tau moved by less than COULOMB_RTOL of the largest
lam_n (the outer loop shared by every frictional solve: `core.coulomb.coulomb_loop`).
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from ..core.coulomb import CoulombStep, coulomb_loop
from .krylov import held_rows, hold, pcg

#: the fixed point on tau = mu lam_n stops when tau changes by less than this fraction of max lam_n
COULOMB_RTOL = 1e-12
#: steps (each one constrained linear solve) before the iteration is declared not converging
MAX_FRICTION_STEPS = 200


def _projector(M: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """I - M_r^T (M_r M_r^T)^(-1) M_r with M_r the `rows` of M: the projection onto M_r x = 0."""
    P = np.eye(M.shape[1])
    Mr = M[rows]
    if len(Mr):
        P -= Mr.T @ np.linalg.solve(Mr @ Mr.T, Mr)
    return P


class FrictionSets:
    """Contact, stick and slip at this rank's constraint points and the projection that holds them."""

    def __init__(self, G: np.ndarray, Gt: np.ndarray, mu: np.ndarray, jn_dofs: np.ndarray, jt_dofs: np.ndarray,
                 free: np.ndarray):
        self.G, self.Gt, self.mu, self.jn, self.jt, self.free = G, Gt, mu, jn_dofs, jt_dofs, free
        m = len(G)
        self.Ginv = np.linalg.inv(G) if m else G
        self.Gtinv = np.linalg.inv(Gt) if m else Gt
        self.contact = np.zeros(m, dtype=bool)
        self.stick = np.zeros(m, dtype=bool)
        self.sign = np.zeros(m)  # the slip direction of the slipping points (0: no friction force)
        self.tau = np.zeros(m)
        self.Pn, self.Pt = np.eye(m), np.eye(m)

    def set(self, contact, stick, sign, tau) -> None:
        self.contact, self.stick, self.sign, self.tau = contact.copy(), stick.copy(), sign.copy(), tau.copy()
        self.Pn = _projector(self.G, np.flatnonzero(contact))
        self.Pt = _projector(self.Gt, np.flatnonzero(stick))

    def project(self, vec: ngs.BaseVector) -> None:
        vals = vec.FV().NumPy()
        vals[~self.free] = 0.0
        if len(self.jn):
            vals[self.jn] = self.Pn @ vals[self.jn]
            vals[self.jt] = self.Pt @ vals[self.jt]

    def held(self):
        """The held values' rows over this rank's dofs: G's contact rows on jn, Gt's sticking rows on jt."""
        return held_rows([(self.G[self.contact], self.jn), (self.Gt[self.stick], self.jt)], len(self.free))

    def slip_forces(self) -> np.ndarray:
        """-Gt^T lam_t of the slipping points (lam_t = tau s): the tangential rows' right-hand side."""
        lam_t = np.where(self.stick, 0.0, self.tau * self.sign)
        return -(self.Gt.T @ lam_t)


def force_residual(op, x: ngs.BaseVector, rhs: ngs.BaseVector, out: ngs.BaseVector) -> None:
    """out = K x - F with `rhs` = F cumulated; `x` and `out` cumulated on return (by `op.cumulate`): the crack
    faces' forces on the crack rows, zero to the solve's tolerance elsewhere."""
    op.cumulate(x)
    op.apply(x, out)
    op.cumulate(out)
    out.data -= rhs  # both cumulated


def friction_loop(comm, op, rhs: ngs.BaseVector, x: ngs.BaseVector, sets: FrictionSets, sign_rtol: float):
    """The steps of the module docstring; returns (steps, CG steps per step). `rhs` is F (distributed), `x` the
    answer (cumulated on return)."""
    from mpi4py import MPI

    rhs_c = rhs.CreateVector()
    rhs_c.data = rhs
    op.cumulate(rhs_c)  # consistent values: the slip forces are added on every copy of a shared crack unknown
    load, residual = rhs_c.CreateVector(), rhs_c.CreateVector()
    cg_steps, pending = [], []

    def step(tau_used: np.ndarray) -> CoulombStep:
        """One constrained solve with the sets and threshold of the last step (held on entry), then the next."""
        if pending:  # the last step's sets, now that the loop goes on
            sets.set(*pending.pop())
            hold(op, sets)
        load.data = rhs_c
        if len(sets.jt):
            load.FV().NumPy()[sets.jt] += sets.slip_forces()
        cg_steps.append(pcg(op, load, x, sets.project))
        force_residual(op, x, rhs_c, residual)
        xv, rv = x.FV().NumPy(), residual.FV().NumPy()
        wn, wt = sets.G @ xv[sets.jn], sets.Gt @ xv[sets.jt]
        lam_n = sets.Ginv.T @ rv[sets.jn]
        lam_t = -(sets.Gtinv.T @ rv[sets.jt])
        w_max = comm.allreduce(float(max(np.max(np.abs(wn), initial=0.0), np.max(np.abs(wt), initial=0.0))),
                               op=MPI.MAX)
        lam_max = comm.allreduce(float(np.max(np.abs(lam_n), initial=0.0)), op=MPI.MAX)
        w_tol, lam_tol = sign_rtol * w_max, sign_rtol * lam_max
        contact = np.where(sets.contact, lam_n > -lam_tol, wn < -w_tol)
        tau = sets.mu * np.maximum(lam_n, 0.0) * contact
        rough = contact & (sets.mu > 0)
        stick = np.where(sets.stick, np.abs(lam_t) <= tau + lam_tol, sets.sign * wt < -w_tol) & rough
        # a slipping point keeps its direction; one that starts to slip takes its force's direction,
        # one that enters contact moving takes its motion's
        sign = np.where(sets.stick, np.sign(lam_t), np.where(sets.sign != 0, sets.sign, np.sign(wt)))
        sign = np.where(rough & ~stick, sign, 0.0)
        changed = comm.allreduce(int(np.count_nonzero((contact != sets.contact) | (stick != sets.stick)
                                                      | (sign != sets.sign))))
        pending.append((contact, stick, sign, tau))
        return CoulombStep(tau, max(lam_max, 1e-300), changed)

    run = coulomb_loop(step, sets.tau, max_steps=MAX_FRICTION_STEPS, bound_rtol=COULOMB_RTOL,
                       what="the crack problem with friction", unit="steps",
                       reduce_max=lambda v: comm.allreduce(v, op=MPI.MAX))
    return run.steps, cg_steps
