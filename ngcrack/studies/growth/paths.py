"""Crack paths: the body's region, and extending a crack tip by one segment.

A tip at p grows to q = p + da (cos phi, sin phi). Where that segment, lengthened by
SNAP_FRACTION da, reaches the body's boundary (its outer polygon), the tip is
taken onto the boundary at the crossing and stops there: the crack then cuts through
(the end point lies on the boundary and is no longer a tip inside the body). Where it
reaches a hole, the tip is taken onto the hole's edge at the crossing the same way: the
crack joins the hole (that end is no tip any more; holes.py: what then). Where the
segment would cross another crack, or come closer to it than CRACK_CLEARANCE da, or
cross its own crack, the tip stops where it is (junctions are not supported). Where it
would pass a circular hole without meeting it, closer than HOLE_CLEARANCE_RTOL of the
body's diameter (the scene checks refuse a crack that near a hole's edge and not on it), the
ligament left would be thinner than any mesh resolves: the tip breaks into the hole at the
point of its edge nearest to the tip, radially (if it turns at most GRAZE_TURN to reach it); else
it grows up to HOLE_STOP times that distance from the hole's edge and stops there.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import shapely
import shapely.ops

from ...planar.scene import tip_label

#: a new segment that reaches the boundary within (1 + SNAP_FRACTION) da ends on the
#: boundary: no sliver of body thinner than about da / 2 is left ahead of a tip
SNAP_FRACTION = 0.5
#: a new segment closer than this fraction of da to another crack (or to its own crack
#: beyond the tip segment) would meet it: the tip stops
CRACK_CLEARANCE = 0.25


#: a new segment that would come closer to a hole than this fraction of the body's
#: diameter stops its tip (the scene checks refuse a crack that near a hole: 1e-3 of the
#: diameter, scene.planar.MIN_GAP_RTOL, with a margin)
HOLE_CLEARANCE_RTOL = 2e-3


#: a crack end closer than this fraction of the body's size to a hole's polygon (and not on it) lies on the
#: hole's circle: pieces() joins it to the polygon
JOIN_RTOL = 1e-3
#: a tip whose segment would pass a circular hole closer than HOLE_CLEARANCE_RTOL of the diameter breaks
#: into it (graze_point) if it turns at most this much (radians) to reach it
GRAZE_TURN = math.radians(60.0)
#: a tip that passes a hole closer than the scene checks allow (and cannot break into it) grows up to
#: this many times HOLE_CLEARANCE_RTOL of the diameter from its edge, and stops there
HOLE_STOP = 1.25
#: ... unless that is less than this fraction of da: then it stops where it is
HOLE_MIN_STEP = 0.1


def _approach(p, d, ring, clearance: float, length: float) -> float:
    """The largest t in [0, length] with the segment p -> p + t d at least `clearance` from `ring`
    (bisection: the segment's distance falls as it lengthens)."""
    def far(t):
        seg = shapely.LineString([p, p + t * d]) if t > 0 else shapely.Point(p)
        return seg.distance(ring) >= clearance

    if not far(0.0):
        return 0.0
    lo, hi = 0.0, length
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if far(mid) else (lo, mid)
    return lo


def hole_hit(hole, p, d, length: float):
    """Where the segment p -> p + length d first meets the edge of `hole` (a circle's itself, on it to
    round-off; a polygon's), as a point, or None if it does not."""
    if hole.is_circle:
        c, r = np.asarray(hole.center, dtype=float), float(hole.radius)
        f = p - c
        b, disc = float(f @ d), float(f @ d) ** 2 - (float(f @ f) - r * r)
        if disc <= 0.0:
            return None
        t = -b - math.sqrt(disc)
        if not 0.0 < t <= length:
            return None
        x = f + t * d
        x = c + r * x / np.linalg.norm(x)
        return float(x[0]), float(x[1])
    hit = shapely.LineString([p, p + length * d]).intersection(shapely.Polygon(hole.polygon).exterior)
    if hit.is_empty:
        return None
    pts = np.array([c for g in getattr(hit, "geoms", [hit]) for c in g.coords], dtype=float)
    x = pts[np.argmin(np.linalg.norm(pts - p, axis=1))]
    return float(x[0]), float(x[1])


def graze_point(hole, p, d, length: float):
    """Where a tip at p whose segment p -> p + length d passes a circular hole without meeting it
    breaks into it: the point of the circle nearest to p (the crack meets the edge at a right angle,
    leaving no sliver), if the tip turns at most GRAZE_TURN to reach it within `length`; else None
    (and None for a polygonal hole)."""
    if not hole.is_circle:
        return None
    c, r = np.asarray(hole.center, dtype=float), float(hole.radius)
    m = np.asarray(p, dtype=float) - c
    x = c + r * m / np.linalg.norm(m)
    v = x - p
    if not 0.0 < np.linalg.norm(v) <= length or float(v @ d) < math.cos(GRAZE_TURN) * np.linalg.norm(v):
        return None
    return float(x[0]), float(x[1])


def body_region(scene) -> shapely.Polygon:
    """The body as a shapely Polygon: the scene's `region()` where it has one (holes
    included), else its outer polygon."""
    region = getattr(scene, "region", None)
    if callable(region):
        return region()
    return shapely.Polygon(scene.polygon)


@dataclass(frozen=True)
class Extension:
    """The outcome of extending one tip: the new end point (None: the tip stops where it is)
    and what happened: "grew", "boundary" (the new end lies on the outer boundary: the crack
    cuts through), "hole" (the segment would reach a hole, or come closer to it than the
    scene checks allow: the tip stops where it is) or "crack"."""

    crack: int
    end: str
    point: tuple[float, float] | None
    outcome: str
    reason: str = ""


def tip_point(crack, end: str) -> np.ndarray:
    return np.asarray(crack.points[0] if end == "first" else crack.points[-1], dtype=float)


def tip_direction(crack, end: str) -> float:
    """The angle (radians, from the x axis) of the tip's e1: the tip segment's tangent pointing out of the crack."""
    pts = np.asarray(crack.points, dtype=float)
    d = pts[0] - pts[1] if end == "first" else pts[-1] - pts[-2]
    return math.atan2(d[1], d[0])


def _others(scene, k: int, end: str, new_segments) -> list[tuple[str, shapely.LineString]]:
    """The crack lines a new segment of tip (k, end) must not meet: every other crack, its own
    crack without the tip segment, and the segments already added in this step."""
    out = []
    for j, c in enumerate(scene.cracks):
        pts = list(c.points)
        if j == k:
            pts = pts[:-1] if end == "last" else pts[1:]
            if len(pts) < 2:
                continue
        out.append((f"crack {j}", shapely.LineString(pts)))
    out += [(f"the new segment of tip {lab}", seg) for lab, seg in new_segments]
    return out


def extend_tip(scene, region: shapely.Polygon, k: int, end: str, phi: float, da: float,
               new_segments=()) -> Extension:
    """Extend tip (k, end) of `scene` by da in the direction phi (radians from the x axis)."""
    crack = scene.cracks[k]
    p = tip_point(crack, end)
    d = np.array([math.cos(phi), math.sin(phi)])
    q = p + da * d
    reach = shapely.LineString([p, p + (1.0 + SNAP_FRACTION) * da * d])
    label = tip_label(k, end)
    outcome = "grew"
    gap = HOLE_CLEARANCE_RTOL * scene.diameter
    for i, ring in enumerate(region.interiors):
        if reach.distance(ring) < gap:
            hole = scene.holes[i] if i < len(scene.holes) else None
            x = hole_hit(hole, p, d, (1.0 + SNAP_FRACTION) * da) if hole is not None else None
            how = ""
            if x is None and hole is not None:  # a near miss: the ligament left would be thinner than a mesh allows
                x, how = graze_point(hole, p, d, (1.0 + SNAP_FRACTION) * da), " (a near miss: it broke into it)"
            if x is not None:  # the crack joins the hole: its end on the hole's edge is no tip any more
                reason = (f"tip {label} reached hole[{i}] at ({x[0]:.4g}, {x[1]:.4g}){how} and joined it (the "
                          f"ligament is cut; the crack ends on the hole's edge)")
                q, outcome = x, "hole"
                break
            reason = (f"tip {label} reached hole[{i}] (it passes the hole's edge closer than the scene checks "
                      f"allow: the tip stops {HOLE_STOP * HOLE_CLEARANCE_RTOL:g} of the body's diameter before it)")
            t = _approach(p, d, ring, HOLE_STOP * gap, (1.0 + SNAP_FRACTION) * da)
            if t < HOLE_MIN_STEP * da:
                return Extension(k, end, None, "hole", reason)
            q, outcome = p + t * d, "hole"
            break
    else:
        hit = reach.intersection(region.exterior)
    if outcome == "grew" and not hit.is_empty:
        # points, or a piece along the boundary: every coordinate it has
        pts = np.array([c for g in getattr(hit, "geoms", [hit]) for c in g.coords], dtype=float)
        dist = np.linalg.norm(pts - p, axis=1)
        ok = dist > 1e-9 * da
        if np.any(ok):
            q = pts[ok][np.argmin(dist[ok])]
            outcome = "boundary"
    seg = shapely.LineString([p, q])
    for name, line in _others(scene, k, end, new_segments):
        if seg.distance(line) < CRACK_CLEARANCE * da:
            meets = "cross" if seg.intersects(line) else "come within " + f"{CRACK_CLEARANCE:g} da of"
            return Extension(k, end, None, "crack",
                             f"tip {label} would {meets} {name} (junctions are not supported)")
    if outcome == "boundary":
        return Extension(k, end, (float(q[0]), float(q[1])), "boundary",
                         f"tip {label} reached the body's boundary at ({q[0]:.4g}, {q[1]:.4g})")
    if outcome == "hole":
        return Extension(k, end, (float(q[0]), float(q[1])), "hole", reason)
    return Extension(k, end, (float(q[0]), float(q[1])), "grew")


def pieces(region: shapely.Polygon, cracks) -> int:
    """How many pieces the cracks (sequences of points) cut the body `region` into: the faces
    of the body's boundary and the crack lines together (a crack with a free end cuts nothing
    there)."""
    lines = [region.exterior, *region.interiors] + [shapely.LineString(c) for c in cracks if len(c) > 1]
    # a crack end on a circular hole lies on the circle, off the region's inscribed polygon by up to its
    # sagitta: joined to the polygon by a line across it (twice the shortest way: a crossing is noded
    # robustly, a line ending on the polygon to round-off is not)
    x0, y0, x1, y1 = region.bounds
    near = JOIN_RTOL * math.hypot(x1 - x0, y1 - y0)
    for c in cracks:
        for end in (c[0], c[-1]) if len(c) > 1 else ():
            e = shapely.Point(end)
            for ring in region.interiors:
                if 0.0 < ring.distance(e) <= near:
                    x = np.asarray(ring.interpolate(ring.project(e)).coords[0])
                    lines.append(shapely.LineString([end, 2.0 * x - np.asarray(end, dtype=float)]))
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(shapely.unary_union(lines))))
    inside = [f for f in faces if region.contains(f.representative_point())]
    return max(len(inside), 1)


