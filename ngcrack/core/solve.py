"""solve(scene, element, ...) -> Solution: the one-shot use of the pipeline.

scene -> mesh -> element forms (condensed) -> K, F -> Schur complement S on the crack
normal jumps -> QP -> recovery of every unknown -> crack profiles and KKT residuals
(ngcrack.core.pipeline holds the stages); with adapt=TOL, the adaptive loop over the same
stages (ngcrack.studies.adapt). A scene without a crack gets one linear solve and no QP.
"""

from __future__ import annotations

import numpy as np

from .discretization import Loads
from .errors import InputError
from .options import CRACK_MODELS, SolveOptions, qp_solvers
from .pipeline import Pipeline, SolveError, scene_loads
from .scene import Scene
from .solution import Solution

__all__ = ["CRACK_MODELS", "Pipeline", "Solution", "SolveError", "SolveOptions", "as_scene", "qp_solvers",
           "scene_loads", "solve"]


def solve(scene: Scene | str, element: str | None = None, *, options: SolveOptions | None = None,
          loads: Loads | None = None, warm_start=None, crack_mesh=None,
          pipeline: Pipeline | None = None, **changes) -> Solution | None:
    """Solve the unilateral crack problem of `scene` (2D or 3D) with one element family.

    Returns the `Solution` of the scene's kind (`PlanarSolution`, `SolidSolution`: the same names
    for what they share, `fronts` among them). Under `mpiexec -n N` (N > 1) the solve is
    distributed and returns the solution on rank 0 and None on the other ranks.

    element: "tdnns" (default: the most accurate per second at the scenes' default meshes,
    measured against the finite bodies' converged answers, README "Which element when"),
    "bdm", "peers", "h1p1" or "h1p2".
    maxh / tip_h / crack_h / grading override the scene's [mesh] values. qp_solver is "pdas" (default),
    "uzawa" or a cvxpy solver ("clarabel", "osqp", ...); qp_options go to the solver unchanged
    (contact.py). linear_solver: "auto" (MKL PARDISO where installed, else SuperLU), "pardiso",
    "superlu", "cholespy" or "ngsolve"; schur: how the Schur complement on the crack is formed,
    "auto", "factor", "blocked" or "columns" (schur.py). warm_start: a previous Solution (its
    contact zone is carried over by crack position; the meshes may differ) or an active set. `loads`
    replaces the scene's loads by NGSolve CoefficientFunctions (manufactured solutions).
    crack_model: "contact" (unilateral contact, the default), "free" (traction-free
    crack faces that may interpenetrate: one linear solve) or "bonded" (jn = 0, the
    faces slide freely but never separate: one linear solve). order: the polynomial
    order of elements that have one (tdnns: 1, 2 or 3; default 1). condition: also
    estimate the 1-norm condition numbers of the condensed matrix K_rr and of the crack
    Schur complement S (a few extra solves), in `sol.conditioning`. max_dof: the largest
    number of unknowns a solve may have; a request estimated above it (before meshing,
    ngcrack.planar.sizing) is refused with a ValueError. None: the default ceiling
    (ngcrack.core.memory.DEFAULT_MAX_DOF) and the machine's available memory. A mesh too coarse across a
    thin part of the body for the element is refused, or warned about (sizing.check_thin_parts).

    Friction (a crack with `friction` > 0, e.g. `scene.with_(friction=0.3)`): the
    tangential jumps stay in the reduced problem and Coulomb's law is solved by
    `friction_method` ("fixed-point" of Tresca problems or "newton"; friction.py) with
    qp_solver "pdas" (native) or a cvxpy solver for the Tresca steps; warm_start is not
    used. `tangential`: keep the tangential jumps in the reduced problem (None: when a
    crack has friction; True with no friction solves the frictionless problem that way).

    adapt: a relative error tolerance in (0, 1): solve, estimate, mark and refine until
    the relative estimate is <= adapt or the next mesh would exceed max_dof unknowns
    (adapt.py, default budget adapt.DEFAULT_BUDGET; the mesh options give the first
    mesh, which the size guard checks); `time_s["total"]` is then the whole run.
    crack_mesh: solve on this mesh (a CrackMesh of the scene) instead of meshing. Every
    solve carries `sol.error_estimate` (estimate.py), None for an element or crack model
    without one.

    hp: L layers of geometric refinement (ratio hp_sigma, default 0.2) towards every crack
    tip of the scene's mesh (ngcrack.planar.hp); with order 2-3 of bdm or tdnns it converges
    exponentially in the unknowns at the tips' square-root singularity.

    3D scenes take front_h (the mesh size at the crack fronts), fronts and front_points (the
    fracture parameters along the fronts) and refuse the planar options by name (tip_h, hp, adapt,
    ...), as a 2D scene refuses the 3D ones; estimate: True computes the error estimate during the
    solve, False never, None (default) when `sol.error_estimate` is first read. Every option is
    checked, by the scene's body for what depends on it, before any meshing.

    `scene` is a Scene or the name of a built-in scene (`ngcrack scenes`). The options
    may also come as one validated `options=SolveOptions(...)` (keywords then change
    it); `pipeline`: a Pipeline whose cached stages this solve may reuse (the explorer,
    a growth path, a user's own loop); None: a fresh one.
    """
    from .. import distributed

    scene = as_scene(scene)
    opts = SolveOptions.of(options, **({"element": element} if element is not None else {}), **changes)
    try:  # what the scene's body cannot take, before any meshing
        _check_given(scene, opts, loads, warm_start, crack_mesh, pipeline)
        opts.check_for(scene)
    except ValueError as exc:  # under mpiexec every rank finds it alike: rank 0 reports it, the others leave quietly
        if distributed.active():
            distributed.refuse(str(exc))
        raise
    if distributed.active():  # under mpiexec -n N, N > 1: one solve over the ranks (None on ranks > 0)
        return distributed.solve(scene, opts)
    if opts.preconditioner is not None:
        raise InputError(f"preconditioner = {opts.preconditioner!r}: the distributed solve's option; this solve runs "
                         "in one process (mpiexec -n N, N > 1, distributes it)")
    pipeline = pipeline if pipeline is not None else Pipeline()
    if opts.adapt is not None:
        from ..studies.adapt import solve_adaptive  # (with the estimate: loaded by an adaptive solve only)

        return solve_adaptive(scene, opts, loads=loads, pipeline=pipeline)  # (it checks the request, as run does)
    return scene.body.solve(pipeline, scene, opts, loads=loads, warm_start=warm_start, crack_mesh=crack_mesh)


