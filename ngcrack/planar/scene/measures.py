"""Low-level plane measures of points, segments and polygons.

The one place where the package measures a polygon (its diameter, its area) or the
distance between points and segments: the scene's validation, the mesher's frame
(``geometry``), the size guard (``sizing``) and the tip table (``tips``) all read these,
so a tolerance computed from the diameter means the same thing everywhere.

This module imports nothing of ngcrack (only numpy; shapely only for a large polygon's
convex hull), so every layer may use it. Points are pairs
``(x, y)``; polygons are sequences of such pairs, not closed (the first vertex is not
repeated).

The distances, the point-in-polygon test and the interior point are computed on numpy
with GEOS's own formulas (shapely's library: the same numbers bit for bit, checked in
tests/test_scene_measures.py), so that a scene is validated without importing shapely (its import's cost:
BENCHMARKS.md, the start-up section).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

__all__ = ["Point", "diameter", "polygon_area", "signed_area"]

Point = tuple[float, float]

#: how many rows of the pairwise distance matrix `diameter` computes at a time
_CHUNK = 1024
#: up to this many points `diameter` compares every pair; above, only the convex hull's (shapely)
_HULL_FROM = 64


def diameter(points) -> float:
    """The largest distance between two of the points (the diameter of a polygon).

    The farthest pair lies on the convex hull, so only the hull's vertices are compared
    (chunked, so that memory stays bounded): near-linear for the polygons met in practice.
    """
    P = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(P) > _HULL_FROM:  # (below, every pair: the same largest distance, computed the same way)
        import shapely

        hull = shapely.MultiPoint(P).convex_hull
        if isinstance(hull, shapely.Polygon):
            P = np.asarray(hull.exterior.coords, dtype=float)[:-1]
        elif isinstance(hull, shapely.LineString):
            P = np.asarray(hull.coords, dtype=float)
    best = 0.0
    for i in range(0, len(P), _CHUNK):
        block = P[i:i + _CHUNK]
        d = np.max(np.hypot(block[:, None, 0] - P[None, :, 0], block[:, None, 1] - P[None, :, 1]))
        best = max(best, float(d))
    return best


def signed_area(poly: Sequence[Point]) -> float:
    """The signed area of a closed loop of vertices (> 0 counter-clockwise), shoelace formula."""
    P = np.asarray(poly, dtype=float).reshape(-1, 2)
    x, y = P[:, 0], P[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def polygon_area(poly: Sequence[Point]) -> float:
    """The area of a simple polygon (either orientation)."""
    return abs(signed_area(poly))


def sub(p: Point, q: Point) -> Point:
    return (p[0] - q[0], p[1] - q[1])


def cross(a: Point, b: Point) -> float:
    return a[0] * b[1] - a[1] * b[0]


def dot(a: Point, b: Point) -> float:
    return a[0] * b[0] + a[1] * b[1]


def dist(p: Point, q: Point) -> float:
    return math.hypot(p[0] - q[0], p[1] - q[1])


def mid(p: Point, q: Point) -> Point:
    return (0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]))


def point_segment_distance(x: Point, p: Point, q: Point) -> float:
    """Distance from the point x to the closed segment p-q (points as pairs or numpy arrays)."""
    (px, py), (ax, ay), (bx, by) = ((float(v[0]), float(v[1])) for v in (x, p, q))
    if (ax, ay) == (bx, by):
        return dist((px, py), (ax, ay))
    dx, dy = bx - ax, by - ay
    len2 = dx * dx + dy * dy  # GEOS's pointToSegment, as point_segment_distances (one pair, in floats)
    r = ((px - ax) * dx + (py - ay) * dy) / len2
    if r <= 0.0:
        return math.sqrt((px - ax) * (px - ax) + (py - ay) * (py - ay))
    if r >= 1.0:
        return math.sqrt((px - bx) * (px - bx) + (py - by) * (py - by))
    return abs(((ay - py) * dx - (ax - px) * dy) / len2) * math.sqrt(len2)


def point_segment_distances(X, A, B) -> np.ndarray:
    """Distances from the points X to the closed segments A-B, elementwise (broadcast; the
    last axis holds x and y), by GEOS's pointToSegment: the same numbers as shapely's."""
    X, A, B = (np.asarray(v, dtype=float) for v in (X, A, B))
    px, py, ax, ay, bx, by = X[..., 0], X[..., 1], A[..., 0], A[..., 1], B[..., 0], B[..., 1]
    dx, dy = bx - ax, by - ay
    len2 = dx * dx + dy * dy
    with np.errstate(divide="ignore", invalid="ignore"):
        r = ((px - ax) * dx + (py - ay) * dy) / len2
        s = ((ay - py) * dx - (ax - px) * dy) / len2
    to_a = np.sqrt((px - ax) * (px - ax) + (py - ay) * (py - ay))
    to_b = np.sqrt((px - bx) * (px - bx) + (py - by) * (py - by))
    point = (ax == bx) & (ay == by)
    return np.where(point | (r <= 0.0), to_a, np.where(r >= 1.0, to_b, np.abs(s) * np.sqrt(len2)))


def segment_distances(A, B, C, D) -> np.ndarray:
    """Distances between the closed segments A-B and C-D, elementwise (broadcast), by
    GEOS's segmentToSegment: zero where they intersect, else the least of the four
    end-point distances."""
    A, B, C, D = (np.asarray(v, dtype=float) for v in (A, B, C, D))
    ax, ay, bx, by, cx, cy, ex, ey = A[..., 0], A[..., 1], B[..., 0], B[..., 1], C[..., 0], C[..., 1], D[..., 0], D[..., 1]
    apart = ((np.minimum(ax, bx) > np.maximum(cx, ex)) | (np.maximum(ax, bx) < np.minimum(cx, ex))
             | (np.minimum(ay, by) > np.maximum(cy, ey)) | (np.maximum(ay, by) < np.minimum(cy, ey)))
    denom = (bx - ax) * (ey - cy) - (by - ay) * (ex - cx)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = ((ay - cy) * (ex - cx) - (ax - cx) * (ey - cy)) / denom
        s = ((ay - cy) * (bx - ax) - (ax - cx) * (by - ay)) / denom
    crossing = ~apart & (denom != 0.0) & (r >= 0.0) & (r <= 1.0) & (s >= 0.0) & (s <= 1.0)
    ends = np.minimum(np.minimum(point_segment_distances(A, C, D), point_segment_distances(B, C, D)),
                      np.minimum(point_segment_distances(C, A, B), point_segment_distances(D, A, B)))
    return np.where(crossing, 0.0, ends)


def _edges(rings) -> tuple[np.ndarray, np.ndarray]:
    """The edges (A, B) of closed loops of vertices."""
    A, B = [], []
    for ring in rings:
        R = np.asarray(ring, dtype=float).reshape(-1, 2)
        A.append(R)
        B.append(np.roll(R, -1, axis=0))
    return np.concatenate(A), np.concatenate(B)


def in_region(P, rings, chunk: int = _CHUNK) -> np.ndarray:
    """True where a point (k, 2) lies strictly inside the region bounded by the closed
    loops `rings` (an outer loop and its holes): an odd number of edge crossings to the
    right and no edge through it (points on an edge are not inside, as in shapely)."""
    P = np.asarray(P, dtype=float).reshape(-1, 2)
    A, B = _edges(rings)
    out = np.zeros(len(P), dtype=bool)
    for i in range(0, len(P), chunk):
        X = P[i:i + chunk, None, :]
        px, py = X[..., 0], X[..., 1]
        ax, ay, bx, by = A[None, :, 0], A[None, :, 1], B[None, :, 0], B[None, :, 1]
        spans = (ay > py) != (by > py)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_cross = ax + (py - ay) * (bx - ax) / (by - ay)
        odd = np.count_nonzero(spans & (px < x_cross), axis=1) % 2 == 1
        on = (point_segment_distances(X, A[None], B[None]) == 0.0).any(axis=1)
        out[i:i + chunk] = odd & ~on
    return out


def inside(x: Point, poly: Sequence[Point]) -> bool:
    """True if x lies strictly inside the simple polygon (points on its boundary are not)."""
    return bool(in_region([x], [poly])[0])


def boundary_distance(x: Point, poly: Sequence[Point]) -> float:
    """Distance from x to the polygon's boundary."""
    A, B = _edges([poly])
    return float(point_segment_distances(np.asarray(x, dtype=float), A, B).min())


