"""Axisymmetric lubrication in a radial (penny) fracture: one implicit step on rings, the time step solved for.

Pure numerics (numpy, scipy). The disc of radius R is cut into N rings (cell 0 the central
disc, where the fluid is injected; cell N - 1 the ring at the front); the elastic crack
enters as a compliance over them, w = C p + w_is (`radial_elastic`: w_k the ring's mean
opening, p_j a pressure uniform on ring j). With no fluid lag and an incompressible fluid,

    dw/dt + (1/r) d(r q)/dr + g = Q(t) delta_0,    q = -(w^3 / mu') dp/dr,    mu' = 12 mu,

g Carter's leak-off through both faces, 2 C_L / sqrt(t - t0(r)). Finite volumes: ring k
holds A_k w_k (A_k its area); the flux through the circle between rings k and k + 1 is
2 pi w_f^3 / mu' (p_k - p_(k+1)) / ln(rho_(k+1) / rho_k), rho_k the ring's log-mean radius
(exp of the area mean of ln r: the pressure of a radial source flow, p = a - b ln r, has its
ring mean at rho_k, so the flux is exact for it; the central disc's rho_0 = r_1 e^(-1/2)), w_f
the mean of the two rings' openings. This carries the injection's logarithmic pressure
singularity without a fine mesh at the centre.

As in the plane model (`flow.py`, whose tip asymptotes it uses), one step advances the
front by a given length and solves for the ring pressures and the step's duration dt
together (Newton, the time step's column by a difference): the mass balance of every ring
but the one next to the front ring, the fluxes by the theta rule (flow.THETA); in that ring,
the mean opening (divided by the elastic solve's calibrated error there) equals the ring's
area-weighted mean of the universal tip asymptote (K, M and, with leak-off, M-tilde joined as
the cube root of the sum of cubes) at the front's speed; the global balance, crack volume =
injected - leaked. The face into the front ring carries the viscosity asymptote's flux
(flow.tip_face_factor, with the circle's length at that face).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .flow import (
    CONTINUATION_DECADES,
    DT_RANGE,
    THETA,
    FluidState,
    Schedule,
    StepError,
    damped_newton,
    dt_column,
    leaked,
    tip_face_factor,
    tip_opening,
    tip_speed,
)

#: Gauss-Legendre points of a ring's mean of the tip asymptote (in u, x = x0 + h u^2 from the front ring)
_GAUSS = np.polynomial.legendre.leggauss(16)


def log_mean_radius(a: float, b: float) -> float:
    """exp of the area mean of ln r over the ring a < r < b (b e^(-1/2) for the central disc, a = 0)."""
    if a <= 0.0:
        return b * math.exp(-0.5)
    return math.exp((b * b * math.log(b) - a * a * math.log(a)) / (b * b - a * a) - 0.5)


def ring_tip_mean(R: float, x0: float, h: float, V: float, K_Ic: float, E_prime: float, mu: float,
                  C_L: float = 0.0) -> float:
    """The tip asymptote's mean over the ring R - x0 - h < r < R - x0 (x the distance behind the front),
    weighted by r (the ring's area)."""
    u, wts = _GAUSS
    u = 0.5 * (u + 1.0)
    if x0 == 0.0:  # x = h u^2: the square root at the front integrated exactly
        x, jac = h * u * u, 2.0 * h * u
    else:
        x, jac = x0 + h * u, np.full(len(u), h)
    weight = 0.5 * wts * jac * (R - x)
    return float(np.sum(weight * tip_opening(x, V, K_Ic, E_prime, mu, C_L)) / np.sum(weight))


@dataclass
class Rings:
    """The fluid cells of one step: ring edges (0 = r_0 < ... < r_N = R), their areas, the compliance
    C (ring-mean opening per unit pressure on each ring), the opening w_is of the other loads, the
    factor `scale` by which the elastic solve's opening in the ring next to the front ring exceeds the
    K field's (`radial_elastic.tip_scale`)."""

    edges: np.ndarray
    C: np.ndarray
    w_is: np.ndarray
    scale: float = 1.0

    @property
    def n(self) -> int:
        return len(self.edges) - 1

    @property
    def R(self) -> float:
        return float(self.edges[-1])

    @property
    def area(self) -> np.ndarray:
        return math.pi * (self.edges[1:] ** 2 - self.edges[:-1] ** 2)

    @property
    def mid(self) -> np.ndarray:
        return 0.5 * (self.edges[1:] + self.edges[:-1])

    @property
    def width(self) -> np.ndarray:
        return np.diff(self.edges)

    def face_geometry(self) -> np.ndarray:
        """2 pi / ln(rho_(k+1) / rho_k) per face between rings k and k + 1 (module docstring)."""
        rho = np.array([log_mean_radius(a, b) for a, b in zip(self.edges[:-1], self.edges[1:])])
        return 2.0 * math.pi / np.log(rho[1:] / rho[:-1])

    def tip_target(self, V: float, K_Ic: float, E_prime: float, mu: float, C_L: float) -> float:
        """The asymptote's mean over the ring next to the front ring."""
        h = self.width
        return ring_tip_mean(self.R, float(h[-1]), float(h[-2]), V, K_Ic, E_prime, mu, C_L)


def _guess(rings: Rings, t_old, t0_old, new_frac, schedule: Schedule, a, previous, fluid, shape=None):
    """(p, dt): the pressure of the given shape (uniform by default) scaled to hold the injected volume less
    the leaked one, at the dt that puts the ring next to the front on its asymptote."""
    from scipy.optimize import brentq

    K_Ic, E_prime, mu, C_L = fluid
    shape = np.ones(rings.n) if shape is None else shape
    unit = rings.C @ shape
    A = rings.area
    held = float(A @ unit)
    new = np.isnan(t0_old)

    def pressure(dt):
        t0 = np.where(new, t_old + new_frac * dt, t0_old)
        volume = schedule.volume(t_old + dt) - leaked(t_old + dt, t0, A, C_L)
        return (volume - A @ rings.w_is) / held

    def gap(log_dt):
        dt = math.exp(log_dt)
        w = unit[-2] * pressure(dt) + rings.w_is[-2]
        return w / rings.scale - rings.tip_target(tip_speed(a, dt, previous), K_Ic, E_prime, mu, C_L)

    lo, hi = -60.0, 60.0
    if gap(lo) * gap(hi) > 0:
        raise StepError("no time step puts the front on its asymptote (the injection does not open the crack)")
    dt = math.exp(brentq(gap, lo, hi, xtol=1e-10))
    return shape * pressure(dt), dt


def _newton(rings: Rings, w_old, p_old, t_old, t0_old, new_frac, schedule: Schedule, a: float, previous, fluid,
            p_guess=None) -> FluidState:
    """One implicit step (module docstring): the front advances by `a` (its speed from `previous` = the last
    step's (advance, duration), or a / dt); w_old, p_old the last step's opening and pressure on these rings
    (p_old None: backward Euler), t0_old the front's arrival time per ring (NaN for the rings the step adds,
    passed at t_old + new_frac dt)."""
    K_Ic, E_prime, mu, C_L = fluid
    n = rings.n
    if n < 4:
        raise StepError(f"{n} rings: the radial flow needs at least 4")
    mu_p = 12.0 * mu
    A, C, w_is = rings.area, rings.C, rings.w_is
    h = rings.width
    geo = rings.face_geometry()
    mid = rings.mid
    # the face into the front ring: the viscosity asymptote's flux (flow.tip_face_factor), the circle's length there
    phi = tip_face_factor(float(h[-1]), float(h[-2]), float(mid[-1] - mid[-2]))
    geo_tip = 2.0 * math.pi * rings.edges[-2] / float(mid[-1] - mid[-2])
    p_guess, dt_guess = _guess(rings, t_old, t0_old, new_frac, schedule, a, previous, fluid, p_guess)
    new = np.isnan(t0_old)
    inj = np.zeros(n)
    inj[0] = 1.0
    w_scale = max(float(np.max(np.abs(C @ p_guess + w_is))), 1e-300)
    p_scale = max(float(np.max(np.abs(p_guess))), 1e-300)
    total_area = float(np.sum(A))
    AC = A @ C
    theta = 1.0 if p_old is None else THETA
    out_old = np.zeros(n)
    if p_old is not None:
        wf_old = np.clip(0.5 * (w_old[1:] + w_old[:-1]), 0.0, None)
        flux_old = geo * wf_old ** 3 / mu_p * -np.diff(p_old)
        out_old[:-1] += flux_old
        out_old[1:] -= flux_old

    def unpack(x):
        return x[:n] * p_scale, dt_guess * math.exp(float(np.clip(x[n], -math.log(DT_RANGE), math.log(DT_RANGE))))

    def residual(x, jacobian=False):
        p, dt = unpack(x)
        w = C @ p + w_is
        t = t_old + dt
        V = tip_speed(a, dt, previous)
        t0 = np.where(new, t_old + new_frac * dt, t0_old)
        wf = np.clip(0.5 * (w[1:] + w[:-1]), 0.0, None)
        g = geo.copy()
        wf[-1] = phi ** (1 / 3) * float(tip_opening(h[-1], V, K_Ic, E_prime, mu, C_L))
        g[-1] = geo_tip
        mob = g * wf ** 3 / mu_p
        flux = -mob * np.diff(p)  # from ring k to k + 1
        out = np.zeros(n)
        out[:-1] += flux
        out[1:] -= flux
        lk = 4.0 * C_L * A * (np.sqrt(np.clip(t - t0, 0.0, None)) - np.sqrt(np.clip(t_old - t0, 0.0, None)))
        dv = schedule.volume(t) - schedule.volume(t_old)
        r = (A * (w - w_old) + dt * (theta * out + (1 - theta) * out_old) + lk - dv * inj) / (A * w_scale)
        r[-2] = (w[-2] / rings.scale - rings.tip_target(V, K_Ic, E_prime, mu, C_L)) / w_scale
        total = (A @ w - schedule.volume(t) + leaked(t, t0, A, C_L)) / (total_area * w_scale)
        r = np.append(r, total)
        if not jacobian:
            return r
        f = np.arange(n - 1)
        dflux = np.zeros((n - 1, n))
        dflux[f, f + 1] -= mob
        dflux[f, f] += mob
        dwf = np.where(wf > 0, 3.0 * g * wf ** 2 / mu_p * 0.5, 0.0) * -np.diff(p)
        dwf[-1] = 0.0  # the front face's opening is the asymptote's (dt only)
        dflux += dwf[:, None] * (C[1:] + C[:-1])
        dout = np.zeros((n, n))
        dout[:-1] += dflux
        dout[1:] -= dflux
        J = np.zeros((n + 1, n + 1))
        J[:n, :n] = (A[:, None] * C + dt * theta * dout) / (A * w_scale)[:, None] * p_scale
        J[n - 2, :n] = C[-2] / rings.scale / w_scale * p_scale
        J[n, :n] = AC / (total_area * w_scale) * p_scale
        return r, dt_column(residual, x, r, J)

    x = damped_newton(residual, np.append(p_guess / p_scale, 0.0))
    p, dt = unpack(x)
    t = t_old + dt
    t0 = np.where(new, t_old + new_frac * dt, t0_old)
    return FluidState(t=t, p=p, w=C @ p + w_is, t0=t0, injected=schedule.volume(t), leaked=leaked(t, t0, A, C_L),
                      dt=dt, calls=0)


def radial_step(rings: Rings, w_old, p_old, t_old, t0_old, new_frac, schedule: Schedule, a: float, previous, fluid,
                p_guess=None) -> FluidState:
    """One implicit step (`_newton`) from the last step's pressure shape, else a uniform one; where both fail
    (a first step far from uniform), a continuation in the viscosity from CONTINUATION_DECADES decades below."""
    error = None
    for start in ([p_guess] if p_guess is not None else []) + [None]:
        try:
            return _newton(rings, w_old, p_old, t_old, t0_old, new_frac, schedule, a, previous, fluid, start)
        except StepError as exc:
            error = exc
    K_Ic, E_prime, mu, C_L = fluid
    state = None
    for k in range(CONTINUATION_DECADES, -1, -1):
        try:
            state = _newton(rings, w_old, p_old, t_old, t0_old, new_frac, schedule, a, previous,
                            (K_Ic, E_prime, mu * 10.0 ** (-k), C_L), None if state is None else state.p)
        except StepError:
            if k == 0:
                raise error from None
            state = None
    return state


def carried_over(edges_old: np.ndarray, w_old: np.ndarray, p_old: np.ndarray, t0_old: np.ndarray, edges: np.ndarray):
    """(w, p, t0, new_frac) on the rings `edges` of the grown disc: the last step's ring values interpolated
    at the new rings' mid radii (the opening 0 at the old front and beyond it); the rings beyond the old
    front are new (t0 NaN, new_frac where in the step the front passed their middle)."""
    mid_old = 0.5 * (edges_old[1:] + edges_old[:-1])
    mid = 0.5 * (edges[1:] + edges[:-1])
    R_old, R = float(edges_old[-1]), float(edges[-1])
    inside = mid <= R_old
    w = np.where(inside, np.interp(mid, np.append(mid_old, R_old), np.append(w_old, 0.0)), 0.0)
    p = np.interp(mid, mid_old, p_old)
    t0 = np.where(inside, np.interp(mid, mid_old, t0_old), np.nan)
    frac = np.where(inside, 0.0, np.clip((mid - R_old) / max(R - R_old, 1e-300), 0.0, 1.0))
    return w, p, t0, frac


def sneddon_ring_compliance(edges: np.ndarray, E_prime: float, points: int = 24) -> np.ndarray:
    """The ring compliance of a penny in an infinite body (Sneddon's axisymmetric solution), exact but for
    quadrature: the opening under an axisymmetric pressure is w(r) = (8 / (pi E')) int_r^R g(t) (t^2 - r^2)^(-1/2)
    dt, g(t) = int_0^t s p(s) (t^2 - s^2)^(-1/2) ds, so a unit pressure on ring j (a_j < r < b_j) has
    g_j(t) = (t^2 - a_j^2)_+^(1/2) - (t^2 - b_j^2)_+^(1/2), and ring k's volume of it is
    V_kj = (16 / E') int_0^R g_k g_j dt (symmetric). Returns V_kj / A_k. The reference the 3D compliance is
    measured against, and an elastic crack for testing the flow alone."""
    u, wts = np.polynomial.legendre.leggauss(points)
    u = 0.5 * (u + 1.0)
    t, w = [], []
    for a, b in zip(edges[:-1], edges[1:]):  # t = a + (b - a) u^2: the square roots at a integrated smoothly
        t.append(a + (b - a) * u * u)
        w.append(0.5 * wts * 2.0 * (b - a) * u)
    t, w = np.concatenate(t), np.concatenate(w)
    g = (np.sqrt(np.clip(t[None, :] ** 2 - edges[:-1, None] ** 2, 0.0, None))
         - np.sqrt(np.clip(t[None, :] ** 2 - edges[1:, None] ** 2, 0.0, None)))
    V = 16.0 / E_prime * (g * w) @ g.T
    return V / (math.pi * (edges[1:] ** 2 - edges[:-1] ** 2))[:, None]
