"""The stages of a solve after the reduction, each a function with a typed result.

    crack problem (`crack_stage` -> CrackAnswer): the QP, or the problem with Coulomb
        friction, on the crack unknowns; jn = 0 without contact
    recovery (`recovery_stage` -> Recovered): every unknown from jn, the fields
    crack faces (`faces_stage` -> CrackFaces): the crack profiles, the KKT residuals at the
        constraint points and at the profiles' samples, the consistent tractions
    tips and estimate (`tips_stage`, `estimate_stage`): on the Solution

`ngcrack.pipeline.Pipeline.run` calls them in this order. The crack problem and the
recovery are dimension-free (they see the element through `ngcrack.discretization`); the
crack faces, the tips and the estimate still call the 2D post-processing by name
(ngcrack.post, ngcrack.tips, ngcrack.estimate): the edges tests/test_layers.py lists in
KNOWN_2D_IMPORTS, to be reached through the element and the mesh when a 3D body comes.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import ngsolve as ngs
import numpy as np

from .constraints import discrete_contact_forces, kkt_at_constraints
from .contact import QPResult, constraint_positions, solve_qp, warm_start_data
from .discretization import Discretization, Loads
from .errors import InputError
from .friction import FrictionResult, solve_crack_problem
from .friction_setup import crack_problem
from .hybrid import CondensedSystem, ContactReduction
from .options import SolveOptions
from .post import (
    CrackProfile,
    component_forces,
    consistent_tractions,
    crack_profile,
    endpoint_map,
    field_scales,
    kkt_residuals,
    lumped_traction,
    tributary_lengths,
)
from .scene.pressure import pressure_values
from .solution import Solution
from .tips import tip_parameters

if TYPE_CHECKING:
    from .geometry import CrackMesh


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
    """The crack problem on the reduction: the QP (warm-started), or with `tangential` the
    problem with Coulomb friction; a bonded or free crack (or none) gives jn = 0."""
    t0 = time.perf_counter()
    o, m = options, len(red.system.contact)
    qp, G = None, None
    if len(contact):
        G = disc.constraint_map() if disc.constraint_map is not None else endpoint_map(
            disc.fes.components[disc.jn], cmesh, disc.facet_order)
    if m and o.crack_model == "contact":
        if tangential:
            qp = solve_crack_problem(crack_problem(red, disc, cmesh, G, friction), solver=o.qp_solver,
                                     solver_options=o.qp_options, method=o.friction_method)
            jn = qp.z
        else:
            positions = constraint_positions(disc, cmesh)
            initial_active, initial_guess = warm_start_data(warm_start, *positions)
            qp = dataclasses.replace(
                solve_qp(red.S, red.b, G=G, solver=o.qp_solver, solver_options=o.qp_options,
                         initial_active=initial_active, initial_guess=initial_guess),
                crack=positions[0], s=positions[1])
            jn = qp.j
    else:  # no crack, or a bonded crack: jn = 0
        jn = np.zeros(m)
    return CrackAnswer(qp=qp, G=G, jn=jn, time=time.perf_counter() - t0)


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


def faces_stage(system: CondensedSystem, disc: Discretization, cmesh: CrackMesh, rec: Recovered,
                answer: CrackAnswer, normal_contact: np.ndarray, friction: list[float] | None, pressures: list,
                case: str) -> CrackFaces:
    """The crack profiles, the KKT residuals (constraint points and samples) and the tractions."""
    profiles = crack_profiles(disc, cmesh, rec.gf, rec.fields, friction, pressures)
    scales = field_scales(cmesh, rec.fields["u"], rec.fields["sigma"]) if profiles else (0.0, 0.0)
    kkt, forces = constraint_kkt(system, rec.y, normal_contact, answer.G, cmesh, profiles, *scales)
    profiles = with_tractions(profiles, disc, system, rec.y, cmesh, answer.G, forces)
    kkt_sampled = kkt_residuals(profiles, *scales)
    # the discrete Coulomb law at the QP's constraint points (0 without friction)
    kkt["friction"] = float(answer.qp.kkt["friction"]) if isinstance(answer.qp, FrictionResult) else 0.0
    sampled = [getattr(p, k) for p in profiles for k in p.__dataclass_fields__ if k != "state"] + [
        np.array(list(kkt.values()) + list(kkt_sampled.values()))]
    if not all(np.all(np.isfinite(a)) for a in sampled):
        raise SolveError(f"{case}: the crack profiles or KKT residuals hold non-finite values")
    return CrackFaces(profiles=profiles, kkt=kkt, kkt_sampled=kkt_sampled, forces=forces)


def tips_stage(sol: Solution, loads: Loads) -> None:
    """K_I, K_II, G at the tips of a solved `sol` (sol.tips; its time in sol.timings)."""
    t0 = time.perf_counter()
    sol.tips = tip_parameters(sol, body_force=loads.body_force)
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
    K_rr = sysm.K[sysm.rest][:, sysm.rest]
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


def constraint_kkt(system: CondensedSystem, y: np.ndarray, contact: np.ndarray, G, cmesh: CrackMesh,
                   profiles: list[CrackProfile], u_scale: float, sigma_scale: float) -> tuple[dict, np.ndarray | None]:
    """(kkt, forces) at the QP's constraint points: w = G j from the answer, the forces from its residual.

    W = the largest jump on the crack (|w| at the constraint points, |[u]| at the edge mid
    points); the body scales are max |u| and max |sigma| times the mean crack edge length.
    """
    if G is None or not len(contact):
        return kkt_at_constraints(np.zeros(0), np.zeros(0), 0.0), None
    w = G @ y[contact]
    forces, bound = discrete_contact_forces(system.K, system.F, y, contact, G)
    jump_max = max([float(np.max(np.abs(w)))] + [float(np.max(np.hypot(p.normal_jump, p.tangential_jump)))
                                                   for p in profiles])
    edge = float(np.mean(np.concatenate([c.length for c in cmesh.cracks])))
    kkt = kkt_at_constraints(w, forces, jump_max, jump_scale=u_scale, force_scale=sigma_scale * edge, lam_bound=bound)
    return kkt, forces


def crack_profiles(disc: Discretization, cmesh: CrackMesh, gf: ngs.GridFunction, fields: dict,
                   friction: list[float] | None, pressures: list | None = None) -> list[CrackProfile]:
    """One CrackProfile per crack from the solved GridFunction (no crack: an empty list);
    `pressures`: each crack's face pressure (scene.pressure fields), kept in the profiles."""
    if disc.jn is None:
        return []
    comps = gf.components
    jn_vals = comps[disc.jn].vec.FV().NumPy()
    jt_vals = comps[disc.jt].vec.FV().NumPy() if disc.jt is not None else None
    displacement = disc.tangential_jump(gf) if disc.tangential_jump is not None else None
    jump_space = disc.fes.components[disc.jn]
    profiles = []
    for k, crack in enumerate(cmesh.cracks):
        jumps = disc.crack_jumps(gf, crack) if disc.crack_jumps is not None else None
        prof = crack_profile(cmesh, crack, jump_space, jn_vals, jt_vals, fields["sigma"],
                             displacement=displacement, jumps=jumps, two_sided=disc.two_sided_traction,
                             friction=friction[k] if friction is not None else 0.0)
        if pressures is not None and pressures[k] is not None:
            prof = dataclasses.replace(prof, face_pressure=pressure_values(pressures[k], prof.s))
        profiles.append(prof)
    return profiles


