"""Scenes: the geometry, material, loads and supports of one cracked 2D body.

Domain: a simple polygon Omega (vertices listed counter-clockwise) holding zero or more
cracks Gamma_c, each a polyline inside Omega whose end points may lie on the boundary.
PDE (solved elsewhere): 2D linear elasticity, -div sigma = f, with unilateral
contact on every crack, frictionless or with Coulomb friction (README, the introduction).

A :class:`Scene` is plain, immutable data. It is validated completely when it is built
(``__post_init__``), before any meshing, so no invalid Scene can exist: every bad field
raises :class:`SceneError` (a ``ValueError``) with a one-line message naming the field
and what is allowed. This module is pure geometry (its predicates and distances are shapely's): it imports neither ngsolve nor netgen.

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

from __future__ import annotations

import dataclasses
import functools
import json
import math
import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import shapely

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]

__all__ = [
    "GEOMETRY_RTOL",
    "HELD_RANK_RTOL",
    "BOUNDARY_TYPES",
    "PLANE_TYPES",
    "EXACT_KINDS",
    "SceneError",
    "FrozenMap",
    "Material",
    "BoundaryCondition",
    "Crack",
    "Part",
    "Scene",
]

#: Relative geometric tolerance. Two points closer than ``GEOMETRY_RTOL * diameter``
#: (diameter of the polygon) are the same point; a point that close to an edge lies on
#: it. Used for "on the boundary", "zero length", "touches" and "crosses" decisions.
GEOMETRY_RTOL = 1e-10

#: Relative threshold on singular values in the rigid-motion rank check of
#: :meth:`Scene.check_held`: the 3 constraint columns (two translations, one rotation
#: about a point inside the part, lengths scaled by the diameter) are O(1), so a
#: singular value below ``HELD_RANK_RTOL`` times the largest one counts as zero.
HELD_RANK_RTOL = 1e-8

#: Allowed boundary-condition types, and whether each takes a ``value``.
BOUNDARY_TYPES: Mapping[str, bool] = {
    "clamped": False,
    "displacement": True,
    "roller": False,
    "traction": True,
}

#: Allowed values of ``material.plane``.
PLANE_TYPES = ("strain", "stress")

#: Allowed ``[exact]`` kinds and their keys (besides ``kind``):
#: ``griffith``: a centre crack of half-length ``a`` under remote tension ``p`` normal
#: to it, centred at ``center``; in plane strain the full opening is
#: ``[u].nu = 4 p (1 - nu^2) / E * sqrt(a^2 - s^2)``, s the distance from the centre.
#: ``uniform-stress``: the exact stress is the constant ``sigma = [s_xx, s_yy, s_xy]``.
#: ``inclined``: a straight crack of half-length ``a`` centred at ``center``, its
#: tangent at ``angle`` degrees from the x axis, under the remote uniaxial stress
#: sigma_yy = ``p`` (p < 0: compression). On the crack, sigma_n = p cos^2(angle) and
#: tau = p sin(angle) cos(angle); the crack opens as Griffith's under sigma_n when
#: sigma_n > 0, stays closed otherwise, and slides as
#: ``[u].t = 4 (1 - nu^2) / E * tau_eff * sqrt(a^2 - s^2)`` (plane strain), tau_eff = tau
#: without friction.
EXACT_KINDS: Mapping[str, tuple[str, ...]] = {
    "griffith": ("a", "p", "center"),
    "uniform-stress": ("sigma",),
    "inclined": ("a", "p", "angle", "center"),
}

Point = tuple[float, float]

_TOP_KEYS = ("name", "description", "domain", "crack", "material", "load", "boundary",
             "mesh", "exact")


class SceneError(ValueError):
    """A scene field is invalid; the message names the field and what is allowed."""


# --------------------------------------------------------------------------------------
# small helpers: numbers, formatting
# --------------------------------------------------------------------------------------


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def _fmt_pt(p: Sequence[float]) -> str:
    return f"({_fmt(p[0])}, {_fmt(p[1])})"


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)


def _finite(v: Any, fld: str, what: str = "a finite number") -> float:
    if not _is_number(v) or not math.isfinite(float(v)):
        raise SceneError(f"{fld} = {v!r}: must be {what}")
    return float(v)


def _positive(v: Any, fld: str) -> float:
    what = "a finite number > 0"
    x = _finite(v, fld, what)
    if not x > 0:
        raise SceneError(f"{fld} = {v!r}: must be {what}")
    return x


def _pair(v: Any, fld: str, what: str = "a list of 2 finite numbers [x, y]") -> Point:
    if (isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) != 2
            or not all(_is_number(c) and math.isfinite(float(c)) for c in v)):
        raise SceneError(f"{fld} = {_short(v)}: must be {what}")
    return (float(v[0]), float(v[1]))


def _points(v: Any, fld: str, minimum: int, what: str) -> tuple[Point, ...]:
    if isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) < minimum:
        raise SceneError(f"{fld} = {_short(v)}: must be {what}")
    return tuple(_pair(p, f"{fld}[{i}]") for i, p in enumerate(v))


def _short(v: Any, limit: int = 60) -> str:
    s = repr(v)
    return s if len(s) <= limit else s[: limit - 3] + "..."


def _check_keys(d: Mapping[str, Any], allowed: Sequence[str], fld: str) -> None:
    unknown = [k for k in d if k not in allowed]
    if unknown:
        where = f"{fld}: unknown key" if fld else "unknown top-level key"
        s = "s" if len(unknown) > 1 else ""
        raise SceneError(f"{where}{s} {', '.join(repr(k) for k in unknown)}; "
                         f"allowed keys: {', '.join(allowed)}")


def _table(d: Mapping[str, Any], key: str, fld: str) -> Mapping[str, Any]:
    t = d.get(key, {})
    if not isinstance(t, Mapping):
        raise SceneError(f"{fld} = {_short(t)}: must be a table ([{fld}] in TOML)")
    return t


def _unique(seq: Sequence[str]) -> list[str]:
    return list(dict.fromkeys(seq))


class FrozenMap(Mapping):
    """An immutable, hashable, insertion-ordered mapping (compares equal as a dict)."""

    __slots__ = ("_d",)

    def __init__(self, items: Mapping[Any, Any] | Sequence[tuple[Any, Any]] = ()) -> None:
        self._d = dict(items)

    def __getitem__(self, key: Any) -> Any:
        return self._d[key]

    def __iter__(self) -> Iterator[Any]:
        return iter(self._d)

    def __len__(self) -> int:
        return len(self._d)

    def __hash__(self) -> int:
        return hash(frozenset(self._d.items()))

    def __repr__(self) -> str:
        return f"FrozenMap({self._d!r})"


# --------------------------------------------------------------------------------------
# plane geometry (shapely's predicates and distances)
# --------------------------------------------------------------------------------------


def _sub(p: Point, q: Point) -> Point:
    return (p[0] - q[0], p[1] - q[1])


def _cross(a: Point, b: Point) -> float:
    return a[0] * b[1] - a[1] * b[0]


def _dot(a: Point, b: Point) -> float:
    return a[0] * b[0] + a[1] * b[1]


def _dist(p: Point, q: Point) -> float:
    return math.hypot(p[0] - q[0], p[1] - q[1])


def _mid(p: Point, q: Point) -> Point:
    return (0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]))


def _point_segment_distance(x: Point, p: Point, q: Point) -> float:
    if p == q:
        return _dist(x, p)
    return shapely.Point(x).distance(shapely.LineString([p, q]))


def _segment_distance(p1: Point, p2: Point, q1: Point, q2: Point) -> float:
    """Distance between two closed segments (0 if they cross or touch)."""
    a = shapely.LineString([p1, p2]) if p1 != p2 else shapely.Point(p1)
    b = shapely.LineString([q1, q2]) if q1 != q2 else shapely.Point(q1)
    return a.distance(b)


def _signed_area(poly: Sequence[Point]) -> float:
    n = len(poly)
    return 0.5 * sum(_cross(poly[i], poly[(i + 1) % n]) for i in range(n))


@functools.lru_cache(maxsize=256)
def _polygon(poly: tuple[Point, ...]) -> shapely.Polygon:
    """The shapely polygon of a simple loop of vertices (cached: scenes are immutable)."""
    return shapely.Polygon(poly)


def _inside(x: Point, poly: Sequence[Point]) -> bool:
    """True if x lies strictly inside the simple polygon (points on its boundary are not)."""
    return _polygon(tuple(poly)).contains(shapely.Point(x))


def _boundary_distance(x: Point, poly: Sequence[Point]) -> float:
    return _polygon(tuple(poly)).exterior.distance(shapely.Point(x))


def _interior_point(poly: Sequence[Point]) -> Point:
    """A point strictly inside a simple polygon."""
    p = _polygon(tuple(poly)).representative_point()
    return (p.x, p.y)


def _check_polyline_simple(pts: Sequence[Point], fld: str, tol: float, closed: bool,
                           what: str) -> None:
    """Refuse zero-length segments, back-tracking adjacent segments and any contact
    between non-adjacent segments."""
    n = len(pts)
    m = n if closed else n - 1
    segs = [(pts[i], pts[(i + 1) % n]) for i in range(m)]
    for i, (p, q) in enumerate(segs):
        if _dist(p, q) <= tol:
            j = (i + 1) % n
            raise SceneError(
                f"{fld}: {what} {i} from point {i} {_fmt_pt(p)} to point {j} {_fmt_pt(q)} "
                f"has zero length; consecutive points must differ"
                + ("; do not repeat the first vertex at the end (the polygon closes "
                   "itself)" if closed and j == 0 else ""))
    for i in range(m):
        for j in range(i + 1, m):
            adjacent = j == i + 1 or (closed and i == 0 and j == m - 1)
            (p1, p2), (q1, q2) = segs[i], segs[j]
            if adjacent:
                # shared point: p2 == q1 (or q2 == p1 when closing the loop); the two
                # segments may only meet there, so neither far end may touch the other
                if j == i + 1:
                    far_a, far_b = p1, q2
                else:
                    far_a, far_b = p2, q1
                bad = (_point_segment_distance(far_a, q1, q2) <= tol
                       or _point_segment_distance(far_b, p1, p2) <= tol)
            else:
                bad = _segment_distance(p1, p2, q1, q2) <= tol
            if bad:
                rule = ("the polygon must be simple" if closed
                        else "a crack must not cross or touch itself")
                raise SceneError(
                    f"{fld}: {what}s {i} {_fmt_pt(p1)}-{_fmt_pt(p2)} and {j} "
                    f"{_fmt_pt(q1)}-{_fmt_pt(q2)} cross, touch or overlap; {rule}")


# --------------------------------------------------------------------------------------
# Material, BoundaryCondition, Crack
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Material:
    """Isotropic linear elastic material.

    ``E`` Young's modulus (> 0, stress units), ``nu`` Poisson's ratio in (-1, 1/2]
    (1/2, incompressible, is allowed: the mixed elements do not lock), ``plane`` the 2D
    reduction: ``"strain"`` (eps_zz = 0, default) or ``"stress"`` (sigma_zz = 0).
    """

    E: float
    nu: float
    plane: str = "strain"

    def __post_init__(self) -> None:
        object.__setattr__(self, "E", _positive(self.E, "material.E"))
        nu = self.nu
        if not _is_number(nu):
            raise SceneError(f"material.nu = {nu!r}: must be a number in (-1, 1/2]")
        if not -1.0 < float(nu) <= 0.5:
            raise SceneError(f"material.nu = {nu!r}: must lie in (-1, 1/2]")
        object.__setattr__(self, "nu", float(nu))
        if not isinstance(self.plane, str) or self.plane not in PLANE_TYPES:
            raise SceneError(f"material.plane = {self.plane!r}: allowed values are "
                             f"{', '.join(PLANE_TYPES)}")

    @classmethod
    def from_dict(cls, d: Any) -> Material:
        """Build from a ``[material]`` table: keys E, nu, plane (optional)."""
        if isinstance(d, Material):
            return d
        if not isinstance(d, Mapping):
            raise SceneError(f"material = {_short(d)}: must be a table with keys E, nu, "
                             f"plane")
        _check_keys(d, ("E", "nu", "plane"), "material")
        for key, hint in (("E", "Young's modulus, a finite number > 0"),
                          ("nu", "Poisson's ratio in (-1, 1/2]")):
            if key not in d:
                raise SceneError(f"material.{key}: missing; give {hint}")
        return cls(E=d["E"], nu=d["nu"], plane=d.get("plane", "strain"))

    def to_dict(self) -> dict[str, Any]:
        return {"E": self.E, "nu": self.nu, "plane": self.plane}


def _condition_parts(type_: Any, value: Any, fld: str) -> tuple[str, Point | None]:
    if not isinstance(type_, str) or type_ not in BOUNDARY_TYPES:
        raise SceneError(f"{fld}.type = {type_!r}: allowed types are "
                         f"{', '.join(BOUNDARY_TYPES)}")
    needs_value = BOUNDARY_TYPES[type_]
    if needs_value and value is None:
        if type_ == "traction":
            edge = fld.split(".", 1)[1] if "." in fld else "<label>"
            raise SceneError(
                f"{fld}.value: missing; type = 'traction' needs value = [gx, gy] "
                f"(sigma n = g); for a traction-free edge omit [boundary.{edge}] entirely")
        raise SceneError(f"{fld}.value: missing; type = {type_!r} needs value = [ux, uy]")
    if not needs_value and value is not None:
        hint = (" (u = 0); use type = 'displacement' to prescribe a value"
                if type_ == "clamped" else " (u.n = 0)")
        raise SceneError(f"{fld}.value = {_short(value)}: type = {type_!r} takes no "
                         f"value{hint}; remove it")
    return type_, (None if value is None else _pair(value, f"{fld}.value"))


@dataclass(frozen=True)
class BoundaryCondition:
    """A condition on every edge piece carrying one label.

    ``type``: ``clamped`` (u = 0), ``displacement`` (u = value), ``roller`` (u.n = 0,
    zero tangential traction; n the outward normal), ``traction`` (sigma n = value).
    ``value``: (x, y) components; required for displacement and traction, refused for
    clamped and roller.
    """

    type: str
    value: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        _, v = _condition_parts(self.type, self.value, "boundary.<label>")
        object.__setattr__(self, "value", v)

    @classmethod
    def from_dict(cls, d: Any, fld: str = "boundary.<label>") -> BoundaryCondition:
        """Build from a ``[boundary.<label>]`` table (keys type, value); ``fld`` names
        the table in error messages."""
        if isinstance(d, BoundaryCondition):
            return d
        if not isinstance(d, Mapping):
            raise SceneError(f"{fld} = {_short(d)}: must be a table with keys type, value")
        _check_keys(d, ("type", "value"), fld)
        if "type" not in d:
            raise SceneError(f"{fld}.type: missing; allowed types are "
                             f"{', '.join(BOUNDARY_TYPES)}")
        t, v = _condition_parts(d["type"], d.get("value"), fld)
        return cls(t, v)

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"type": self.type}
        if self.value is not None:
            d["value"] = list(self.value)
        return d

    @property
    def holds(self) -> str:
        """Which rigid motions a piece with this condition removes: ``"all"`` (clamped,
        displacement), ``"normal"`` (roller) or ``"none"`` (traction)."""
        return {"clamped": "all", "displacement": "all", "roller": "normal"}.get(
            self.type, "none")


def _crack_points(v: Any, fld: str, tol: float | None) -> tuple[Point, ...]:
    """Coerce and check a crack polyline on its own (not against the domain)."""
    pts = _points(v, f"{fld}.points", 2,
                  "a list of 2 or more points [[x0, y0], [x1, y1], ...]")
    if tol is None:
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        tol = GEOMETRY_RTOL * math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    _check_polyline_simple(pts, f"{fld}.points", tol, closed=False, what="segment")
    return pts


def _friction(v: Any, fld: str) -> float:
    """A Coulomb coefficient: a finite number >= 0."""
    what = "a finite number >= 0 (the Coulomb friction coefficient; 0: frictionless)"
    x = _finite(v, fld, what)
    if x < 0:
        raise SceneError(f"{fld} = {v!r}: must be {what}")
    return x


@dataclass(frozen=True)
class Crack:
    """A crack: a polyline of two or more points, from ``points[0]`` to ``points[-1]``.

    On each segment the unit tangent ``t`` points from the first towards the last point
    and the normal is ``nu = (-t_y, t_x)``; the ``+`` face is the side ``nu`` points
    into, ``[u] = u+ - u-``, and the contact condition is ``[u].nu >= 0``.
    ``friction`` is the Coulomb coefficient mu >= 0 of the faces (0: frictionless):
    |sigma_t| <= mu |sigma_n|, with no sliding where the inequality is strict.
    """

    points: tuple[tuple[float, float], ...]
    friction: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", _crack_points(self.points, "crack", None))
        object.__setattr__(self, "friction", _friction(self.friction, "crack.friction"))

    @property
    def segments(self) -> list[tuple[Point, Point]]:
        """The segments ``(p, q)``, in order from the first point."""
        return [(self.points[i], self.points[i + 1]) for i in range(len(self.points) - 1)]

    def segment_lengths(self) -> list[float]:
        return [_dist(p, q) for p, q in self.segments]

    @property
    def length(self) -> float:
        """Total arc length."""
        return sum(self.segment_lengths())

    def tangents(self) -> list[Point]:
        """Unit tangent of each segment, pointing from the first towards the last point."""
        return [((q[0] - p[0]) / L, (q[1] - p[1]) / L)
                for (p, q), L in zip(self.segments, self.segment_lengths())]

    def normals(self) -> list[Point]:
        """Unit normal of each segment: the tangent turned by +90 degrees, (-t_y, t_x)."""
        return [(-t[1], t[0]) for t in self.tangents()]

    def arclength_of_segment_start(self) -> list[float]:
        """Arc length s from the first point to the start of each segment (first is 0)."""
        s, out = 0.0, []
        for L in self.segment_lengths():
            out.append(s)
            s += L
        return out

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"points": [list(p) for p in self.points]}
        if self.friction:
            d["friction"] = self.friction
        return d


# --------------------------------------------------------------------------------------
# Parts of the body
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Part:
    """One connected piece of the body after the through cracks have cut it.

    ``loop``: its boundary vertices, counter-clockwise (outer edges and crack faces).
    ``pieces``: its pieces of the outer boundary, ``(label, p, q)``, counter-clockwise.
    ``crack_faces``: ``(crack index, p, q)`` for each crack segment on its boundary, in
    the loop's direction. ``cracks``: indices of the cracks inside or bounding it.
    ``point``: a point strictly inside it (used to name it in messages).
    """

    loop: tuple[Point, ...]
    pieces: tuple[tuple[str, Point, Point], ...]
    crack_faces: tuple[tuple[int, Point, Point], ...]
    cracks: tuple[int, ...]
    point: Point

    @property
    def labels(self) -> tuple[str, ...]:
        """Distinct labels of its outer-boundary pieces, in loop order."""
        return tuple(_unique([lab for lab, _, _ in self.pieces]))

    @property
    def area(self) -> float:
        return _signed_area(self.loop)

    def contains(self, x: Sequence[float]) -> bool:
        """True if ``x`` lies strictly inside (points on the loop are not inside)."""
        p = (float(x[0]), float(x[1]))
        tol = GEOMETRY_RTOL * max(_dist(a, b) for a in self.loop for b in self.loop)
        return _boundary_distance(p, self.loop) > tol and _inside(p, self.loop)


# --------------------------------------------------------------------------------------
# Scene
# --------------------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class Scene:
    """A cracked 2D elastic body: polygon, cracks, material, loads, supports, mesh sizes.

    Fields (all validated on construction; lists and tables are accepted and stored as
    tuples, :class:`Crack`, :class:`Material`, :class:`BoundaryCondition`):

    ``name``; ``polygon`` the vertices, counter-clockwise; ``labels`` one per edge
    (edge i runs from vertex i to vertex i+1; default ``e0, e1, ...``); ``cracks``;
    ``material``; ``body_force`` f = (fx, fy) or None; ``boundary`` label -> condition
    (unnamed edges are traction-free); ``maxh`` global mesh size, ``crack_h`` size along the cracks, ``grading`` how fast sizes grow (netgen, 0.3 default) and ``tip_h`` local
    size at crack tips (None: the solver decides); ``description`` one line;
    ``exact`` closed-form metadata (see :data:`EXACT_KINDS`) or None.
    """

    name: str
    polygon: tuple[tuple[float, float], ...]
    material: Material
    labels: tuple[str, ...] = ()
    cracks: tuple[Crack, ...] = ()
    body_force: tuple[float, float] | None = None
    boundary: Mapping[str, BoundaryCondition] = field(default_factory=FrozenMap)
    maxh: float | None = None
    tip_h: float | None = None
    crack_h: float | None = None
    grading: float | None = None
    description: str = ""
    exact: Mapping[str, Any] | None = None

    # ---------------------------------------------------------------- validation
    def __post_init__(self) -> None:
        set_ = functools.partial(object.__setattr__, self)
        if not isinstance(self.name, str) or not self.name.strip():
            raise SceneError(f"name = {self.name!r}: must be a non-empty string")
        if not isinstance(self.description, str) or "\n" in self.description:
            raise SceneError(f"description = {_short(self.description)}: must be a "
                             f"one-line string")

        # domain.polygon
        poly = _points(self.polygon, "domain.polygon", 3,
                       "a list of 3 or more vertices [[x0, y0], [x1, y1], ...], "
                       "counter-clockwise")
        set_("polygon", poly)
        diameter = max(_dist(p, q) for p in poly for q in poly)
        if diameter == 0.0:
            raise SceneError("domain.polygon: all vertices coincide; give 3 or more "
                             "distinct vertices, counter-clockwise")
        tol = GEOMETRY_RTOL * diameter
        _check_polyline_simple(poly, "domain.polygon", tol, closed=True, what="edge")
        area = _signed_area(poly)
        if area <= tol * diameter:
            if area < -tol * diameter:
                raise SceneError("domain.polygon: is clockwise; list the vertices "
                                 "counter-clockwise")
            raise SceneError("domain.polygon: has zero area; give a simple polygon with "
                             "its vertices counter-clockwise")

        # domain.labels
        n = len(poly)
        labels = self.labels
        if labels is None or (isinstance(labels, Sequence) and len(labels) == 0):
            labels = tuple(f"e{i}" for i in range(n))
        if isinstance(labels, (str, bytes)) or not isinstance(labels, Sequence):
            raise SceneError(f"domain.labels = {_short(labels)}: must be a list of "
                             f"{n} strings, one per edge")
        if len(labels) != n:
            raise SceneError(f"domain.labels: {len(labels)} labels for {n} edges; give "
                             f"one label per edge (edge i runs from vertex i to vertex "
                             f"i+1)")
        for i, lab in enumerate(labels):
            if not isinstance(lab, str) or not lab:
                raise SceneError(f"domain.labels[{i}] = {lab!r}: must be a non-empty "
                                 f"string")
        set_("labels", tuple(labels))

        # material, load, mesh
        set_("material", Material.from_dict(self.material))
        if self.body_force is not None:
            set_("body_force", _pair(self.body_force, "load.body_force",
                                     "a list of 2 finite numbers [fx, fy]"))
        if self.maxh is not None:
            set_("maxh", _positive(self.maxh, "mesh.maxh"))
        if self.tip_h is not None:
            set_("tip_h", _positive(self.tip_h, "mesh.tip_h"))
        if self.crack_h is not None:
            set_("crack_h", _positive(self.crack_h, "mesh.crack_h"))
        if self.grading is not None:
            g = _positive(self.grading, "mesh.grading")
            if g > 1.0:
                raise SceneError(f"mesh.grading = {_fmt(g)}: must lie in (0, 1] (netgen's default is 0.3)")
            set_("grading", g)

        # cracks
        raw = self.cracks
        if isinstance(raw, (str, bytes, Mapping)) or not isinstance(raw, Sequence):
            raise SceneError(f"crack = {_short(raw)}: must be a list of cracks "
                             f"([[crack]] tables with points = [[x, y], ...] and "
                             f"optionally friction = mu)")
        cracks = []
        for i, c in enumerate(raw):
            fld = f"crack[{i}]"
            pts_raw = c.points if isinstance(c, Crack) else c
            mu = c.friction if isinstance(c, Crack) else 0.0
            if isinstance(pts_raw, Mapping):
                _check_keys(pts_raw, ("points", "friction"), fld)
                if "points" not in pts_raw:
                    raise SceneError(f"{fld}.points: missing; give a polyline "
                                     f"[[x0, y0], [x1, y1], ...]")
                mu = _friction(pts_raw.get("friction", 0.0), f"{fld}.friction")
                pts_raw = pts_raw["points"]
            pts = _crack_points(pts_raw, fld, tol)
            self._check_crack_in_domain(pts, fld, tol)
            for j, other in enumerate(cracks):
                self._check_cracks_disjoint(pts, other.points, i, j, tol)
            cracks.append(c if isinstance(c, Crack) else Crack(pts, mu))
        set_("cracks", tuple(cracks))

        # boundary
        bnd = self.boundary
        if not isinstance(bnd, Mapping):
            raise SceneError(f"boundary = {_short(bnd)}: must be a table of "
                             f"[boundary.<label>] tables")
        allowed = _unique(self.labels)
        conds = {}
        for lab, cond in bnd.items():
            if lab not in allowed:
                raise SceneError(f"boundary.{lab}: unknown edge label; allowed labels: "
                                 f"{', '.join(allowed)}")
            conds[lab] = BoundaryCondition.from_dict(cond, f"boundary.{lab}")
        set_("boundary", FrozenMap(conds))

        # exact
        if self.exact is not None:
            set_("exact", _check_exact(self.exact))

        self.check_held()

    def _check_crack_in_domain(self, pts: tuple[Point, ...], fld: str, tol: float) -> None:
        poly = self.polygon
        n = len(poly)
        last = len(pts) - 1
        for k, p in enumerate(pts):
            d = _boundary_distance(p, poly)
            on = d <= tol
            if not on and not _inside(p, poly):
                raise SceneError(
                    f"{fld}.points[{k}] = {_fmt_pt(p)} lies outside domain.polygon; every "
                    f"crack point must lie inside the polygon (end points may lie on its "
                    f"boundary)")
            if on and 0 < k < last:
                raise SceneError(
                    f"{fld}.points[{k}] = {_fmt_pt(p)} lies on the boundary of "
                    f"domain.polygon; only a crack's first and last points may lie on the "
                    f"boundary, interior points must lie strictly inside")
        ends_on = {k: _boundary_distance(pts[k], poly) <= tol for k in (0, last)}
        for s in range(last):
            a, b = pts[s], pts[s + 1]
            where = f"{fld}.points: segment {s} from {_fmt_pt(a)} to {_fmt_pt(b)}"
            rule = ("a crack must lie inside the polygon and may touch its boundary only "
                    "at its first or last point")
            for e in range(n):
                c, d = poly[e], poly[(e + 1) % n]
                if _segment_distance(a, b, c, d) > tol:
                    continue
                edge = f"edge {e} {self.labels[e]!r} of domain.polygon"
                contacts = [x for x in (a, b) if _point_segment_distance(x, c, d) <= tol]
                contacts += [x for x in (c, d) if _point_segment_distance(x, a, b) <= tol]
                if not contacts:
                    raise SceneError(f"{where} crosses {edge}; {rule}")
                if max(_dist(x, y) for x in contacts for y in contacts) > tol:
                    raise SceneError(f"{where} runs along {edge}; {rule}")
                x = contacts[0]
                allowed = [pts[k] for k in (0, last) if ends_on[k]]
                if not any(_dist(x, y) <= tol for y in allowed):
                    raise SceneError(f"{where} touches {edge} at {_fmt_pt(x)}; {rule}")
            m = _mid(a, b)
            if _boundary_distance(m, poly) <= tol or not _inside(m, poly):
                raise SceneError(f"{where} leaves the domain (its midpoint "
                                 f"{_fmt_pt(m)} is not inside domain.polygon); {rule}")

    @staticmethod
    def _check_cracks_disjoint(pts: Sequence[Point], other: Sequence[Point], i: int,
                               j: int, tol: float) -> None:
        for s in range(len(pts) - 1):
            for r in range(len(other) - 1):
                if _segment_distance(pts[s], pts[s + 1], other[r], other[r + 1]) <= tol:
                    raise SceneError(
                        f"crack[{i}].points: segment {s} {_fmt_pt(pts[s])}-"
                        f"{_fmt_pt(pts[s + 1])} crosses or touches crack[{j}] (segment "
                        f"{r}); cracks must be disjoint (join them into one polyline "
                        f"or move them apart)")

    # ---------------------------------------------------------------- geometry
    @property
    def diameter(self) -> float:
        """Largest distance between two polygon vertices."""
        return max(_dist(p, q) for p in self.polygon for q in self.polygon)

    @property
    def tol(self) -> float:
        """Absolute geometric tolerance, ``GEOMETRY_RTOL * diameter``."""
        return GEOMETRY_RTOL * self.diameter

    def edges(self) -> list[tuple[str, Point, Point]]:
        """The polygon edges ``(label, p, q)``, edge i from vertex i to vertex i+1."""
        n = len(self.polygon)
        return [(self.labels[i], self.polygon[i], self.polygon[(i + 1) % n])
                for i in range(n)]

    def on_boundary(self, x: Sequence[float]) -> bool:
        """True if ``x`` lies on the polygon's boundary (within :attr:`tol`)."""
        return _boundary_distance((float(x[0]), float(x[1])), self.polygon) <= self.tol

    def crack_end_on_boundary(self, i: int) -> tuple[bool, bool]:
        """Whether the first and the last point of crack ``i`` lie on the boundary."""
        pts = self.cracks[i].points
        return self.on_boundary(pts[0]), self.on_boundary(pts[-1])

    def crack_tips(self) -> list[tuple[int, Point]]:
        """Crack end points strictly inside the domain, as ``(crack index, point)``."""
        out = []
        for i, c in enumerate(self.cracks):
            for k, on in zip((0, -1), self.crack_end_on_boundary(i)):
                if not on:
                    out.append((i, c.points[k]))
        return out

    def through_cracks(self) -> list[int]:
        """Indices of the cracks with both ends on the boundary (they cut a part in two)."""
        return [i for i in range(len(self.cracks)) if all(self.crack_end_on_boundary(i))]

    def edge_pieces(self) -> list[tuple[str, Point, Point]]:
        """The polygon edges split at every crack end point lying on them, as
        ``(label, p, q)`` in counter-clockwise order."""
        tol = self.tol
        ends = [c.points[k] for i, c in enumerate(self.cracks)
                for k, on in zip((0, -1), self.crack_end_on_boundary(i)) if on]
        out = []
        for lab, p, q in self.edges():
            d = _sub(q, p)
            cuts = sorted(_dot(_sub(x, p), d) / _dot(d, d) for x in ends
                          if _point_segment_distance(x, p, q) <= tol
                          and _dist(x, p) > tol and _dist(x, q) > tol)
            pts = [p] + [(p[0] + t * d[0], p[1] + t * d[1]) for t in cuts] + [q]
            out += [(lab, pts[k], pts[k + 1]) for k in range(len(pts) - 1)]
        return out

    def parts(self) -> tuple[Part, ...]:
        """The connected pieces of the body after the through cracks cut it."""
        return self._parts

    @functools.cached_property
    def _parts(self) -> tuple[Part, ...]:
        tol = self.tol
        n = len(self.polygon)
        # a loop: vertices V and tags T, T[i] for the edge V[i] -> V[i+1]
        loops: list[tuple[list[Point], list[tuple[str, Any]]]] = [
            (list(self.polygon), [("edge", self.labels[i]) for i in range(n)])]
        through = self.through_cracks()
        for c in through:
            P = self.cracks[c].points
            mid = _mid(P[0], P[1])
            li = next(k for k, (V, _) in enumerate(loops) if _inside(mid, V))
            V, T = list(loops[li][0]), list(loops[li][1])
            _insert_on_loop(V, T, P[0], tol)
            _insert_on_loop(V, T, P[-1], tol)
            i0 = _insert_on_loop(V, T, P[0], tol)  # index again after the 2nd insertion
            i1 = _insert_on_loop(V, T, P[-1], tol)
            m = len(V)

            def arc(a: int, b: int) -> list[int]:
                return [(a + k) % m for k in range((b - a) % m + 1)]

            inner = list(P[1:-1])
            ia, ib = arc(i0, i1), arc(i1, i0)
            crack_tags = [("crack", c)] * (len(P) - 1)
            # a: boundary from the crack's first to its last point, back along the crack
            loop_a = ([V[k] for k in ia] + inner[::-1],
                      [T[k] for k in ia[:-1]] + crack_tags)
            # b: boundary from the crack's last to its first point, on along the crack
            loop_b = ([V[k] for k in ib] + inner, [T[k] for k in ib[:-1]] + crack_tags)
            loops[li:li + 1] = [loop_a, loop_b]

        parts = []
        for V, T in loops:
            m = len(V)
            pieces, faces, ids = [], [], []
            for k in range(m):
                p, q = V[k], V[(k + 1) % m]
                kind, tag = T[k]
                if kind == "edge":
                    pieces.append((tag, p, q))
                else:
                    faces.append((tag, p, q))
                    ids.append(tag)
            for i, crack in enumerate(self.cracks):
                if i not in through and _inside(
                        _mid(crack.points[0], crack.points[1]), V):
                    ids.append(i)
            parts.append(Part(loop=tuple(V), pieces=tuple(pieces),
                              crack_faces=tuple(faces), cracks=tuple(sorted(set(ids))),
                              point=_interior_point(V)))
        return tuple(parts)

    def check_held(self) -> None:
        """Refuse a scene in which some part can move rigidly (the answer is not unique).

        Rigid motions are v(x) = a + theta (-y, x). Each clamped or displacement piece
        imposes v = 0 at its two end points, each roller piece v.n = 0 there; a part is
        held when these constraints have rank 3. Contact on crack faces is unilateral
        and holds nothing.
        """
        L = self.diameter
        for part in self.parts():
            c = part.point
            rows, rollers = [], []
            for lab, p, q in part.pieces:
                cond = self.boundary.get(lab)
                length = _dist(p, q)
                if cond is None or cond.holds == "none" or length <= self.tol:
                    continue
                n_out = ((q[1] - p[1]) / length, -(q[0] - p[0]) / length)
                if cond.holds == "normal":
                    rollers.append(lab)
                for x in (p, q):
                    X, Y = (x[0] - c[0]) / L, (x[1] - c[1]) / L
                    if cond.holds == "all":
                        rows += [[1.0, 0.0, -Y], [0.0, 1.0, X]]
                    else:
                        rows.append([n_out[0], n_out[1], -n_out[0] * Y + n_out[1] * X])
            where = f"boundary: the part of the body containing point {_fmt_pt(c)}"
            if not rows:
                raise SceneError(
                    f"{where} is held by nothing (no clamped, displacement or roller "
                    f"edge), so the answer is not unique; add a clamped/displacement/"
                    f"roller edge to it")
            _, s, vt = np.linalg.svd(np.array(rows), full_matrices=True)
            rank = int(np.sum(s > HELD_RANK_RTOL * s[0]))
            if rank < 3:
                a1, a2, th = vt[-1]
                if abs(th) <= HELD_RANK_RTOL * math.hypot(a1, a2):
                    free = f"the translation along {_fmt_pt(_direction(a1, a2))}"
                else:
                    free = ("the rotation about "
                            f"{_fmt_pt((c[0] - L * a2 / th, c[1] + L * a1 / th))}")
                raise SceneError(
                    f"{where} is held only by roller edges "
                    f"({', '.join(_unique(rollers))}) that leave {free} free, so the answer "
                    f"is not unique; add a clamped/displacement edge or a roller with a "
                    f"non-parallel normal to it")

    # ---------------------------------------------------------------- I/O
    @classmethod
    def from_dict(cls, d: Mapping[str, Any], name: str | None = None) -> Scene:
        """Build from the TOML structure (a dict as ``tomllib`` returns it).

        ``name``, if given, overrides ``d["name"]``; one of the two is required.
        """
        if not isinstance(d, Mapping):
            raise SceneError(f"scene = {_short(d)}: must be a table (the TOML document)")
        _check_keys(d, _TOP_KEYS, "")
        if name is None:
            if "name" not in d:
                raise SceneError("name: missing; give the scene a name (a non-empty "
                                 "string)")
            name = d["name"]
        domain = _table(d, "domain", "domain")
        _check_keys(domain, ("polygon", "labels"), "domain")
        if "polygon" not in domain:
            raise SceneError("domain.polygon: missing; give 3 or more vertices "
                             "[[x0, y0], [x1, y1], ...], counter-clockwise")
        cracks = d.get("crack", [])
        if isinstance(cracks, Mapping) or isinstance(cracks, (str, bytes)) \
                or not isinstance(cracks, Sequence):
            raise SceneError(f"crack = {_short(cracks)}: must be an array of tables "
                             f"([[crack]] with points = [[x, y], ...])")
        for i, c in enumerate(cracks):
            if not isinstance(c, Mapping):
                raise SceneError(f"crack[{i}] = {_short(c)}: must be a table with key "
                                 f"points ([[crack]] in TOML)")
        if "material" not in d:
            raise SceneError("material: missing; give a [material] table with E, nu and "
                             "optionally plane")
        load = _table(d, "load", "load")
        _check_keys(load, ("body_force",), "load")
        boundary = _table(d, "boundary", "boundary")
        mesh = _table(d, "mesh", "mesh")
        _check_keys(mesh, ("maxh", "tip_h", "crack_h", "grading"), "mesh")
        return cls(
            name=name,
            description=d.get("description", ""),
            polygon=domain["polygon"],
            labels=domain.get("labels", ()),
            cracks=tuple(cracks),
            material=d["material"],
            body_force=load.get("body_force"),
            boundary=boundary,
            maxh=mesh.get("maxh"),
            tip_h=mesh.get("tip_h"),
            crack_h=mesh.get("crack_h"),
            grading=mesh.get("grading"),
            exact=d.get("exact"),
        )

    @classmethod
    def from_toml_string(cls, text: str, name: str | None = None,
                         source: str = "scene") -> Scene:
        """Parse TOML text; ``name`` as in :meth:`from_dict`; ``source`` names the text
        in the message of a TOML syntax error."""
        try:
            d = tomllib.loads(text)
        except tomllib.TOMLDecodeError as err:
            raise SceneError(f"{source}: not valid TOML: {err}") from err
        return cls.from_dict(d, name=name)

    @classmethod
    def from_toml(cls, path: str | Path) -> Scene:
        """Read a scene file; without a ``name`` key the file's stem is the name."""
        path = Path(path)
        try:
            d = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as err:
            raise SceneError(f"{path}: not valid TOML: {err}") from err
        return cls.from_dict(d, name=None if "name" in d else path.stem)

    def to_dict(self) -> dict[str, Any]:
        """The TOML structure (plain dicts, lists, floats, strings); inverse of
        :meth:`from_dict`. Empty optional sections are left out."""
        d: dict[str, Any] = {"name": self.name}
        if self.description:
            d["description"] = self.description
        d["domain"] = {"polygon": [list(p) for p in self.polygon],
                       "labels": list(self.labels)}
        if self.cracks:
            d["crack"] = [c.to_dict() for c in self.cracks]
        d["material"] = self.material.to_dict()
        if self.body_force is not None:
            d["load"] = {"body_force": list(self.body_force)}
        if self.boundary:
            d["boundary"] = {lab: bc.to_dict() for lab, bc in self.boundary.items()}
        mesh = {k: v for k, v in (("maxh", self.maxh), ("tip_h", self.tip_h), ("crack_h", self.crack_h), ("grading", self.grading))
                if v is not None}
        if mesh:
            d["mesh"] = mesh
        if self.exact is not None:
            d["exact"] = {k: list(v) if isinstance(v, tuple) else v
                          for k, v in self.exact.items()}
        return d

    def to_toml_string(self) -> str:
        """The scene as TOML text; ``Scene.from_toml_string`` of it gives an equal scene."""
        return _dump_toml(self.to_dict())

    def with_(self, **changes: Any) -> Scene:
        """A new, validated scene with some fields replaced.

        Accepts any field (``name``, ``polygon``, ``labels``, ``cracks``, ``material``,
        ``body_force``, ``boundary``, ``maxh``, ``tip_h``, ``description``, ``exact``)
        and the material's ``E``, ``nu``, ``plane``. ``boundary`` replaces the whole
        mapping (label -> BoundaryCondition or {"type": ..., "value": ...}).
        ``friction`` sets the Coulomb coefficient of every crack.
        """
        names = [f.name for f in dataclasses.fields(self)]
        mat_keys = ("E", "nu", "plane")
        if "friction" in changes:
            mu = _friction(changes.pop("friction"), "friction")
            cracks = changes.get("cracks", self.cracks)
            if isinstance(cracks, (str, bytes, Mapping)) or not isinstance(cracks, Sequence):
                raise SceneError(f"crack = {_short(cracks)}: must be a list of cracks")
            changes["cracks"] = tuple(
                dataclasses.replace(c, friction=mu) if isinstance(c, Crack)
                else {**c, "friction": mu} if isinstance(c, Mapping) else {"points": c, "friction": mu}
                for c in cracks)
        unknown = [k for k in changes if k not in names and k not in mat_keys]
        if unknown:
            allowed = ", ".join(names + list(mat_keys))
            raise SceneError(f"with_: unknown field{'s' if len(unknown) > 1 else ''} "
                             f"{', '.join(unknown)}; allowed: {allowed}")
        mat = {k: changes.pop(k) for k in mat_keys if k in changes}
        if mat:
            base = Material.from_dict(changes.get("material", self.material))
            changes["material"] = dataclasses.replace(base, **mat)
        return dataclasses.replace(self, **changes)


