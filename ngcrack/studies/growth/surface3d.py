"""Planar growth of surface and corner cracks: fronts that end on the free surface, grown as ellipses (or curves).

A surface crack (ngcrack.solid.surface) is a disc, an ellipse or a curve that crosses the body's faces; its
front is the arc inside the body, its two end points on the surface. It grows as the engineering
codes grow it (NASGRO, BS 7910; FRANC3D fits a curve through the advanced points), keeping a shape
the scene and its mesh support:

1. K along the front. The solve gives K at stations equally spaced in arc length, the two ends on
   the surface carrying the value of the first station a bump half-width inside (surface_take):
   K falls in the surface's boundary layer, where the square-root singularity is not the field's.
   K_eq at the inner stations is smoothed by a least-squares polynomial in the arc length of
   degree SMOOTH_DEGREE (fewer with few stations): a low-pass, as the Fourier one of a closed front.
2. The surface point's K (K_C). Each end point grows with the smoothed K at SURFACE_K_FRACTION of the
   front's length (surface to surface) in from its end, the engineering practice of taking the
   surface value a little inside; where the mesh puts its first inner station farther in, the fit
   is continued linearly to that point from its value and slope at that station. Every front point
   nearer to an end than that point takes its K_C: the advance is flat in the boundary layer.
3. The advance. Each point by the rule of embedded fronts (fronts3d: Paris or quasi-static, the
   leading point da), inner points along the front's in-plane normal, the end points along the
   face they lie on (the normal projected into the face and the crack's plane), so that they stay
   on the surface.
4. The new crack. An ellipse with the old one's centre (on the face, or on an edge for a corner
   crack), plane and axes, its semi-axes the least-squares fit of FIT_POINTS advanced points
   equally spaced along the front (the radial distance from the centre): a smooth front whose ends
   lie on the face to round-off, and a scene the mesh and the open fronts already handle.

A surface crack given as a ``curve`` (a spline crossing the faces) grows by steps 1-3 and, in place of
step 4, becomes the curve through the advanced points completed beyond the faces by its mirror images
(surface_curve.py): a free front shape. The functions here dispatch on the shape (the arc length along
the front, the rays, the grown crack, its depth and length); the ellipse fit stays the rule for ellipses.

The reference, ngcrack.studies.growth.newman_raju_growth, integrates Newman and Raju's K at the
deepest point and at the same SURFACE_K_FRACTION point with the same Paris law.

Refused by name (before meshing): an ellipse crossing the faces whose centre is off the surface (it
would not stay an ellipse centred where it grows from), a crack crossing them in more than one arc, and
a curve that its mirror images cannot complete (surface_curve.py).
"""

from __future__ import annotations

import math

import numpy as np

from ...core.errors import InputError
from .faces3d import NORMAL_STEP_RTOL, along_faces, carried, domain_size, thickness  # noqa: F401  (carried: fronts3d's)

#: the surface point grows with K this fraction of the front's length in from the surface (module docstring)
SURFACE_K_FRACTION = 0.05
#: the degree of the polynomial that smooths K_eq along an open front (at most half its inner stations, at least 2:
#: a straight line through a front's K, which peaks inside, would flatten it)
SMOOTH_DEGREE = 4
#: advanced points along the front the new ellipse is fitted to
FIT_POINTS = 65
#: a surface crack's centre lies on the body's surface within this fraction of its size
CENTRE_ON_SURFACE_RTOL = 1e-6


def is_surface_crack(domain, crack) -> bool:
    """A disc, an ellipse or a curve crossing the body's faces (its front ends on the surface)."""
    from ngcrack.solid.surface import crosses

    return crack.shape in ("disc", "ellipse", "curve") and crosses(domain, crack)


def check_surface_growable(domain, i: int, crack) -> None:
    """Refuse, by name, a crack crossing the faces that grows off its ellipse, or a curve that cannot be completed
    beyond the faces (module docstring)."""
    from ngcrack.solid.surface import clearance, inside_arcs

    if crack.shape == "curve":
        from .surface_curve import check_curve_growable

        check_curve_growable(domain, i, crack)
        return
    off = abs(float(clearance(domain, crack.center[None])[0]))
    if off > CENTRE_ON_SURFACE_RTOL * crack.size:
        raise InputError(f"crack[{i}]: crosses the body's faces with its centre {off:.3g} off them; a crack reaching "
                         f"the surface grows as an ellipse centred on a face (a semi-elliptical surface crack) or on "
                         f"an edge (a quarter-elliptical corner crack): put its centre on the surface")
    arcs = inside_arcs(domain, crack)
    if len(arcs) != 1:
        raise InputError(f"crack[{i}]: its front inside the body is {len(arcs)} arcs; a surface crack grows with one "
                         f"front from surface to surface")


