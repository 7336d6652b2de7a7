"""Rank 0's part after a distributed 3D solve: the gathered unknowns into the serial system,
the contact forces and KKT residuals from the serial system's residual, the serial
post-processing, one SolidSolution.

Rank 0 assembles the serial forms on its mesh (no factorization) so that the fronts' K_I,
K_II, K_III, G, the crack summaries, the KKT certificate and the error estimate are those
of the serial code (`solid.stages.run_solid`), computed from the distributed answer. This
stage does not scale with the ranks (BENCHMARKS section 18).
"""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..core.sparse_contact import ContactResult
from ..core.sparse_contact import certificate as contact_certificate
from ..core.sparse_friction import certificate
from ..core.stages import SolveError
from ..solid.output import SolidSolution
from .assemble0 import reduced_unknowns
from .mesh import MATCH_RTOL
from .solid_mesh import scatter_into


def _rows_of_dofs(smesh, disc) -> np.ndarray:
    """Per dof of the jn component: its constraint point (the row of `constraint_map`), face by face."""
    import ngsolve as ngs

    space = disc.fes.components[disc.jn]
    per = None
    row_of = np.full(space.ndof, -1, dtype=int)
    row = 0
    for c in smesh.cracks:
        for f in c.faces:
            dofs = list(space.GetDofNrs(ngs.NodeId(ngs.FACE, int(f))))
            per = len(dofs)
            row_of[dofs] = row + np.arange(per)
            row += per
    return row_of


def solution_on_rank0(pipe, scene, opts: dict, smesh, gathered, timings: dict, info: dict,
                      t_start: float, friction=None) -> SolidSolution:
    """The SolidSolution from the gathered unknowns (module docstring); `friction`: (the serial FrictionPoints,
    the last `solid_friction.PointState`) of a frictional solve, certified as the serial one
    (`core.sparse_friction.certificate`)."""
    from ..solid.stages import SIZES, post_process

    t0 = time.perf_counter()
    disc, loads = pipe.discretization(scene, smesh, opts)
    system = pipe.system(disc, loads, False)
    full, flags = scatter_into(gathered, smesh.mesh, disc.fes, MATCH_RTOL * scene.size)
    y = reduced_unknowns(system, full)
    timings["rank0_system"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    contact, G = None, None
    if disc.has_crack:
        G = disc.constraint_map()
    if disc.has_crack and opts["crack_model"] == "contact":
        rng = disc.fes.Range(disc.jn)
        rows = _rows_of_dofs(smesh, disc)
        active = np.zeros(G.shape[0], dtype=bool)
        active[rows[np.flatnonzero(flags[rng.start:rng.stop])]] = True
        w = G @ y[system.contact]
        w[active] = 0.0  # the values the last step held at zero are zero (their round-off would read as open)
        y[system.contact] = spla.spsolve(sp.csc_matrix(G), w)
        lam, kkt = contact_certificate(system.K, system.F, y, w, system.contact, G)
        contact = ContactResult(y, w, lam * disc.force_unit, active, info["active_set_steps"], kkt)
        if friction is not None:
            points, state = friction
            contact = certificate(system.K, system.F, y, w, system.contact, G, points, active, state.stick, state.g,
                                  info["active_set_steps"])
            for name in ("lam", "lam_t", "bound"):  # the system is in units of E (solid.stages.friction_stage)
                setattr(contact, name, getattr(contact, name) * disc.force_unit)
            contact.points = points
    gf = system.expand(y)
    if not np.all(np.isfinite(gf.vec.FV().NumPy())):
        raise SolveError(f"scene {scene.name!r}: the local recovery gave non-finite values")
    timings["rank0_post"] = time.perf_counter() - t0
    timings.update(condense=timings["rank0_system"], linear=timings["solve"], contact=0.0)
    public = {k: v for k, v in opts.items() if k not in SIZES}
    public["distributed"] = info
    sol = SolidSolution(scene=scene, smesh=smesh, disc=disc, system=system, y=y, gf=gf, contact=contact, G=G,
                        options=public, timings=timings, distributed=info)
    post_process(sol, opts, loads)
    timings["total"] = time.perf_counter() - t_start
    return sol
