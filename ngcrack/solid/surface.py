"""Cracks that reach the body's surface: where a planar crack leaves the body, and its open fronts.

A planar crack (disc, ellipse, polygon, curve) may cross the faces of its box or cylinder: the crack
is its part inside the body, and its front the part of its outline inside the body: open
arcs (or polygon sides) that end on the free surface, where the crack's mouth lies. A curve's
arcs are found as an ellipse's, along its spline's parameter (`inside_arcs` takes its point
function, which ngcrack.solid.curve, a layer above, gives), so that a surface or corner crack
may have a free front shape (a grown one: ngcrack.studies.growth.surface3d). This
module holds the geometry of that clipping in plain numpy, for the scene's checks
(``ngcrack.solid.scene``), the mesh (``ngcrack.solid.geometry`` names the clipped face's edges)
and the fronts (``ngcrack.solid.front`` wraps a closed front into an :class:`ArcFront`).

The domain is duck-typed: a box has ``lo`` and ``hi``, a cylinder ``center``, ``axis``,
``radius`` and ``height`` (``ngcrack.solid.scene.Box`` and ``Cylinder``), a STEP part
(``ngcrack.solid.parts.StepPart``) its own ``clearance`` and ``face_distances`` (OCC's, a few ms
a point: its outlines are sampled at STEP_SAMPLES points, each end of an arc still refined by
bisection). `inside_measures` gives the diameter, area and front length of a crack's part inside
the body, for the default mesh sizes and the size guard.
"""

from __future__ import annotations

import numpy as np

#: the parametric angles sampled to find where a disc's or an ellipse's outline leaves the body
ARC_SAMPLES = 4096
#: bisection steps refining each end of an arc (the angle to 2 pi 2^-40 / ARC_SAMPLES)
ARC_BISECTIONS = 40
#: outline samples on a STEP part (OCC's distance takes a few ms a point; ARC_BISECTIONS refine the ends as on a box)
STEP_SAMPLES = 128
#: outline samples measuring a crack's part inside the body (`inside_measures`), and the measures kept
MEASURE_SAMPLES, MEASURE_CACHE = 512, 256
#: grid points per side measuring the area of a crack's part inside a box or a cylinder (`inside_measures`)
MEASURE_GRID = 400
#: outline points of the polygon standing for a curve's face when its area inside a STEP part is measured
CURVE_AREA_POINTS = 1024
#: a point within this fraction of the body's size of a face is on it (an edge of the clipped crack on the surface)
ON_SURFACE_RTOL = 1e-7
#: the body beyond the front of a crack reaching a face is at least this many front_h thick (a thinner
#: sliver has fewer elements across than the domain integral's tube and the contact need)
LIGAMENT_FRONT_H = 1.0
#: on a front ending on the surface, K is reported at points at least this many bump half-widths
#: (front.HALF_WIDTH_H front_h) from the surface, and the surface point carries the value of the nearest
#: of them: the domain integral's bump and tube are cut there by the free surface, where the singularity
#: changes; the integral at the surface itself came 15-17% below Newman-Raju's surface value
SURFACE_INSET = 1.0


def is_step(domain) -> bool:
    """Whether the domain is a STEP part (``ngcrack.solid.parts.StepPart``: its distances are OCC's, a few ms a point)."""
    return not hasattr(domain, "lo") and not hasattr(domain, "axis")


def samples(domain, n: int) -> int:
    """n outline samples on a box or a cylinder, at most STEP_SAMPLES on a STEP part."""
    return min(n, STEP_SAMPLES) if is_step(domain) else n


def face_distances(domain, p: np.ndarray) -> dict[str, np.ndarray]:
    """The signed distance of each point (rows of p) to each face's surface, positive inside (a STEP part: the
    distance to each label's faces, negative at a point outside for the label nearest to it)."""
    p = np.atleast_2d(p)
    if is_step(domain):
        return domain.face_distances(p)
    if hasattr(domain, "lo"):
        out = {}
        for k, ax in enumerate("xyz"):
            out[ax + "min"] = p[:, k] - domain.lo[k]
            out[ax + "max"] = domain.hi[k] - p[:, k]
        return out
    d = p - domain.center
    h = d @ domain.axis
    r = np.linalg.norm(d - np.outer(h, domain.axis), axis=1)
    return {"bottom": h + 0.5 * domain.height, "top": 0.5 * domain.height - h, "side": domain.radius - r}