def _check_given(scene: Scene, opts: SolveOptions, loads, warm_start, crack_mesh, pipeline) -> None:
    """The objects handed in besides the options, by type and by what the solve can take, before any work."""
    if loads is not None and not isinstance(loads, Loads):
        raise TypeError(f"loads = {loads!r}: must be None (the scene's loads) or an ngcrack.Loads of "
                         "NGSolve CoefficientFunctions")
    if warm_start is not None and not isinstance(warm_start, (Solution, np.ndarray, list, tuple)):
        raise TypeError(f"warm_start = {warm_start!r}: must be None, a previous Solution or an active set "
                         "(a boolean array over the constraints)")
    if scene.dimension == 3:
        given = [k for k, v in (("loads", loads), ("warm_start", warm_start)) if v is not None]
        if given:
            raise InputError(f"{given[0]}: not available for a 3D scene yet")
    from .. import distributed

    if distributed.active():
        given = [k for k, v in (("loads", loads), ("warm_start", warm_start), ("crack_mesh", crack_mesh),
                                ("pipeline", pipeline), ("adapt", opts.adapt)) if v is not None]
        if given:
            raise InputError(f"{given[0]}: not available in a distributed solve (mpiexec -n N, N > 1)")
    if opts.adapt is not None and crack_mesh is not None:
        raise InputError("crack_mesh: adapt=TOL makes its own first mesh from maxh, tip_h, crack_h and grading; "
                         "give either adapt or crack_mesh")


def as_scene(scene) -> Scene:
    """A Scene, or the built-in scene of that name; anything else is refused naming `scene`."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, str):
        from ..scenes import load

        return as_scene(load(scene))  # refuses an unknown name, listing the built-in scenes
    raise TypeError(f"scene = {scene!r}: must be a Scene (nc.Scene.from_toml, nc.scenes.load) or the name of a "
                    "built-in scene")


