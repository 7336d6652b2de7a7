"""The stages of a solve after the reduction, each a function with a typed result.

    crack problem (`crack_stage` -> CrackAnswer, `sparse_contact_stage` -> SparseAnswer): the
        crack problem posed once (`crack_problem.ContactProblem`) and solved by the strategy
        its size and the communicator choose (`crack_problem.choose_strategy`); jn = 0
        without contact
    recovery (`recovery_stage` -> Recovered): every unknown from jn, the fields
    crack faces (`faces_stage` -> CrackFaces): the crack profiles, the KKT residuals at the
        constraint points and at the profiles' samples, the consistent tractions
    tips and estimate (`tips_stage`, `estimate_stage`): on the Solution

`ngcrack.core.pipeline.Pipeline.run` calls them in this order. Every stage is dimension-free:
it sees the element through its `Discretization` and what depends on the body's
dimension after the recovery (the crack profiles and their tractions, the tips, the
estimate) through the post-processor the pipeline chose once (`PostProcessing`; the 2D
one is `ngcrack.planar.post2d.PLANE`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import ngsolve as ngs
import numpy as np

from . import crack_problem as problems
from .constraints import discrete_contact_forces, kkt_at_constraints
from .contact import QPResult
from .discretization import Discretization, Loads, PostProcessing
from .errors import InputError
from .friction import FrictionResult
from .friction_setup import crack_problem
from .hybrid import CondensedSystem, ContactReduction
from .options import SolveOptions
from .solution import Solution

if TYPE_CHECKING:
    from ..planar.geometry import CrackMesh
    from ..planar.post import CrackProfile


class SolveError(RuntimeError):
    """A solve produced something unusable (a singular system, non-finite numbers)."""


@dataclass(frozen=True)
class CrackAnswer:
    """The crack problem's answer: `qp` (a QPResult, a FrictionResult, or None without
    contact), `G` the constraint map (None without a crack), `jn` the crack unknowns."""

    qp: QPResult | FrictionResult | None
    G: np.ndarray | None
    jn: np.ndarray
    time: float


@dataclass(frozen=True)
class Recovered:
    """Every unknown from the crack unknowns: the global vector `y`, the GridFunction, the fields."""

    y: np.ndarray
    gf: ngs.GridFunction
    fields: dict
    time: float


@dataclass(frozen=True)
class CrackFaces:
    """The crack faces: one CrackProfile per crack (with its consistent tractions), the KKT
    residuals at the constraint points (`kkt`) and at the profiles' samples
    (`kkt_sampled`), the discrete contact forces (None without a crack)."""

    profiles: list[CrackProfile]
    kkt: dict
    kkt_sampled: dict
    forces: np.ndarray | None


def crack_stage(red: ContactReduction, disc: Discretization, cmesh: CrackMesh, contact: np.ndarray,
                options: SolveOptions, tangential: bool, friction: list[float], warm_start=None) -> CrackAnswer:
    """The crack problem on the reduction (`crack_problem.ContactProblem`), solved by its strategy: the
    dense QP (warm-started) or, with `tangential`, the problem with Coulomb friction on S; above the
    dense strategy's size the sparse active set (its answer recorded as a QPResult). A bonded or
    free crack (or none) gives jn = 0."""
    t0 = time.perf_counter()
    o, m = options, len(red.system.contact)
    qp, G = None, None
    if len(contact):
        G = disc.constraint_map()
    if m and o.crack_model == "contact":
        system = red.system
        problem = problems.ContactProblem(K=system.K_csr, F=system.F, contact=system.contact, G=G, reduction=red,
                                          coulomb=crack_problem(red, disc, cmesh, G, friction) if tangential else None)
        choice = problems.SolverChoice(qp_solver=o.qp_solver, qp_options=o.qp_options, friction_method=o.friction_method,
                                       linear_solver=o.linear_solver, warm_start=warm_start)
        positions = None if tangential else disc.constraint_positions()
        strategy = problem.strategy()
        if strategy == "sparse":
            qp = _as_qp(problems.solve(problem, strategy, choice), system.contact, positions)
        else:
            qp = problems.solve(problem, strategy, choice, positions)
        jn = problems.crack_unknowns(qp, system.contact)
    else:  # no crack, or a bonded crack: jn = 0
        jn = np.zeros(m)
    return CrackAnswer(qp=qp, G=G, jn=jn, time=time.perf_counter() - t0)


def _as_qp(result, contact: np.ndarray, positions) -> QPResult:
    """The sparse strategy's answer on a reduction's system as the QP's record: j = y at the crack
    unknowns, w = G j, the forces read from the residual, its KKT residuals."""
    return QPResult(j=np.asarray(result.y)[contact], w=np.asarray(result.w), multiplier=np.asarray(result.lam),
                    active=np.flatnonzero(result.active), solver="sparse active set", iterations=result.iterations,
                    kkt=dict(result.kkt), time_s=float(result.timings.get("total", 0.0)), crack=positions[0], s=positions[1])


def recovery_stage(red: ContactReduction, system: CondensedSystem, disc: Discretization, jn: np.ndarray,
                   case: str) -> Recovered:
    """y from jn through the kept factorization, the local unknowns by static condensation, the fields."""
    t0 = time.perf_counter()
    y = red.recover(jn)
    if not np.all(np.isfinite(y)):
        raise SolveError(f"{case}: the condensed solve gave non-finite values (singular system)")
    gf = system.expand(y)
    elapsed = time.perf_counter() - t0
    if not np.all(np.isfinite(gf.vec.FV().NumPy())):
        raise SolveError(f"{case}: the local recovery gave non-finite values")
    return Recovered(y=y, gf=gf, fields=disc.fields(gf), time=elapsed)


def faces_stage(system: CondensedSystem, disc: Discretization, post: PostProcessing, rec: Recovered,
                answer: CrackAnswer, normal_contact: np.ndarray, friction: list[float] | None, pressures: list,
                case: str) -> CrackFaces:
    """The crack profiles, the KKT residuals (constraint points and samples) and the tractions."""
    profiles = post.profiles(disc, rec.gf, rec.fields, friction, pressures)
    u_scale, sigma_scale, jump, length = post.scales(disc, rec.fields, profiles)
    kkt, forces = constraint_kkt(system, rec.y, normal_contact, answer.G, jump, length, u_scale, sigma_scale)
    profiles = post.with_tractions(profiles, disc, system, rec.y, answer.G, forces)
    kkt_sampled = post.sampled_kkt(profiles, u_scale, sigma_scale)
    # the discrete Coulomb law at the QP's constraint points (0 without friction)
    kkt["friction"] = float(answer.qp.kkt["friction"]) if isinstance(answer.qp, FrictionResult) else 0.0
    sampled = [getattr(p, k) for p in profiles for k in p.__dataclass_fields__ if k != "state"] + [
        np.array(list(kkt.values()) + list(kkt_sampled.values()))]
    if not all(np.all(np.isfinite(a)) for a in sampled):
        raise SolveError(f"{case}: the crack profiles or KKT residuals hold non-finite values")
    return CrackFaces(profiles=profiles, kkt=kkt, kkt_sampled=kkt_sampled, forces=forces)


def tips_stage(sol: Solution, loads: Loads, post: PostProcessing) -> None:
    """The fracture parameters of a solved `sol` (sol.tips; its time in sol.timings)."""
    t0 = time.perf_counter()
    sol.tips = post.tips(sol, loads.body_force)
    sol.timings["tips"] = time.perf_counter() - t0
    sol.timings["total"] += sol.timings["tips"]


# ------------------------------------------------------------------ the pieces of the stages

def condition_estimates(red: ContactReduction) -> dict:
    """1-norm condition estimates of D K_rr D and of D_S S D_S (Hager/Higham).

    D = diag(K_rr)^(-1/2) (1 on a zero diagonal): the Jacobi-scaled matrices, whose
    condition does not depend on the units of the unknowns (PEERS mixes rotations and
    displacements) and is what the factorization and the QP (scaled the same way) see.
    Keys "K" and "S" (S only with a crack). The inverse goes through the factorization.
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    sysm = red.system
    K_rr = sysm.K_csr[sysm.rest][:, sysm.rest].to_scipy()
    n = K_rr.shape[0]
    diag = np.abs(K_rr.diagonal())
    d = np.where(diag > 0, 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0)), 1.0)
    scaled = sp.diags(d) @ K_rr @ sp.diags(d)

    def solve_scaled(b):
        b = np.asarray(b, dtype=float)
        dd = d if b.ndim == 1 else d[:, None]
        return red.factorization.solve(b / dd) / dd

    inv = spla.LinearOperator((n, n), matvec=solve_scaled, rmatvec=solve_scaled, matmat=solve_scaled, dtype=float)
    out = {"K": float(spla.onenormest(scaled) * spla.onenormest(inv))}
    if red.S.size:
        ds = 1.0 / np.sqrt(np.abs(np.diag(red.S)))
        out["S"] = float(np.linalg.cond(ds[:, None] * red.S * ds[None, :], 1))
    return out


