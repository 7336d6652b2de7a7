"""How big a 3D solve will be, before meshing: tetrahedra, unknowns, memory; the 3D size guard.

A 3D request grows with the inverse cube of its mesh sizes: a penny at front_h = 0.005 was
still meshing after 180 s, larger ones ended "out of memory" after minutes. `check_size`
estimates the request in milliseconds from the body, the cracks and the sizes, and refuses
it with one line (an InputError, exit 2 on the command line) when the estimated unknowns
exceed the ceiling `max_dof` (default DEFAULT_MAX_DOF) or the estimated peak memory exceeds
what this process may still allocate (`ngcrack.core.memory`), as the 2D guard does
(`ngcrack.planar.sizing`).

The tetrahedron estimate. Netgen makes tetrahedra of edge about the local mesh size h(x),
so a region of volume dV holds about dV / h^3 of them times a constant. The size is maxh = H
away from the cracks; each crack's faces ask for crack_h = h_c, its front (the crack's edge)
for front_h = h_0, and h grows from them with the distance d at the rate g (grading), until
it reaches H. Integrated in closed form, the three parts of the density are

    bulk   V / H^3                                                            (V the body's volume)
    faces  2 A [ (1/(2 g)) (1/h_c^2 - 1/s_c^2) - D / H^3 ],  s_c = h_c + g D, D = min((H - h_c)/g, V/(2A))
    front  L [ (2 pi / g^2) (1/(2 h_0) - 1/s_0 + h_0/(2 s_0^2)) - pi R^2 / H^3 ],
           s_0 = h_0 + g R, R = min((H - h_0)/g, sqrt(V/(pi L)))

(A the cracks' area, L their fronts' length; the faces' band on both sides, the front's tube
all around it, each less the bulk it replaces), and the tetrahedra are TETS_PER_DENSITY times
TETS_PER_BULK, TETS_PER_FACES, TETS_PER_FRONT times them (fitted to the largest relative error
on the measured meshes). Measured against netgen on 19 meshes of 8 scenes (the penny in boxes
of side 20a and 6a and in a cylinder, the bent beam, the inclined penny, an ellipse and a
square crack; front_h 0.03a to 0.5a, crack_h = front_h to 8 front_h, grading 0.2 to 0.8; 509
to 48,727 tetrahedra): estimate / netgen within ESTIMATE_SPREAD, 0.68 to 1.47 (BENCHMARKS.md,
"The 3D size guard"); the front's tube owes most of the tetrahedra of a penny.

Unknowns per tetrahedron and peak memory per unknown are constants of the element and order
(UNKNOWNS_PER_TET, BYTES_PER_UNKNOWN above BASE_MEMORY: measured, the constants say where).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..core.memory import DEFAULT_MAX_DOF, MEMORY_FRACTION, available_memory, check_max_dof, memory_limits
from ..core.memory import format_bytes as _bytes
from .surface import inside_measures

#: tetrahedra per unit of each part of the density integral (module docstring), fitted on 19 netgen meshes
TETS_PER_BULK, TETS_PER_FACES, TETS_PER_FRONT = 10.05, 11.31, 5.30
#: estimate / netgen on those meshes lies in this range (the small meshes and grading 0.2, 0.5 at its ends)
ESTIMATE_SPREAD = (0.68, 1.47)
#: unknowns (total, before condensation) per tetrahedron, by (element, order), measured on the penny (6,809
#: tetrahedra) and the bent beam (1,170): tdnns 48.6-48.9 and 115.0-115.7, h1p1 0.56-0.64, h1p2 4.2-4.5
UNKNOWNS_PER_TET = {("tdnns", 1): 49.0, ("tdnns", 2): 116.0, ("h1p1", 1): 0.64, ("h1p2", 2): 4.5}
#: peak resident memory per unknown in bytes, by (element, order), above BASE_MEMORY: tdnns the largest of the
#: penny solves of BENCHMARKS.md section 17 (closed faces, two active sets: 5.2 kB at order 1, 6.1 kB at order
#: 2), h1p2 measured at 59k and 131k unknowns (31 and 33 kB: the 3D fill of its sparse factorization); h1p1 as
#: h1p2 (its fill per unknown is smaller: an upper bound)
BYTES_PER_UNKNOWN = {("tdnns", 1): 5800, ("tdnns", 2): 6400, ("h1p1", 1): 33000, ("h1p2", 2): 33000}
#: the memory of a 3D solve's process before its unknowns (the interpreter, NGSolve, the mesh): 0.4 GB measured
BASE_MEMORY = 0.4e9
#: the smallest mesh size netgen is asked for, as a fraction of the body's diameter (as in 2D)
MIN_SIZE_RTOL = 1e-6
#: points per curve of a crack's outline when its front's length is measured
OUTLINE_POINTS = 512


def _volume(domain) -> float:
    if hasattr(domain, "volume"):  # a STEP part (solid.parts.StepPart)
        return float(domain.volume)
    if hasattr(domain, "lo"):
        return float(np.prod(np.asarray(domain.hi) - np.asarray(domain.lo)))
    return float(math.pi * domain.radius ** 2 * domain.height)


def front_length(crack) -> float:
    """The length of a crack's front (its outline's perimeter)."""
    p = crack.outline(OUTLINE_POINTS)
    return float(np.sum(np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)))


def density_parts(scene, maxh=None, crack_h=None, front_h=None, grading=None) -> dict[str, float]:
    """The bulk's, the crack faces' and the fronts' parts of the integral of 1 / h^3 (module docstring)."""
    s = scene.mesh_sizes(maxh, crack_h, front_h, grading)
    H, g = s["maxh"], s["grading"]
    hc = min(s["crack_h"], H)
    h0 = min(s["front_h"], hc)
    V = _volume(scene.domain)
    inside = [inside_measures(scene.domain, c) for c in scene.cracks]  # a surface crack: its part inside the body
    A = sum(m[1] for m in inside)
    L = sum(m[2] for m in inside)
    parts = {"maxh": V / H ** 3, "crack_h": 0.0, "front_h": 0.0}
    if A > 0:
        D = min((H - hc) / g, V / (2.0 * A))
        sc = hc + g * D
        parts["crack_h"] = max(2.0 * A * ((1.0 / (2.0 * g)) * (1.0 / hc ** 2 - 1.0 / sc ** 2) - D / H ** 3), 0.0)
    if L > 0:
        R = min((H - h0) / g, math.sqrt(V / (math.pi * L)))
        s0 = h0 + g * R
        tube = (2.0 * math.pi / g ** 2) * (0.5 / h0 - 1.0 / s0 + 0.5 * h0 / s0 ** 2)
        parts["front_h"] = max(L * (tube - math.pi * R ** 2 / H ** 3), 0.0)
    return parts


