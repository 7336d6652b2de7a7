"""Adaptive refinement to a requested accuracy: solve -> estimate -> mark -> refine.

    sol = nc.solve(scene, element="bdm", adapt=0.01, max_dof=200_000)
    sol.adapt_history          # one row per step: ndof, estimate, error, times, mesh sizes

Each step solves on the current mesh (the QP warm-started from the previous step's
contact zone), reads the error estimate of estimate.py (every solve computes one),
marks the triangles with the largest indicators by Doerfler's bulk criterion
(the fewest triangles holding DOERFLER_THETA of eta^2), and bisects them with netgen
(plus netgen's closure for conformity); the cracks are then re-identified on the
refined mesh (geometry.refine_crack_mesh): crack edges stay edges, tips stay vertices.
The loop stops when the relative estimate eta / ||sigma_h||_A is at most `adapt`, or
when the next mesh would exceed `max_dof` unknowns (then it returns the last solution,
warns, and says so in sol.options["adapt"]["reached"]).
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

from .estimate import ESTIMATE_CRACK_MODELS, METHODS
from .geometry import CrackMesh, make_mesh, refine_crack_mesh

#: Doerfler's bulk parameter: mark the fewest triangles that hold this share of eta^2
DOERFLER_THETA = 0.5
#: the budget of unknowns when none is given (a few seconds per step on 2 cores)
DEFAULT_MAX_DOF = 200_000
#: at most this many refinement steps (each bisects a Doerfler set: the dof grow 1.2-2 times)
MAX_STEPS = 40


def check_adapt_options(adapt, max_dof, element: str, crack_model: str, scene=None) -> None:
    """Refuse a tolerance outside (0, 1), a non-positive budget, or an element / crack
    model / material without an estimate, naming the field, before any meshing."""
    if isinstance(adapt, bool) or not (isinstance(adapt, (int, float)) and math.isfinite(adapt) and 0 < adapt < 1):
        raise ValueError(f"adapt = {adapt!r}: the relative error tolerance must lie in (0, 1)")
    if max_dof is not None and (isinstance(max_dof, bool) or not isinstance(max_dof, (int, np.integer)) or max_dof <= 0):
        raise ValueError(f"max_dof = {max_dof!r}: must be a positive integer (a number of unknowns)")
    if element not in METHODS:
        raise ValueError(f"element = {element!r}: adaptivity needs an error estimate; elements with one: {', '.join(METHODS)}")
    if crack_model not in ESTIMATE_CRACK_MODELS:
        raise ValueError(f"crack_model = {crack_model!r}: adaptivity needs an error estimate; crack models with one: "
                         f"{', '.join(ESTIMATE_CRACK_MODELS)}")
    if scene is not None and METHODS[element] == "prager-synge":
        mat = scene.material
        if mat.plane == "strain" and mat.nu >= 0.5:
            raise ValueError("material.nu = 0.5: the Prager-Synge estimate needs nu < 1/2 in plane strain "
                             "(C eps(w) is infinite); adaptivity is not available there")


# ------------------------------------------------------------ the four steps

def solve_step(scene, crack_mesh: CrackMesh, element: str, previous, options: dict):
    """Solve on a given mesh, the QP warm-started from the previous step's solution."""
    from .solve import solve

    return solve(scene, element=element, crack_mesh=crack_mesh, warm_start=previous, **options)


def estimate_step(sol):
    """The solve's error estimate (every solve computes one)."""
    if sol.error_estimate is None:
        raise ValueError(f"element = {sol.element!r}: this solve has no error estimate ({sol.options.get('error_estimate')})")
    return sol.error_estimate


