"""Holes in the body: polygons or circles inside the domain, with labelled edges.

A hole is either a polygon (``polygon = [[x, y], ...]``, counter-clockwise like the
domain, with optional ``labels``, one per edge) or a circle (``center = [x, y]``,
``radius = r``, optional ``label``), and optionally ``maxh``, the mesh size along its
edges (default: its perimeter over HOLE_SEGMENTS). Its edges carry supports or loads through
``[boundary.LABEL]`` like the domain's; without labels every edge of hole ``k`` is
labelled ``hole{k}``. The mesher meshes a circle as a circle (netgen's rational splines);
the checks here and the body's region use the polygon of ``CIRCLE_SEGMENTS`` sides
inscribed in it (a relative deviation of 7.5e-5 of the radius).

A hole must lie strictly inside the domain, away from its boundary, the cracks and the
other holes (at least ``MIN_GAP_RTOL`` of the diameter): the body's checks refuse it by
field (``hole[k].polygon``, ``hole[k].center``, ...). A crack may end on a hole's edge (its
first or last point within the scene's tolerance of it, like an edge crack on the outer
boundary): that end is then no tip, and the crack joins the hole.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...core.fields import SceneError, check_keys, fmt, fmt_pt, pair, points, positive, short
from .measures import Point, diameter, point_segment_distance, signed_area
from .planar import MIN_GAP_RTOL, Walls, check_polyline_simple, pairs_within
from .types import MAX_SCALE, MIN_SIZE_RTOL, RESERVED_LABEL_PREFIX

__all__ = ["CIRCLE_SEGMENTS", "MAX_HOLES", "Hole", "check_holes"]

#: sides of the polygon inscribed in a circular hole for the checks, the region and the
#: rigid-motion check (the mesh follows the true circle)
CIRCLE_SEGMENTS = 256
#: the default mesh size along a hole's edges is its perimeter (pi times its size) over
#: this: stresses concentrate there (3 times the remote one at a circular hole)
HOLE_SEGMENTS = 64
#: a vertex of a circle's inscribed polygon closer than this fraction of its radius to a crack end on
#: the circle is left out of the loop (the crack end is the vertex there)
THROUGH_MERGE_RTOL = 1e-6
#: the most holes a scene may have
MAX_HOLES = 100
#: the most vertices of one polygonal hole
MAX_HOLE_VERTICES = 2000


@dataclass(frozen=True)
class Hole:
    """A hole: a polygon (``polygon``, counter-clockwise; ``labels`` one per edge) or a
    circle (``center``, ``radius``; ``labels`` its one label). Edge ``i`` of a polygonal
    hole runs from vertex ``i`` to vertex ``i + 1``."""

    polygon: tuple[Point, ...] | None = None
    labels: tuple[str, ...] = ()
    center: Point | None = None
    radius: float | None = None
    maxh: float | None = None

    @property
    def edge_h(self) -> float:
        """The mesh size asked for along its edges: ``maxh`` if given, else the length of
        one of HOLE_SEGMENTS equal arcs of its perimeter (of a circle of its size)."""
        return self.maxh if self.maxh is not None else math.pi * self.size / HOLE_SEGMENTS

    @property
    def is_circle(self) -> bool:
        return self.center is not None

    def loop(self, circle_segments: int | None = None, through: Sequence[Point] = ()) -> tuple[Point, ...]:
        """The vertices (counter-clockwise) the checks use: the polygon, or the polygon of
        ``circle_segments`` (default CIRCLE_SEGMENTS) sides inscribed in the circle, with the
        points ``through`` (crack ends on the circle) among its vertices, as given."""
        if not self.is_circle:
            return self.polygon
        (cx, cy), r, n = self.center, self.radius, circle_segments or CIRCLE_SEGMENTS
        angle = lambda p: math.atan2(p[1] - cy, p[0] - cx) % (2 * math.pi)  # noqa: E731
        pts = [(2 * math.pi * k / n, (cx + r * math.cos(2 * math.pi * k / n), cy + r * math.sin(2 * math.pi * k / n)))
               for k in range(n)]
        if through:  # a vertex all but on a crack end gives way to it
            ends = [(angle(p), (float(p[0]), float(p[1]))) for p in through]
            pts = [(a, p) for a, p in pts if min(math.dist(p, q) for _, q in ends) > THROUGH_MERGE_RTOL * r] + ends
            pts.sort()
        return tuple(p for _, p in pts)

    def edge_labels(self, circle_segments: int | None = None, through: Sequence[Point] = ()) -> tuple[str, ...]:
        """One label per edge of :meth:`loop` (of ``circle_segments`` sides for a circle)."""
        return self.labels * len(self.loop(circle_segments, through)) if self.is_circle else self.labels

    def edge_distance(self, x: Sequence[float]) -> float:
        """The distance of the point ``x`` to the hole's edge (the circle's itself, not a polygon's)."""
        if self.is_circle:
            return abs(math.dist((float(x[0]), float(x[1])), self.center) - self.radius)
        n = len(self.polygon)
        return min(point_segment_distance(x, self.polygon[i], self.polygon[(i + 1) % n]) for i in range(n))

    @property
    def area(self) -> float:
        return math.pi * self.radius**2 if self.is_circle else signed_area(self.polygon)

    @property
    def size(self) -> float:
        """Its diameter: twice the radius, or the largest distance between two vertices."""
        return 2.0 * self.radius if self.is_circle else diameter(self.polygon)

    def to_dict(self) -> dict[str, Any]:
        if self.is_circle:
            d = {"center": list(self.center), "radius": self.radius, "label": self.labels[0]}
        else:
            d = {"polygon": [list(p) for p in self.polygon], "labels": list(self.labels)}
        if self.maxh is not None:
            d["maxh"] = self.maxh
        return d

    def scaled(self, factor: float) -> Hole:
        """The hole with every length multiplied by ``factor``."""
        h = None if self.maxh is None else self.maxh * factor
        if self.is_circle:
            return Hole(center=(self.center[0] * factor, self.center[1] * factor),
                        radius=self.radius * factor, labels=self.labels, maxh=h)
        return Hole(polygon=tuple((x * factor, y * factor) for x, y in self.polygon), labels=self.labels,
                    maxh=h)