def estimate_tets(scene, maxh=None, crack_h=None, front_h=None, grading=None) -> float:
    """The estimated tetrahedra of netgen's mesh of `scene` at these sizes (the scene's where None)."""
    p = density_parts(scene, maxh, crack_h, front_h, grading)
    return TETS_PER_BULK * p["maxh"] + TETS_PER_FACES * p["crack_h"] + TETS_PER_FRONT * p["front_h"]


@dataclass(frozen=True)
class SolidSizeEstimate:
    """The estimated size of one 3D solve: tetrahedra, unknowns, peak memory in bytes, and the mesh size that owes
    most of the tetrahedra (`culprit`, its value `size`)."""

    tets: float
    unknowns: float
    memory: float
    culprit: str
    size: float

    def describe(self) -> str:
        return f"about {self.tets:.3g} tetrahedra, {self.unknowns:.3g} unknowns and {_bytes(self.memory)} of memory"


def estimate_size(scene, element: str = "tdnns", order: int | None = None, maxh=None, crack_h=None, front_h=None,
                  grading=None) -> SolidSizeEstimate:
    """Estimated tetrahedra, unknowns and peak memory of a 3D solve of `scene` (module docstring)."""
    order = order or (2 if element == "h1p2" else 1)
    parts = density_parts(scene, maxh, crack_h, front_h, grading)
    weighted = {"maxh": TETS_PER_BULK * parts["maxh"], "crack_h": TETS_PER_FACES * parts["crack_h"],
                "front_h": TETS_PER_FRONT * parts["front_h"]}
    tets = sum(weighted.values())
    unknowns = tets * UNKNOWNS_PER_TET[(element, order)]
    culprit = max(weighted, key=weighted.get)
    size = scene.mesh_sizes(maxh, crack_h, front_h, grading)[culprit]
    return SolidSizeEstimate(tets=tets, unknowns=unknowns, memory=BASE_MEMORY + unknowns * BYTES_PER_UNKNOWN[(element, order)],
                             culprit=culprit, size=size)


