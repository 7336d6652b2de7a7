"""The ``curve`` crack shape: a closed planar outline through points, a smooth periodic spline.

``shape = "curve"`` with ``points`` (MIN_CURVE_POINTS or more, in one plane): the crack is the
region inside the periodic cubic spline through the points in their order, parametrised by the
chord length between them (C2 everywhere, the same curve whatever the frame). The normal follows
the right-hand rule of the point order, as a polygon's. A grown front is written back to a scene
as such a crack (ngcrack.studies.growth.fronts3d).

Validation (SceneError naming the field): enough points, finite, pairwise distinct neighbours, one
plane (PLANARITY_RTOL of the size), and a simple outline (the spline, sampled at OUTLINE_CHECK
points, does not cross itself).

Mesh: OCC's periodic interpolation through the points is not the chord-length C2 spline (its
parametrisation differs near its seam: 4% of the size off with 8 points on an ellipse), so OCC is
given OCC_POINTS points of this module's spline instead; its own interpolation through them lies
within about 1e-5 of the size of the spline, the curve the front's geometry (CurveFront) uses.

Front: CurveFront implements the front geometry of ngcrack.solid.front (points, frames, curvature
and turning, reach, arc length, the coordinates of space points), so that front_parameters treats
a curve as it treats an ellipse. The reach at a front point is the radius of the largest disc inside
the crack that touches the front there (the distance inwards to the medial axis): for each point p
with inward normal m the least |q - p|^2 / (2 (q - p).m) over the outline's points q.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.fields import SceneError, is_number, short

#: the fewest points of a curve crack (a periodic cubic spline through fewer is hardly a shape)
MIN_CURVE_POINTS = 5
#: points of the spline OCC interpolates again for the mesh (module docstring)
OCC_POINTS = 256
#: samples of the outline when its simplicity is checked, and of the front's tables (arc length, reach)
OUTLINE_CHECK, TABLE_POINTS = 1024, 2048
#: points of the front at which the reach is tabulated (interpolated in between)
REACH_POINTS = 512
#: outline points of the polygon whose area is the curve's (within 1e-6 of it on a circle)
AREA_POINTS = 4096
#: neighbouring points closer than this fraction of the size are refused (a repeated point)
DISTINCT_RTOL = 1e-9
#: points off their plane by more than this fraction of the size are refused (as a polygon's)
PLANARITY_RTOL = 1e-6


def _frame(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(the mean point, the unit normal by the right-hand rule of the order, e_a: from the first point to the
    second, in the plane)."""
    c = points.mean(axis=0)
    newell = np.sum(np.cross(points - c, np.roll(points, -1, axis=0) - c), axis=0)
    n = newell / np.linalg.norm(newell)
    e_a = points[1] - points[0]
    e_a = e_a - np.dot(e_a, n) * n
    return c, n, e_a / np.linalg.norm(e_a)


class PlaneSpline:
    """The periodic chord-length cubic spline through points in a plane, in the plane's coordinates
    (u, v) along (e_a, e_b) from `origin`; t in [0, T) its parameter."""

    def __init__(self, points: np.ndarray, origin: np.ndarray, e_a: np.ndarray, normal: np.ndarray):
        self.origin, self.e_a, self.normal = origin, e_a, normal
        self.e_b = np.cross(normal, e_a)
        d = points - origin
        uv = np.column_stack([d @ self.e_a, d @ self.e_b])
        closed = np.vstack([uv, uv[:1]])
        t = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(closed, axis=0), axis=1))]
        self.T = float(t[-1])
        self.knots = t[:-1]
        from scipy.interpolate import CubicSpline  # (scipy on first use: the scene module imports this one)

        self.spline = CubicSpline(t, closed, bc_type="periodic")

    def uv(self, t, nu: int = 0) -> np.ndarray:
        return self.spline(np.asarray(t) % self.T, nu)

    def xyz(self, t) -> np.ndarray:
        q = self.uv(t)
        return self.origin + np.multiply.outer(q[..., 0], self.e_a) + np.multiply.outer(q[..., 1], self.e_b)

    def to_xyz(self, uv_vectors: np.ndarray) -> np.ndarray:
        """In-plane vectors (.., 2) as 3D vectors."""
        return np.multiply.outer(uv_vectors[..., 0], self.e_a) + np.multiply.outer(uv_vectors[..., 1], self.e_b)


def spline_of(crack) -> PlaneSpline:
    """The spline of a curve crack."""
    return PlaneSpline(crack.points, crack.center, crack.e_a, crack.normal)


def _point(q: Any, fld: str) -> np.ndarray:
    if (isinstance(q, (str, bytes)) or not isinstance(q, Sequence) or len(q) != 3
            or not all(is_number(c) and math.isfinite(float(c)) for c in q)):
        raise SceneError(f"{fld} = {short(q)}: must be a list of 3 finite numbers [x, y, z]")
    return np.array([float(c) for c in q])


