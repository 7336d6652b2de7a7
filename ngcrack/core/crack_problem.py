"""The crack problem in the crack unknowns, posed once, and the strategies that solve it.

The problem (`ContactProblem`), in any dimension: the condensed system K y = F (K sparse,
symmetric positive definite, in the body's own unknowns), the crack unknowns `contact`
(the rows whose residual the crack faces carry), the constraint map G (w = G y_c >= 0 at
the constraint points: Signorini) and, with Coulomb friction, the friction coefficients
and the tangential blocks: either the 2D problem on the Schur complement of the normal
and tangential jumps (`friction.CrackProblem`, built by `friction_setup.crack_problem`)
or the slip rows B at the friction points of the crack faces
(`sparse_friction.FrictionPoints`). A `ContactReduction` (K_rr factorized, the dense S
and b on the crack unknowns: the pipeline's cached stage) may come with it.

The strategies (`STRATEGIES`), chosen by `choose_strategy` from the number of crack
unknowns and the ranks of the communicator, never from the dimension:

- "dense": the Schur complement S on the crack unknowns and the crack QP on it
  (`contact.solve_qp`: pdas, uzawa or a cvxpy solver); with friction the Coulomb problem
  on S (`friction.solve_crack_problem`, or the semismooth Newton method of
  `sparse_friction` reduced to the crack). Up to constraints.SCHUR_MAX_M crack unknowns (S has m^2
  entries: 288 MB at 6000).
- "sparse": the primal-dual active set on the factorized condensed system, one sparse
  factorization per active set, nothing of size m^2 (`sparse_contact`, `sparse_friction`
  method "sparse"): above constraints.SCHUR_MAX_M crack unknowns. The 2D problem with friction is
  posed on S and takes the dense strategy at every size.
- "krylov": the projected conjugate gradients over MPI ranks (`ngcrack.distributed`: each
  active-set step one constrained solve by BDDC-preconditioned CG): whenever the
  communicator has more than one rank. It runs inside the distributed solve, which
  owns the distributed operator; `solve` here refuses it by name.

Every strategy's answer is certified by the same functions (`constraints.discrete_contact_forces`
and `constraints.kkt_at_constraints`: the forces from the whole system's residual, the KKT
residuals relative to the largest jump and force), in the solve's stages.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from . import constraints
from .contact import QPResult, solve_qp, warm_start_data
from .errors import InputError
from .friction import CrackProblem, FrictionResult, solve_crack_problem

if TYPE_CHECKING:
    from .hybrid import ContactReduction
    from .sparse_friction import FrictionPoints

#: the strategies and what each solves with (module docstring)
STRATEGIES = {
    "dense": "the Schur complement on the crack unknowns and the crack QP on it (pdas, uzawa or a cvxpy solver)",
    "sparse": "the primal-dual active set on the factorized condensed system (one sparse factorization per step)",
    "krylov": "projected conjugate gradients over the MPI ranks, BDDC-preconditioned (ngcrack.distributed)",
}


def dense_max() -> int:
    """The most crack unknowns the dense strategy takes (`constraints.SCHUR_MAX_M`, read when asked)."""
    return constraints.SCHUR_MAX_M


def choose_strategy(m: int, ranks: int = 1, frictional_on_schur: bool = False) -> str:
    """The strategy for `m` crack unknowns on a communicator of `ranks` ranks: "krylov" over
    more than one rank, else "dense" up to `dense_max()` crack unknowns (and always for the
    2D problem with friction, `frictional_on_schur`, which is posed on S), else "sparse"."""
    if ranks > 1:
        return "krylov"
    return "dense" if frictional_on_schur or m <= dense_max() else "sparse"


@dataclass
class ContactProblem:
    """The crack problem (module docstring) as data: `K`, `F` the condensed system, `contact` the
    crack unknowns' rows (normal jumps first; with 2D friction the tangential ones after them), `G`
    the constraint map of the normal ones (None: the identity), `reduction` the dense reduction
    when one was formed, `coulomb` the 2D problem with friction on S, `points` the friction
    points of a 3D crack (their slip rows B and coefficients)."""

    K: object
    F: np.ndarray
    contact: np.ndarray
    G: object = None
    reduction: ContactReduction | None = None
    coulomb: CrackProblem | None = None
    points: FrictionPoints | None = None

    @property
    def m(self) -> int:
        """The number of crack unknowns (normal and, with friction, tangential: with friction points
        the unknowns their slip rows touch as well)."""
        if self.points is None:
            return len(self.contact)
        import scipy.sparse as sp

        return len(np.union1d(np.asarray(self.contact, dtype=int), np.unique(sp.csr_matrix(self.points.B).indices)))

    @property
    def frictional(self) -> bool:
        """Whether Coulomb friction acts on the crack faces."""
        return self.coulomb is not None or self.points is not None

    def strategy(self, ranks: int = 1) -> str:
        """`choose_strategy` for this problem."""
        return choose_strategy(self.m, ranks, frictional_on_schur=self.coulomb is not None)


@dataclass(frozen=True)
class SolverChoice:
    """How the strategy's inner solves run: the QP's solver and its options, the Coulomb method,
    the sparse factorization's backend, a warm start (an earlier Solution or an active set)."""

    qp_solver: str = "pdas"
    qp_options: dict | None = None
    friction_method: str = "fixed-point"
    linear_solver: str = "auto"
    warm_start: object = None


