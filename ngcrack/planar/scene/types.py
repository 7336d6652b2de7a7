"""The small value types of a scene: material, boundary condition, crack; their constants.

Each is a frozen dataclass validated on construction (a bad field raises
:class:`SceneError` naming it), built from its TOML table by ``from_dict`` and written
back by ``to_dict``. The allowed values (boundary types, plane reductions, closed-form
kinds) are data here, so that messages and the TOML reader list the same choices.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ...core.fields import (
    FrozenMap,
    SceneError,
    check_keys,
    finite,
    fmt,
    is_number,
    pair,
    points,
    positive,
    short,
)
from .measures import Point, diameter, dist
from .planar import check_polyline_simple
from .pressure import Pressure, check_pressure, pressure_to_toml

__all__ = [
    "BOUNDARY_TYPES",
    "EXACT_KINDS",
    "GEOMETRY_RTOL",
    "PLANE_TYPES",
    "BoundaryCondition",
    "Crack",
    "Material",
    "tip_label",
]

#: Relative geometric tolerance. Two points closer than ``GEOMETRY_RTOL * diameter``
#: (diameter of the polygon) are the same point; a point that close to an edge lies on
#: it. Used for "on the boundary", "zero length", "touches" and "crosses" decisions.
GEOMETRY_RTOL = 1e-10

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

#: The most points a crack polyline may have. Validation is near-linear; netgen's
#: meshing grows faster (measured here: a crack of 2000 points 16 s, 3000 points 18-29 s,
#: 5000 points 57 s), so the ceilings keep the largest admitted scene near 10 s.
MAX_CRACK_POINTS = 1500
#: The most boundary points of a scene: polygon and hole vertices plus twice the crack
#: points (each crack point is a vertex of both faces).
MAX_BOUNDARY_POINTS = 6000

from ...core.fields import MAX_SCALE, MIN_SIZE_RTOL  # noqa: E402,F401  (re-exported: the scales of either body)

#: Boundary labels starting with this are the mesher's own (the crack segments'); a
#: scene may not use them.
RESERVED_LABEL_PREFIX = "ngcrack_"


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
        object.__setattr__(self, "E", positive(self.E, "material.E"))
        nu = self.nu
        if not is_number(nu):
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
            raise SceneError(f"material = {short(d)}: must be a table with keys E, nu, "
                             f"plane")
        check_keys(d, ("E", "nu", "plane"), "material")
        for key, hint in (("E", "Young's modulus, a finite number > 0"),
                          ("nu", "Poisson's ratio in (-1, 1/2]")):
            if key not in d:
                raise SceneError(f"material.{key}: missing; give {hint}")
        return cls(E=d["E"], nu=d["nu"], plane=d.get("plane", "strain"))

    def to_dict(self) -> dict[str, Any]:
        """The TOML table of this value (what `Scene.to_toml` writes)."""
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
        raise SceneError(f"{fld}.value = {short(value)}: type = {type_!r} takes no "
                         f"value{hint}; remove it")
    return type_, (None if value is None else pair(value, f"{fld}.value"))


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
            raise SceneError(f"{fld} = {short(d)}: must be a table with keys type, value")
        check_keys(d, ("type", "value"), fld)
        if "type" not in d:
            raise SceneError(f"{fld}.type: missing; allowed types are "
                             f"{', '.join(BOUNDARY_TYPES)}")
        t, v = _condition_parts(d["type"], d.get("value"), fld)
        return cls(t, v)

    def to_dict(self) -> dict[str, Any]:
        """The TOML table of this value (what `Scene.to_toml` writes)."""
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

    def scaled(self, factor: float) -> BoundaryCondition:
        """The condition with its value (if any) multiplied by ``factor``."""
        if self.value is None:
            return self
        return BoundaryCondition(self.type, (self.value[0] * factor, self.value[1] * factor))


def crack_points(v: Any, fld: str, tol: float | None) -> tuple[Point, ...]:
    """Coerce and check a crack polyline on its own (not against the domain)."""
    pts = points(v, f"{fld}.points", 2,
                 "a list of 2 or more points [[x0, y0], [x1, y1], ...]", MAX_CRACK_POINTS)
    if tol is None:
        tol = GEOMETRY_RTOL * diameter(pts)
    check_polyline_simple(pts, f"{fld}.points", tol, closed=False, what="segment")
    return pts


def friction_coefficient(v: Any, fld: str) -> float:
    """A Coulomb coefficient: a finite number >= 0."""
    what = "a finite number >= 0 (the Coulomb friction coefficient; 0: frictionless)"
    x = finite(v, fld, what)
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
    ``pressure`` is the load on both faces, pushing them apart (``scene.pressure``): None
    (none), a number, a table ((s, p), ...) piecewise linear in the arc length s from the
    first point, or a callable p(s).
    """

    points: tuple[tuple[float, float], ...]
    friction: float = 0.0
    pressure: Pressure = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", crack_points(self.points, "crack", None))
        object.__setattr__(self, "friction", friction_coefficient(self.friction, "crack.friction"))
        object.__setattr__(self, "pressure", check_pressure(self.pressure, "crack.pressure", self.length))

    @property
    def segments(self) -> list[tuple[Point, Point]]:
        """The segments ``(p, q)``, in order from the first point."""
        return [(self.points[i], self.points[i + 1]) for i in range(len(self.points) - 1)]

    def segment_lengths(self) -> list[float]:
        """The length of each segment, in order."""
        return [dist(p, q) for p, q in self.segments]

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

    def scaled(self, factor: float, load: float = 1.0) -> Crack:
        """The crack with every point multiplied by ``factor`` (its friction kept, its
        pressure multiplied by ``load``, a table's arc lengths by ``factor``)."""
        p = self.pressure
        if isinstance(p, float):
            p = p * load
        elif isinstance(p, tuple):
            p = tuple((s * factor, v * load) for s, v in p)
        elif p is not None:
            fn = p

            def p(s: float) -> float:
                return load * fn(s / factor)
        return Crack(tuple((x * factor, y * factor) for x, y in self.points), self.friction, p)

    def to_dict(self) -> dict[str, Any]:
        """The TOML table of this value (what `Scene.to_toml` writes)."""
        d: dict[str, Any] = {"points": [list(p) for p in self.points]}
        if self.friction:
            d["friction"] = self.friction
        if self.pressure is not None:
            d["pressure"] = pressure_to_toml(self.pressure, "crack.pressure")
        return d


