"""Loads and supports at points of the outer boundary: ``[[point]]`` tables.

A point condition sits at ``at = [x, y]`` on an edge of the outer polygon and acts on
the short boundary segment of length ``width`` centred there (the segment the scene
inserts into the polygon and labels ``label``, default ``point{k}``):

``force``   the total force ``value = [Fx, Fy]`` (force per unit thickness), spread as
            the uniform traction value / width over the segment;
``pin``     the mean displacement of the segment is held at zero (both components):
            the segment's centre cannot move, the body may turn about it (a clamped
            segment would hold its rotation too);
``roller``  the mean normal displacement of the segment is held at zero (its outward
            normal n: u.n averaged over the segment), the tangential motion is free.

Pins and rollers are constraints on the segment's mean displacement, so their reaction
is a uniform traction over the segment: the mean is work-conjugate to the total force.
Without ``width`` the segment is POINT_WIDTH_FRACTION of the scene's mesh size (maxh, or
a tenth of the body's diameter without one). A point must lie on an edge (not at a
corner, not on a hole), its segment must fit on that edge at least MIN_GAP_RTOL of the
diameter from the edge's ends, and two segments may not overlap; each is refused by
field (``point[k].at``, ``point[k].width``, ...) before any meshing.

The scene stores its polygon with the segments inserted (the mesher and every other
consumer see plain labelled edges) and a force as a traction on its segment's label;
:func:`insert_points` is idempotent (a segment already in the polygon is kept), and
:func:`strip_points` gives back the polygon as the user wrote it (the TOML writer).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

from ...core.fields import SceneError, check_keys, fmt, fmt_pt, pair, positive, short
from .measures import Point, dist, dot, point_segment_distance, sub
from .planar import MIN_GAP_RTOL
from .types import RESERVED_LABEL_PREFIX, BoundaryCondition

__all__ = ["MAX_POINTS", "POINT_TYPES", "POINT_WIDTH_FRACTION", "PointCondition"]

#: the point condition types and whether each takes a value
POINT_TYPES: Mapping[str, bool] = {"force": True, "pin": False, "roller": False}
#: the default width of a point's segment, as a fraction of the mesh size
POINT_WIDTH_FRACTION = 0.5
#: the default mesh size when the scene gives none, as a fraction of its diameter (as in sizing)
DEFAULT_H_FRACTION = 0.1
#: the most point conditions of a scene
MAX_POINTS = 100
#: a force stored as a traction must equal value / width to this relative tolerance
FORCE_RTOL = 1e-9


@dataclass(frozen=True)
class PointCondition:
    """A load or support at a point of the outer boundary (module docstring).

    ``at`` the point, ``type`` one of POINT_TYPES, ``value`` the total force [Fx, Fy]
    (force only), ``width`` the segment's length (None: the default), ``label`` the
    segment's boundary label (None: ``point{k}``, k its index in the scene).
    """

    at: Point
    type: str = "force"
    value: Point | None = None
    width: float | None = None
    label: str | None = None

    def __post_init__(self) -> None:
        fld = "point"
        object.__setattr__(self, "at", pair(self.at, f"{fld}.at", "a list of 2 finite numbers [x, y]"))
        if not isinstance(self.type, str) or self.type not in POINT_TYPES:
            raise SceneError(f"{fld}.type = {self.type!r}: allowed types are {', '.join(POINT_TYPES)}")
        if POINT_TYPES[self.type]:
            if self.value is None:
                raise SceneError(f"{fld}.value: missing; type = {self.type!r} needs value = [Fx, Fy] "
                                 f"(the total force)")
            object.__setattr__(self, "value", pair(self.value, f"{fld}.value", "a list of 2 finite numbers [Fx, Fy]"))
        elif self.value is not None:
            raise SceneError(f"{fld}.value = {short(self.value)}: type = {self.type!r} takes no value; remove it")
        if self.width is not None:
            object.__setattr__(self, "width", positive(self.width, f"{fld}.width"))
        if self.label is not None:
            if not isinstance(self.label, str) or not self.label:
                raise SceneError(f"{fld}.label = {self.label!r}: must be a non-empty string")
            if self.label.startswith(RESERVED_LABEL_PREFIX):
                raise SceneError(f"{fld}.label = {self.label!r}: labels starting with {RESERVED_LABEL_PREFIX!r} "
                                 f"are reserved; choose another label")

    @classmethod
    def from_dict(cls, d: Any, fld: str = "point") -> PointCondition:
        """Build from a ``[[point]]`` table (keys at, type, value, width, label)."""
        if isinstance(d, PointCondition):
            return d
        if not isinstance(d, Mapping):
            raise SceneError(f"{fld} = {short(d)}: must be a table with keys at, type, value, width, label")
        check_keys(d, ("at", "type", "value", "width", "label"), fld)
        if "at" not in d:
            raise SceneError(f"{fld}.at: missing; give the point [x, y] on the body's boundary")
        if "type" not in d:
            raise SceneError(f"{fld}.type: missing; allowed types are {', '.join(POINT_TYPES)}")
        try:
            return cls(at=d["at"], type=d["type"], value=d.get("value"), width=d.get("width"), label=d.get("label"))
        except SceneError as exc:
            raise SceneError(str(exc).replace("point.", f"{fld}.", 1)) from None

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"at": list(self.at), "type": self.type}
        if self.value is not None:
            d["value"] = list(self.value)
        if self.width is not None:
            d["width"] = self.width
        if self.label is not None:
            d["label"] = self.label
        return d

    @property
    def holds(self) -> str:
        """``"all"`` (pin: both mean components), ``"normal"`` (roller) or ``"none"`` (force)."""
        return {"pin": "all", "roller": "normal"}.get(self.type, "none")

    def traction(self) -> tuple[float, float] | None:
        """The uniform traction value / width of a force (None for a support)."""
        if self.value is None or self.width is None:
            return None
        return (self.value[0] / self.width, self.value[1] / self.width)

    def scaled(self, size: float, force: float) -> PointCondition:
        """The point with its position and width times ``size`` and its force times ``force``."""
        value = None if self.value is None else (self.value[0] * force, self.value[1] * force)
        width = None if self.width is None else self.width * size
        return replace(self, at=(self.at[0] * size, self.at[1] * size), value=value, width=width)


def segment_ends(at: Point, p: Point, q: Point, width: float) -> tuple[Point, Point]:
    """The ends of the segment of length ``width`` centred at ``at`` on the edge p -> q, in the edge's order."""
    L = dist(p, q)
    t = ((q[0] - p[0]) / L, (q[1] - p[1]) / L)
    h = 0.5 * width
    return (at[0] - h * t[0], at[1] - h * t[1]), (at[0] + h * t[0], at[1] + h * t[1])


