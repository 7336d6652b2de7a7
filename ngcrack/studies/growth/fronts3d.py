"""Planar growth of 3D crack fronts: the front-point rules and the new front as a ``curve`` crack.

Each front point (a station of ngcrack.solid.front: equally spaced in arc length) has K_I, K_II,
K_III at the scene's load. Its equivalent factor is

    K_eq = sqrt(K_mts^2 + K_III^2 / (1 - nu)),

K_mts the MTS factor of (K_I, K_II) (criteria.mts_keq; K_I = 0 where the faces are closed) and
the K_III term the one with the same energy release rate (G = K^2/E' in mode I, K_III^2/(2 mu)
in mode III, E'/(2 mu) = 1/(1 - nu)); in pure mode I, K_eq = K_I. `kink_deg` is the MTS kink of
(K_I, K_II): the angle a non-planar code would turn the front point by. Planar growth ignores it;
where it is large the planar path is no longer the crack's.

Advance of each point, in the crack's plane along the front's outward normal e1:

- quasi-static: the points at the largest K_eq (K_Ic at the step's load factor) within
  GROW_TOGETHER_RTOL advance by da, those below (1 - 2 GROW_TOGETHER_RTOL) of it do not, and a
  linear ramp joins them (a step in the advance would put a corner in the front);
- fatigue (Paris): da (Delta K_i / Delta K_max)^m, none at or below the threshold Delta K_th,
  Delta K = (1 - R) K_max (fatigue.delta_K).

Both rules take K_eq smoothed along the front (`K_drive`): the computed K scatters by 0.5-1.5% from
point to point (on the coarse penny, with the mesh), m times that in a Paris advance, and the largest
of scattered values runs ahead of the front's mean (the leading point's cycles too short). The
smoothing keeps the Fourier modes of K_eq along the front up to SMOOTH_MODES_FRACTION of the number
of points (a low-pass that leaves an ellipse's modes 0, 2 and 4 alone).

The new front: NEW_POINTS_PER_STATION points per station (at least MIN_NEW_POINTS) equally spaced in
arc length along the old front, each moved by its advance; ngcrack.solid.curve passes the periodic
spline through them (the front smoothed), and the grown crack is that curve in the same plane,
its points in the old front's order (the same normal).
"""

from __future__ import annotations

import math

import numpy as np

from ...core.errors import InputError
from .criteria import mts_angle, mts_keq
from .fatigue import delta_K
from .surface3d import carried, check_surface_growable, is_surface_crack, surface_drive

#: quasi-static: the points whose K_eq lies within this fraction of the largest advance by da (as 2D tips
#: grow together within loop.GROW_TOGETHER_RTOL)
GROW_TOGETHER_RTOL = 0.02
#: fatigue: the advance keeps its Fourier modes along the front up to this fraction of the number of points
SMOOTH_MODES_FRACTION = 0.25
#: points of the new front per station of the old one, and at least this many
NEW_POINTS_PER_STATION, MIN_NEW_POINTS = 2, 32
#: a grown crack keeps this fraction of its size away from the boundary and the other cracks (the scene's rule,
#: ngcrack.solid.scene.CLEARANCE_RTOL)
CLEARANCE_RTOL = 0.05


def point_values(front, nu: float, scene=None) -> dict:
    """Per front point: K_eq (module docstring) and the MTS kink (radians), as arrays; K_drive the smoothed K_eq
    (a front ending on the surface of `scene`'s body: surface3d.surface_drive)."""
    k1 = np.where(np.asarray(front.closed, dtype=bool), 0.0, np.maximum(np.asarray(front.K_I, dtype=float), 0.0))
    kink = np.array([mts_angle(a, b) for a, b in zip(k1, front.K_II)])
    k_mts = np.array([mts_keq(a, b, t) for a, b, t in zip(k1, front.K_II, kink)])
    K_eq = np.sqrt(np.maximum(k_mts, 0.0) ** 2 + np.asarray(front.K_III, dtype=float) ** 2 / (1.0 - nu))
    if scene is not None and is_surface_crack(scene.domain, scene.cracks[front.crack]):
        return {"K_eq": K_eq, "kink": kink, "K_drive": surface_drive(front.angle, K_eq, scene.cracks[front.crack])}
    return {"K_eq": K_eq, "kink": kink, "K_drive": np.maximum(low_pass(K_eq), 0.0)}


def quasi_static_advance(K_eq: np.ndarray, da: float, together: float = GROW_TOGETHER_RTOL,
                         top: float | None = None) -> np.ndarray:
    """The advance of each point in quasi-static growth (module docstring); `top`: the largest K_eq of every
    front (default: of these points)."""
    top = float(np.max(K_eq)) if top is None else float(top)
    if top <= 0:
        return np.zeros_like(K_eq)
    return da * np.clip((K_eq / top - (1.0 - 2.0 * together)) / together, 0.0, 1.0)


