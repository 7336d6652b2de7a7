"""The options of a 3D solve: what a SolveOptions may ask of the solid body, checked before any meshing.

`check_solid(scene, options)` refuses by name what a 3D scene cannot take (the planar body's own
options, an element or order it has not, the bonded crack model, an unknown QP solver, an estimate
or friction with an element that has none). The QP solver solves the crack problem on the Schur
complement (`ngcrack.core.sparse_contact`, up to `constraints.SCHUR_MAX_M` crack unknowns); the
sparse active set above that size is its own method, so there only "pdas" is taken); `solid_options(options)` is the
stages' dictionary of a checked request (`ngcrack.solid.stages.run_solid`).
"""

from __future__ import annotations

from ..core.contact import NATIVE_SOLVERS
from ..core.errors import InputError
from ..core.fields import is_finite
from ..core.options import qp_solvers
from . import h1
from .element import ORDERS
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
    if qp not in NATIVE_SOLVERS and qp not in qp_solvers():
        raise InputError(f"qp_solver = {qp!r}: allowed values are {', '.join(qp_solvers())}")
    for key in ("maxh", "crack_h", "front_h", "grading"):
        v = options.get(key)
        if v is not None and not (is_finite(v) and v > 0):
            raise InputError(f"{key} = {v!r}: must be a finite number > 0")
    if options.get("grading") is not None and options["grading"] > 1:
        raise InputError(f"grading = {options['grading']!r}: must lie in (0, 1] (netgen's default is 0.3)")
    estimate = options.get("estimate")
    if estimate is not None and not isinstance(estimate, bool):
        raise InputError(f"estimate = {estimate!r}: must be None (when asked for), True or False")
    if estimate and element not in ESTIMATES:
        raise InputError(f"estimate = True: 3D error estimates are for {', '.join(ESTIMATES)} only (element = "
                         f"{element!r}: its stress C eps(u) is not equilibrated)")
    return {"element": element, "order": int(order), "crack_model": model, "estimate": estimate, "qp_solver": qp,
            "linear_solver": options.get("linear_solver") or "auto",
            "fronts": options.get("fronts", True), "front_points": options.get("front_points")}


#: the options of a planar body only (ngcrack.core.options.SolveOptions), with what a 3D scene takes instead
PLANAR_ONLY = {"tip_h": "front_h (the mesh size at the crack fronts)", "hp": "", "hp_sigma": "", "path_grading": "",
               "adapt": "", "schur": "", "friction_method": "", "tangential": "", "condition": "", "qp_options": ""}


def check_solid(scene: SolidScene, options) -> None:
    """Every option of `options` (a SolveOptions) that a 3D scene cannot take, refused by name before
    any meshing: the planar body's own options, the element and its order, the crack model, the QP
    solver, an estimate or friction with an element that has none."""
    for name in options.given():
        if name in PLANAR_ONLY:
            instead = f": use {PLANAR_ONLY[name]}" if PLANAR_ONLY[name] else ""
            raise InputError(f"{name}: an option of 2D scenes only; scene {scene.name!r} is 3D{instead}")
    opts = check_options({"element": options.element, "order": options.order, "crack_model": options.crack_model,
                          "qp_solver": options.qp_solver, "estimate": options.estimate})
    mu = [float(c.friction) for c in scene.cracks]
    if any(m > 0 for m in mu) and opts["crack_model"] == "contact" and opts["element"] != "tdnns":
        i = next(i for i, m in enumerate(mu) if m > 0)
        raise InputError(f"crack[{i}].friction = {mu[i]:g}: Coulomb friction in 3D is solved with element = 'tdnns' "
                         f"(not {opts['element']!r}); set friction = 0 or element = 'tdnns'")
    SCENE_CHECKS.get(opts["element"], lambda scene: None)(scene)


def solid_options(options, scene: SolidScene | None = None) -> dict:
    """The stages' options of a SolveOptions checked for the 3D body (`check_solid`), with the mesh sizes: those
    `options.accuracy` asks for on `scene` (`sizing.accuracy_sizes`), else the given ones."""
    opts = check_options({"element": options.element, "order": options.order, "crack_model": options.crack_model,
                          "estimate": options.estimate, "linear_solver": options.linear_solver,
                          "qp_solver": options.qp_solver, "fronts": options.fronts, "front_points": options.front_points})
    sizes = {"crack_h": options.crack_h, "front_h": options.front_h}
    if getattr(options, "accuracy", None) is not None:
        if scene is None:
            raise InputError("accuracy: the mesh sizes it asks for need the scene (solid_options(options, scene))")
        from .sizing import accuracy_sizes

        sizes = accuracy_sizes(scene, options.accuracy)
    return {**opts, "maxh": options.maxh, **sizes, "grading": options.grading}