def _direction(a: float, b: float) -> Point:
    """The unit vector along (a, b), signed so that its larger component is positive,
    with round-off components set to zero (for messages)."""
    h = math.hypot(a, b)
    a, b = a / h, b / h
    if (a if abs(a) >= abs(b) else b) < 0:
        a, b = -a, -b
    return (0.0 if abs(a) < HELD_RANK_RTOL else a, 0.0 if abs(b) < HELD_RANK_RTOL else b)


def _insert_on_loop(V: list[Point], T: list[Any], x: Point, tol: float) -> int:
    """Index of ``x`` among the loop's vertices, inserting it on its edge if needed."""
    for i, v in enumerate(V):
        if _dist(v, x) <= tol:
            return i
    m = len(V)
    for i in range(m):
        if _point_segment_distance(x, V[i], V[(i + 1) % m]) <= tol:
            V.insert(i + 1, x)
            T.insert(i + 1, T[i])
            return i + 1
    raise AssertionError(f"{_fmt_pt(x)} is not on the loop")  # excluded by validation


def _check_exact(ex: Any) -> FrozenMap:
    if not isinstance(ex, Mapping):
        raise SceneError(f"exact = {_short(ex)}: must be a table with key kind "
                         f"({', '.join(EXACT_KINDS)})")
    kind = ex.get("kind")
    if kind not in EXACT_KINDS:
        raise SceneError(f"exact.kind = {kind!r}: allowed kinds are "
                         f"{', '.join(EXACT_KINDS)}")
    keys = EXACT_KINDS[kind]
    _check_keys(ex, ("kind",) + keys, "exact")
    out: dict[str, Any] = {"kind": kind}
    for k in keys:
        if k not in ex:
            raise SceneError(f"exact.{k}: missing; exact.kind = {kind!r} needs keys "
                             f"{', '.join(keys)}")
        v, fld = ex[k], f"exact.{k}"
        if k == "a":
            out[k] = _positive(v, fld)
        elif k in ("p", "angle"):
            out[k] = _finite(v, fld)
        elif k == "center":
            out[k] = _pair(v, fld)
        elif k == "sigma":
            if (isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) != 3
                    or not all(_is_number(c) and math.isfinite(c) for c in v)):
                raise SceneError(f"{fld} = {_short(v)}: must be 3 finite numbers "
                                 f"[s_xx, s_yy, s_xy]")
            out[k] = tuple(float(c) for c in v)
    return FrozenMap(out)