def outward_normal(p: Point, q: Point) -> Point:
    """The outward unit normal of the counter-clockwise polygon's edge p -> q."""
    L = dist(p, q)
    return ((q[1] - p[1]) / L, -(q[0] - p[0]) / L)


def coerce_points(raw: Any, mesh_h: float | None, diameter: float) -> tuple[PointCondition, ...]:
    """The ``[[point]]`` list as PointConditions with their labels and widths resolved."""
    if isinstance(raw, (str, bytes, Mapping)) or not isinstance(raw, Sequence):
        raise SceneError(f"point = {short(raw)}: must be a list of point conditions ([[point]] tables with at, "
                         f"type and, for a force, value)")
    if len(raw) > MAX_POINTS:
        raise SceneError(f"point: {len(raw)} point conditions; at most {MAX_POINTS} are allowed")
    h = mesh_h if mesh_h is not None else DEFAULT_H_FRACTION * diameter
    out = []
    for k, d in enumerate(raw):
        pc = PointCondition.from_dict(d, f"point[{k}]")
        out.append(replace(pc, label=pc.label or f"point{k}", width=pc.width or POINT_WIDTH_FRACTION * h))
    labels = [pc.label for pc in out]
    for k, lab in enumerate(labels):
        if lab in labels[:k]:
            raise SceneError(f"point[{k}].label = {lab!r}: already the label of point[{labels.index(lab)}]; "
                             f"give each point its own label")
    return tuple(out)