def cut_through(region: shapely.Polygon, before, after) -> bool:
    """Whether the grown cracks `after` cut the body into more pieces than `before` (lists of point
    sequences): a crack reached the boundary or a hole and separated a piece of the body."""
    return pieces(region, after) > pieces(region, before)


def extended_cracks(scene, extensions) -> list:
    """The scene's cracks with the new end points of `extensions` (a list of Extension) added."""
    from ngcrack.planar.scene import Crack

    pts = [list(c.points) for c in scene.cracks]
    for ext in extensions:
        if ext.point is None:
            continue
        if ext.end == "last":
            pts[ext.crack].append(ext.point)
        else:
            pts[ext.crack].insert(0, ext.point)
    # each crack keeps its other fields (friction, face pressure; a pressure table stays in the
    # arc length from the crack's first point, which moves when that end grows)
    return [dataclasses.replace(c, points=tuple(p)) if isinstance(c, Crack) else Crack(tuple(p), c.friction)
            for p, c in zip(pts, scene.cracks)]


def _hole_size(hole) -> float:
    """A length of `hole`: its radius, or its polygon's largest extent."""
    if hole.is_circle:
        return float(hole.radius)
    pts = np.asarray(hole.polygon, dtype=float)
    return float(np.ptp(pts, axis=0).max())