def with_tractions(profiles: list[CrackProfile], disc: Discretization, system: CondensedSystem, y: np.ndarray,
                   cmesh: CrackMesh, G, forces) -> list[CrackProfile]:
    """The profiles with the element's consistent (or, for the baselines, lumped nodal) crack tractions."""
    if not profiles or not any(c is not None for c in disc.traction_rows):
        return profiles
    lumped = disc.traction_rows[0] is not None and forces is not None  # nodal contact forces
    tractions = consistent_tractions(system, y, cmesh, skip=("normal_stress", "shear_stress") if lumped else ())
    if lumped:
        space = disc.fes.components[disc.jn]
        w = tributary_lengths(space, cmesh, G)
        normal = lumped_traction(space, cmesh, G, forces, w)
        # the nodal forces are the contact's; the faces carry the crack-face pressure besides
        normal = [nv - p.face_pressure for nv, p in zip(normal, profiles)]
        shear = lumped_traction(space, cmesh, G, component_forces(system, y, disc.traction_rows[1], G), w)
        tractions = [dict(t, normal_stress=n, shear_stress=q) for t, n, q in zip(tractions, normal, shear)]
    return [dataclasses.replace(p, **t) for p, t in zip(profiles, tractions)]


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


def estimate_stage(sol: Solution, loads: Loads, crack_model: str):
    """The solve's error estimate (estimate.py), or None where none exists (with the reason
    in sol.no_estimate)."""
    from .estimate import estimate

    try:
        est = estimate(sol, loads, crack_model)
    except InputError as exc:
        sol.no_estimate = str(exc)
        return None
    sol.timings["estimate"] = est.time
    return est