def _inserted(poly: Sequence[Point], labels: Sequence[str], pc: PointCondition, tol: float) -> bool:
    """Whether the point's segment is already an edge of the polygon carrying its label."""
    n = len(poly)
    for i in range(n):
        if labels[i] != pc.label:
            continue
        p, q = poly[i], poly[(i + 1) % n]
        m = (0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]))
        if dist(m, pc.at) <= tol and abs(dist(p, q) - pc.width) <= tol:
            return True
    return False


def insert_points(poly: Sequence[Point], labels: Sequence[str], pts: Sequence[PointCondition],
                  other_labels: Sequence[str], diameter: float, tol: float) -> tuple[tuple, tuple]:
    """The polygon and labels with every point's segment inserted (idempotent), checked by field."""
    poly, labels = list(poly), list(labels)
    own = {pc.label for pc in pts}
    done = [_inserted(poly, labels, pc, tol) for pc in pts]
    for k, pc in enumerate(pts):
        if pc.label in other_labels:
            raise SceneError(f"point[{k}].label = {pc.label!r}: already the label of a hole's edge; choose another "
                             f"label")
        if not done[k] and pc.label in labels:
            raise SceneError(f"point[{k}].label = {pc.label!r}: already the label of a polygon edge; choose another "
                             f"label")
    for k, pc in enumerate(pts):
        fld = f"point[{k}]"
        if done[k]:
            continue
        n = len(poly)
        dists = [point_segment_distance(pc.at, poly[i], poly[(i + 1) % n]) for i in range(n)]
        i = min(range(n), key=dists.__getitem__)
        if dists[i] > tol:
            raise SceneError(f"{fld}.at = {fmt_pt(pc.at)}: not on the body's outer boundary (it is {fmt(dists[i])} "
                             f"from the nearest edge, {labels[i]!r}); a point condition sits on an edge of "
                             f"domain.polygon")
        if labels[i] in own:
            j = next(j for j, o in enumerate(pts) if o.label == labels[i])
            raise SceneError(f"{fld}.at = {fmt_pt(pc.at)}: lies on the segment of point[{j}]; two point "
                             f"conditions may not overlap")
        p, q = poly[i], poly[(i + 1) % n]
        gap = MIN_GAP_RTOL * diameter
        if min(dist(pc.at, p), dist(pc.at, q)) <= tol:
            raise SceneError(f"{fld}.at = {fmt_pt(pc.at)}: lies at a corner of domain.polygon; put it on an edge, "
                             f"at least width / 2 + {fmt(gap)} from its ends")
        if pc.width < gap:
            raise SceneError(f"{fld}.width = {fmt(pc.width)}: must be at least {fmt(gap)} ({MIN_GAP_RTOL:g} of the "
                             f"body's diameter; the mesher fails on shorter segments)")
        a, b = segment_ends(pc.at, p, q, pc.width)
        d = sub(q, p)
        ta, tb = dot(sub(a, p), d) / dot(d, d), dot(sub(b, p), d) / dot(d, d)
        room = min(dist(pc.at, p), dist(pc.at, q)) - gap
        if ta * dist(p, q) < gap or (1.0 - tb) * dist(p, q) < gap:
            beyond = labels[i - 1] if ta * dist(p, q) < gap else labels[(i + 1) % n]
            what = (f"the segment of point[{next(j for j, o in enumerate(pts) if o.label == beyond)}]"
                    if beyond in own else "the end of the edge")
            raise SceneError(f"{fld}.width = {fmt(pc.width)}: the segment centred at {fmt_pt(pc.at)} does not fit "
                             f"on edge {labels[i]!r} from {fmt_pt(p)} to {fmt_pt(q)} (it reaches {what}); "
                             f"give a width below {fmt(max(2.0 * room, 0.0))} or move the point")
        poly[i + 1:i + 1] = [a, b]
        labels[i + 1:i + 1] = [pc.label, labels[i]]
    return tuple(poly), tuple(labels)