def paris_advance(K_eq: np.ndarray, da: float, m: float, R: float, dK_th: float = 0.0,
                  top: float | None = None) -> np.ndarray:
    """The advance of each point under Paris's law, the leading point's da (module docstring); `top`: the
    largest K_max of every front (default: of these points)."""
    dK = np.array([delta_K(k, R) for k in K_eq])
    top = float(np.max(dK)) if top is None else delta_K(top, R)
    if top <= 0:
        return np.zeros_like(K_eq)
    return np.where(dK > dK_th, da * (np.maximum(dK, 0.0) / top) ** m, 0.0)


def low_pass(values: np.ndarray, fraction: float = SMOOTH_MODES_FRACTION) -> np.ndarray:
    """The periodic values (equally spaced) with their Fourier modes above `fraction` of their number removed."""
    n = len(values)
    spec = np.fft.rfft(values)
    keep = max(2, int(fraction * n))
    spec[keep + 1:] = 0.0
    return np.fft.irfft(spec, n)


def periodic_fourier(values: np.ndarray, s: np.ndarray, period: float) -> np.ndarray:
    """The trigonometric interpolant of values at n equally spaced points of a period, at s."""
    n = len(values)
    spec = np.fft.fft(values) / n
    k = np.fft.fftfreq(n, d=1.0 / n)
    if n % 2 == 0:  # the Nyquist mode split evenly, so that the interpolant is real
        spec[n // 2] *= 0.5
        spec = np.r_[spec, spec[n // 2]]
        k = np.r_[k, n // 2]
    return np.real(np.exp(2j * np.pi * np.outer(s, k) / period) @ spec)


def periodic_linear(values: np.ndarray, s_i: np.ndarray, s: np.ndarray, period: float) -> np.ndarray:
    return np.interp(s % period, np.r_[s_i, period], np.r_[values, values[0]])


def new_front(crack, advance: np.ndarray, angles: np.ndarray, smooth: bool) -> np.ndarray:
    """The points of the grown front: each point of the old front moved along its outward normal by the advance
    (given at the stations `angles`, interpolated: smooth (Fourier) or linear), module docstring."""
    from ngcrack.solid.front import front_geometry

    geom = front_geometry(crack)
    P = geom.periodic
    s_i = geom.arc(angles)
    n_out = max(MIN_NEW_POINTS, NEW_POINTS_PER_STATION * len(angles))
    phi, s = geom.stations(1.0, 0.0, 0.0, n_out)
    if smooth:
        adv = np.maximum(periodic_fourier(advance, s - s_i[0], P), 0.0)
    else:
        order = np.argsort(s_i)
        adv = periodic_linear(advance[order], s_i[order], s, P)
    e1, _, _ = geom.frame(phi)
    return geom.point(phi) + adv[:, None] * e1


def grown_crack(crack, points: np.ndarray) -> dict:
    """The scene dictionary of the grown crack: a curve through `points`, the crack's friction and pressure."""
    return {"shape": "curve", "points": np.asarray(points, dtype=float).tolist(), **carried(crack)}


def clearance_reason(scene, i: int, crack) -> str:
    """Why the grown crack `i` cannot stay in the scene: it reaches the boundary or another crack ("" if neither)."""
    gap = CLEARANCE_RTOL * crack.size
    clear = scene.domain.clearance(crack.outline(256))
    if clear.min() < gap and not is_surface_crack(scene.domain, crack):  # (a surface crack's faces: the scene's check)
        return (f"boundary: crack[{i}]'s front comes within {max(clear.min(), 0.0):.3g} of the body's boundary (at least "
                f"{gap:.3g} needed)")
    for j, other in enumerate(scene.cracks):
        if j == i:
            continue
        dist = np.min(np.linalg.norm(crack.fill()[:, None] - other.fill()[None], axis=-1))
        need = CLEARANCE_RTOL * max(crack.size, other.size)
        if dist < need:
            return f"crack: crack[{i}]'s front meets crack[{j}] (distance {dist:.3g}, at least {need:.3g} needed)"
    return ""


def check_growable(scene) -> None:
    """Refuse, by name, the cracks of a 3D scene that planar front growth cannot grow (before any meshing)."""
    if not scene.cracks:
        raise InputError(f"scene {scene.name!r}: has no crack, so no front can grow")
    for i, c in enumerate(scene.cracks):
        if c.shape == "polygon":
            raise InputError(f"crack[{i}]: a polygon's front has corners, where K is not computed, so it cannot grow; "
                             f"give the outline as shape = \"curve\" (a smooth spline through its points)")
        if is_surface_crack(scene.domain, c):  # a surface or corner crack (surface3d.py)
            check_surface_growable(scene.domain, i, c)
            continue
        gap = CLEARANCE_RTOL * c.size
        if float(np.min(scene.domain.clearance(c.outline(256)))) < gap:
            raise InputError(f"crack[{i}]: comes within {gap:.3g} of the body's faces without crossing them; growth "
                             f"takes cracks inside the body or crossing a face (surface cracks)")


def equivalent_radius(crack) -> float:
    """sqrt(area / pi): the radius of a penny of the crack's area (its size in the cycle integral)."""
    return math.sqrt(float(crack.area) / math.pi)
