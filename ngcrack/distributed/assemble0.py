"""Rank 0's part after the distributed solve: the gathered unknowns into the serial system,
the element-local unknowns recovered, the serial post-processing, one Solution.

Rank 0 assembles the serial forms on its mesh (no factorization) so that the profiles,
the KKT residuals (the definitions of `constraints.py`, at the same constraint points),
the tips' K_I, K_II, G and the error estimate are those of the serial code, computed
from the distributed answer. This stage does not scale with the ranks (BENCHMARKS).
"""

from __future__ import annotations

import time
import weakref

import numpy as np

from ..core.contact import QPResult
from ..core.friction import FrictionResult, coulomb_residual
from ..core.solution import Backend
from ..core.stages import CrackAnswer, Recovered, SolveError, faces_stage
from ..planar.solution import PlanarSolution as Solution
from .gather import scatter_into
from .mesh import MATCH_RTOL


def solution_on_rank0(pipe, scene, o, cmesh, gathered, timings: dict, info: dict, t_start: float,
                      slips=None) -> Solution:
    """The Solution from the gathered unknowns; `slips` (gathered slip directions per constraint point) with
    friction."""
    t0 = time.perf_counter()
    disc, loads = pipe.discretization(scene, cmesh, o)
    tangential = slips is not None
    mu = [float(c.friction) for c in scene.cracks]
    system = pipe.system(disc, loads, tangential)
    normal_contact = system.contact if system.n_normal is None else system.contact[:system.n_normal]
    if o.crack_model == "free":
        system = system.without_contact()
    full, flags = scatter_into(gathered, cmesh.mesh, disc.fes, MATCH_RTOL * scene.diameter)
    y = reduced_unknowns(system, full)
    timings["rank0_system"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    case = f"scene {scene.name!r}, element {o.element!r}"
    m = len(system.contact)
    G, qp = None, None
    if len(normal_contact):
        G = disc.constraint_map()
    jn = y[normal_contact] if len(normal_contact) else np.zeros(0)
    if m and o.crack_model == "contact":
        rng = disc.fes.Range(disc.jn)
        active = np.flatnonzero(flags[rng.start:rng.stop])
        positions = disc.constraint_positions()
        if tangential:
            codes, _ = scatter_into(slips, cmesh.mesh, disc.fes, MATCH_RTOL * scene.diameter)
            qp = friction_result(system, disc, cmesh, y, G, active, np.sign(codes[rng.start:rng.stop]), mu,
                                 positions, info["active_set_steps"])
            y[system.contact] = qp.z  # the held values exactly zero, as in the serial answer
            jn = qp.j
        else:
            qp = QPResult(j=jn, w=G @ jn, multiplier=np.zeros(len(jn)), active=active, solver="distributed-pdas",
                          iterations=info["active_set_steps"], crack=positions[0], s=positions[1])
    gf = system.expand(y)
    if not np.all(np.isfinite(gf.vec.FV().NumPy())):
        raise SolveError(f"{case}: the local recovery gave non-finite values")
    rec = Recovered(y=y, gf=gf, fields=disc.fields(gf), time=0.0)
    answer = CrackAnswer(qp=qp, G=G, jn=jn, time=0.0)
    faces = faces_stage(system, disc, scene.body.post, rec, answer, normal_contact, mu if tangential else None,
                        [c.pressure for c in scene.cracks], case)
    if qp is not None and faces.forces is not None:
        qp.multiplier = np.asarray(faces.forces)
        qp.kkt = dict(faces.kkt)
    timings["rank0_post"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_start
    # the serial solve's keys: the distributed linear solves and active-set steps are "solve"
    timings.update(factorize=0.0, schur=0.0, qp=0.0, recover=timings["rank0_post"])
    timings["linear"] = timings["solve"] + timings["recover"]
    timings["contact"] = 0.0
    linear = "bddc-cg" if info["preconditioner"].startswith("bddc") else "direct-cg"
    backend = Backend(qp_solver="distributed-pdas", linear_solver=linear, schur="none", largest_dense=0,
                      tangential=tangential,
                      friction=tuple(f if o.crack_model == "contact" and tangential else 0.0 for f in mu))
    report = backend.report(o)
    report["distributed"] = info
    sol = Solution(
        scene=scene, element=o.element, crack_mesh=cmesh, disc=disc, gf=rec.gf, fields=rec.fields,
        profiles=faces.profiles, kkt=faces.kkt, qp=qp, timings=timings,
        ndof={"total": disc.fes.ndof, "global": system.n, "contact": m},
        built=list(disc.built) + [f"distributed over {info['ranks']} ranks ({info['subdomains']} subdomains): CG, "
                                  f"preconditioner {info['preconditioner']}, {info['active_set_steps']} active-set "
                                  f"steps, CG steps {info['cg_steps']}"],
        options=report, solve_options=o, backend=backend, conditioning={}, kkt_sampled=faces.kkt_sampled,
        forces=faces.forces, post=scene.body.post,
    )
    pipe.post_process(sol, loads)
    pipe._pending = [weakref.ref(sol)]
    return sol


def friction_result(system, disc, cmesh, y: np.ndarray, G: np.ndarray, active: np.ndarray, slip: np.ndarray,
                    mu: list[float], positions, steps: int) -> FrictionResult:
    """The serial solve's FrictionResult from the distributed answer: values at the constraint points (those
    held by the last step exactly zero, and the crack unknowns `z` from them), the forces from the serial
    system's residual (lam_n = G^-T r_n, lam_t = -Gt^-T r_t), the Coulomb residuals."""
    nn = system.n_normal
    cols = np.asarray(system.tangential_dofs, dtype=int)
    sub = disc.tangential_point_map(cmesh, G)[:, cols]
    rows = np.flatnonzero(np.any(sub != 0.0, axis=1))
    Gt = sub[rows]
    r = system.K @ y - system.F
    jn, jt = y[system.contact[:nn]], y[system.contact[nn:]]
    lam_n = np.linalg.solve(G.T, r[system.contact[:nn]])
    lam_t = -np.linalg.solve(Gt.T, r[system.contact[nn:]])
    w, wt = G @ jn, Gt @ jt
    # as the serial answer (friction._result): no contact force off the contact set (there the residual holds the
    # Krylov solve's round-off only, and its largest value would set the force scale of the residuals)
    held = np.zeros(len(lam_n), dtype=bool)
    held[active] = True
    lam_n = np.where(held, lam_n, 0.0)
    # the values the last step held at zero are zero (their round-off would read as open or moving faces)
    w[active] = 0.0
    wt[(slip[rows] == 0) & np.isin(rows, active)] = 0.0
    mu_pt = np.asarray(mu, dtype=float)[np.maximum(positions[0], 0)][rows]
    kkt = coulomb_residual(w, lam_n, wt, lam_t, rows, mu_pt * lam_n[rows])
    jn, jt = np.linalg.solve(G, w), np.linalg.solve(Gt, wt)  # the unknowns of the zeroed values
    return FrictionResult(
        j=jn, w=w, multiplier=lam_n, active=active, solver="distributed-pdas", iterations=steps, kkt=kkt,
        crack=positions[0], s=positions[1], z=np.concatenate([jn, jt]), jt=jt, wt=wt, lam_t=lam_t,
        slip=slip[rows].astype(int), t_point=rows, mu=mu_pt, coulomb_iterations=steps, steps=steps,
        method="distributed fixed point")


def reduced_unknowns(system, full):
    """The condensed system's unknowns y of the gathered values `full` of the whole space (T y = full on the free
    unknowns, T's columns orthogonal: each unknown read from its own rows); refused if not finite."""
    T = system._T
    norm = np.asarray(T.multiply(T).sum(axis=0)).ravel()
    y = (T.T @ full[system._free]) / np.where(norm > 0, norm, 1.0)
    if not np.all(np.isfinite(y)):
        raise SolveError("distributed solve: non-finite values in the gathered solution")
    return y
