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

import time
import warnings

import numpy as np

from ..core.errors import InputError
from ..core.options import SolveOptions
from ..core.pipeline import Pipeline
from ..planar.estimate import ESTIMATE_CRACK_MODELS, METHODS
from ..planar.geometry import CrackMesh, refine_crack_mesh

#: Doerfler's bulk parameter: mark the fewest triangles that hold this share of eta^2
DOERFLER_THETA = 0.5
#: the budget of unknowns when none is given (a few seconds per step on 2 cores)
DEFAULT_BUDGET = 200_000
#: at most this many refinement steps (each bisects a Doerfler set: the dof grow 1.2-2 times)
MAX_STEPS = 40


def check_adapt_options(options: SolveOptions, scene=None) -> None:
    """Refuse an element / crack model / material without an estimate, naming the field,
    before any meshing (the tolerance and the budget are checked by SolveOptions)."""
    element, crack_model = options.element, options.crack_model
    if element not in METHODS:
        raise InputError(f"element = {element!r}: adaptivity needs an error estimate; elements with one: {', '.join(METHODS)}")
    if crack_model not in ESTIMATE_CRACK_MODELS:
        raise InputError(f"crack_model = {crack_model!r}: adaptivity needs an error estimate; crack models with one: "
                          f"{', '.join(ESTIMATE_CRACK_MODELS)}")
    if scene is not None and METHODS[element] == "prager-synge":
        mat = scene.material
        if mat.plane == "strain" and mat.nu >= 0.5:
            raise InputError("material.nu = 0.5: the Prager-Synge estimate needs nu < 1/2 in plane strain "
                              "(C eps(w) is infinite); adaptivity is not available there")


# ------------------------------------------------------------ the four steps

def solve_step(pipeline: Pipeline, scene, crack_mesh: CrackMesh, options: SolveOptions, previous, loads=None):
    """Solve on a given mesh, the QP warm-started from the previous step's solution."""
    return pipeline.run(scene, options, crack_mesh=crack_mesh, warm_start=previous, loads=loads)


def estimate_step(sol):
    """The solve's error estimate (every solve computes one)."""
    if sol.error_estimate is None:
        raise InputError(f"element = {sol.element!r}: this solve has no error estimate ({sol.no_estimate})")
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

def solve_adaptive(scene, options: SolveOptions | str, adapt: float | None = None, *, loads=None,
                   theta: float = DOERFLER_THETA, monitor=None, pipeline: Pipeline | None = None, **changes):
    """Refine until the relative estimate is <= adapt or the budget max_dof is reached.

    `options`: a SolveOptions, or an element name (then `changes` are the other solve
    options: maxh, max_dof, ...); `adapt` the tolerance (None: options.adapt).
    `pipeline`: the Pipeline to run the steps on (None: a fresh one).

    Returns the last Solution with `adapt_history` (a pandas DataFrame: step, ndof,
    global and contact unknowns, triangles, hmin, hmax, estimate (relative), energy
    (absolute), solve / estimate / refine seconds and the cumulated wall time) and
    options["adapt"] = {"tol", "max_dof", "theta", "steps", "reached"}; `timings["total"]`
    is the whole adaptive run (every step's meshing, solve, estimate and refinement),
    `timings["last_step"]` the last solve alone. `monitor(sol)`, if given, returns a dict
    of further columns for each step's row (e.g. a measured error).
    """
    import pandas as pd

    if isinstance(options, SolveOptions):
        options = options.replace(**changes)
    else:
        options = SolveOptions.of(element=options, **changes)
    if adapt is not None:
        options = options.replace(adapt=adapt)
    adapt = options.adapt
    if adapt is None:
        raise InputError("adapt = None: give the relative error tolerance in (0, 1)")
    check_adapt_options(options, scene)
    budget = DEFAULT_BUDGET if options.max_dof is None else options.max_dof
    step_options = options.replace(adapt=None)
    pipeline = pipeline if pipeline is not None else Pipeline()
    pipeline.check(scene, step_options, loads)  # the checks of Pipeline.run, the size guard on the first mesh
    t_start = time.perf_counter()
    t0 = time.perf_counter()
    cmesh = pipeline.mesh(scene, step_options)
    t_mesh = time.perf_counter() - t0
    rows, sol, reached = [], None, False
    for step in range(MAX_STEPS):
        sol = solve_step(pipeline, scene, cmesh, step_options, sol, loads)
        est = estimate_step(sol)
        edges = np.linalg.norm(cmesh.points[cmesh.triangles] - cmesh.points[np.roll(cmesh.triangles, 1, axis=1)], axis=2)
        row = {"step": step, "ndof": int(sol.ndof["total"]), "global": int(sol.ndof["global"]),
               "contact": int(sol.ndof["contact"]), "triangles": int(sol.mesh.ne),
               "hmin": float(edges.max(axis=1).min()), "hmax": float(edges.max(axis=1).max()),
               "estimate": float(est.relative), "energy": float(est.energy),
               "time_solve": float(sol.timings["total"]),
               "time_estimate": float(est.time), "time_refine": t_mesh}
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
    sol.timings["last_step"] = sol.timings["total"]
    sol.timings["total"] = time.perf_counter() - t_start
    sol.timings["adapt_total"] = sol.timings["total"]
    sol.options["adapt"] = {"tol": float(adapt), "max_dof": budget, "theta": float(theta), "steps": len(rows),
                            "reached": reached}
    if not reached:
        warnings.warn(f"adapt: the relative estimate {rows[-1]['estimate']:.3g} is above the tolerance {adapt:g} "
                      f"after {len(rows)} steps; the next mesh would exceed max_dof = {budget} unknowns "
                      f"(or {MAX_STEPS} steps were reached); returning the last solution", stacklevel=3)
    return sol