def ellipse_arc(crack, phi: np.ndarray) -> np.ndarray:
    """The arc length along the crack's ellipse (a curve's spline: surface_curve.curve_arc) from phi[0] to each phi
    (phi increasing, unwrapped)."""
    if crack.shape == "curve":
        from .surface_curve import curve_arc

        return curve_arc(crack, phi)
    a, b = crack.semi_axes
    grid = np.linspace(phi[0], phi[-1], 4001)
    mid = 0.5 * (grid[1:] + grid[:-1])
    s = np.r_[0.0, np.cumsum(np.hypot(a * np.sin(mid), b * np.cos(mid)) * np.diff(grid))]
    return np.interp(phi, grid, s)


def surface_drive(angles: np.ndarray, K_eq: np.ndarray, crack, fraction: float = SURFACE_K_FRACTION) -> np.ndarray:
    """K_drive along an open front (module docstring, steps 1-2): its points at the parametric `angles` (the
    ends on the surface first and last), K_eq at them."""
    phi = np.asarray(angles, dtype=float)
    K = np.asarray(K_eq, dtype=float)
    s = ellipse_arc(crack, phi)
    length = float(s[-1])
    inner = np.arange(1, len(s) - 1) if len(s) > 2 else np.arange(len(s))
    x = 2.0 * s / length - 1.0
    deg = int(min(SMOOTH_DEGREE, max(len(inner) // 2, 2), len(inner) - 1))
    fit = np.polynomial.Legendre.fit(x[inner], K[inner], deg, domain=[-1.0, 1.0]) if deg >= 0 else None
    drive = fit(x) if fit is not None else K.copy()
    d_fit = fit.deriv() if deg > 0 else None
    x_in = 2.0 * fraction - 1.0  # the K_C points in x, each end's
    for end, x_c, x_first in ((0, x_in, x[inner[0]]), (1, -x_in, x[inner[-1]])):
        beyond = x_c < x_first if end == 0 else x_c > x_first
        if beyond and d_fit is not None:  # the first inner station is farther in: the fit continued linearly
            K_c = fit(x_first) + d_fit(x_first) * (x_c - x_first)
        else:
            K_c = fit(x_c)
        near = x <= x_c if end == 0 else x >= x_c
        drive[near] = K_c
    return np.maximum(drive, 0.0)


def _rays(domain, crack, phi: np.ndarray, ends: bool):
    """(the front's points at the angles phi, their directions of advance): the outward in-plane normal, at the
    first and last point (`ends`: the front's ends on the surface) projected into their faces."""
    if crack.shape == "curve":
        from .surface_curve import point_and_normal

        p, d = point_and_normal(crack, phi)
    else:
        a, b = crack.semi_axes
        p = crack.center + np.outer(a * np.cos(phi), crack.e_a) + np.outer(b * np.sin(phi), crack.e_b)
        d = np.outer(b * np.cos(phi), crack.e_a) + np.outer(a * np.sin(phi), crack.e_b)  # the outward in-plane normal
        d /= np.linalg.norm(d, axis=1, keepdims=True)
    return p, along_faces(domain, crack, p, d) if ends else d


def advanced_points(domain, crack, angles: np.ndarray, advance: np.ndarray, n: int = FIT_POINTS) -> np.ndarray:
    """n points equally spaced in arc length along the front moved by the advance (interpolated in arc length from
    the stations at `angles`), the end points along their faces."""
    phi_i = np.asarray(angles, dtype=float)
    s_i = ellipse_arc(crack, phi_i)
    grid = np.linspace(phi_i[0], phi_i[-1], 4001)
    s = np.linspace(0.0, s_i[-1], n)
    phi = np.interp(s, ellipse_arc(crack, grid), grid)
    adv = np.interp(s, s_i, np.asarray(advance, dtype=float))
    p, d = _rays(domain, crack, phi, True)
    return p + adv[:, None] * d


def fit_ellipse(crack, points: np.ndarray, start: tuple[float, float]) -> tuple[float, float]:
    """The semi-axes (along e_a, e_b) of the ellipse with the crack's centre and axes nearest to the points, in the
    least squares of their radial distances from it."""
    from scipy.optimize import least_squares

    q = points - crack.center
    u, v = q @ crack.e_a, q @ crack.e_b
    r = np.hypot(u, v)
    cos, sin = u / r, v / r

    def residual(x):
        A, B = np.exp(x)
        return r - 1.0 / np.sqrt((cos / A) ** 2 + (sin / B) ** 2)

    sol = least_squares(residual, np.log(np.asarray(start, dtype=float)), xtol=1e-14, ftol=1e-14, gtol=1e-14)
    A, B = np.exp(sol.x)
    return float(A), float(B)


def grown_surface_crack(domain, crack, angles: np.ndarray, advance: np.ndarray, lead: int) -> tuple[dict, float]:
    """(the grown crack's scene dictionary, the actual advance of the station `lead`): module docstring, step 4 (a
    curve: the curve through the advanced points completed beyond the faces, surface_curve.py)."""
    if crack.shape == "curve":
        from .surface_curve import grown_surface_curve

        return grown_surface_curve(domain, crack, angles, advance, lead)
    moved = advanced_points(domain, crack, angles, advance)
    A0, B0 = crack.semi_axes
    mean = float(np.mean(advance))
    A, B = fit_ellipse(crack, moved, (A0 + mean, B0 + mean))
    d = {"shape": "ellipse", "center": crack.center.tolist(), "normal": crack.normal.tolist(),
         "semi_axes": [A, B], "major_axis": crack.e_a.tolist(), **carried(crack)}
    phi = np.asarray(angles, dtype=float)
    p, ray = _rays(domain, crack, phi[[lead]], lead in (0, len(phi) - 1))
    return d, _ray_to_ellipse(crack, A, B, p[0], ray[0])


def _ray_to_ellipse(crack, A: float, B: float, p: np.ndarray, d: np.ndarray) -> float:
    """The distance along the ray p + t d (t >= 0) to the ellipse of semi-axes (A, B) about the crack's centre."""
    q = p - crack.center
    u0, v0, du, dv = q @ crack.e_a, q @ crack.e_b, d @ crack.e_a, d @ crack.e_b
    qa = (du / A) ** 2 + (dv / B) ** 2
    qb = 2 * (u0 * du / A ** 2 + v0 * dv / B ** 2)
    qc = (u0 / A) ** 2 + (v0 / B) ** 2 - 1.0
    disc = max(qb * qb - 4 * qa * qc, 0.0)
    return float((-qb + math.sqrt(disc)) / (2 * qa))


def depth_axis(domain, crack) -> int:
    """0 if the crack's first axis (e_a) crosses the face its centre lies on (it measures the depth), else 1; a
    corner crack's centre lies on two faces: the depth runs through the body's thinner direction of the two (a
    plate's thickness)."""
    from ngcrack.solid.surface import face_distances

    size = crack.size
    dist = face_distances(domain, crack.center[None])
    on = [k for k, v in dist.items() if abs(v[0]) <= CENTRE_ON_SURFACE_RTOL * size] or [min(dist, key=lambda k: abs(dist[k][0]))]
    normals = []
    for key in on:
        h = NORMAL_STEP_RTOL * size
        g = np.array([(face_distances(domain, (crack.center + h * e)[None])[key][0]
                       - face_distances(domain, (crack.center - h * e)[None])[key][0]) / (2 * h) for e in np.eye(3)])
        normals.append(g / np.linalg.norm(g))  # inward
    if len(normals) > 1:  # the thinner direction; probed from a point inside both faces' edge, along each normal
        probe = crack.center + 1e-3 * size * sum(normals)
        normals.sort(key=lambda n: thickness(domain, probe, n, domain_size(domain)))
    nf = normals[0]
    return 0 if abs(np.dot(crack.e_a, nf)) > abs(np.dot(crack.e_b, nf)) else 1


def depth_and_length(domain, crack) -> tuple[float, float]:
    """(a, c) of a surface crack: the semi-axis across the face its centre lies on (the depth) and the other one
    (the half-length on the surface; a corner crack's length along its second face); a curve's measured on its
    front (surface_curve.curve_depth_and_length)."""
    if crack.shape == "curve":
        from .surface_curve import curve_depth_and_length

        return curve_depth_and_length(domain, crack)
    A, B = crack.semi_axes
    return (A, B) if depth_axis(domain, crack) == 0 else (B, A)
