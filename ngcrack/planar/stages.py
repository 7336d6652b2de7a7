"""The planar body: what the stages of a solve ask of a 2D scene (`scene.body` of a PlanarScene).

The checks before any work (the element against the material, the size guard, the supports of
given loads, an undetermined pressure), the mesh and what it depends on (netgen's mesh with the
cracks as interior edges; hp layers at the tips), the element family's forms, the crack-face
pressures as CoefficientFunctions, the pin and roller points' held means, and the post-processing
of a planar solve (`post2d.PLANE`). `ngcrack.core.pipeline` caches each under its key.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.discretization import Discretization, Loads
from ..core.errors import InputError
from ..core.options import SolveOptions
from . import elements as _elements
from .crack_loads import pressure_cf
from .geometry import CrackMesh, make_mesh
from .hp import hp_mesh
from .materials import compliance
from .post2d import PLANE
from .scene import BoundaryCondition, Scene
from .scene.points import held_directions
from .sizing import check_request
from .solution import PlanarSolution
from .tips import effective_modulus

__all__ = ["BODY", "PLANAR", "PlanarBody", "check_pressure_determined", "check_supports", "geometry_key"]


#: the options of a 3D body only (ngcrack.core.options.SolveOptions), with what a 2D scene takes instead
SOLID_ONLY = {"front_h": "tip_h (the mesh size at the crack tips)", "fronts": "", "front_points": "",
              "accuracy": "adapt=TOL (refinement until the relative error estimate is <= TOL)"}


def geometry_key(scene: Scene) -> tuple:
    """What the mesh depends on: the polygon, its labels, the cracks' points and the mesh sizes."""
    return (scene.polygon, scene.labels, tuple(c.points for c in scene.cracks),
            scene.holes, scene.maxh, scene.tip_h, scene.crack_h, scene.grading)


