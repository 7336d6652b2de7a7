"""Surface and corner cracks grown with a free front shape: the new crack a curve through the advanced points.

A ``curve`` crack (ngcrack.solid.curve: a closed planar spline through points) may cross the body's
faces as an ellipse does (ngcrack.solid.surface): its front is the arc of the spline inside the body.
Such a crack grows by the rules of surface3d.py (steps 1-3: K along the front, the surface points'
K a little inside, every point advanced, the end points along their faces) and only step 4 differs:

4'. The new crack. CURVE_FRONT_POINTS (at least two per station) points equally spaced in arc length
    along the front, each moved by its advance (interpolated from the stations by a C2 cubic spline in arc
    length, the station values extended evenly beyond the ends: its slope vanishes at the surface, so that
    the completed front below has no corner there). The spline must
    close beyond the faces so that its part inside the body is exactly the advanced front: the
    advanced points are mirrored in the crack's plane across the trace of each end's face (the line
    where the face meets the plane, through the end point). A surface crack (both ends on one face) is
    closed by its mirror image across that face's trace; a corner crack (the ends on two faces whose
    traces meet at a right angle) by its images across each trace and across both (a point reflection
    about the edge). The spline through these points is symmetric about each trace, so it crosses the
    face at the end points and at a right angle, as the fitted ellipse centred on the face does; in
    between it passes through the advanced points (the periodic spline smooths the front as an
    embedded front's is smoothed).

An ellipse grows as a curve when it is given as one: ``curve_of_ellipse`` writes the scene table of
a curve through points of an ellipse (or a disc), the front the same shape to the spline's accuracy.

depth_and_length measures a curve's front: the depth a the front's largest distance from the face
its mouth lies on (a corner crack: from the face through the body's thinner direction), the half-length
c half the mouth's length on the surface (a corner crack: the front's largest distance from the other face).

Refused by name (before meshing): a front inside the body that is more than one arc; an end on a face
that is not planar (a cylinder's side, a STEP part's faces: the mirror image would not stay outside
the body); a corner crack whose two faces do not meet at a right angle in the crack's plane (the four
images would not close); a face nearly parallel to the crack's plane.
"""

from __future__ import annotations

import numpy as np

from ...core.errors import InputError
from .faces3d import along_faces, carried, domain_size, face_normal, thickness

#: advanced points along the front through which the new curve passes (at least two per station)
CURVE_FRONT_POINTS = 65
#: points of a curve written through an ellipse (curve_of_ellipse)
ELLIPSE_CURVE_POINTS = 48
#: the traces of a corner crack's two faces meet at a right angle to within this cosine
RIGHT_ANGLE_COS = 1e-6
#: a face whose normal's component in the crack's plane is below this is parallel to the crack (refused)
PARALLEL_SINE = 0.2
#: both ends of a surface crack lie on their face's trace to within this fraction of the crack's size
ON_TRACE_RTOL = 1e-6


def _spline(crack):
    from ngcrack.solid.curve import spline_of

    s = spline_of(crack)
    return s, s.T / (2 * np.pi)


def curve_arc(crack, phi: np.ndarray) -> np.ndarray:
    """The arc length along the curve's spline from phi[0] to each phi (phi increasing, unwrapped; phi is the spline's
    parameter scaled to 2 pi, the angle of its front)."""
    spline, scale = _spline(crack)
    phi = np.asarray(phi, dtype=float)
    grid = np.linspace(phi[0], phi[-1], 4001)
    mid = 0.5 * (grid[1:] + grid[:-1])
    speed = np.linalg.norm(spline.uv(mid * scale, 1), axis=-1) * scale
    return np.interp(phi, grid, np.r_[0.0, np.cumsum(speed * np.diff(grid))])


