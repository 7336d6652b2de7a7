"""Planar checks of a scene's polylines: simple, inside the body, apart from each other.

A polygon must be simple, a crack must not touch itself, lie inside the polygon (its end
points may lie on the boundary) and keep clear of every other crack. Each check refuses
with a :class:`SceneError` naming the field, the segments and the points involved. The
predicates and distances are shapely's, with the absolute tolerance ``tol`` the caller
derives from the polygon's diameter (``GEOMETRY_RTOL * diameter``).
"""

from __future__ import annotations

from collections.abc import Sequence

from .fields import SceneError, fmt_pt
from .measures import (
    Point,
    boundary_distance,
    dist,
    inside,
    mid,
    point_segment_distance,
    segment_distance,
)


def check_polyline_simple(pts: Sequence[Point], fld: str, tol: float, closed: bool,
                          what: str) -> None:
    """Refuse zero-length segments, back-tracking adjacent segments and any contact
    between non-adjacent segments."""
    n = len(pts)
    m = n if closed else n - 1
    segs = [(pts[i], pts[(i + 1) % n]) for i in range(m)]
    for i, (p, q) in enumerate(segs):
        if dist(p, q) <= tol:
            j = (i + 1) % n
            raise SceneError(
                f"{fld}: {what} {i} from point {i} {fmt_pt(p)} to point {j} {fmt_pt(q)} "
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
                bad = (point_segment_distance(far_a, q1, q2) <= tol
                       or point_segment_distance(far_b, p1, p2) <= tol)
            else:
                bad = segment_distance(p1, p2, q1, q2) <= tol
            if bad:
                rule = ("the polygon must be simple" if closed
                        else "a crack must not cross or touch itself")
                raise SceneError(
                    f"{fld}: {what}s {i} {fmt_pt(p1)}-{fmt_pt(p2)} and {j} "
                    f"{fmt_pt(q1)}-{fmt_pt(q2)} cross, touch or overlap; {rule}")


def check_crack_in_domain(poly: Sequence[Point], labels: Sequence[str], pts: Sequence[Point],
                          fld: str, tol: float) -> None:
    """Refuse a crack that leaves the polygon, runs along or crosses an edge, or touches
    the boundary anywhere but at its first or last point."""
    n = len(poly)
    last = len(pts) - 1
    for k, p in enumerate(pts):
        d = boundary_distance(p, poly)
        on = d <= tol
        if not on and not inside(p, poly):
            raise SceneError(
                f"{fld}.points[{k}] = {fmt_pt(p)} lies outside domain.polygon; every "
                f"crack point must lie inside the polygon (end points may lie on its "
                f"boundary)")
        if on and 0 < k < last:
            raise SceneError(
                f"{fld}.points[{k}] = {fmt_pt(p)} lies on the boundary of "
                f"domain.polygon; only a crack's first and last points may lie on the "
                f"boundary, interior points must lie strictly inside")
    ends_on = {k: boundary_distance(pts[k], poly) <= tol for k in (0, last)}
    for s in range(last):
        a, b = pts[s], pts[s + 1]
        where = f"{fld}.points: segment {s} from {fmt_pt(a)} to {fmt_pt(b)}"
        rule = ("a crack must lie inside the polygon and may touch its boundary only "
                "at its first or last point")
        for e in range(n):
            c, d = poly[e], poly[(e + 1) % n]
            if segment_distance(a, b, c, d) > tol:
                continue
            edge = f"edge {e} {labels[e]!r} of domain.polygon"
            contacts = [x for x in (a, b) if point_segment_distance(x, c, d) <= tol]
            contacts += [x for x in (c, d) if point_segment_distance(x, a, b) <= tol]
            if not contacts:
                raise SceneError(f"{where} crosses {edge}; {rule}")
            if max(dist(x, y) for x in contacts for y in contacts) > tol:
                raise SceneError(f"{where} runs along {edge}; {rule}")
            x = contacts[0]
            allowed = [pts[k] for k in (0, last) if ends_on[k]]
            if not any(dist(x, y) <= tol for y in allowed):
                raise SceneError(f"{where} touches {edge} at {fmt_pt(x)}; {rule}")
        m = mid(a, b)
        if boundary_distance(m, poly) <= tol or not inside(m, poly):
            raise SceneError(f"{where} leaves the domain (its midpoint "
                             f"{fmt_pt(m)} is not inside domain.polygon); {rule}")


def check_cracks_disjoint(pts: Sequence[Point], other: Sequence[Point], i: int, j: int,
                          tol: float) -> None:
    """Refuse crack ``i`` (points ``pts``) touching crack ``j`` (points ``other``)."""
    for s in range(len(pts) - 1):
        for r in range(len(other) - 1):
            if segment_distance(pts[s], pts[s + 1], other[r], other[r + 1]) <= tol:
                raise SceneError(
                    f"crack[{i}].points: segment {s} {fmt_pt(pts[s])}-"
                    f"{fmt_pt(pts[s + 1])} crosses or touches crack[{j}] (segment "
                    f"{r}); cracks must be disjoint (join them into one polyline "
                    f"or move them apart)")