def clearance(domain, p: np.ndarray) -> np.ndarray:
    """The signed distance to the body's boundary (positive inside)."""
    if is_step(domain):
        return domain.clearance(np.atleast_2d(p))
    return np.min(np.stack(list(face_distances(domain, p).values())), axis=0)


def on_surface(domain, p: np.ndarray, size: float) -> np.ndarray:
    """True for points on the body's boundary (within ON_SURFACE_RTOL of its size)."""
    return np.abs(clearance(domain, p)) <= ON_SURFACE_RTOL * size


def crosses(domain, crack) -> bool:
    """Whether the crack's outline leaves the body (the crack reaches the surface)."""
    return bool(clearance(domain, crack.outline(samples(domain, 512))).min() < 0.0)


def face_problem(domain, crack, rtol: float, boundary, front_h) -> str | None:
    """What is wrong with where the crack meets the faces (None: nothing), for the scene's check.

    A crack stays `rtol` of its size (the scene's clearance) inside every face, or crosses it by as much (a surface crack:
    its part inside the body is the crack); the faces it crosses are free (no entry in `boundary`); its outline
    lies partly inside; a surface crack reaches at least LIGAMENT_FRONT_H front_h into the body from each face it
    crosses, and the body beyond its front is as thick (`front_h()`, called only then): a thinner crack or sliver
    the mesh cannot resolve."""
    gap = rtol * crack.size
    outline = crack.outline(samples(domain, 1024))
    dist = face_distances(domain, outline)
    crossed = [k for k, d in dist.items() if d.min() < 0]
    for k in crossed:
        if dist[k].min() > -gap:
            return (f"crosses face {k} by only {-dist[k].min():.3g}; a crack must stay at least {gap:.3g} "
                    f"({rtol:g} of its size) inside a face or cross it by as much")
        if k in boundary:
            return (f"crosses face {k}, which carries a {boundary[k].type} condition; a crack may reach free faces "
                    f"only (faces without a [boundary.<label>] table)")
    inside = clearance(domain, outline) > 0
    if not inside.any():
        return ("its outline lies wholly outside the body or on its surface, so that it misses the body, lies in a "
                "face or cuts the body in two; a crack's front must lie partly inside the body")
    need = LIGAMENT_FRONT_H * front_h() if crossed else gap
    for k, depth in depths_from_faces(dist, inside).items():
        if depth < need:
            return (f"reaches only {depth:.3g} into the body from face {k}, less than the mesh resolves; at least "
                    f"{need:.3g} is needed ({LIGAMENT_FRONT_H:g} front_h: give a smaller mesh.front_h or a deeper crack)")
    for k, d in dist.items():
        if k in crossed or d[inside].min() >= need:
            continue
        if crossed:
            return (f"leaves a sliver of body {d[inside].min():.3g} thick between its front and face {k}, thinner "
                    f"than the mesh resolves; at least {need:.3g} is needed ({LIGAMENT_FRONT_H:g} front_h: give a "
                    f"smaller mesh.front_h or a shallower crack)")
        return (f"comes within {d.min():.3g} of face {k} without crossing it; keep at least {gap:.3g} "
                f"({rtol:g} of its size) inside a face, or let it cross the face by as much (a surface crack)")
    return None


def depths_from_faces(dist: dict[str, np.ndarray], inside: np.ndarray) -> dict[str, float]:
    """The crack's extent into the body from each face it crosses: per face whose distances `dist` (of the outline's
    points, `face_distances`) go negative, the largest distance from it of the points `inside` the body (a
    semi-ellipse's a from the face it crosses; a corner crack's extents from its two faces)."""
    return {k: float(d[inside].max()) for k, d in dist.items() if d.min() < 0}


_MEASURES: dict = {}


