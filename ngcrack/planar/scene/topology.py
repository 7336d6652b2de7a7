"""The body's topology: its connected parts after through cracks cut it, and whether
each part is held against rigid motion.

A crack with both ends on the boundary cuts the part it crosses in two. Each part gets
its loop of outer-boundary pieces and crack faces (:class:`Part`); :func:`check_held`
then asks, per part, whether its supports remove all three rigid motions (two
translations, one rotation) and refuses the scene by name when they do not: the answer
would not be unique. Contact on crack faces is unilateral and holds nothing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...core.fields import SceneError, fmt, fmt_pt, unique
from .holes import hole_ends
from .measures import (
    Point,
    boundary_distance,
    diameter,
    dist,
    inside,
    interior_point,
    mid,
    point_segment_distance,
    signed_area,
)
from .planar import Walls
from .types import GEOMETRY_RTOL

__all__ = ["HELD_MARGIN_RTOL", "HELD_RANK_RTOL", "Part", "check_held", "parts"]

#: Relative threshold on singular values in the rigid-motion rank check of
#: :func:`check_held`: the 3 constraint columns (two translations, one rotation
#: about a point inside the part, lengths scaled by the diameter) are O(1), so a
#: singular value below ``HELD_RANK_RTOL`` times the largest one counts as zero.
HELD_RANK_RTOL = 1e-8
#: A part held with rank 3 but whose smallest singular value of the same constraints is
#: below ``HELD_MARGIN_RTOL`` times the largest is held only marginally (supports a
#: tiny fraction of the body apart): refused for every element alike. Measured on a unit
#: square clamped on one bottom edge of length s and pulled at the top: bdm, tdnns, h1p1
#: and h1p2 solve it down to s = 1e-6 (ratio 2.8e-7), peers's condensed system is
#: singular to working precision up to s = 4e-5 (ratio 1.1e-5) and solves it from
#: s = 5e-5 (1.4e-5) on.
HELD_MARGIN_RTOL = 2e-5


@dataclass(frozen=True)
class Part:
    """One connected piece of the body after the through cracks have cut it.

    ``loop``: its boundary vertices, counter-clockwise (outer edges and crack faces).
    ``pieces``: its pieces of the outer boundary, ``(label, p, q)``, counter-clockwise.
    ``crack_faces``: ``(crack index, p, q)`` for each crack segment on its boundary, in
    the loop's direction. ``cracks``: indices of the cracks inside or bounding it.
    ``point``: a point strictly inside it (used to name it in messages). ``holes``: the
    indices of the holes inside it; a polygonal hole's edges are among ``pieces``, oriented
    with the part on their left (clockwise around the hole).
    """

    loop: tuple[Point, ...]
    pieces: tuple[tuple[str, Point, Point], ...]
    crack_faces: tuple[tuple[int, Point, Point], ...]
    cracks: tuple[int, ...]
    point: Point
    hole_loops: tuple[tuple[Point, ...], ...] = ()
    holes: tuple[int, ...] = ()

    @property
    def labels(self) -> tuple[str, ...]:
        """Distinct labels of its outer-boundary pieces, in loop order."""
        return tuple(unique([lab for lab, _, _ in self.pieces]))

    @property
    def area(self) -> float:
        return signed_area(self.loop)

    def contains(self, x: Sequence[float]) -> bool:
        """True if ``x`` lies strictly inside (points on the loop are not inside)."""
        p = (float(x[0]), float(x[1]))
        tol = GEOMETRY_RTOL * diameter(self.loop)
        return (boundary_distance(p, self.loop) > tol and inside(p, self.loop)
                and not any(boundary_distance(p, h) <= tol or inside(p, h) for h in self.hole_loops))


def _insert_on_loop(V: list[Point], T: list[Any], x: Point, tol: float) -> int:
    """Index of ``x`` among the loop's vertices, inserting it on its edge if needed."""
    for i, v in enumerate(V):
        if dist(v, x) <= tol:
            return i
    m = len(V)
    for i in range(m):
        if point_segment_distance(x, V[i], V[(i + 1) % m]) <= tol:
            V.insert(i + 1, x)
            T.insert(i + 1, T[i])
            return i + 1
    raise AssertionError(f"{fmt_pt(x)} is not on the loop")  # excluded by validation