def hole_approaches(scene, paths) -> list[dict]:
    """The closest approach of the cracks (`paths`: point sequences) to each hole of `scene`:
    one dict per hole, {"hole", "label", "distance", "crack", "point"} (the crack point nearest
    the hole's edge; distance to the exact circle for a circular hole)."""
    out = []
    lines = [shapely.LineString(p) if len(p) > 1 else shapely.Point(p[0]) for p in paths]
    for i, hole in enumerate(scene.holes):
        best = None
        for k, line in enumerate(lines):
            if hole.is_circle:
                centre = shapely.Point(hole.center)
                q = shapely.ops.nearest_points(line, centre)[0]
                d = q.distance(centre) - hole.radius
            else:
                ring = shapely.LinearRing(hole.polygon)
                q = shapely.ops.nearest_points(line, ring)[0]
                d = q.distance(ring)
            # a tie within round-off (a crack that joined the hole and one that leaves it) goes to
            # the first crack, whatever the last bits of the points
            if best is None or d < best[0] - 1e-9 * _hole_size(hole):
                best = (d, k, (float(q.x), float(q.y)))
        if best is not None:
            out.append({"hole": i, "label": hole.labels[0] if hole.labels else f"hole[{i}]",
                        "distance": float(best[0]), "crack": best[1], "point": list(best[2])})
    return out