def inside_measures(domain, crack, n: int = MEASURE_SAMPLES) -> tuple[float, float, float]:
    """(diameter, area, front length) of the crack's part inside the body: the whole crack's if it stays inside,
    else from n outline samples (at most STEP_SAMPLES on a STEP part), the mouth closed by chords. The default mesh
    sizes (the diameter) and the size guard (the area and the front's length) use them: a semi-elliptical crack
    has half its ellipse's area and front, a corner crack a quarter."""
    key = (id(domain), id(crack), n)
    hit = _MEASURES.get(key)
    if hit is not None and hit[0] is domain and hit[1] is crack:
        return hit[2]
    p = crack.outline(samples(domain, n))
    inside = clearance(domain, p) > 0
    seg = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
    if inside.all():
        out = (float(crack.size), float(crack.area), float(seg.sum()))
    elif not inside.any():
        out = (0.0, 0.0, 0.0)
    else:
        q = p[inside]
        diameter = float(np.max(np.linalg.norm(q[:, None] - q[None], axis=-1)))
        both, one = inside & np.roll(inside, -1), inside ^ np.roll(inside, -1)  # a crossing segment: half of it
        out = (diameter, _inside_area(domain, crack), float(seg[both].sum() + 0.5 * seg[one].sum()))
    if len(_MEASURES) > MEASURE_CACHE:
        _MEASURES.clear()
    _MEASURES[key] = (domain, crack, out)
    return out


def _inside_area(domain, crack) -> float:
    """The area of the crack's part inside the body: OCC's on a STEP part (the crack's face cut by the solid),
    else a grid of MEASURE_GRID^2 points over the crack (the clearance is numpy's)."""
    if is_step(domain):
        return float(sum(f.mass for f in (_occ_face(crack) * domain.occ_shape()).faces))
    import shapely

    uv = _plane_outline(crack, 1024)
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    m = MEASURE_GRID
    u, v = np.meshgrid(lo[0] + (np.arange(m) + 0.5) * (hi[0] - lo[0]) / m, lo[1] + (np.arange(m) + 0.5) * (hi[1] - lo[1]) / m)
    u, v = u.ravel(), v.ravel()
    p = crack.center + np.multiply.outer(u, crack.e_a) + np.multiply.outer(v, crack.e_b)
    keep = shapely.contains_xy(shapely.Polygon(uv), u, v) & (clearance(domain, p) > 0)
    return float(keep.sum() * np.prod(hi - lo) / m ** 2)


