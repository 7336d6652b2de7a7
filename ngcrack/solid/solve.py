"""solve_solid(scene, ...) -> SolidSolution: the 3D pipeline in one call.

scene -> mesh (geometry.make_mesh) -> hybridized TDNNS with the crack's jumps
(element.build) -> the condensed sparse system (ngcrack.hybrid.condense, shared with 2D)
-> the contact problem on it (contact.solve_contact: a primal-dual active set with one
sparse factorization per active set; with friction, friction.solve_friction: a sparse
semismooth Newton method on the Coulomb cone) -> the fields, the crack summaries and the front's
fracture parameters (front.front_parameters). `nc.solve` sends a 3D scene here.
"""

from __future__ import annotations

import time

import ngsolve as ngs
import numpy as np

from ..elements.base import Loads
from ..errors import InputError
from ..hybrid import condense
from ..parallel import task_manager
from ..schur import Factorization
from . import h1
from .contact import solve_contact
from .element import ORDERS, build
from .friction import solve_friction
from .friction_points import friction_points
from .geometry import SolidMesh, make_mesh
from .output import SolidSolution
from .scene import SolidScene

#: the 3D elements and their orders: hybridized TDNNS (the default), the displacement baselines
ELEMENT_ORDERS = {"tdnns": ORDERS, "h1p1": (1,), "h1p2": (2,)}
#: the builders, (smesh, E, nu, loads, order, pressure) -> SolidDiscretization
BUILDERS = {"tdnns": lambda smesh, E, nu, loads, order, pressure: build(smesh, E, nu, loads, order, pressure),
            "h1p1": lambda smesh, E, nu, loads, order, pressure: h1.build(smesh, E, nu, loads, "h1p1", pressure),
            "h1p2": lambda smesh, E, nu, loads, order, pressure: h1.build(smesh, E, nu, loads, "h1p2", pressure)}
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
    """The scene's boundary data and body force as NGSolve CoefficientFunctions."""
    traction, displacement, clamped, roller = {}, {}, set(), set()
    for label, cond in scene.boundary.items():
        if cond.type == "traction":
            traction[label] = ngs.CF(tuple(cond.value))
        elif cond.type == "displacement":
            displacement[label] = ngs.CF(tuple(cond.value))
        elif cond.type == "clamped":
            clamped.add(label)
        else:
            roller.add(label)
    body = None if scene.body_force is None else ngs.CF(tuple(scene.body_force))
    return Loads(body_force=body, traction=traction, displacement=displacement, clamped=frozenset(clamped),
                 roller=frozenset(roller))


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


def solve_solid(scene: SolidScene, *, smesh: SolidMesh | None = None, **options) -> SolidSolution:
    """Solve the unilateral crack problem of a 3D scene (options: OPTIONS)."""
    opts = check_options(options)
    mu = [float(c.friction) for c in scene.cracks]
    frictional = any(m > 0 for m in mu) and opts["crack_model"] == "contact"
    if frictional and opts["element"] != "tdnns":
        i = next(i for i, m in enumerate(mu) if m > 0)
        raise InputError(f"crack[{i}].friction = {mu[i]:g}: Coulomb friction in 3D is solved with element = 'tdnns' "
                         f"(not {opts['element']!r}); set friction = 0 or element = 'tdnns'")
    SCENE_CHECKS.get(opts["element"], lambda scene: None)(scene)
    t0 = time.perf_counter()
    timings = {}
    if smesh is None:
        smesh = make_mesh(scene, options.get("maxh"), options.get("crack_h"), options.get("front_h"),
                          options.get("grading"))
    timings["mesh"] = time.perf_counter() - t0
    loads = scene_loads(scene)
    t1 = time.perf_counter()
    pressure = [c.pressure for c in scene.cracks]
    disc = BUILDERS[opts["element"]](smesh, scene.material.E, scene.material.nu, loads, opts["order"],
                                     pressure if any(pressure) else None)
    timings["assemble"] = time.perf_counter() - t1
    t2 = time.perf_counter()
    system = condense(disc, loads)
    timings["condense"] = time.perf_counter() - t2
    G = disc.constraint_map() if disc.jn is not None else None
    result = None
    t3 = time.perf_counter()
    if disc.jn is None or opts["crack_model"] == "free":
        y = Factorization(system.K, opts["linear_solver"]).solve(system.F)
        timings["linear"] = time.perf_counter() - t3
        timings["contact"] = 0.0
    elif frictional:
        points = friction_points(smesh, disc, system, mu)
        result = solve_friction(system.K, system.F, system.contact, G, points, linear_solver=opts["linear_solver"])
        for name in ("lam", "lam_t", "bound"):  # the system is in units of E (element.build)
            setattr(result, name, getattr(result, name) * disc.force_unit)
        result.points = points
        y = result.y
        timings["linear"] = 0.0
        timings["contact"] = time.perf_counter() - t3
    else:
        result = solve_contact(system.K, system.F, system.contact, G, linear_solver=opts["linear_solver"])
        result.lam = result.lam * disc.force_unit  # the system is in units of E (element.build)
        y = result.y
        timings["linear"] = 0.0
        timings["contact"] = time.perf_counter() - t3
    with task_manager():
        gf = system.expand(y)
    sol = SolidSolution(scene=scene, smesh=smesh, disc=disc, system=system, y=y, gf=gf, contact=result, G=G,
                        options=opts, timings=timings)
    if opts["fronts"] and smesh.cracks:
        from .front import front_parameters

        t4 = time.perf_counter()
        sol.fronts = front_parameters(sol, points=opts["front_points"])
        timings["fronts"] = time.perf_counter() - t4
    if opts["estimate"]:
        from .estimate import prager_synge

        t5 = time.perf_counter()
        sol.error_estimate = prager_synge(sol, loads)
        timings["estimate"] = time.perf_counter() - t5
    timings["total"] = time.perf_counter() - t0
    return sol