# --------------------------------------------------------------------------------------
# a small TOML writer for the scene structure
# --------------------------------------------------------------------------------------

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _toml_key(k: str) -> str:
    return k if _BARE_KEY.match(k) else _toml_value(k)


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise SceneError(f"cannot write {v!r} to TOML")  # excluded by validation
        return repr(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, Mapping) for x in v)


def _dump_toml(d: Mapping[str, Any]) -> str:
    lines: list[str] = []

    def scalars(t: Mapping[str, Any]) -> None:
        for k, v in t.items():
            if not isinstance(v, Mapping) and not _is_table_array(v):
                lines.append(f"{_toml_key(k)} = {_toml_value(v)}")

    def tables(path: list[str], t: Mapping[str, Any]) -> None:
        for k, v in t.items():
            sub = path + [_toml_key(k)]
            if isinstance(v, Mapping):
                has_scalars = any(not isinstance(x, Mapping) and not _is_table_array(x)
                                  for x in v.values())
                if has_scalars or not v:
                    lines.extend(["", f"[{'.'.join(sub)}]"])
                    scalars(v)
                tables(sub, v)
            elif _is_table_array(v):
                for item in v:
                    lines.extend(["", f"[[{'.'.join(sub)}]]"])
                    scalars(item)
                    tables(sub, item)

    scalars(d)
    tables([], d)
    return "\n".join(lines) + "\n"