def _occ_face(crack):
    """The crack's plane face in OCC (a disc, an ellipse, a polygon or a curve), for its area inside a STEP part."""
    from netgen import occ

    if crack.shape in ("polygon", "curve"):  # a curve: the polygon of CURVE_AREA_POINTS of its outline (its area to ~1e-6)
        pts = [occ.Pnt(*map(float, p)) for p in (crack.points if crack.shape == "polygon" else crack.outline(CURVE_AREA_POINTS))]
        return occ.Face(occ.Wire([occ.Segment(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]))
    a, b = crack.semi_axes
    major, (a, b) = (crack.e_a, (a, b)) if a >= b else (crack.e_b, (b, a))
    wp = occ.WorkPlane(occ.Axes(tuple(crack.center), n=occ.Dir(*crack.normal), h=occ.Dir(*major)))
    return (wp.Circle(a) if a == b else wp.Ellipse(a, b)).Face()


def outline_point(crack):
    """A disc's or an ellipse's outline as a function of its parametric angle phi (a curve's is its spline's,
    ngcrack.solid.curve.curve_point, which this module's layer does not import: give it to `inside_arcs`)."""
    if crack.shape not in ("disc", "ellipse"):
        raise ValueError(f"outline_point: a {crack.shape}'s outline is not an ellipse's; give inside_arcs its point "
                         f"function (a curve's: ngcrack.solid.curve.curve_point)")
    a, b = crack.semi_axes
    return lambda phi: (crack.center + np.multiply.outer(a * np.cos(phi), crack.e_a)
                        + np.multiply.outer(b * np.sin(phi), crack.e_b))


def inside_arcs(domain, crack, point=None) -> list[tuple[float, float]]:
    """The parametric intervals (phi0, phi1), phi0 < phi1 < phi0 + 2 pi, of a closed outline inside the body, each
    end refined by bisection to the face: `point(phi)` the outline (default a disc's or an ellipse's, `outline_point`;
    a curve's spline, its parameter scaled to 2 pi: ngcrack.solid.curve.curve_point, or its front's ``point``). Empty
    if the whole outline is outside; one interval (0, 2 pi) if the outline does not leave the body."""
    point = point or outline_point(crack)
    m = samples(domain, ARC_SAMPLES)
    phi = np.linspace(0.0, 2 * np.pi, m, endpoint=False)
    inside = clearance(domain, point(phi)) > 0
    if inside.all():
        return [(0.0, 2 * np.pi)]
    if not inside.any():
        return []
    step = 2 * np.pi / m
    start = int(np.flatnonzero(~inside)[0])  # walk the circle from an outside sample
    order = (start + np.arange(m)) % m
    arcs, first = [], None
    for k in range(1, m + 1):
        prev, cur = inside[order[k - 1]], inside[order[k % m]]
        t = (start + k) * step  # the angle of sample k (unwrapped)
        if cur and not prev:
            first = _refine(domain, point, t - step, t)
        elif prev and not cur:
            arcs.append((first, _refine(domain, point, t, t - step)))
    return [(a % (2 * np.pi), a % (2 * np.pi) + (b - a)) for a, b in arcs]


def _refine(domain, point, outside: float, inside: float) -> float:
    """The angle between an outside and an inside angle where the outline `point(phi)` crosses the surface."""
    for _ in range(ARC_BISECTIONS):
        mid = 0.5 * (outside + inside)
        if clearance(domain, point(np.array([mid])))[0] > 0:
            inside = mid
        else:
            outside = mid
    return 0.5 * (outside + inside)


def clip_segment(domain, A: np.ndarray, B: np.ndarray) -> tuple[float, float] | None:
    """The parameters (t0, t1) in [0, 1] of the part of the segment A B inside the body (None: outside).

    A box's section of a line is one interval; a cylinder's too (it is convex)."""
    t = np.linspace(0.0, 1.0, samples(domain, 1024) + 1)
    inside = clearance(domain, A + np.outer(t, B - A)) > 0
    if not inside.any():
        return None
    k = np.flatnonzero(inside)
    lo, hi = float(t[k[0]]), float(t[k[-1]])
    step = t[1] - t[0]

    def bisect(out_t, in_t):
        for _ in range(ARC_BISECTIONS):
            mid = 0.5 * (out_t + in_t)
            if clearance(domain, (A + mid * (B - A))[None])[0] > 0:
                in_t = mid
            else:
                out_t = mid
        return 0.5 * (out_t + in_t)

    t0 = 0.0 if k[0] == 0 else bisect(lo - step, lo)
    t1 = 1.0 if k[-1] == len(t) - 1 else bisect(hi + step, hi)
    return t0, t1


def clipped_area(domain, crack, n: int = 2000) -> float:
    """The area of the crack's part inside the body, by a fine grid in the crack's plane (a check)."""
    import shapely

    uv = _plane_outline(crack, 4 * n)
    region = shapely.Polygon(uv)
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    u, v = np.meshgrid(np.linspace(lo[0], hi[0], n), np.linspace(lo[1], hi[1], n), indexing="ij")
    du, dv = (hi[0] - lo[0]) / (n - 1), (hi[1] - lo[1]) / (n - 1)
    p = crack.center + np.multiply.outer(u.ravel(), crack.e_a) + np.multiply.outer(v.ravel(), crack.e_b)
    keep = shapely.contains_xy(region, u.ravel(), v.ravel()) & (clearance(domain, p) > 0)
    return float(keep.sum() * du * dv)


def _plane_outline(crack, n: int) -> np.ndarray:
    p = crack.outline(n) - crack.center
    return np.column_stack([p @ crack.e_a, p @ crack.e_b])


# ---------------------------------------------------------------------------- open fronts
class ArcFront:
    """The part phi0 < phi < phi1 of a closed front (a disc's or an ellipse's ``FrontGeometry``, a curve's
    ``CurveFront``) inside the body: an open front whose ends lie on the free surface.

    It keeps the closed front's points, frames, curvature and foot-point coordinates (delegated) and
    changes what an open front changes: the arc length runs from phi0 (``arc``; an angle is taken in the
    turn centred on the arc's middle), distances along it are not periodic, ``within`` keeps points whose
    foot is on the arc or within `pad` of its ends, and ``stations`` spreads the points over the whole arc,
    ends included (``front.surface_weights`` clips each point's bump at the ends).
    """

    periodic = None
    start = 0.0
    open_arc = True
    surface_ends = (True, True)
    ligament = None  # set by open_arcs: the body's thickness beyond the front

    def __init__(self, base, phi0: float, phi1: float):
        self.base, self.phi0, self.phi1 = base, float(phi0), float(phi1)
        self.crack = base.crack
        self.mid = 0.5 * (self.phi0 + self.phi1)
        self._s0 = float(base.arc_unwrapped(self.phi0))
        self.length = float(base.arc_unwrapped(self.phi1) - self._s0)

    def __getattr__(self, name):  # point, frame, speed, coordinates, turning, reach: the closed front's
        return getattr(self.base, name)

    def unwrap(self, phi):
        """phi in the turn centred on the arc's middle."""
        return (np.asarray(phi, dtype=float) - self.mid + np.pi) % (2 * np.pi) - np.pi + self.mid

    def arc(self, phi):
        """The arc length from the arc's start (negative before it, beyond `length` after its end)."""
        return self.base.arc_unwrapped(self.unwrap(phi)) - self._s0

    def delta(self, s, s0):
        return s - s0

    def within(self, phi, pad):
        s = self.arc(phi)
        return (s > -pad) & (s < self.length + pad)

    def stations(self, h: float, L: float, R: float, n_points: int | None):
        """The two ends on the surface and n points (default one per 2 h, 3 at least) from SURFACE_INSET L
        inside one end to as far inside the other (`surface_take` gives the ends the values of their neighbours)."""
        inset = min(SURFACE_INSET * L, 0.25 * self.length)
        n = n_points or max(3, int((self.length - 2 * inset) / (2 * h)) + 1) | 1  # odd: a symmetric arc's middle
        s_i = np.concatenate([[0.0], np.linspace(inset, self.length - inset, n), [self.length]])
        phi = np.interp(s_i + self._s0, self.base.arc_unwrapped(self._grid()), self._grid())
        return phi, s_i

    def _grid(self):
        return np.linspace(self.phi0, self.phi1, 4001)


def bump_inside(s_k: np.ndarray, L: float, length: float) -> np.ndarray:
    """int h(s - s_k) ds over the front 0 < s < length, h the cos^2 bump of half-width L (L when it fits)."""
    def primitive(x):  # int_{-L}^{x} cos^2(pi t / 2L) dt for |x| <= L
        x = np.clip(x, -L, L)
        return 0.5 * (x + L) + L / (2 * np.pi) * np.sin(np.pi * x / L)

    return primitive(length - s_k) - primitive(-s_k)


def surface_extrapolation(s: np.ndarray, values: np.ndarray, valid: np.ndarray, at: float) -> np.ndarray:
    """The values at arc length `at` (a surface end) extrapolated linearly from the two valid points nearest to it."""
    k = np.flatnonzero(valid)
    near = k[np.argsort(np.abs(s[k] - at))[:2]]
    if len(near) < 2:
        return values[near[0]] if len(near) else np.zeros(values.shape[1:])
    s0, s1 = s[near]
    w = (at - s0) / (s1 - s0)
    return (1 - w) * values[near[0]] + w * values[near[1]]


def ligament(domain, crack, points: np.ndarray) -> float:
    """The least distance from the points (a front's) to the faces the crack does not cross: the body's
    thickness beyond the front, which a domain integral's tube must not span."""
    crossed = {k for k, d in face_distances(domain, crack.outline(samples(domain, 512))).items() if d.min() < 0}
    rest = [d for k, d in face_distances(domain, points).items() if k not in crossed]
    return float(np.min(rest)) if rest else np.inf


def open_arcs(sol, base) -> list:
    """A disc's, an ellipse's or a curve's front in the body: [base] if it stays inside, else one ArcFront per arc."""
    domain = sol.scene.domain
    arcs = inside_arcs(domain, base.crack, base.point)  # (the front's angle: an ellipse's, a curve's spline's)
    if arcs == [(0.0, 2 * np.pi)]:
        return [base]
    out = []
    for phi0, phi1 in arcs:
        g = ArcFront(base, phi0, phi1)
        g.ligament = ligament(domain, base.crack, base.point(np.linspace(phi0, phi1, samples(domain, 256) + 1)))
        out.append(g)
    return out


def open_sides(sol, crack, segment_front) -> list:
    """A polygon's sides in the body (`segment_front(crack, side)` each), a side crossing a face cut to its part
    inside (its corners on the surface are then the front's ends); sides wholly outside are left out."""
    domain = sol.scene.domain
    out = []
    for j in range(len(crack.points)):
        g = segment_front(crack, j)
        t = clip_segment(domain, g.A, g.A + g.length * g.t)
        if t is None:
            continue
        if t != (0.0, 1.0):
            g.start += t[0] * g.length
            g.A, g.length = g.A + t[0] * g.length * g.t, (t[1] - t[0]) * g.length
            g = ClippedSide(g, (t[0] > 0.0, t[1] < 1.0))
        out.append(g)
    return out


class ClippedSide:
    """A polygon side (``front.SegmentFront``, already cut to the body) with one or both ends on the surface:
    its points keep L + R from a corner, as a side's do, but only SURFACE_INSET L from a surface end, and the
    surface ends are front points too (``surface_take`` gives them the values of their neighbours)."""

    def __init__(self, side, surface_ends: tuple[bool, bool]):
        self.side, self.surface_ends = side, surface_ends

    def __getattr__(self, name):
        return getattr(self.side, name)

    def stations(self, h: float, L: float, R: float, n_points: int | None, spacing: float | None = None):
        inset = min(SURFACE_INSET * L, 0.25 * self.length)
        m0, m1 = (inset if e else L + R for e in self.surface_ends)
        room = self.length - m0 - m1
        if room < 0:
            return np.zeros(0), np.zeros(0)
        n = max(2, int(room / (spacing or 2 * h)) + 1)
        s_i = np.linspace(m0, self.length - m1, n)
        s_i = np.concatenate([[0.0] if self.surface_ends[0] else [], s_i, [self.length] if self.surface_ends[1] else []])
        return s_i, s_i


def surface_take(s_i: np.ndarray, length: float, L: float, ends=(True, True)) -> tuple[np.ndarray, np.ndarray]:
    """(kept, take): the stations of an open front reported (its ends on the surface, `ends`, and the points at
    least SURFACE_INSET bump half-widths L from them), and for each the station whose values it reports: its own,
    or at a surface end the nearest station that far inside (the engineering codes' practice of reporting the
    surface value from a point a small distance inside; the clipped integral at the end came 15-17% low)."""
    inset = min(SURFACE_INSET * L, 0.25 * length)
    tol = 1e-12 * max(length, 1.0)
    lo = s_i >= (inset if ends[0] else 0.0) - tol
    hi = s_i <= length - (inset if ends[1] else 0.0) + tol
    inner = lo & hi
    at_end = (ends[0] & (s_i <= tol)) | (ends[1] & (s_i >= length - tol))
    kept = np.flatnonzero(inner | at_end)
    if not inner.any():
        return kept, np.full(len(kept), int(np.argmin(np.abs(s_i - 0.5 * length))))
    k = np.flatnonzero(inner)
    take = np.array([j if inner[j] else (k[0] if s_i[j] < 0.5 * length else k[-1]) for j in kept])
    return kept, take