def _label(lab: Any, fld: str) -> str:
    if not isinstance(lab, str) or not lab:
        raise SceneError(f"{fld} = {lab!r}: must be a non-empty string")
    if lab.startswith(RESERVED_LABEL_PREFIX):
        raise SceneError(f"{fld} = {lab!r}: labels starting with {RESERVED_LABEL_PREFIX!r} are "
                         f"reserved (the mesher names the crack faces so); choose another label")
    return lab


def make_hole(raw: Any, k: int, tol: float) -> Hole:
    """Hole ``k`` from a ``[[hole]]`` table or a Hole, checked on its own (not against the
    domain): a simple counter-clockwise polygon, or a circle of positive radius."""
    fld = f"hole[{k}]"
    if isinstance(raw, Hole):
        raw = raw.to_dict()
    if not isinstance(raw, Mapping):
        raise SceneError(f"{fld} = {short(raw)}: must be a table with polygon = [[x, y], ...] "
                         f"(and optionally labels) or center = [x, y] and radius = r (and optionally "
                         f"label)")
    default = f"hole{k}"
    h = None if raw.get("maxh") is None else positive(raw["maxh"], f"{fld}.maxh")
    if "polygon" in raw:
        check_keys(raw, ("polygon", "labels", "maxh"), fld)
        poly = points(raw["polygon"], f"{fld}.polygon", 3,
                      "a list of 3 or more vertices [[x0, y0], [x1, y1], ...], counter-clockwise",
                      MAX_HOLE_VERTICES)
        for i, p in enumerate(poly):
            if max(abs(p[0]), abs(p[1])) > MAX_SCALE:
                raise SceneError(f"{fld}.polygon[{i}]: coordinates must lie within +-{MAX_SCALE:g}")
        check_polyline_simple(poly, f"{fld}.polygon", tol, closed=True, what="edge")
        area = signed_area(poly)
        if area < 0:
            raise SceneError(f"{fld}.polygon: is clockwise; list the vertices counter-clockwise "
                             f"(as for domain.polygon)")
        if area <= tol * diameter(poly):
            raise SceneError(f"{fld}.polygon: has zero area; give a simple polygon")
        labels = raw.get("labels", ())
        if isinstance(labels, (str, bytes)) or not isinstance(labels, Sequence):
            raise SceneError(f"{fld}.labels = {short(labels)}: must be a list of {len(poly)} strings, "
                             f"one per edge")
        if not labels:
            labels = (default,) * len(poly)
        if len(labels) != len(poly):
            raise SceneError(f"{fld}.labels: {len(labels)} labels for {len(poly)} edges; give one "
                             f"label per edge (edge i runs from vertex i to vertex i+1)")
        labels = tuple(_label(lab, f"{fld}.labels[{i}]") for i, lab in enumerate(labels))
        return Hole(polygon=poly, labels=labels, maxh=h)
    if "center" in raw or "radius" in raw:
        check_keys(raw, ("center", "radius", "label", "maxh"), fld)
        for key, hint in (("center", "[x, y]"), ("radius", "a finite number > 0")):
            if key not in raw:
                raise SceneError(f"{fld}.{key}: missing; a circular hole needs center = [x, y] and "
                                 f"radius = r (give {key} = {hint})")
        center = pair(raw["center"], f"{fld}.center")
        radius = positive(raw["radius"], f"{fld}.radius")
        if radius <= tol:
            raise SceneError(f"{fld}.radius = {radius:g}: too small for this body (at most the "
                             f"geometric tolerance {tol:g})")
        label = _label(raw.get("label", default), f"{fld}.label")
        return Hole(center=center, radius=radius, labels=(label,), maxh=h)
    raise SceneError(f"{fld}: give either polygon = [[x, y], ...] (and optionally labels) or "
                     f"center = [x, y] and radius = r (and optionally label); it has keys "
                     f"{', '.join(map(repr, raw)) or 'none'}")


