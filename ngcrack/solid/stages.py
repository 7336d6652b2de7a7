"""A 3D body in the pipeline's stages: what `ngcrack.core.pipeline.Pipeline` asks of a 3D scene.

`SOLID` (a `SolidBody`) gives the pipeline's stages the parts that depend on the body's
dimension, as `ngcrack.planar.stages.PLANAR` does for a plane body: the mesh key and the OCC
mesh (`solid.geometry`), the element and its key (`solid.element`, `solid.h1`), the
loads' crack pressures and held means. `run_solid(pipeline, scene, options)` runs the stages on a 3D
scene with the pipeline's caches:

    scene -> mesh (Pipeline.mesh) -> forms, the loads as NGSolve Parameters
          (Pipeline.discretization: a new load value re-assembles the load vector only)
          -> condensed system (Pipeline.system: a new load rebuilds F only)
          -> crack problem (stages.sparse_contact_stage: the crack problem posed once,
             `core.crack_problem`, its strategy chosen by size: "dense", one sparse
             factorization with the crack unknowns last and the crack QP on their dense
             Schur complement, or "sparse" above `core.constraints.SCHUR_MAX_M`; with
             friction `friction_stage`: the semismooth Newton method on the Coulomb cone,
             likewise reduced to the crack; the factorization timed as "linear", the rest
             as "contact") -> SolidSolution -> the fronts' K_I, K_II, K_III, G
          (and, asked for, the error estimate: `solid.estimate`)

`options` is the checked dict of `solid.solve.check_options` with the mesh sizes.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import time

from ..core.discretization import Loads
from ..core.parallel import task_manager
from ..core.stages import SparseAnswer, sparse_contact_stage
from . import h1
from .element import build
from .geometry import SolidMesh, make_mesh
from .output import SolidSolution
from .scene import SolidScene

#: the keys of a 3D solve's options dict that size the mesh
SIZES = ("maxh", "crack_h", "front_h", "grading")
#: the 3D element builders, (smesh, E, nu, loads, order, pressure) -> SolidDiscretization
BUILDERS = {"tdnns": lambda smesh, E, nu, loads, order, pressure: build(smesh, E, nu, loads, order, pressure),
            "h1p1": lambda smesh, E, nu, loads, order, pressure: h1.build(smesh, E, nu, loads, "h1p1", pressure),
            "h1p2": lambda smesh, E, nu, loads, order, pressure: h1.build(smesh, E, nu, loads, "h1p2", pressure)}


class SolidBody:
    """What the stages ask of a 3D body (module docstring)."""

    dimension = 3
    #: the files `ngcrack solve` can write of its solutions besides the JSON record
    outputs = ("vtk",)

    @staticmethod
    def solve(pipeline, scene: SolidScene, options, *, loads=None, warm_start=None, crack_mesh=None) -> SolidSolution:
        """One solve of a checked request (a SolveOptions) through `pipeline`'s stages (`run_solid`)."""
        from .options import solid_options

        opts = solid_options(options, scene)
        if crack_mesh is None:
            check_request(scene, opts, options.max_dof)
        return run_solid(pipeline, scene, opts, crack_mesh)

    @staticmethod
    def check_options(scene: SolidScene, options) -> None:
        """What a 3D scene cannot take of a SolveOptions, refused by name before any meshing (`solve.check_solid`)."""
        from .options import check_solid

        check_solid(scene, options)

    def mesh_key(self, scene: SolidScene, options: dict) -> tuple:
        """The domain, the cracks' geometry and the resolved mesh sizes."""
        cracks = [{k: v for k, v in dataclasses.replace(c, pressure=0.0).to_dict().items() if k != "friction"}
                  for c in scene.cracks]
        sizes = scene.mesh_sizes(*(options.get(k) for k in SIZES))
        points = [(pc.at.tolist(), pc.width, pc.label) for pc in scene.points]
        return json.dumps({"domain": scene.domain.to_dict(), "crack": cracks, "sizes": sizes, "points": points},
                          sort_keys=True)

    def make_mesh(self, scene: SolidScene, options: dict) -> SolidMesh:
        """The OCC mesh of the scene (`solid.geometry.make_mesh`)."""
        return make_mesh(scene, *(options.get(k) for k in SIZES))

    def element_key(self, scene: SolidScene, options: dict) -> tuple:
        """The element and its order, the material and the cracks' uniform pressures (the
        elements assemble them as numbers: a new pressure re-assembles)."""
        return (options["element"], options["order"], scene.material.E, scene.material.nu,
                tuple(c.pressure for c in scene.cracks), tuple(sorted((k, id(c.value)) for k, c in scene.tractions.items())))

    def build(self, scene: SolidScene, smesh: SolidMesh, options: dict, loads: Loads):
        """The element's spaces and assembled forms (BUILDERS: `solid.element`, `solid.h1`); the tractions
        and pressures that vary over a face or a crack as CoefficientFunctions of position (`solid.loads`)."""
        from .loads import coefficients
        from .point_means import patch_area

        pressure, traction = coefficients(scene, loads.traction)  # as the distributed solve's (distributed.solid)
        for pc in scene.points:  # the patch's traction scaled to its meshed area: the force's resultant exact
            if pc.label in traction:
                traction[pc.label] = traction[pc.label] * (pc.area / patch_area(smesh.mesh, pc.label))
        loads = dataclasses.replace(loads, traction=traction)
        return BUILDERS[options["element"]](smesh, scene.material.E, scene.material.nu, loads, options["order"],
                                            pressure if any(p is not None for p in pressure) else None)

    def crack_pressure(self, scene: SolidScene, k: int, parameter) -> None:
        """None: the 3D elements take the cracks' pressures as numbers (`element_key`), not as loads."""
        return None

    def held_mean(self, scene: SolidScene) -> dict:
        """label -> the directions whose mean over the patch of a pin or roller point is held (`solid.points`)."""
        from .points import held_directions

        return held_directions(scene.points)

    @staticmethod
    def crack_volume(sol, cracks: list[int]) -> float:
        """The volume between the faces of the given cracks: the integral of the normal jump over their faces
        (`solid.volume.crack_volume`)."""
        from .volume import crack_volume

        return float(sum(crack_volume(sol, k) for k in cracks))

    @staticmethod
    def volume_compliance(scene: SolidScene, cracks: list[int]) -> float:
        """dV/dp of the given cracks, each as a penny of its area in an infinite body (Sneddon:
        V = 16 a^3 p / (3 E'), a = sqrt(area / pi)): a scale for volume control's first pressure and its strain check."""
        a = [math.sqrt(scene.cracks[k].area / math.pi) for k in cracks]
        return sum(16.0 * r ** 3 / 3.0 for r in a) / SolidBody.effective_modulus(scene)

    @staticmethod
    def effective_modulus(scene: SolidScene) -> float:
        """E' = E / (1 - nu^2), the modulus of K_I^2 = E' G along a 3D front."""
        return scene.material.E / (1.0 - scene.material.nu ** 2)


