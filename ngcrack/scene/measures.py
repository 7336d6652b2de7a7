"""Low-level plane measures of points, segments and polygons.

The one place where the package measures a polygon (its diameter, its area) or the
distance between points and segments: the scene's validation, the mesher's frame
(``geometry``), the size guard (``sizing``) and the tip table (``tips``) all read these,
so a tolerance computed from the diameter means the same thing everywhere.

This module imports nothing of ngcrack (only numpy and shapely), so every layer may use
it. Points are pairs ``(x, y)``; polygons are sequences of such pairs, not closed (the
first vertex is not repeated).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np
import shapely

__all__ = ["Point", "diameter", "polygon_area", "signed_area"]

Point = tuple[float, float]

#: how many rows of the pairwise distance matrix `diameter` computes at a time
_CHUNK = 1024


def diameter(points) -> float:
    """The largest distance between two of the points (the diameter of a polygon).

    The farthest pair lies on the convex hull, so only the hull's vertices are compared
    (chunked, so that memory stays bounded): near-linear for the polygons met in practice.
    """
    P = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(P) > 3:
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
    x, p, q = ((float(v[0]), float(v[1])) for v in (x, p, q))
    if p == q:
        return dist(x, p)
    return shapely.Point(x).distance(shapely.LineString([p, q]))


@functools.lru_cache(maxsize=256)
def shapely_polygon(poly: tuple[Point, ...]) -> shapely.Polygon:
    """The shapely polygon of a simple loop of vertices (cached: scenes are immutable)."""
    p = shapely.Polygon(poly)
    shapely.prepare(p)
    return p


def inside(x: Point, poly: Sequence[Point]) -> bool:
    """True if x lies strictly inside the simple polygon (points on its boundary are not)."""
    return shapely_polygon(tuple(poly)).contains(shapely.Point(x))


def boundary_distance(x: Point, poly: Sequence[Point]) -> float:
    """Distance from x to the polygon's boundary."""
    return shapely_polygon(tuple(poly)).exterior.distance(shapely.Point(x))


def interior_point(poly: Sequence[Point]) -> Point:
    """A point strictly inside a simple polygon."""
    p = shapely_polygon(tuple(poly)).representative_point()
    return (p.x, p.y)
