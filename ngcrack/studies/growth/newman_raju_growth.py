"""The reference fatigue life of a semi-elliptical surface crack: Newman and Raju's K integrated with Paris's law.

The engineering codes (NASGRO, BS 7910, API 579) grow a surface crack as a semi-ellipse with two
degrees of freedom, the depth a (the deepest point A) and the half-length c on the surface (the
surface point C), each by Paris's law with its own K:

    da/dN = C_p Delta K_A^m,   dc/dN = C_p Delta K_C^m,

so that, with a as the variable, dc/da = (K_C / K_A)^m and dN/da = 1 / (C_p Delta K_A^m). K is
Newman and Raju's (ngcrack.studies.newman_raju for a/c <= 1; the deep branch a/c > 1 of the same
1981 paper here). K_C is taken as 3D growth takes it (SURFACE_K_FRACTION in
ngcrack.studies.growth.surface3d): at the point of the front SURFACE_K_FRACTION of the front's
length (surface to surface) in from the surface, where the surface's boundary layer has not yet
lowered it. Newman and Raju's equation at phi = 0 is itself their fit of values taken near the
surface; their K at the 5% point is 3.5% below it to 2% above it for a/c 0.4-1.2 (33% above it at
a/c = 0.2, where their K rises steeply away from the surface), and the trajectories at fraction 0
settle about 5% lower in a/c (BENCHMARKS, "Fatigue growth of surface cracks against Newman-Raju").

A corner crack (`corner=True`): their corner-crack equation, both ends of the quarter front on a face
and both K taken SURFACE_K_FRACTION of the front in from their ends, as the growth takes them.

The integration: fourth-order Runge-Kutta in a on (c, N), RK_STEPS steps (the trajectory and the
cycles to about 1e-6).
"""

from __future__ import annotations

import math

import numpy as np

from ..newman_raju import corner_crack_K, shape_factor, surface_crack_K

#: Runge-Kutta steps of the reference integration
RK_STEPS = 400
#: points of the arc-length table that finds the parametric angle at a distance along the front
ARC_TABLE = 2001


def surface_K_any(S: float, a: float, c: float, t: float, b: float, phi) -> np.ndarray:
    """Newman and Raju's K_I of a surface crack in tension for any a/c (phi from the surface, pi/2 the deepest
    point): their shallow equation (a/c <= 1) or their deep one (a/c > 1: c/a takes the place of a/c)."""
    if a <= c:
        return surface_crack_K(S, a, c, t, b, phi)
    phi = np.asarray(phi, dtype=float)
    q = c / a  # their deep branch: M1 = sqrt(c/a) (1 + 0.04 c/a), M2 = 0.2 (c/a)^4, M3 = -0.11 (c/a)^4
    s = a / t
    m1, m2, m3 = math.sqrt(q) * (1.0 + 0.04 * q), 0.2 * q ** 4, -0.11 * q ** 4
    g = 1.0 + (0.1 + 0.35 * q * s * s) * (1.0 - np.sin(phi)) ** 2
    f_phi = ((q * np.sin(phi)) ** 2 + np.cos(phi) ** 2) ** 0.25
    f_w = 1.0 / math.sqrt(math.cos(0.5 * math.pi * c / b * math.sqrt(s)))
    return S * math.sqrt(math.pi * a / shape_factor(q)) * (m1 + m2 * s * s + m3 * s ** 4) * g * f_phi * f_w


def phi_in_from_surface(a: float, c: float, fraction: float, quarter: bool = False) -> float:
    """The parametric angle of the front point `fraction` of the front's length in from the surface (the front
    (c cos phi, a sin phi), 0 <= phi <= pi; a corner crack's front, `quarter`, 0 <= phi <= pi/2)."""
    if fraction <= 0:
        return 0.0
    phi = np.linspace(0.0, 0.5 * np.pi, ARC_TABLE)
    mid = 0.5 * (phi[1:] + phi[:-1])
    speed = np.hypot(c * np.sin(mid), a * np.cos(mid))
    s = np.r_[0.0, np.cumsum(speed * np.diff(phi))]
    length = s[-1] * (1.0 if quarter else 2.0)
    return float(np.interp(fraction * length, s, phi))