def check_request(scene: SolidScene, opts: dict, max_dof: int | None) -> None:
    """The 3D size guard before any meshing (`solid.sizing.check_size`): the mesh sizes netgen can mesh, the
    estimated unknowns under max_dof (default: the ceiling and the memory this process may still allocate)."""
    from .sizing import check_size

    check_size(scene, opts["element"], opts["order"], max_dof=max_dof, **{k: opts[k] for k in SIZES})


#: the one 3D body
SOLID = BODY = SolidBody()


def friction_stage(smesh: SolidMesh, disc, system, mu: list[float], linear_solver: str) -> SparseAnswer:
    """The crack problem with Coulomb friction on the sparse system (`stages.sparse_contact_stage` with the
    friction points of `solid.friction_points`), its forces in the element's force unit."""
    from .friction_points import friction_points

    t0 = time.perf_counter()
    points = friction_points(smesh, disc, system, mu)
    t_points = time.perf_counter() - t0
    answer = sparse_contact_stage(system, disc, "contact", linear_solver, points=points)
    result = answer.result
    for name in ("lam", "lam_t", "bound"):  # the system is in units of E (element.build)
        setattr(result, name, getattr(result, name) * disc.force_unit)
    result.points = points
    return dataclasses.replace(answer, time_contact=answer.time_contact + t_points)