def warn_held_mouths(pts: Sequence[PointCondition], cracks: Sequence[Sequence[Point]], tol: float) -> None:
    """Warn in one line of each pin or roller whose segment holds a crack's mouth (a crack end on the
    boundary): its mean displacement then ties the two crack faces together at the mouth, which is
    seldom meant and changes K (the three-point-bend beam with its pin moved under the crack: K_I
    5.59 becomes 0.41). Allowed, as a support there may be meant, but said."""
    for k, pc in enumerate(pts):
        if pc.holds == "none" or pc.width is None:
            continue
        for i, crack in enumerate(cracks):
            for end in (crack[0], crack[-1]):
                if dist(pc.at, end) <= 0.5 * pc.width + tol:
                    warnings.warn(f"point[{k}] ({pc.type} at {fmt_pt(pc.at)}, width {fmt(pc.width)}) holds the mouth of "
                                  f"crack[{i}] at {fmt_pt(end)}: its mean displacement ties the two crack faces together "
                                  f"there, which changes K; move it off the crack if that is not meant", stacklevel=2)


def strip_points(poly: Sequence[Point], labels: Sequence[str], pts: Sequence[PointCondition]) -> tuple[list, list]:
    """The polygon and labels without the points' segments (the inverse of insert_points)."""
    own = {pc.label for pc in pts}
    poly, labels = list(poly), list(labels)
    i = 0
    while i < len(poly):
        if labels[i] in own and len(poly) > 3:
            # vertices i and i + 1 were inserted; the edge before i keeps its label
            n = len(poly)
            j = (i + 1) % n
            for idx in sorted({i, j}, reverse=True):
                del poly[idx]
                del labels[idx]
            i = max(i - 1, 0)
            continue
        i += 1
    return poly, labels


def force_conditions(pts: Sequence[PointCondition], boundary: Mapping[str, Any]) -> dict[str, BoundaryCondition]:
    """The tractions of the force points, checked against ``boundary`` entries of their labels."""
    out = {}
    for k, pc in enumerate(pts):
        given = boundary.get(pc.label)
        if pc.type != "force":
            if given is not None:
                raise SceneError(f"boundary.{pc.label}: the segment of point[{k}] (a {pc.type}) takes its condition "
                                 f"from the point; remove [boundary.{pc.label}]")
            continue
        bc = BoundaryCondition("traction", pc.traction())
        if given is not None:
            g = BoundaryCondition.from_dict(given, f"boundary.{pc.label}")
            scale = math.hypot(*bc.value) or 1.0
            if g.type != "traction" or math.hypot(g.value[0] - bc.value[0], g.value[1] - bc.value[1]) > FORCE_RTOL * scale:
                raise SceneError(f"boundary.{pc.label}: the segment of point[{k}] carries its force "
                                 f"{fmt_pt(pc.value)} / width {fmt(pc.width)}; give the force in [[point]] only "
                                 f"and remove [boundary.{pc.label}]")
        out[pc.label] = bc
    return out


def from_tractions(pts: Sequence[PointCondition], boundary: Mapping[str, Any]) -> tuple[PointCondition, ...]:
    """The force points with their value taken from a traction given for their label in
    ``boundary`` (a changed boundary mapping carries the forces: a scaled or turned load)."""
    out = []
    for pc in pts:
        g = boundary.get(pc.label) if pc.type == "force" else None
        if g is not None:
            g = BoundaryCondition.from_dict(g, f"boundary.{pc.label}")
            if g.type == "traction":
                pc = replace(pc, value=(g.value[0] * pc.width, g.value[1] * pc.width))
        out.append(pc)
    return tuple(out)


def held_directions(poly: Sequence[Point], labels: Sequence[str],
                    pts: Sequence[PointCondition]) -> dict[str, tuple[Point, ...]]:
    """label -> the directions whose segment mean is held: (e_x, e_y) for a pin, the
    segment's outward normal for a roller (the polygon as stored, segments inserted)."""
    out: dict[str, tuple[Point, ...]] = {}
    n = len(poly)
    for pc in pts:
        if pc.type == "pin":
            out[pc.label] = ((1.0, 0.0), (0.0, 1.0))
        elif pc.type == "roller":
            i = labels.index(pc.label)
            out[pc.label] = (outward_normal(poly[i], poly[(i + 1) % n]),)
    return out