def constraint_kkt(system: CondensedSystem, y: np.ndarray, contact: np.ndarray, G, sampled_jump: float,
                   length: float, u_scale: float, sigma_scale: float) -> tuple[dict, np.ndarray | None]:
    """(kkt, forces) at the QP's constraint points: w = G j from the answer, the forces from its residual.

    W = the largest jump on the crack (|w| at the constraint points, `sampled_jump` at the
    post-processor's samples); the body scales are max |u| and max |sigma| times `length`
    (the mean crack edge length).
    """
    if G is None or not len(contact):
        return kkt_at_constraints(np.zeros(0), np.zeros(0), 0.0), None
    w = G @ y[contact]
    forces, bound = discrete_contact_forces(system.K_csr, system.F, y, contact, G)
    jump_max = max(float(np.max(np.abs(w))), sampled_jump)
    kkt = kkt_at_constraints(w, forces, jump_max, jump_scale=u_scale, force_scale=sigma_scale * length, lam_bound=bound)
    return kkt, forces


@dataclass(frozen=True)
class SparseAnswer:
    """The sparse contact stage's answer: every condensed unknown `y`, the contact solver's
    `result` (None for a free crack or none), the constraint map `G` (None without a crack),
    and the seconds of the plain linear solve or of the contact solve."""

    y: np.ndarray
    result: object
    G: object
    time_linear: float
    time_contact: float


