"""Scenes: the geometry, material, loads and supports of one cracked 2D body.

Domain: a simple polygon (vertices listed counter-clockwise), less zero or more holes
(polygons or circles inside it), holding zero or more cracks Gamma_c, each a polyline
inside the body whose end points may lie on the outer boundary.
PDE (solved elsewhere): 2D linear elasticity, -div sigma = f, with unilateral
contact on every crack, frictionless or with Coulomb friction (README, the introduction).

A :class:`PlanarScene` (a kind of :class:`ngcrack.core.scene.Scene`, which ``nc.Scene(...)`` makes
from these fields) is plain, immutable data. It is validated completely when it is built,
before any meshing, so no invalid Scene can exist: every bad field raises
:class:`SceneError` (a ``ValueError``) with a one-line message naming the field and
what is allowed. The package is pure geometry (its predicates and distances are
GEOS's formulas on numpy, shapely only for large or holed scenes): it imports neither
ngsolve nor netgen.

Modules, lowest first (each imports only those above it):

``measures``  plane measures: diameter, area, distances (imports nothing of ngcrack)
``planar``    simple polylines, cracks inside the polygon and apart from each other
``types``     Material, BoundaryCondition, Crack and the allowed values
``holes``     Hole: polygons and circles inside the body
``points``    PointCondition: loads and supports at points of the outer boundary
``topology``  the parts the through cracks cut, the rigid-motion (held) check
``toml``      reading and writing scene files
``body``      the Scene itself

Conventions
-----------
* Edge ``i`` of the polygon runs from vertex ``i`` to vertex ``i + 1`` (cyclically) and
  carries ``labels[i]``; several edges may share a label.
* A crack's unit tangent ``t`` points from its first towards its last point along each
  segment; its normal is ``nu = (-t_y, t_x)`` (``t`` turned by +90 degrees). The ``+``
  face is the side ``nu`` points into, and the jump is ``[u] = u+ - u-``.
* Boundary conditions, by label: ``clamped`` (u = 0), ``displacement`` (u = value),
  ``roller`` (u.n = 0 and zero tangential traction), ``traction`` (sigma n = value).
  Edges whose label is not named are traction-free.
* Units are the user's, but consistent: E and tractions in stress units, body force in
  force per unit volume (per unit area of the plane, unit thickness).

Geometric comparisons use the absolute tolerance ``GEOMETRY_RTOL * diameter`` where
``diameter`` is the largest distance between two polygon vertices.
"""

from ...core.fields import FrozenMap, SceneError
from .body import MAX_POLYGON_VERTICES, PlanarScene, Scene
from .holes import CIRCLE_SEGMENTS, MAX_HOLES, Hole
from .measures import Point, diameter, polygon_area
from .points import MAX_POINTS, POINT_TYPES, PointCondition
from .topology import HELD_RANK_RTOL, Part
from .types import (
    BOUNDARY_TYPES,
    EXACT_KINDS,
    GEOMETRY_RTOL,
    MAX_BOUNDARY_POINTS,
    MAX_CRACK_POINTS,
    MAX_SCALE,
    MIN_SIZE_RTOL,
    PLANE_TYPES,
    BoundaryCondition,
    Crack,
    Material,
    tip_label,
)

__all__ = [
    "BOUNDARY_TYPES",
    "CIRCLE_SEGMENTS",
    "EXACT_KINDS",
    "GEOMETRY_RTOL",
    "HELD_RANK_RTOL",
    "MAX_BOUNDARY_POINTS",
    "MAX_CRACK_POINTS",
    "MAX_HOLES",
    "MAX_POINTS",
    "MAX_POLYGON_VERTICES",
    "MAX_SCALE",
    "MIN_SIZE_RTOL",
    "PLANE_TYPES",
    "POINT_TYPES",
    "BoundaryCondition",
    "Crack",
    "FrozenMap",
    "Hole",
    "Material",
    "Part",
    "Point",
    "PointCondition",
    "PlanarScene",
    "Scene",
    "SceneError",
    "diameter",
    "polygon_area",
    "tip_label",
]