def run_solid(pipeline, scene: SolidScene, options: dict, smesh: SolidMesh | None = None) -> SolidSolution:
    """Solve the 3D scene through `pipeline`'s stages (module docstring); `options` checked
    (`solid.solve.check_options`) with the mesh sizes; `smesh` a ready mesh of the scene."""
    pipeline.redone = []
    t0 = time.perf_counter()
    timings = {}
    smesh = smesh if smesh is not None else pipeline.mesh(scene, options)
    timings["mesh"] = time.perf_counter() - t0
    t1 = time.perf_counter()
    disc, loads = pipeline.discretization(scene, smesh, options)
    timings["assemble"] = time.perf_counter() - t1
    t2 = time.perf_counter()
    system = pipeline.system(disc, loads, False)
    timings["condense"] = time.perf_counter() - t2
    mu = [float(c.friction) for c in scene.cracks]
    if disc.has_crack and options["crack_model"] == "contact" and any(m > 0 for m in mu):
        answer = friction_stage(smesh, disc, system, mu, options["linear_solver"])
    else:
        answer = sparse_contact_stage(system, disc, options["crack_model"], options["linear_solver"],
                                      qp_solver=options.get("qp_solver") or "pdas")
        if answer.result is not None:  # the system is in the element's force unit (solid.element.build)
            answer.result.lam = answer.result.lam * disc.force_unit
    timings.update(linear=answer.time_linear, contact=answer.time_contact)
    factorize = (getattr(answer.result, "timings", None) or {}).get("factorize")
    if factorize is not None:  # the "schur" method's one sparse factorization is the body's linear solve
        timings.update(linear=timings["linear"] + factorize, contact=timings["contact"] - factorize)
    with task_manager():
        gf = system.expand(answer.y)
    public = {k: v for k, v in options.items() if k not in SIZES}
    sol = SolidSolution(scene=scene, smesh=smesh, disc=disc, system=system, y=answer.y, gf=gf,
                        contact=answer.result, G=answer.G, options=public, timings=timings)
    post_process(sol, options, loads)
    pipeline.keep_pending(sol)
    timings["total"] = time.perf_counter() - t0
    return sol


def post_process(sol: SolidSolution, options: dict, loads: Loads) -> None:
    """The fronts' K (and, asked for, the error estimate) of a solved 3D scene, timed into `sol.timings`."""
    if options["fronts"] and sol.smesh.cracks:
        from .front import front_parameters

        t0 = time.perf_counter()
        sol.fronts = front_parameters(sol, points=options["front_points"])
        sol.timings["fronts"] = time.perf_counter() - t0
    from .options import ESTIMATES

    if options.get("estimate") is False or options["element"] not in ESTIMATES:
        sol.no_estimate = ("not asked for (estimate = False)" if options.get("estimate") is False else
                           f"element {options['element']!r}: its stress C eps(u) is not equilibrated")
        return
    sol.defer_estimate(functools.partial(_estimate, sol, loads))  # when first asked for (Solution.error_estimate)
    if options.get("estimate"):
        sol.error_estimate  # noqa: B018 -- asked for: computed now, inside the solve


def _estimate(sol: SolidSolution, loads: Loads) -> dict:
    """The Prager-Synge estimate of a solved 3D scene (ngcrack.solid.estimate), its seconds in `sol.timings`."""
    from .estimate import prager_synge

    t0 = time.perf_counter()
    estimate = prager_synge(sol, loads)
    sol.timings["estimate"] = time.perf_counter() - t0
    return estimate