def sparse_contact_stage(system: CondensedSystem, disc: Discretization, crack_model: str,
                         linear_solver: str, qp_solver: str = "pdas", points=None) -> SparseAnswer:
    """The crack problem on the sparse condensed system (`crack_problem.ContactProblem`, no reduction
    formed before it), solved by the strategy its size chooses: "dense" (one partial factorization,
    the crack QP on the dense Schur complement) or "sparse" (`sparse_contact`: one sparse
    factorization per active set); with `points` (friction points) the problem with Coulomb
    friction (`sparse_friction`). A free crack or none: one linear solve."""
    from .schur import Factorization

    G = disc.constraint_map() if disc.has_crack else None
    t0 = time.perf_counter()
    if not disc.has_crack or crack_model == "free":
        y = Factorization(system.K, linear_solver).solve(system.F)
        return SparseAnswer(y=y, result=None, G=G, time_linear=time.perf_counter() - t0, time_contact=0.0)
    problem = problems.ContactProblem(K=system.K, F=system.F, contact=system.contact, G=G, points=points)
    result = problems.solve(problem, choice=problems.SolverChoice(qp_solver=qp_solver, linear_solver=linear_solver))
    return SparseAnswer(y=result.y, result=result, G=G, time_linear=0.0, time_contact=time.perf_counter() - t0)


def built_line(qp, m: int, o: SolveOptions, disc: Discretization) -> str:
    """What the crack stage did, for `sol.built`."""
    if isinstance(qp, FrictionResult):
        return (f"crack problem with friction: {len(qp.w)} normal and {len(qp.wt)} tangential values, solver "
                f"{o.qp_solver}, {qp.method}: {qp.coulomb_iterations} iterations, {qp.steps} active-set steps")
    if qp is not None:
        return f"contact QP: {m} unknowns, solver {o.qp_solver}"
    if disc.jn is None:
        return "no crack: one linear solve, no QP"
    return f"crack model {o.crack_model!r}: one linear solve, no QP"


def estimate_stage(sol: Solution, loads: Loads, crack_model: str, post: PostProcessing):
    """The solve's error estimate, or None where none exists (with the reason in sol.no_estimate)."""
    try:
        est = post.estimate(sol, loads, crack_model)
    except InputError as exc:
        sol.no_estimate = str(exc)
        return None
    sol.timings["estimate"] = est.time
    return est