def _crosses(walls: Walls, loop: np.ndarray, tol: float) -> bool:
    """True if an edge of the closed ``loop`` comes within ``tol`` of an edge of ``walls``."""
    return bool(pairs_within((loop, np.roll(loop, -1, axis=0)), walls.A, walls.B, tol).size)


def check_holes(raw: Any, outer: Walls, diam: float, tol: float) -> tuple[Hole, ...]:
    """The holes, each checked on its own, inside the domain and apart from the others."""
    if isinstance(raw, (str, bytes, Mapping)) or not isinstance(raw, Sequence):
        raise SceneError(f"hole = {short(raw)}: must be a list of holes ([[hole]] tables with "
                         f"polygon = [[x, y], ...] or center = [x, y] and radius = r)")
    if len(raw) > MAX_HOLES:
        raise SceneError(f"hole: {len(raw)} holes; at most {MAX_HOLES} are allowed")
    holes = tuple(make_hole(h, k, tol) for k, h in enumerate(raw))
    shapes = []
    for k, h in enumerate(holes):
        fld = f"hole[{k}]" + (".center" if h.is_circle else ".polygon")
        if h.size < MIN_GAP_RTOL * diam:
            raise SceneError(f"{fld}: the hole is {fmt(h.size)} across, smaller than "
                             f"{MIN_GAP_RTOL:g} of the body's diameter ({fmt(MIN_GAP_RTOL * diam)}); "
                             f"netgen cannot mesh it reliably: make it larger or leave it out")
        if h.maxh is not None and not MIN_SIZE_RTOL * diam <= h.maxh <= MAX_SCALE * diam:
            raise SceneError(f"hole[{k}].maxh = {fmt(h.maxh)}: must lie between {MIN_SIZE_RTOL:g} and "
                             f"{MAX_SCALE:g} times the body's diameter {fmt(diam)}")
        loop = np.asarray(h.loop())
        inside = outer.inside(loop)
        if not inside.all() or outer.distance(loop).min() <= tol or _crosses(outer, loop, tol):
            where = (f"center {fmt_pt(h.center)}, radius {fmt(h.radius)}" if h.is_circle
                     else f"vertex {int(np.argmin(inside))} {fmt_pt(loop[int(np.argmin(inside))])}")
            raise SceneError(f"{fld}: the hole ({where}) is not strictly inside domain.polygon; a "
                             f"hole must lie inside the body without touching its boundary")
        if len(holes) == 1:
            break
        import shapely  # (a scene with two holes or more)

        shape = shapely.Polygon(loop)
        for j, other in enumerate(shapes):
            if shape.distance(other) <= tol:
                raise SceneError(f"{fld}: hole[{k}] touches, overlaps or contains hole[{j}]; holes "
                                 f"must be apart from each other (merge them into one polygon)")
        shapes.append(shape)
    return holes


def hole_ends(holes: Sequence[Hole], ends: Sequence[Point], tol: float) -> list[tuple[Point, ...]]:
    """For every hole, the points of ``ends`` (crack end points) on its edge if it is a circle (the
    vertices its loop must have: Hole.loop's ``through``), else none (a polygon's edge takes them
    as the outer polygon's does)."""
    return [tuple(p for p in ends if h.edge_distance(p) <= tol) if h.is_circle else () for h in holes]


def check_not_on_holes(holes: Sequence[Hole], pts: Sequence[Point], fld: str, tol: float) -> None:
    """Refuse a crack point other than the first or the last on a circular hole's edge (the walls'
    checks see the circle as its inscribed polygon)."""
    for k, p in enumerate(pts[1:-1], start=1):
        for j, h in enumerate(holes):
            if h.is_circle and h.edge_distance(p) <= tol:
                raise SceneError(f"{fld}.points[{k}] = {fmt_pt(p)} lies on hole[{j}]; only a crack's first "
                                 f"and last points may lie on a hole's edge, interior points must lie "
                                 f"strictly inside the body")