def solve(problem: ContactProblem, strategy: str | None = None, choice: SolverChoice | None = None,
          positions: tuple[np.ndarray, np.ndarray] | None = None):
    """Solve `problem` by `strategy` (None: `problem.strategy()`): a QPResult or friction.FrictionResult
    where the dense strategy works on a given reduction (the answer is the crack unknowns; the stages
    recover the rest), else a sparse_contact.ContactResult or sparse_friction.FrictionResult holding
    every condensed unknown y. `positions`: (crack, s) of the constraint points, for warm starts
    and for the QP's record."""
    strategy = strategy or problem.strategy()
    if strategy not in STRATEGIES:
        raise InputError(f"strategy = {strategy!r}: allowed values are {', '.join(STRATEGIES)}")
    if strategy == "krylov":
        raise InputError("strategy = 'krylov': the projected Krylov strategy runs over MPI ranks "
                         "(mpiexec -n N, N > 1: ngcrack.distributed)")
    c = choice or SolverChoice()
    if strategy == "dense" and problem.reduction is not None:
        return _dense_on_reduction(problem, c, positions)
    if problem.coulomb is not None:
        raise InputError("strategy = 'sparse': the 2D problem with friction is posed on the Schur complement "
                         "(strategy 'dense')")
    method = "schur" if strategy == "dense" else "sparse"
    K = problem.K.to_scipy() if hasattr(problem.K, "to_scipy") else problem.K  # a csr.CSR (the 2D system) as scipy's
    if problem.points is not None:
        from .sparse_friction import solve_friction

        return solve_friction(K, problem.F, problem.contact, problem.G, problem.points,
                              linear_solver=c.linear_solver, method=method)
    from .sparse_contact import solve_contact  # (scipy.sparse: loaded by the sparse strategies only)

    return solve_contact(K, problem.F, problem.contact, problem.G, linear_solver=c.linear_solver,
                                        method=method, qp_solver=c.qp_solver, qp_options=c.qp_options)


def _dense_on_reduction(problem: ContactProblem, c: SolverChoice, positions) -> QPResult | FrictionResult:
    """The dense strategy on the pipeline's reduction: the Coulomb problem on S, or the crack QP (warm-started)."""
    red = problem.reduction
    if problem.coulomb is not None:
        return solve_crack_problem(problem.coulomb, solver=c.qp_solver, solver_options=c.qp_options, method=c.friction_method)
    import dataclasses

    crack, s = positions if positions is not None else (np.zeros(0, dtype=int), np.zeros(0))
    initial_active, initial_guess = warm_start_data(c.warm_start, crack, s) if positions is not None else (None, None)
    qp = solve_qp(red.S, red.b, G=problem.G, solver=c.qp_solver, solver_options=c.qp_options,
                  initial_active=initial_active, initial_guess=initial_guess)
    return dataclasses.replace(qp, crack=crack, s=s) if positions is not None else qp


def crack_unknowns(result, contact: np.ndarray) -> np.ndarray:
    """The crack unknowns of any strategy's answer: j (z with friction) of the dense one on a
    reduction, y at `contact` of one that solved every condensed unknown."""
    if isinstance(result, FrictionResult):
        return result.z
    if isinstance(result, QPResult):
        return result.j
    return np.asarray(result.y)[np.asarray(contact, dtype=int)]