def curve_frame(v: Any, fld: str) -> dict[str, np.ndarray]:
    """{points, center, normal, e_a} of a curve crack from its `points`, validated (module docstring); the scene
    (ngcrack.solid.scene) makes the crack of them."""
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) < MIN_CURVE_POINTS:
        raise SceneError(f"{fld}.points = {short(v)}: must be {MIN_CURVE_POINTS} or more points [[x, y, z], ...] in one "
                         f"plane (a closed outline, a periodic spline through them)")
    p = np.array([_point(q, f"{fld}.points[{k}]") for k, q in enumerate(v)])
    size = float(np.max(np.linalg.norm(p[:, None] - p[None], axis=-1)))
    gaps = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
    if size == 0.0 or gaps.min() <= DISTINCT_RTOL * size:
        k = int(gaps.argmin())
        raise SceneError(f"{fld}.points[{(k + 1) % len(p)}]: repeats points[{k}]; the points of a curve must be distinct "
                         f"(the outline closes by itself: do not repeat the first point at the end)")
    c = p.mean(axis=0)
    newell = np.sum(np.cross(p - c, np.roll(p, -1, axis=0) - c), axis=0)
    if np.linalg.norm(newell) <= 1e-12 * size * size:
        raise SceneError(f"{fld}.points: the curve has no area (points on one line)")
    _, normal, e_a = _frame(p)
    off = np.abs((p - c) @ normal)
    if off.max() > PLANARITY_RTOL * size:
        raise SceneError(f"{fld}.points[{int(off.argmax())}]: {off.max():.3g} off the curve's plane; a crack must be planar")
    import shapely

    spline = PlaneSpline(p, c, e_a, normal)
    uv = spline.uv(np.linspace(0.0, spline.T, OUTLINE_CHECK, endpoint=False))
    ring = shapely.Polygon(uv)
    if not ring.is_valid or ring.area <= 0:
        raise SceneError(f"{fld}.points: the spline through the points crosses itself; give the points of a simple "
                         f"closed outline in order (more points where it turns sharply)")
    centroid = np.array(ring.centroid.coords[0])
    center = c + centroid[0] * e_a + centroid[1] * np.cross(normal, e_a)
    return {"points": p, "center": center, "normal": normal, "e_a": e_a}


def curve_point(crack):
    """The curve as a function of phi in [0, 2 pi) (its spline's parameter scaled to 2 pi: the angle of its front,
    CurveFront), for ngcrack.solid.surface.inside_arcs (a curve crossing the body's faces)."""
    s = spline_of(crack)
    return lambda phi: s.xyz(np.asarray(phi) * (s.T / (2 * np.pi)))


def curve_outline(crack, n: int) -> np.ndarray:
    """n points of the curve, equally spaced in its parameter."""
    s = spline_of(crack)
    return s.xyz(np.linspace(0.0, s.T, max(n, 8), endpoint=False))


def occ_curve_face(crack):
    """The crack's OCC face: a BSpline through OCC_POINTS points of the spline (module docstring)."""
    from netgen import occ

    pts = curve_outline(crack, OCC_POINTS)
    edge = occ.SplineInterpolation([occ.Pnt(*map(float, q)) for q in pts], periodic=True)
    return occ.Face(occ.Wire([edge]))


class ClosedArcs:
    """Arc lengths along a closed front parametrized by phi in [0, 2 pi): the table of s(phi) from the front's
    `speed` (|dx/dphi|), its length `periodic`, and the front points equally spaced in arc length. The fronts of
    discs and ellipses (ngcrack.solid.front.FrontGeometry) and of curves (`CurveFront`) share it."""

    def _tabulate(self, points: int) -> None:
        """The table of s(phi) at `points` + 1 angles (the mid-point rule on `speed`)."""
        self._phis = np.linspace(0, 2 * np.pi, points + 1)
        mid = 0.5 * (self._phis[1:] + self._phis[:-1])
        self._arc = np.concatenate([[0.0], np.cumsum(self.speed(mid) * np.diff(self._phis))])
        #: the front's length (the front is closed: arc lengths wrap around it)
        self.periodic = float(self._arc[-1])

    def arc(self, phi):
        """The arc length from phi = 0 to phi."""
        return np.interp(np.asarray(phi) % (2 * np.pi), self._phis, self._arc)

    def arc_unwrapped(self, phi):
        """The arc length from phi = 0 to phi counted through every turn (increasing in phi)."""
        phi = np.asarray(phi, dtype=float)
        return np.floor(phi / (2 * np.pi)) * self.periodic + self.arc(phi)

    def delta(self, s, s0):
        """The arc length from s0 to s the short way round."""
        P = self.periodic
        return (s - s0 + 0.5 * P) % P - 0.5 * P

    def stations(self, h: float, L: float, R: float, n_points: int | None):
        """The front points: n equally spaced in arc length (default one per 2 h, 8 at least)."""
        n = n_points or max(8, int(self.periodic / (2 * h)))
        s_i = np.arange(n) * self.periodic / n
        return np.interp(s_i, self._arc, self._phis), s_i

    def within(self, phi, pad):
        """Every angle lies on a closed front."""
        return np.ones(np.shape(phi), dtype=bool)