def check_mesh_sizes(scene, maxh=None, crack_h=None, front_h=None, grading=None) -> None:
    """Refuse sizes netgen cannot mesh, by name: not a finite number > 0, grading above 1 (netgen gives up and spins:
    grading 5 took 83 s CPU without an answer), a size below MIN_SIZE_RTOL of the body's diameter."""
    given = {"maxh": maxh, "crack_h": crack_h, "front_h": front_h, "grading": grading}
    for name, value in given.items():
        if value is not None and (isinstance(value, (bool, np.bool_))
                                  or not isinstance(value, (int, float, np.integer, np.floating))
                                  or not math.isfinite(float(value)) or not float(value) > 0):
            raise InputError(f"{name} = {value!r}: must be a finite number > 0")
    sizes = scene.mesh_sizes(maxh, crack_h, front_h, grading)
    if sizes["grading"] > 1.0:
        where = "" if grading is not None else " (the scene's [mesh] grading)"
        raise InputError(f"grading = {sizes['grading']:g}{where}: must lie in (0, 1] (netgen's default is 0.3; "
                         f"above 1 netgen gives up meshing)")
    D = scene.size
    for name in ("maxh", "crack_h", "front_h"):
        if sizes[name] < MIN_SIZE_RTOL * D:
            where = "" if given[name] is not None else " (the scene's or the default)"
            raise InputError(f"{name} = {sizes[name]:g}{where}: below the smallest mesh size netgen meshes, "
                             f"{MIN_SIZE_RTOL:g} of the body's diameter {D:g}; give {name} >= {MIN_SIZE_RTOL * D:.3g}")


def check_size(scene, element: str = "tdnns", order: int | None = None, maxh=None, crack_h=None, front_h=None,
               grading=None, max_dof=None) -> SolidSizeEstimate:
    """Refuse a 3D solve, with one line before any meshing, whose mesh sizes netgen cannot mesh
    (`check_mesh_sizes`), whose estimated unknowns exceed the ceiling (max_dof, default DEFAULT_MAX_DOF) or, with
    max_dof None, whose estimated peak memory exceeds MEMORY_FRACTION of what this process may still allocate. The
    line names the size that owes most of the tetrahedra, the estimate and the override; the estimate otherwise."""
    check_max_dof(max_dof)
    check_mesh_sizes(scene, maxh, crack_h, front_h, grading)
    est = estimate_size(scene, element, order, maxh, crack_h, front_h, grading)
    others = " or ".join(k for k in ("maxh", "crack_h", "front_h") if k != est.culprit)
    how = (f"use a larger {est.culprit} (it owes most of the tetrahedra; or a larger {others}), or raise the limit "
           f"with max_dof=N in Python or --max-dof N on the command line")
    case = f"{est.culprit} = {est.size:g}: scene {scene.name!r}, element {element!r}"
    ceiling = DEFAULT_MAX_DOF if max_dof is None else max_dof
    if est.unknowns > ceiling:
        limit = "the default ceiling" if max_dof is None else "max_dof"
        raise InputError(f"{case} would need {est.describe()}; that exceeds {limit} of {int(ceiling)} unknowns; {how}")
    if max_dof is None:
        avail = available_memory()
        if avail is not None and est.memory > MEMORY_FRACTION * avail:
            kind = next((k for k, v in memory_limits().items() if v == avail), "machine")
            where = {"machine": "this machine has", "address space": "this process's address-space limit leaves",
                     "cgroup": "this process's cgroup memory limit leaves"}.get(kind, "this process has")
            raise InputError(f"{case} would need {est.describe()}; {where} {_bytes(avail)} available; {how} (at "
                             f"your own risk)")
    return est
