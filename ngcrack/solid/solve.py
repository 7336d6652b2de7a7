"""solve_solid(scene, ...) -> SolidSolution: the 3D pipeline in one call.

The options are checked here, before any meshing; the solve then runs through the
stages of an `ngcrack.core.pipeline.Pipeline` (`stages.run_solid`), cached as in 2D:
scene -> mesh (geometry.make_mesh) -> hybridized TDNNS with the crack's jumps
(element.build) -> the condensed sparse system (ngcrack.core.hybrid.condense, shared with 2D)
-> the crack problem on it (ngcrack.core.crack_problem: the dense or the sparse strategy by
its size; with friction, core.sparse_friction.solve_friction: a semismooth Newton method
on the Coulomb cone) -> the fields, the crack summaries and the front's
fracture parameters (front.front_parameters). `nc.solve` sends a 3D scene here.
"""

from __future__ import annotations

from ..core.discretization import Loads
from .geometry import SolidMesh
from .options import (  # noqa: F401  (re-exported: the 3D options by name)
    CRACK_MODELS,
    ELEMENT_ORDERS,
    ESTIMATES,
    OPTIONS,
    PLANAR_ONLY,
    SCENE_CHECKS,
    check_options,
    check_solid,
    solid_options,
)
from .output import SolidSolution
from .scene import SolidScene


def scene_loads(scene: SolidScene) -> Loads:
    """The scene's boundary data and body force as NGSolve CoefficientFunctions (of Parameters:
    `ngcrack.core.pipeline.ParameterLoads` of the 3D body)."""
    from ..core.pipeline import ParameterLoads
    from .stages import SOLID

    return ParameterLoads(scene, SOLID).loads


def solve_solid(scene: SolidScene, options=None, *, smesh: SolidMesh | None = None, pipeline=None,
                **changes) -> SolidSolution:
    """Solve the unilateral crack problem of a 3D scene through the stages of `pipeline` (an
    `ngcrack.core.pipeline.Pipeline` whose cached stages the solve may reuse; None: a fresh one),
    `ngcrack.solid.stages.run_solid`. `options`: a SolveOptions (keywords change it), checked for
    the 3D body before any meshing."""
    from ..core.options import SolveOptions
    from ..core.pipeline import Pipeline
    from .stages import run_solid

    opts = SolveOptions.of(options, **changes)
    opts.check_for(scene)
    return run_solid(pipeline if pipeline is not None else Pipeline(), scene, solid_options(opts, scene), smesh)