def interior_point(poly: Sequence[Point], holes: Sequence[Sequence[Point]] = ()) -> Point:
    """A point strictly inside a polygon (with holes), GEOS's interior point of an area
    (shapely's representative_point): the middle of the widest interval that a
    horizontal line near the middle, through no vertex, has inside the polygon."""
    rings = [np.asarray(r, dtype=float).reshape(-1, 2) for r in (poly, *holes)]
    lo, hi = float(rings[0][:, 1].min()), float(rings[0][:, 1].max())
    centre = (lo + hi) / 2.0
    for y in (float(v) for r in rings for v in np.append(r[:, 1], r[0, 1])):
        if y <= centre:
            lo = y if y > lo else lo
        elif y < hi:
            hi = y
    Y = (hi + lo) / 2.0
    crossings = []
    for r in rings:
        if Y < r[:, 1].min() or Y > r[:, 1].max():
            continue
        closed = np.vstack([r, r[:1]])
        for (x0, y0), (x1, y1) in zip(closed[:-1].tolist(), closed[1:].tolist()):
            if (y0 > Y and y1 > Y) or (y0 < Y and y1 < Y) or y0 == y1:
                continue
            if (y0 == Y and y1 < Y) or (y1 == Y and y0 < Y):
                continue
            crossings.append(x0 if x0 == x1 else x0 + (Y - y0) / ((y1 - y0) / (x1 - x0)))
    crossings.sort()
    best, point = 0.0, (float(rings[0][0, 0]), float(rings[0][0, 1]))
    for x1, x2 in zip(crossings[0::2], crossings[1::2]):
        if x2 - x1 > best:
            best, point = x2 - x1, ((x1 + x2) / 2.0, Y)
    return point