class CurveFront(ClosedArcs):
    """The front of a curve crack: phi in [0, 2 pi) is 2 pi t / T along the spline's parameter t (the
    protocol of ngcrack.solid.front.FrontGeometry; this module needs no NGSolve, so a scene with a curve is
    validated without it)."""

    def __init__(self, crack):
        self.crack = crack
        self.c, self.n = crack.center, crack.normal
        self.s = spline_of(crack)
        self._scale = self.s.T / (2 * np.pi)
        self._tabulate(TABLE_POINTS)
        table = self._phis[:-1]
        from scipy.spatial import cKDTree

        self._tree = cKDTree(self.s.uv(table * self._scale))
        self._table = table
        self._reach_phi = np.linspace(0, 2 * np.pi, REACH_POINTS + 1)
        r = self._medial_radius(self._reach_phi[:-1])
        self._reach = np.r_[r, r[:1]]

    def _t(self, phi):
        return (np.asarray(phi) % (2 * np.pi)) * self._scale

    def point(self, phi):
        return self.s.xyz(self._t(phi))

    def _derivatives(self, phi):
        t = self._t(phi)
        return self.s.uv(t, 1), self.s.uv(t, 2)

    def curvature(self, phi):
        """The signed curvature (> 0 where the front is convex)."""
        d1, d2 = self._derivatives(phi)
        return (d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]) / np.linalg.norm(d1, axis=-1) ** 3

    def frame(self, phi):
        d1, _ = self._derivatives(phi)
        t = self.s.to_xyz(d1 / np.linalg.norm(d1, axis=-1, keepdims=True))
        e1 = np.cross(t, self.n)
        e2 = np.broadcast_to(self.n, e1.shape)
        return e1, e2, np.cross(e1, e2)

    def speed(self, phi):
        d1, _ = self._derivatives(phi)
        return np.linalg.norm(d1, axis=-1) * self._scale

    def reach(self, phi):
        return np.interp(np.asarray(phi) % (2 * np.pi), self._reach_phi, self._reach)

    def _medial_radius(self, phi):
        """The radius of the largest disc inside the crack touching the front at each phi (module docstring)."""
        p = self.s.uv(self._t(phi))
        d1, _ = self._derivatives(phi)
        inward = np.column_stack([-d1[:, 1], d1[:, 0]]) / np.linalg.norm(d1, axis=1)[:, None]
        q = self.s.uv(self._table * self._scale)
        out = np.empty(len(p))
        size = float(np.ptp(q, axis=0).max())
        for k in range(len(p)):
            d = q - p[k]
            along = d @ inward[k]
            ok = along > 1e-12 * size
            out[k] = np.min(np.sum(d[ok] ** 2, axis=1) / (2.0 * along[ok])) if ok.any() else size
        return out

    def coordinates(self, x: np.ndarray):
        d = x - self.c
        u, v, z = d @ self.s.e_a, d @ self.s.e_b, d @ self.n
        # (the spline's origin is the crack's centre: spline_of)
        _, nearest = self._tree.query(np.column_stack([u, v]))
        t = self._table[nearest] * self._scale
        target = np.column_stack([u, v])
        for _ in range(6):  # Newton steps to the nearest point of the spline
            q, d1, d2 = self.s.uv(t), self.s.uv(t, 1), self.s.uv(t, 2)
            f = np.sum((q - target) * d1, axis=1)
            df = np.sum(d1 * d1, axis=1) + np.sum((q - target) * d2, axis=1)
            t = t - f / np.where(np.abs(df) > 1e-14, df, 1e-14)
        phi = (t / self._scale) % (2 * np.pi)
        e1, _, _ = self.frame(phi)
        x1 = np.sum((x - self.point(phi)) * e1, axis=1)
        kappa = self.curvature(phi)
        dphi_dx3 = -1.0 / (self.speed(phi) * np.maximum(1.0 + kappa * x1, 1e-3))
        return phi, x1, z, dphi_dx3

    def turning(self, phi, x1):
        kappa = self.curvature(phi)
        return kappa / np.maximum(1.0 + kappa * x1, 1e-3)
