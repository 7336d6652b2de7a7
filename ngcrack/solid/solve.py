"""solve_solid(scene, ...) -> SolidSolution: the 3D pipeline in one call.

The options are checked here, before any meshing; the solve then runs through the
stages of an `ngcrack.core.pipeline.Pipeline` (`stages.run_solid`), cached as in 2D:
scene -> mesh (geometry.make_mesh) -> hybridized TDNNS with the crack's jumps
(element.build) -> the condensed sparse system (ngcrack.core.hybrid.condense, shared with 2D)
-> the contact problem on it (contact.solve_contact: a primal-dual active set with one
sparse factorization per active set; with friction, friction.solve_friction: a sparse
semismooth Newton method on the Coulomb cone) -> the fields, the crack summaries and the front's
fracture parameters (front.front_parameters). `nc.solve` sends a 3D scene here.
"""

from __future__ import annotations

import numpy as np

from ..core.errors import InputError
from ..planar.elements.base import Loads
from . import h1
from .element import ORDERS
from .geometry import SolidMesh
from .output import SolidSolution
from .scene import SolidScene

#: the 3D elements and their orders: hybridized TDNNS (the default), the displacement baselines
ELEMENT_ORDERS = {"tdnns": ORDERS, "h1p1": (1,), "h1p2": (2,)}
#: checks of the scene an element needs before any meshing
SCENE_CHECKS = {"h1p1": h1.check_scene, "h1p2": h1.check_scene}
#: crack_model values: unilateral contact, traction-free faces (one linear solve)
CRACK_MODELS = ("contact", "free")
#: the options a 3D solve takes (others are refused by name)
OPTIONS = ("element", "order", "maxh", "crack_h", "front_h", "grading", "crack_model", "linear_solver", "fronts",
           "front_points", "qp_solver", "estimate")
#: the elements with an error estimate (ngcrack.solid.estimate); the displacement elements' stress is
#: not equilibrated, so the Prager-Synge estimate has nothing to measure there
ESTIMATES = ("tdnns",)


def scene_loads(scene: SolidScene) -> Loads:
    """The scene's boundary data and body force as NGSolve CoefficientFunctions (of Parameters:
    `ngcrack.core.pipeline.ParameterLoads` of the 3D body)."""
    from ..core.pipeline import ParameterLoads
    from .stages import SOLID

    return ParameterLoads(scene, SOLID).loads


def check_options(options: dict) -> dict:
    """The 3D solve's options, each refused by name before any meshing."""
    unknown = [k for k in options if k not in OPTIONS]
    if unknown:
        raise InputError(f"{unknown[0]}: not an option of a 3D solve; allowed: {', '.join(OPTIONS)}")
    element = options.get("element") or "tdnns"
    if element not in ELEMENT_ORDERS:
        raise InputError(f"element = {element!r}: allowed values in 3D are {', '.join(ELEMENT_ORDERS)} (the weakly "
                         "symmetric bdm/peers family is 2D only)")
    allowed = ELEMENT_ORDERS[element]
    order = options.get("order") or allowed[0]
    if order not in allowed:
        raise InputError(f"order = {order!r}: allowed values for {element} in 3D are {', '.join(map(str, allowed))}")
    model = options.get("crack_model") or "contact"
    if model not in CRACK_MODELS:
        raise InputError(f"crack_model = {model!r}: allowed values in 3D are {', '.join(CRACK_MODELS)}")
    qp = options.get("qp_solver") or "pdas"
    if qp != "pdas":
        raise InputError(f"qp_solver = {qp!r}: 3D contact is solved by the sparse active set (allowed values: pdas)")
    for key in ("maxh", "crack_h", "front_h", "grading"):
        v = options.get(key)
        if v is not None and not (isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v) and v > 0):
            raise InputError(f"{key} = {v!r}: must be a finite number > 0")
    estimate = options.get("estimate", False)
    if not isinstance(estimate, bool):
        raise InputError(f"estimate = {estimate!r}: must be True or False")
    if estimate and element not in ESTIMATES:
        raise InputError(f"estimate = True: 3D error estimates are for {', '.join(ESTIMATES)} only (element = "
                         f"{element!r}: its stress C eps(u) is not equilibrated)")
    return {"element": element, "order": int(order), "crack_model": model, "estimate": estimate,
            "linear_solver": options.get("linear_solver") or "auto",
            "fronts": options.get("fronts", True), "front_points": options.get("front_points")}


def solve_solid(scene: SolidScene, *, smesh: SolidMesh | None = None, pipeline=None, **options) -> SolidSolution:
    """Solve the unilateral crack problem of a 3D scene (options: OPTIONS) through the
    stages of `pipeline` (an `ngcrack.core.pipeline.Pipeline` whose cached stages the solve may
    reuse; None: a fresh one), `ngcrack.solid.stages.run_solid`."""
    opts = check_options(options)
    mu = [float(c.friction) for c in scene.cracks]
    frictional = any(m > 0 for m in mu) and opts["crack_model"] == "contact"
    if frictional and opts["element"] != "tdnns":
        i = next(i for i, m in enumerate(mu) if m > 0)
        raise InputError(f"crack[{i}].friction = {mu[i]:g}: Coulomb friction in 3D is solved with element = 'tdnns' "
                         f"(not {opts['element']!r}); set friction = 0 or element = 'tdnns'")
    SCENE_CHECKS.get(opts["element"], lambda scene: None)(scene)
    from ..core.pipeline import Pipeline
    from .stages import run_solid

    sizes = {k: options.get(k) for k in ("maxh", "crack_h", "front_h", "grading")}
    return run_solid(pipeline if pipeline is not None else Pipeline(), scene, {**opts, **sizes}, smesh)