def tip_label(crack: int, end: str) -> str:
    """`crack,end`, e.g. `0,last` (crack index, its "first" or "last" point): the one name
    of a crack end in tables, columns and messages (`ngcrack.planar.tips.Tip.label`)."""
    return f"{crack},{end}"


def check_exact(ex: Any) -> FrozenMap:
    """The ``[exact]`` table (closed-form metadata) checked against :data:`EXACT_KINDS`."""
    if not isinstance(ex, Mapping):
        raise SceneError(f"exact = {short(ex)}: must be a table with key kind "
                         f"({', '.join(EXACT_KINDS)})")
    kind = ex.get("kind")
    if kind not in EXACT_KINDS:
        raise SceneError(f"exact.kind = {kind!r}: allowed kinds are "
                         f"{', '.join(EXACT_KINDS)}")
    keys = EXACT_KINDS[kind]
    check_keys(ex, ("kind",) + keys, "exact")
    out: dict[str, Any] = {"kind": kind}
    for k in keys:
        if k not in ex:
            raise SceneError(f"exact.{k}: missing; exact.kind = {kind!r} needs keys "
                             f"{', '.join(keys)}")
        v, fld = ex[k], f"exact.{k}"
        if k == "a":
            out[k] = positive(v, fld)
        elif k in ("p", "angle"):
            out[k] = finite(v, fld)
        elif k == "center":
            out[k] = pair(v, fld)
        elif k == "sigma":
            if (isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) != 3
                    or not all(is_number(c) and math.isfinite(c) for c in v)):
                raise SceneError(f"{fld} = {short(v)}: must be 3 finite numbers "
                                 f"[s_xx, s_yy, s_xy]")
            out[k] = tuple(float(c) for c in v)
    return FrozenMap(out)


def check_load(value: Sequence[float], to_strain: float, fld: str, what: str) -> None:
    """Refuse a load whose nonzero components, as strains (``value * to_strain``), or
    whose own size leave the range 1/MAX_SCALE .. MAX_SCALE."""
    for c in value:
        if c != 0.0 and not (1.0 / MAX_SCALE <= abs(c) * to_strain <= MAX_SCALE
                             and 1.0 / MAX_SCALE <= abs(c) <= MAX_SCALE):
            raise SceneError(
                f"{fld} = [{fmt(value[0])}, {fmt(value[1])}]: out of range ({what} is "
                f"{abs(c) * to_strain:.3g}); each component must be 0 or, in size and as {what}, "
                f"lie between {1.0 / MAX_SCALE:g} and {MAX_SCALE:g} (change the units)")