class PlanarBody:
    """What the stages ask of a plane body (`scene.body`): the checks of a request before any
    work, the mesh and its key, the element and its key, the crack-face pressures and the held
    means of its loads, and the post-processor (`post2d.PLANE`). The 3D counterpart is
    `ngcrack.solid.stages.SOLID`."""

    dimension = 2
    post = PLANE
    #: what a solve of the body returns
    solution_type = PlanarSolution
    #: the files `ngcrack solve` can write of its solutions besides the JSON record
    outputs = ("plot", "vtk")

    @staticmethod
    def solve(pipeline, scene: Scene, options: SolveOptions, *, loads: Loads | None = None, warm_start=None,
              crack_mesh: CrackMesh | None = None):
        """One solve of a checked request through `pipeline`'s stages (`Pipeline.run`)."""
        if crack_mesh is not None and not isinstance(crack_mesh, CrackMesh):
            raise TypeError(f"crack_mesh = {crack_mesh!r}: must be None or a CrackMesh of the scene (geometry.make_mesh)")
        return pipeline.run(scene, options, loads=loads, warm_start=warm_start, crack_mesh=crack_mesh)

    @staticmethod
    def check_options(scene: Scene, options: SolveOptions) -> None:
        """The options of a 3D body only, refused by name for a 2D scene (before any meshing)."""
        for name in options.given():
            if name in SOLID_ONLY:
                instead = f": use {SOLID_ONLY[name]}" if SOLID_ONLY[name] else ""
                raise InputError(f"{name}: an option of 3D scenes only (their crack fronts); scene {scene.name!r} is "
                                 f"2D{instead}")

    @staticmethod
    def check(scene: Scene, options: SolveOptions, loads: Loads | None = None, size: bool = True) -> None:
        """What the element cannot solve (nu = 1/2), the size guard and the thin parts (`size`), the
        supports of given loads, an undetermined pressure: every check of the body before any work."""
        o = options
        _elements.check_material(o.element, scene.material)
        if size:
            check_request(scene, o.element, o.maxh, o.tip_h, o.crack_h, o.grading, order=o.order, max_dof=o.max_dof)
        if loads is not None:
            check_supports(scene, loads)
        check_pressure_determined(scene, loads)

    def mesh_key(self, scene: Scene, options: SolveOptions) -> tuple:
        """The scene's geometry and mesh sizes and the options' mesh sizes."""
        return geometry_key(scene), options.mesh_key

    def make_mesh(self, scene: Scene, options: SolveOptions) -> CrackMesh:
        """geometry.make_mesh; with options.hp, hp.hp_mesh: a base mesh coarse at the tips
        and hp geometric layers towards them."""
        o = options
        sizes = dict(maxh=o.maxh, tip_h=o.tip_h, crack_h=o.crack_h, grading=o.grading)
        if o.path_grading is not None:  # the crack's size graded from its tips (ngcrack.planar.path_sizes)
            sizes["path_grading"] = o.path_grading
        # hp: the coarse base mesh of hp.base_mesh (unless sizes are given) and the layers
        return hp_mesh(scene, o.hp, sigma=o.hp_sigma, **sizes) if o.hp else make_mesh(scene, **sizes)

    def element_key(self, scene: Scene, options: SolveOptions) -> tuple:
        """The element and its order, the material."""
        mat = scene.material
        return options.element_key, (mat.E, mat.nu, mat.plane)

    def build(self, scene: Scene, crack_mesh: CrackMesh, options: SolveOptions, loads: Loads) -> Discretization:
        """The element family's spaces and assembled forms (`ngcrack.planar.elements.build`)."""
        mat = scene.material
        return _elements.build(options.element, crack_mesh, compliance(mat.E, mat.nu, mat.plane), loads,
                               order=options.order)

    def crack_pressure(self, scene: Scene, k: int, parameter):
        """The pressure on crack k's faces as a CoefficientFunction of position (a uniform
        one through `parameter`); None where the element takes it as a number instead."""
        crack = scene.cracks[k]
        return pressure_cf(crack.pressure, np.asarray(crack.points), scene.diameter, parameter=parameter)

    def held_mean(self, scene: Scene) -> dict:
        """The pin and roller points' held means (label -> directions)."""
        return held_directions(scene.polygon, scene.labels, getattr(scene, "points", ()))

    @staticmethod
    def crack_volume(sol, cracks: list[int]) -> float:
        """The area between the faces of the given cracks, per unit thickness: the sum over crack edges of the
        mid-point normal jump times the edge length (exact for jumps linear on each edge: P0 and P1 jumps)."""
        return float(sum(np.sum(sol.profiles[k].normal_jump * sol.crack_mesh.cracks[k].length) for k in cracks))

    @staticmethod
    def volume_compliance(scene: Scene, cracks: list[int]) -> float:
        """dV/dp of the given cracks as one straight crack of their total length 2a in an infinite plate
        (Sneddon: V = 2 pi a^2 p / E'): a scale for volume control's first pressure and its strain check."""
        mat = scene.material
        a = 0.5 * sum(scene.cracks[k].length for k in cracks)
        return 2 * math.pi * a * a / effective_modulus(mat.E, mat.nu, mat.plane)

    @staticmethod
    def effective_modulus(scene: Scene) -> float:
        """E' of the plane state: E in plane stress, E / (1 - nu^2) in plane strain."""
        return effective_modulus(scene.material.E, scene.material.nu, scene.material.plane)





def check_supports(scene: Scene, loads: Loads) -> None:
    """Loads given directly: the scene's exact rigid-motion check on their supports."""
    boundary = {lab: BoundaryCondition("clamped") for lab in loads.clamped}
    boundary.update({lab: BoundaryCondition("roller") for lab in loads.roller})
    boundary.update({lab: BoundaryCondition("displacement", (0.0, 0.0)) for lab in loads.displacement})
    scene.with_(boundary=boundary)  # raises SceneError (a ValueError) if a part is not held


def check_pressure_determined(scene: Scene, loads: Loads | None = None) -> None:
    """Refuse an incompressible body (plane strain, nu = 1/2) with no traction edge.

    Then sigma + c I solves the problem for every constant c: the pressure is
    undetermined. An edge absent from [boundary] is traction-free and fixes it.
    `loads`: loads given instead of the scene's (None: the scene's supports).
    """
    mat = scene.material
    if mat.plane != "strain" or mat.nu != 0.5:
        return
    if loads is None:
        held = {lab for lab, bc in scene.boundary.items() if bc.type in ("clamped", "roller", "displacement")}
    else:
        held = set(loads.clamped) | set(loads.roller) | set(loads.displacement)
    if set(scene.boundary_labels) <= held:
        raise InputError(
            "material.nu = 0.5 (incompressible, plane strain) with every edge clamped, displaced or on rollers: "
            "the pressure is undetermined; leave at least one edge traction-free or loaded by a traction, "
            "or use nu < 0.5"
        )


#: the one plane body
PLANAR = BODY = PlanarBody()