def mark(eta: np.ndarray, theta: float = DOERFLER_THETA) -> np.ndarray:
    """Doerfler marking: the smallest set M of triangles with sum_M eta_T^2 >= theta sum eta_T^2."""
    e2 = np.asarray(eta, dtype=float) ** 2
    order = np.argsort(e2)[::-1]
    cum = np.cumsum(e2[order])
    k = int(np.searchsorted(cum, theta * cum[-1])) + 1 if cum[-1] > 0 else len(e2)
    marked = np.zeros(len(e2), dtype=bool)
    marked[order[:k]] = True
    return marked


def refine(crack_mesh: CrackMesh, scene, marked: np.ndarray) -> CrackMesh:
    """Bisect the marked triangles (netgen), cracks re-identified."""
    return refine_crack_mesh(crack_mesh, scene, marked)


# ------------------------------------------------------------------ the loop

def solve_adaptive(scene, element: str, adapt: float, max_dof: int | None = None, maxh=None, tip_h=None,
                   crack_h=None, grading=None, theta: float = DOERFLER_THETA, monitor=None, **options):
    """Refine until the relative estimate is <= adapt or the budget max_dof is reached.

    Returns the last Solution with `adapt_history` (a pandas DataFrame: step, ndof,
    global and contact unknowns, triangles, hmin, hmax, estimate (relative), energy
    (absolute), solve / estimate / refine seconds and the cumulated wall time) and
    options["adapt"] = {"tol", "max_dof", "theta", "steps", "reached"}. `monitor(sol)`, if
    given, returns a dict of further columns for each step's row (e.g. a measured error).
    """
    import pandas as pd

    check_adapt_options(adapt, max_dof, element, options.get("crack_model", "contact"), scene)
    budget = DEFAULT_MAX_DOF if max_dof is None else int(max_dof)
    t_start = time.perf_counter()
    t0 = time.perf_counter()
    cmesh = make_mesh(scene, maxh=maxh, tip_h=tip_h, crack_h=crack_h, grading=grading)
    t_mesh = time.perf_counter() - t0
    rows, sol, reached = [], None, False
    for step in range(MAX_STEPS):
        sol = solve_step(scene, cmesh, element, sol, options)
        est = estimate_step(sol)
        edges = np.linalg.norm(cmesh.points[cmesh.triangles] - cmesh.points[np.roll(cmesh.triangles, 1, axis=1)], axis=2)
        row = {"step": step, "ndof": int(sol.ndof["total"]), "global": int(sol.ndof["global"]),
               "contact": int(sol.ndof["contact"]), "triangles": int(sol.mesh.ne),
               "hmin": float(edges.max(axis=1).min()), "hmax": float(edges.max(axis=1).max()),
               "estimate": float(est.relative), "energy": float(est.energy),
               "time_solve": float(sol.timings["total"]), "time_estimate": float(est.time),
               "time_refine": t_mesh}
        if monitor is not None:
            row.update(monitor(sol))
        rows.append(row)
        if est.relative <= adapt:
            reached = True
            break
        t0 = time.perf_counter()
        marked = mark(est.eta, theta)
        new = refine(cmesh, scene, marked)
        t_mesh = time.perf_counter() - t0
        # the unknowns grow with the triangles at a fixed ratio per element family
        predicted = sol.ndof["total"] * new.mesh.ne / sol.mesh.ne
        if predicted > budget:
            break
        cmesh = new
    history = pd.DataFrame(rows)
    history["time_total"] = (history["time_solve"] + history["time_estimate"] + history["time_refine"]).cumsum()
    sol.adapt_history = history
    sol.timings["adapt_total"] = time.perf_counter() - t_start
    sol.options["adapt"] = {"tol": float(adapt), "max_dof": budget, "theta": float(theta), "steps": len(rows),
                            "reached": reached}
    if not reached:
        warnings.warn(f"adapt: the relative estimate {rows[-1]['estimate']:.3g} is above the tolerance {adapt:g} "
                      f"after {len(rows)} steps; the next mesh would exceed max_dof = {budget} unknowns "
                      f"(or {MAX_STEPS} steps were reached); returning the last solution", stacklevel=3)
    return sol