def point_and_normal(crack, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(the curve's points at phi, its outward unit normals in the crack's plane)."""
    spline, scale = _spline(crack)
    t = np.asarray(phi, dtype=float) * scale
    d1 = spline.uv(t, 1)
    out = np.column_stack([d1[:, 1], -d1[:, 0]]) / np.linalg.norm(d1, axis=1, keepdims=True)
    return spline.xyz(t), spline.to_xyz(out)


def _arc(domain, crack, i: int | None = None) -> tuple[float, float]:
    from ngcrack.solid.curve import curve_point
    from ngcrack.solid.surface import inside_arcs

    arcs = inside_arcs(domain, crack, curve_point(crack))
    if len(arcs) != 1:
        raise InputError(f"crack[{i}]: its front inside the body is {len(arcs)} arcs; a surface crack grows with one "
                         f"front from surface to surface")
    return arcs[0]


def front_points(domain, crack, n: int = CURVE_FRONT_POINTS) -> np.ndarray:
    """n points equally spaced in arc length along the curve's front inside the body, its ends on the surface."""
    phi0, phi1 = _arc(domain, crack)
    grid = np.linspace(phi0, phi1, 4001)
    phi = np.interp(np.linspace(0.0, 1.0, n), curve_arc(crack, grid) / curve_arc(crack, grid)[-1], grid)
    return point_and_normal(crack, phi)[0]


def _trace(domain, crack, p: np.ndarray) -> tuple[str, np.ndarray, float]:
    """(the face the surface point p lies on, the unit normal in the crack's plane of the face's trace there,
    pointing out of the body, the sine of the angle between the face and the crack's plane)."""
    from ngcrack.solid.surface import face_distances

    dist = face_distances(domain, p[None])
    key = min(dist, key=lambda k: abs(dist[k][0]))
    nf = face_normal(domain, p, crack.size)
    m = nf - np.dot(nf, crack.normal) * crack.normal
    sine = float(np.linalg.norm(m))
    return key, m / max(sine, 1e-300), sine


def _planar_face(domain, key: str) -> bool:
    from ngcrack.solid.surface import is_step

    if is_step(domain):
        return False
    return hasattr(domain, "lo") or key != "side"


def _mirrors(domain, crack, ends: np.ndarray, i: int | None = None) -> list[tuple[np.ndarray, np.ndarray]]:
    """The reflections completing the front beyond the faces: [(a point on the trace, its outward unit normal)],
    one for a surface crack, two (the first end's face, the last end's) for a corner crack; refused by name
    where the completion would not hold (module docstring)."""
    traces = [_trace(domain, crack, e) for e in ends]
    for key, _, sine in traces:
        if not _planar_face(domain, key):
            raise InputError(f"crack[{i}]: a curve crack's front ends on face {key}, which is not planar; a curve crossing "
                             f"the faces grows with its ends on planar faces (a box's faces, a cylinder's ends), where "
                             f"its mirror image beyond the face completes it")
        if sine < PARALLEL_SINE:
            raise InputError(f"crack[{i}]: face {key} is nearly parallel to the crack's plane (sine {sine:.3g} < "
                             f"{PARALLEL_SINE:g}); a curve crack grows across faces it crosses at an angle")
    (k0, m0, _), (k1, m1, _) = traces
    if k0 == k1:
        off = abs(float(np.dot(ends[1] - ends[0], m0)))
        if off > ON_TRACE_RTOL * crack.size:
            raise InputError(f"crack[{i}]: the two ends of its front on face {k0} are {off:.3g} apart across the face's "
                             f"trace; a curve crack grows with both ends on one planar face")
        return [(ends[0], m0)]
    cos = abs(float(np.dot(m0, m1)))
    if cos > RIGHT_ANGLE_COS:
        raise InputError(f"crack[{i}]: faces {k0} and {k1}, where its front ends, do not meet at a right angle in the "
                         f"crack's plane (cosine {cos:.3g}); a corner crack grows as a curve between perpendicular faces")
    return [(ends[0], m0), (ends[1], m1)]


def _reflect(q: np.ndarray, mirror: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    o, m = mirror
    return q - 2.0 * np.outer((q - o) @ m, m)


def completed(points: np.ndarray, mirrors: list) -> np.ndarray:
    """The closed outline through the front's points (ends on the faces, first and last) and their images beyond the
    faces (module docstring): a surface crack's front and its mirror image, a corner crack's four images."""
    p = np.asarray(points, dtype=float)
    if len(mirrors) == 1:
        return np.vstack([p, _reflect(p[-2:0:-1], mirrors[0])])
    first, last = mirrors
    return np.vstack([p, _reflect(p[-2::-1], last), _reflect(_reflect(p[1:], last), first),
                      _reflect(p[-2:0:-1], first)])


def check_curve_growable(domain, i: int, crack) -> None:
    """Refuse, by name, a curve crossing the faces that cannot grow as one (module docstring)."""
    _arc(domain, crack, i)
    _mirrors(domain, crack, front_points(domain, crack, 3)[[0, -1]], i)


def symmetric_interpolant(s_i: np.ndarray, values: np.ndarray):
    """The C2 cubic spline through values at the arc lengths s_i (s_i[0] = 0 and s_i[-1] the front's ends on the
    surface) extended evenly beyond both ends: its slope vanishes at the ends, as the slope of the advance of a
    front whose completion beyond the face is its mirror image must (a slope there would put a corner in the curve
    at the face)."""
    from scipy.interpolate import CubicSpline

    s_i, values = np.asarray(s_i, dtype=float), np.asarray(values, dtype=float)
    L = s_i[-1]  # the even extension about both ends is periodic (period 2 L): its periodic spline is even
    s = np.r_[s_i, 2 * L - s_i[-2::-1]]
    v = np.r_[values, values[-2::-1]]
    return CubicSpline(s, v, bc_type="periodic")


def grown_surface_curve(domain, crack, angles: np.ndarray, advance: np.ndarray, lead: int) -> tuple[dict, float]:
    """(the grown curve's scene dictionary, the advance of the station `lead`): module docstring, step 4'."""
    phi_i = np.asarray(angles, dtype=float)
    adv_i = np.asarray(advance, dtype=float)
    s_i = curve_arc(crack, phi_i)
    n = max(CURVE_FRONT_POINTS, 2 * len(phi_i) + 1)
    grid = np.linspace(phi_i[0], phi_i[-1], 4001)
    s = np.linspace(0.0, s_i[-1], n)
    phi = np.interp(s, curve_arc(crack, grid), grid)
    adv = np.maximum(symmetric_interpolant(s_i, adv_i)(s), 0.0)
    p, d = point_and_normal(crack, phi)
    moved = p + adv[:, None] * along_faces(domain, crack, p, d)
    outline = completed(moved, _mirrors(domain, crack, moved[[0, -1]]))
    d_new = {"shape": "curve", "points": outline.tolist(), **carried(crack)}
    return d_new, float(adv_i[lead])


def curve_depth_and_length(domain, crack) -> tuple[float, float]:
    """(a, c) of a curve crossing the faces (module docstring)."""
    from ngcrack.solid.surface import face_distances

    p = front_points(domain, crack, 513)
    (k0, m0, _), (k1, m1, _) = (_trace(domain, crack, e) for e in p[[0, -1]])
    dist = face_distances(domain, p)
    if k0 == k1:
        return float(dist[k0].max()), 0.5 * float(np.linalg.norm(p[-1] - p[0]))
    size = domain_size(domain)
    # the depth runs through the body's thinner direction of the two faces' (a plate's thickness)
    t0, t1 = (thickness(domain, e, -m, size) for e, m in ((p[0], m0), (p[-1], m1)))
    a_key, c_key = (k0, k1) if t0 <= t1 else (k1, k0)
    return float(dist[a_key].max()), float(dist[c_key].max())


def curve_of_ellipse(crack, n: int = ELLIPSE_CURVE_POINTS) -> dict:
    """The scene table of a curve through n points of a disc's or an ellipse's outline, in its order (the same
    normal), at half-steps of the parametric angle from its major axis (none on a face through the centre)."""
    a, b = crack.semi_axes
    phi = 2 * np.pi * (np.arange(n) + 0.5) / n
    p = crack.center + np.outer(a * np.cos(phi), crack.e_a) + np.outer(b * np.sin(phi), crack.e_b)
    return {"shape": "curve", "points": p.tolist(), **carried(crack)}