def trajectory(a0: float, c0: float, a_end: float, t: float, b: float, C: float, m: float, R: float = 0.0,
               S: float = 1.0, fraction: float | None = None, steps: int = RK_STEPS, corner: bool = False) -> dict:
    """The depth a, half-length c and cumulative cycles N of a surface crack from (a0, c0) to depth a_end under
    Paris's law (module docstring); {"a", "c", "N"} arrays of steps + 1 values.

    `corner`: a quarter-elliptical corner crack (depth a into the thickness t, length c along the width b, their
    corner-crack equation, a/c <= 1): both ends of its front lie on a face, so K_A too is taken the fraction of the
    front in from its end; the arrays stop where a/c would pass 1 (the equation's range)."""
    from .surface3d import SURFACE_K_FRACTION

    frac = SURFACE_K_FRACTION if fraction is None else float(fraction)
    dK = (1.0 - max(float(R), 0.0)) * S

    def rates(a, c):
        if corner:
            if a > c:
                raise _OutOfRange
            K_A = float(corner_crack_K(dK, a, c, t, b, 0.5 * np.pi - phi_in_from_surface(c, a, frac, quarter=True)))
            K_C = float(corner_crack_K(dK, a, c, t, b, phi_in_from_surface(a, c, frac, quarter=True)))
        else:
            K_A = float(surface_K_any(dK, a, c, t, b, 0.5 * np.pi))
            K_C = float(surface_K_any(dK, a, c, t, b, phi_in_from_surface(a, c, frac)))
        return (K_C / K_A) ** m, 1.0 / (C * K_A ** m)

    a_grid = np.linspace(a0, a_end, steps + 1)
    h = a_grid[1] - a_grid[0]
    c_out, N_out = [c0], [0.0]
    c, N = c0, 0.0
    for a in a_grid[:-1]:
        try:
            k1 = rates(a, c)
            k2 = rates(a + 0.5 * h, c + 0.5 * h * k1[0])
            k3 = rates(a + 0.5 * h, c + 0.5 * h * k2[0])
            k4 = rates(a + h, c + h * k3[0])
        except _OutOfRange:
            break
        c += h * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]) / 6.0
        N += h * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]) / 6.0
        c_out.append(c)
        N_out.append(N)
    return {"a": a_grid[:len(c_out)], "c": np.array(c_out), "N": np.array(N_out)}


class _OutOfRange(Exception):
    """A corner crack's a/c past the equation's range."""


def rule_trajectory(scene, da: float, steps: int, m: float, stations: int = 17, inset: float = 0.0,
                    t: float | None = None, b: float | None = None, heun: bool = False) -> dict:
    """The depth a and half-length c of scene's surface crack (crack[0]) grown by 3D growth's rule of a step
    (ngcrack.studies.growth.surface3d) with Newman and Raju's K at the front's stations in place of the solve's:
    `stations` inner points equally spaced in arc length from `inset` (a fraction of the front's length) inside
    either end, the ends carrying the values of the nearest inner point as a solve's do. It separates the rule's
    own error (the fitted ellipse, the advance of a step) from the error of the computed K. {"a", "c"} arrays.

    `heun`: the predictor-corrector step (Heun's): the advance of each station the mean of its advance on the
    crack and on the crack grown by that advance (the predictor; a second K per step), second order in da."""
    from ngcrack.solid.scene import SolidScene

    from .surface3d import depth_and_length, grown_surface_crack

    domain = scene.domain
    lo, hi = np.asarray(domain.lo), np.asarray(domain.hi)
    t = float(hi[2] - lo[2]) if t is None else t
    b = float(0.5 * (hi[0] - lo[0])) if b is None else b
    d = scene.to_dict()
    crack = scene.cracks[0]
    out_a, out_c = [], []
    for _ in range(steps + 1):
        a, c = depth_and_length(domain, crack)
        out_a.append(a)
        out_c.append(c)
        phi, adv, top = _rule_advance(domain, crack, da, m, stations, inset, t, b)
        if heun:
            d["crack"][0] = grown_surface_crack(domain, crack, phi, adv, top)[0]
            _, adv_p, _ = _rule_advance(domain, SolidScene.from_dict(d).cracks[0], da, m, stations, inset, t, b)
            adv = 0.5 * (adv + adv_p)
        d["crack"][0] = grown_surface_crack(domain, crack, phi, adv, top)[0]
        crack = SolidScene.from_dict(d).cracks[0]
    return {"a": np.array(out_a), "c": np.array(out_c)}


def _rule_advance(domain, crack, da, m, stations, inset, t, b):
    """(the stations' angles, their advance by the rule with Newman and Raju's K, the leading station)."""
    from .fronts3d import paris_advance
    from .surface3d import depth_and_length, depth_axis, ellipse_arc, surface_drive

    a, c = depth_and_length(domain, crack)
    grid = np.linspace(0.0, np.pi, 4001)  # the front from the surface point at phi = 0 round to phi = pi
    s_grid = ellipse_arc(crack, grid)
    length = s_grid[-1]
    s_in = np.linspace(inset * length, (1 - inset) * length, stations)
    phi = np.interp(np.r_[0.0, s_in, length], s_grid, grid)
    A, B = crack.semi_axes
    u, v = A * np.cos(phi), B * np.sin(phi)
    x, y = (v, u) if depth_axis(domain, crack) == 0 else (u, v)  # along the surface, in depth
    nr_phi = np.arctan2(np.abs(y) / a, x / c)  # Newman and Raju's angle: the point (c cos phi, a sin phi)
    K = surface_K_any(1.0, a, c, t, b, np.minimum(nr_phi, np.pi - nr_phi))
    K[0], K[-1] = K[1], K[-2]
    drive = surface_drive(phi, K, crack)
    return phi, paris_advance(drive, da, m, 0.0), int(np.argmax(drive))
