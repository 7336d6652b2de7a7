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

from ..contact import QPResult
from ..solution import Backend, Solution
from ..stages import CrackAnswer, Recovered, SolveError, faces_stage
from .gather import scatter_into
from .mesh import MATCH_RTOL


def solution_on_rank0(pipe, scene, o, cmesh, gathered, timings: dict, info: dict, t_start: float) -> Solution:
    t0 = time.perf_counter()
    disc, loads = pipe.discretization(scene, cmesh, o)
    system = pipe.system(disc, loads, False)
    normal_contact = system.contact
    if o.crack_model == "free":
        system = system.without_contact()
    full, flags = scatter_into(gathered, cmesh.mesh, disc.fes, MATCH_RTOL * scene.diameter)
    T = system._T
    norm = np.asarray(T.multiply(T).sum(axis=0)).ravel()
    y = (T.T @ full[system._free]) / np.where(norm > 0, norm, 1.0)
    if not np.all(np.isfinite(y)):
        raise SolveError("distributed solve: non-finite values in the gathered solution")
    timings["rank0_system"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    case = f"scene {scene.name!r}, element {o.element!r}"
    m = len(system.contact)
    G, qp = None, None
    if len(normal_contact):
        G = disc.constraint_map()
    gf = system.expand(y)
    if not np.all(np.isfinite(gf.vec.FV().NumPy())):
        raise SolveError(f"{case}: the local recovery gave non-finite values")
    rec = Recovered(y=y, gf=gf, fields=disc.fields(gf), time=0.0)
    jn = y[normal_contact] if len(normal_contact) else np.zeros(0)
    if m and o.crack_model == "contact":
        rng = disc.fes.Range(disc.jn)
        active = np.flatnonzero(flags[rng.start:rng.stop])
        positions = disc.constraint_positions()
        qp = QPResult(j=jn, w=G @ jn, multiplier=np.zeros(len(jn)), active=active, solver="distributed-pdas",
                      iterations=info["active_set_steps"], crack=positions[0], s=positions[1])
    answer = CrackAnswer(qp=qp, G=G, jn=jn, time=0.0)
    faces = faces_stage(system, disc, pipe.post, rec, answer, normal_contact, None, [c.pressure for c in scene.cracks], case)
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
                      tangential=False, friction=tuple(0.0 for _ in scene.cracks))
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
        forces=faces.forces, post=pipe.post,
    )
    pipe.post_process(sol, loads)
    pipe._pending = [weakref.ref(sol)]
    return sol