def parts(scene) -> tuple[Part, ...]:
    """The connected pieces of ``scene``'s body after its through cracks cut it."""
    if scene.hole_joins():
        return _joined_parts(scene)
    tol = scene.tol
    n = len(scene.polygon)
    # a loop: vertices V and tags T, T[i] for the edge V[i] -> V[i+1]
    loops: list[tuple[list[Point], list[tuple[str, Any]]]] = [
        (list(scene.polygon), [("edge", scene.labels[i]) for i in range(n)])]
    through = scene.through_cracks()
    for c in through:
        P = scene.cracks[c].points
        m0 = mid(P[0], P[1])
        li = next(k for k, (V, _) in enumerate(loops) if inside(m0, V))
        V, T = list(loops[li][0]), list(loops[li][1])
        _insert_on_loop(V, T, P[0], tol)
        _insert_on_loop(V, T, P[-1], tol)
        i0 = _insert_on_loop(V, T, P[0], tol)  # index again after the 2nd insertion
        i1 = _insert_on_loop(V, T, P[-1], tol)
        m = len(V)

        def arc(a: int, b: int, m: int = m) -> list[int]:
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

    out = []
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
        for i, crack in enumerate(scene.cracks):
            if i not in through and inside(mid(crack.points[0], crack.points[1]), V):
                ids.append(i)
        holes = [k for k, h in enumerate(scene.holes) if inside(h.loop()[0], V)]
        hole_loops = tuple(scene.holes[k].loop() for k in holes)
        for k in holes:  # a polygonal hole's edges; circles are held by their own rows
            if not scene.holes[k].is_circle:
                loop, labels = scene.holes[k].loop(), scene.holes[k].edge_labels()
                pieces += [(labels[i], loop[(i + 1) % len(loop)], loop[i]) for i in range(len(loop))]
        point = interior_point(V)
        if hole_loops:
            point = interior_point(V, hole_loops)
        out.append(Part(loop=tuple(V), pieces=tuple(pieces), crack_faces=tuple(faces),
                        cracks=tuple(sorted(set(ids))), point=point, hole_loops=hole_loops,
                        holes=tuple(holes)))
    return tuple(out)


def _joined_parts(scene) -> tuple[Part, ...]:
    """The parts of a body some of whose cracks join holes: the faces of the body's boundary loops
    (circles as their inscribed polygons with the crack ends among their vertices) and the crack
    lines, each face's edges told apart as crack faces or boundary pieces (their labels) by where
    their midpoints lie. A circular hole no crack touches is listed in ``holes`` (check_held holds
    it by its own points); every other hole's edges are among ``pieces``."""
    import shapely  # (cracks joining holes only)

    tol = scene.tol
    ends = [scene.cracks[i].points[k] for i, k, _ in scene.hole_joins()]
    through = hole_ends(scene.holes, ends, tol)
    loops = [h.loop(through=through[k]) for k, h in enumerate(scene.holes)]
    walls = Walls([(scene.polygon, scene.labels, "domain.polygon")]
                  + [(loops[k], h.edge_labels(through=through[k]), f"hole[{k}]") for k, h in enumerate(scene.holes)])
    region = shapely.Polygon(scene.polygon, loops)
    lines = [shapely.LineString(c.points) for c in scene.cracks]
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(shapely.unary_union(
        [region.exterior, *region.interiors, *lines]))))
    out = []
    for face in faces:
        if not region.contains(face.representative_point()):
            continue
        face = shapely.geometry.polygon.orient(face, 1.0)
        rings = [face.exterior, *face.interiors]
        pieces, faces_, ids, holes = [], [], [], []
        for ring in rings:
            P = [tuple(map(float, x)) for x in ring.coords[:-1]]
            untouched = [k for k, h in enumerate(scene.holes) if h.is_circle and not through[k]
                         and all(h.edge_distance(x) <= 1e-3 * h.radius for x in P)]
            if untouched:
                holes.append(untouched[0])
                continue
            for p, q in zip(P, P[1:] + P[:1]):
                m = np.array([[(p[0] + q[0]) / 2, (p[1] + q[1]) / 2]])
                crack = next((i for i, ln in enumerate(lines) if ln.distance(shapely.Point(m[0])) <= 10 * tol), None)
                if crack is not None:
                    faces_.append((crack, p, q))
                    ids.append(crack)
                    continue
                li, e = walls.owner[int(walls.nearest_edge(m)[0])]
                pieces.append((walls.loops[li][1][e], p, q))
        ids += [i for i, ln in enumerate(lines) if face.contains(ln.interpolate(0.5, normalized=True))]
        point = face.representative_point()
        out.append(Part(loop=tuple(tuple(map(float, x)) for x in face.exterior.coords[:-1]), pieces=tuple(pieces),
                        crack_faces=tuple(faces_), cracks=tuple(sorted(set(ids))), point=(point.x, point.y),
                        hole_loops=tuple(tuple(tuple(map(float, x)) for x in r.coords[:-1]) for r in face.interiors),
                        holes=tuple(holes)))
    return tuple(out)


def _direction(a: float, b: float) -> Point:
    """The unit vector along (a, b), signed so that its larger component is positive,
    with round-off components set to zero (for messages)."""
    h = math.hypot(a, b)
    a, b = a / h, b / h
    if (a if abs(a) >= abs(b) else b) < 0:
        a, b = -a, -b
    return (0.0 if abs(a) < HELD_RANK_RTOL else a, 0.0 if abs(b) < HELD_RANK_RTOL else b)


def check_held(scene) -> None:
    """Refuse a scene in which some part can move rigidly (the answer is not unique).

    Rigid motions are v(x) = a + theta (-y, x). Each clamped or displacement piece
    imposes v = 0 at its two end points, each roller piece v.n = 0 there, a pin point
    v = 0 at its centre and a roller point v.n = 0 there; a part is
    held when these constraints have rank 3. Contact on crack faces is unilateral
    and holds nothing.
    """
    L, tol = scene.diameter, scene.tol
    for part in scene.parts():
        c = part.point
        rows: list[list[float]] = []
        held: dict[tuple[str, str], float] = {}  # (type, label) -> total length
        points = {pc.label: pc for pc in getattr(scene, "points", ())}
        for lab, p, q in part.pieces:
            cond = scene.boundary.get(lab)
            length = dist(p, q)
            pc = points.get(lab)
            if pc is not None and pc.holds != "none":  # a pin or roller point: its segment's mean, at its centre
                X, Y = (pc.at[0] - c[0]) / L, (pc.at[1] - c[1]) / L
                n_out = ((q[1] - p[1]) / length, -(q[0] - p[0]) / length)
                held[(pc.type, lab)] = length
                rows += ([[1.0, 0.0, -Y], [0.0, 1.0, X]] if pc.holds == "all"
                         else [[n_out[0], n_out[1], -n_out[0] * Y + n_out[1] * X]])
                continue
            if cond is None or cond.holds == "none" or length <= tol:
                continue
            n_out = ((q[1] - p[1]) / length, -(q[0] - p[0]) / length)
            held[(cond.type, lab)] = held.get((cond.type, lab), 0.0) + length
            for x in (p, q):
                X, Y = (x[0] - c[0]) / L, (x[1] - c[1]) / L
                if cond.holds == "all":
                    rows += [[1.0, 0.0, -Y], [0.0, 1.0, X]]
                else:
                    rows.append([n_out[0], n_out[1], -n_out[0] * Y + n_out[1] * X])
        for k in part.holes:  # a circle: its own points and normals (not a polygon's)
            hole = scene.holes[k]
            cond = scene.boundary.get(hole.labels[0])
            if not hole.is_circle or cond is None or cond.holds == "none":
                continue
            held[(cond.type, hole.labels[0])] = math.pi * hole.size
            for x in hole.loop(8):
                X, Y = (x[0] - c[0]) / L, (x[1] - c[1]) / L
                if cond.holds == "all":
                    rows += [[1.0, 0.0, -Y], [0.0, 1.0, X]]
                else:  # out of the body: towards the centre
                    n_out = ((hole.center[0] - x[0]) / hole.radius, (hole.center[1] - x[1]) / hole.radius)
                    rows.append([n_out[0], n_out[1], -n_out[0] * Y + n_out[1] * X])
        where = f"boundary: the part of the body containing point {fmt_pt(c)}"
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
                free = f"the translation along {fmt_pt(_direction(a1, a2))}"
            else:
                centre = (c[0] - L * a2 / th, c[1] + L * a1 / th)
                centre = tuple(0.0 if abs(v) <= tol else v for v in centre)
                free = f"the rotation about {fmt_pt(centre)}"
            rollers = [lab for (typ, lab) in held if typ == "roller"]
            pieces = [f"{typ} edge {lab!r} ({fmt(length)} long)"
                      for (typ, lab), length in held.items() if typ != "roller"]
            if rollers:
                pieces.append(f"roller edges ({', '.join(rollers)})")
            short_fixed = [lab for (typ, lab), length in held.items()
                           if typ != "roller" and length <= HELD_RANK_RTOL ** 0.5 * L]
            if short_fixed:
                advice = (f"a support as short as {', '.join(map(repr, short_fixed))} holds only a "
                          f"point; make it longer, or add another clamped/displacement edge or a "
                          f"roller edge elsewhere")
            else:
                advice = ("add a clamped/displacement edge or a roller with a non-parallel "
                          "normal to it")
            raise SceneError(
                f"{where} is held only by {' and '.join(pieces)} that leave{'s' if len(pieces) == 1 and not rollers else ''} "
                f"{free} free, so the "
                f"answer is not unique; {advice}")
        if s[-1] < HELD_MARGIN_RTOL * s[0]:
            supports = ", ".join(f"{typ} edge {lab!r} ({fmt(length)} long)" for (typ, lab), length in held.items())
            raise SceneError(
                f"{where} is held only marginally by {supports}: its rigid motions are fixed with a "
                f"conditioning of {s[-1] / s[0]:.1e}, below the {HELD_MARGIN_RTOL:g} that every element "
                f"solves reliably (peers fails first); lengthen the supports, or add one farther away")
