"""A viscous Newtonian fluid in a plane crack: lubrication, the tip asymptotes, one implicit step.

Pure numerics (numpy, scipy): the elastic crack enters as a compliance C over the fluid
cells (the crack's mesh edges), w = C p + w_is, from ngcrack's own mixed solve
(`elastic.py`). Along the crack's arc length s, with no fluid lag (the fluid front is the
crack tip) and an incompressible fluid:

    dw/dt + dq/ds + g = Q(t) delta(s - s_inj),    q = -(w^3 / mu') dp/ds,    mu' = 12 mu

(Poiseuille flow between the faces), g the Carter leak-off through both faces,
2 C_L / sqrt(t - t0(s)), t0(s) the time the tip passed s. Finite volumes on the cells:
the flux between neighbouring cells uses the mean opening of the two cubed; no flux
through a crack end.

Fixed length increments, the time step the unknown: in one step each tip advances by a
given length (0 for an arrested tip), and the step solves for the cell pressures p and
the step's duration dt together (Newton with a backtracking line search; a first step
Newton cannot start is reached by continuation in the viscosity). The equations: the mass
balance of every cell but the one next to each moving tip, the fluxes integrated in time by
a theta rule a little above the trapezoidal one (THETA); in the cell next to each moving
tip, the opening (divided by the elastic solve's calibrated error there, `tip_calibration`)
equals the mean over the cell of the tip asymptote at the tip's speed V (second order in
time, `tip_speed`); and the global balance, crack volume = injected volume - leaked volume
(exact, whatever remeshing did to the cells). The tip asymptote between the toughness vertex
w = K' x^(1/2) / E' and the viscosity one w = beta_m (mu' V / E')^(1/3) x^(2/3) is Dontsov and
Peirce's universal one (2015, JFM 781 R1; their delta correction, TIP_ASYMPTOTE = "universal",
`km_opening`): w = (K' x^(1/2) / E') (1 + 3 C1(delta) x~)^(1/3), x~ = (x / l_mk)^(1/2),
l_mk = (K'^3 / (E'^2 mu' V))^2, delta = (beta_m^3 / 3) x~ / (1 + beta_m^3 x~); its zeroth order,
the cube root of the sum of the vertices' cubes ("cubes"), is up to 1.2% narrower in between
(measured on KGD at K_m = 0.5-3: the length changes by 0.02-0.1%). With leak-off the M-tilde
asymptote w = beta (4 C'^2 mu'^2 V / E'^2)^(1/8) x^(5/8) joins it as the cube root of the sum of
the cubes (exact at each vertex; that transition is an interpolation). The face into the tip cell takes the mobility that carries
the viscosity asymptote's flux V w between the two cells' mean pressures (`tip_face_factor`).

Regimes (Adachi and Detournay 2002, plane strain): the dimensionless toughness
K_m = K' / (E'^3 mu' Q0)^(1/4), K' = 4 (2/pi)^(1/2) K_Ic; K_m < 1 viscosity-dominated (the
M-vertex), K_m > 4 toughness-dominated (the K-vertex), between them both matter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: beta_m of the viscosity tip asymptote w = beta_m (mu' V / E')^(1/3) x^(2/3) (2^(1/3) 3^(5/6))
BETA_M = 2.0 ** (1.0 / 3.0) * 3.0 ** (5.0 / 6.0)
#: beta of the leak-off (M-tilde) tip asymptote w = beta (4 C'^2 mu'^2 V / E'^2)^(1/8) x^(5/8), C' = 2 C_L
BETA_MT = 4.0 / (15.0 ** 0.25 * (math.sqrt(2.0) - 1.0) ** 0.25)
#: K' / K_Ic = 4 (2 / pi)^(1/2)
K_PRIME = 4.0 * math.sqrt(2.0 / math.pi)
#: K_m above this: toughness-dominated (K-vertex); below K_M_VISCOUS: viscosity-dominated
K_M_TOUGHNESS = 4.0
K_M_VISCOUS = 1.0
#: M-vertex of the KGD fracture (Adachi and Detournay 2002): l = L_M (E' Q0^3 t^4 / mu')^(1/6),
#: w0 = W_M (mu' Q0^3 t^2 / E')^(1/6) (Q0 the whole injection rate, l the half-length)
L_M, W_M = 0.6152, 1.1265
#: Gauss-Legendre points of the tip cell's mean opening (in u, x = h u^2)
_GAUSS = np.polynomial.legendre.leggauss(12)
#: the step's equations are met to this fraction of their scales (Newton stops there), and
#: a step whose line search stalls (round-off) is accepted below STALL_RTOL
STEP_RTOL = 1e-10
STALL_RTOL = 1e-7
#: a step's duration is searched within this factor of its first guess, either way
DT_RANGE = 1e6
#: Newton steps of one implicit step at most, and the largest change of log(dt) in one
MAX_NEWTON = 60
#: the weight of the step's end in the time integral of the fluxes: a little above the trapezoidal
#: rule's 1/2, which oscillates where the fluid diffuses without growth (behind an arrested tip its
#: K_I alternated 0.52 / 0.96 from step to step at 1/2, settles to 0.8-0.9 at 0.6); backward Euler
#: (1) is first order (KGD's M-vertex 3.2% off at 80 cells where 1/2 gives 0.64%, 0.6 0.80%)
THETA = 0.6
#: decades of viscosity of the continuation that starts a step Newton cannot start
CONTINUATION_DECADES = 8
MAX_LOG_DT_STEP = 2.0
#: the step in log(dt) of the Jacobian's time-step column (`dt_column`)
DT_EPS = 1e-7
#: the toughness-viscosity tip asymptote: "universal" (Dontsov and Peirce 2015, the delta correction) or
#: "cubes" (its zeroth order, the cube root of the sum of the vertices' cubes)
TIP_ASYMPTOTE = "universal"


def k_prime(K_Ic: float) -> float:
    return K_PRIME * K_Ic


def k_m(K_Ic: float, E_prime: float, mu: float, Q0: float) -> float:
    """Adachi-Detournay's dimensionless toughness of the KGD fracture, K' / (E'^3 mu' Q0)^(1/4)."""
    if mu <= 0:
        return math.inf
    return k_prime(K_Ic) / (E_prime ** 3 * 12.0 * mu * Q0) ** 0.25


def m_vertex(t, E_prime: float, mu: float, Q0: float):
    """(half-length, opening at the injection point) of the KGD M-vertex at time t."""
    mu_p = 12.0 * mu
    t = np.asarray(t, dtype=float)
    return (L_M * (E_prime * Q0 ** 3 * t ** 4 / mu_p) ** (1 / 6), W_M * (mu_p * Q0 ** 3 * t ** 2 / E_prime) ** (1 / 6))


def k_vertex(t, E_prime: float, K_Ic: float, Q0: float):
    """(half-length, pressure, opening at the centre) of the KGD K-vertex (uniform pressure) at time t."""
    t = np.asarray(t, dtype=float)
    l = (E_prime * Q0 * t / (2.0 * math.sqrt(math.pi) * K_Ic)) ** (2 / 3)
    p = K_Ic / np.sqrt(math.pi * l)
    return l, p, 4.0 * p * l / E_prime


def c1(delta):
    """Dontsov and Peirce's C1(delta) = 4 (1 - 2 delta) tan(pi delta) / (delta (1 - delta)): 4 pi at delta = 0
    (the toughness end), beta_m^3 / 3 = 6 sqrt(3) at delta = 1/3 (the viscosity end)."""
    d = np.asarray(delta, dtype=float)
    small = d < 1e-8
    d_safe = np.where(small, 0.25, d)
    value = 4.0 * (1.0 - 2.0 * d_safe) * np.tan(math.pi * d_safe) / (d_safe * (1.0 - d_safe))
    return np.where(small, 4.0 * math.pi, value)


def km_opening(x, V: float, K_prime: float, E_prime: float, mu_prime: float, universal: bool = True):
    """The toughness-viscosity tip asymptote at distance x behind a tip moving at V, without leak-off:
    Dontsov and Peirce's universal one (`universal`, their delta correction) or its zeroth order, the
    sum of cubes (w_k^3 + w_m^3)^(1/3) (module docstring)."""
    x = np.asarray(x, dtype=float)
    wk = K_prime * np.sqrt(x) / E_prime
    if mu_prime <= 0 or V <= 0:
        return wk
    if K_prime <= 0:
        return BETA_M * (mu_prime * V / E_prime) ** (1 / 3) * x ** (2 / 3)
    xt = np.sqrt(x) * E_prime ** 2 * mu_prime * V / K_prime ** 3  # (x / l_mk)^(1/2), l_mk = (K'^3 / (E'^2 mu' V))^2
    b3 = BETA_M ** 3
    coefficient = 3.0 * c1(b3 / 3.0 * xt / (1.0 + b3 * xt)) if universal else b3
    return wk * np.cbrt(1.0 + coefficient * xt)


def tip_opening(x, V: float, K_Ic: float, E_prime: float, mu: float, C_L: float = 0.0):
    """The tip asymptote at distance x behind a tip moving at V (module docstring): the toughness-viscosity
    one of TIP_ASYMPTOTE, with leak-off joined to the M-tilde one as the cube root of the sum of cubes."""
    x = np.asarray(x, dtype=float)
    V = max(V, 0.0)
    mu_p = 12.0 * mu
    wkm = km_opening(x, V, k_prime(K_Ic), E_prime, mu_p, TIP_ASYMPTOTE == "universal")
    if C_L == 0:
        return wkm
    wc = BETA_MT * (4.0 * (2.0 * C_L) ** 2 * mu_p ** 2 * V / E_prime ** 2) ** (1 / 8) * x ** (5 / 8)
    return np.cbrt(wkm ** 3 + wc ** 3)


def tip_cell_mean(h: float, V: float, K_Ic: float, E_prime: float, mu: float, x0: float = 0.0, C_L: float = 0.0) -> float:
    """The tip asymptote's mean over a cell of length h from x0 to x0 + h behind the tip."""
    u, wts = _GAUSS
    u = 0.5 * (u + 1.0)
    if x0 == 0.0:  # x = h u^2: the square root at the tip integrated exactly
        return float(np.sum(0.5 * wts * tip_opening(h * u * u, V, K_Ic, E_prime, mu, C_L) * 2.0 * u))
    return float(np.sum(0.5 * wts * tip_opening(x0 + h * u, V, K_Ic, E_prime, mu, C_L)))


@dataclass
class Schedule:
    """The injection rate against time: rate[i] from time[i] to time[i + 1] (the last one on
    for ever); a rate of 0 is a shut-in. `volume(t)`: the volume injected by t."""

    time: np.ndarray
    rate: np.ndarray

    @classmethod
    def constant(cls, Q0: float) -> Schedule:
        return cls(np.array([0.0]), np.array([float(Q0)]))

    def volume(self, t: float) -> float:
        edges = np.append(self.time, max(t, self.time[-1]))
        dt = np.clip(np.minimum(edges[1:], t) - edges[:-1], 0.0, None)
        return float(np.sum(self.rate * dt))

    @property
    def largest_rate(self) -> float:
        return float(np.max(self.rate))

    def time_of(self, volume: float) -> float | None:
        """The time by which `volume` has been injected (None: never, after a shut-in)."""
        t, v = 0.0, 0.0
        for i, q in enumerate(self.rate):
            end = self.time[i + 1] if i + 1 < len(self.time) else math.inf
            if q > 0 and v + q * (end - self.time[i]) >= volume:
                return float(self.time[i] + (volume - v) / q)
            if end == math.inf:
                return None
            v += q * (end - self.time[i])
            t = end
        return None if volume > v else t


@dataclass
class Cells:
    """The fluid cells of one step: mid arc lengths `s`, lengths `h`, the compliance `C`
    (opening at cell i for a unit pressure in cell j) and the opening `w_is` of the scene's
    other loads (in-situ stress); `tips`: (cell index, advance of that tip in the step) per
    crack end that is a tip; `inj`: the injection cell; `scale`: per cell where a tip asymptote is
    imposed, the factor by which the elastic solve's opening there exceeds the K-field's (the
    mesh's error near the tip, `tip_calibration`): the opening divided by it meets the asymptote."""

    s: np.ndarray
    h: np.ndarray
    C: np.ndarray
    w_is: np.ndarray
    tips: list
    inj: int
    scale: dict = field(default_factory=dict)


@dataclass
class FluidState:
    """The fluid after a step: time, pressure and opening per cell, the arrival times of the tip
    at the cells (for leak-off), the injected and leaked volumes, the step's duration and solver calls."""

    t: float
    p: np.ndarray
    w: np.ndarray
    t0: np.ndarray
    injected: float
    leaked: float
    dt: float
    calls: int

    @property
    def efficiency(self) -> float:
        return 1.0 - self.leaked / self.injected if self.injected > 0 else 1.0


class StepError(RuntimeError):
    """The implicit step did not converge."""


def tip_speed(a: float, dt: float, previous) -> float:
    """The tip's speed at the step's end: the slope at t + dt of the quadratic through the tip's
    last three positions (second order) when `previous` = (its advance, duration) of the step
    before is known, else the step's mean speed a / dt."""
    if previous is None or previous[0] <= 0:
        return a / dt
    a0, dt0 = previous
    return a / dt + dt * (a / dt - a0 / dt0) / (dt + dt0)


def tip_face_factor(h_tip: float, h_next: float, d: float) -> float:
    """phi: the mobility phi w(h_tip)^3 / mu' of the face into a tip cell that gives, between the
    two cells' mean pressures, the flux V w(h_tip) of the viscosity asymptote (where the pressure
    goes as x^(-1/3): p = P x^(-1/3) with q = V w, so phi = d / (3 h_tip^(4/3) (mean over the tip
    cell of x^(-1/3) - mean over the next cell))). 0.539 for equal cells; the mean of the two
    cells' openings would make the face 1.6 times too mobile, their smaller one 2.5 times too little."""
    mean_tip = 1.5 * h_tip ** (-1 / 3)
    mean_next = 1.5 * ((h_tip + h_next) ** (2 / 3) - h_tip ** (2 / 3)) / h_next
    return d / (3.0 * h_tip ** (4 / 3) * (mean_tip - mean_next))


def leaked(t: float, t0: np.ndarray, h: np.ndarray, C_L: float) -> float:
    """Carter's leaked volume by time t through both faces: sum 4 C_L h sqrt(t - t0)."""
    if C_L == 0:
        return 0.0
    return float(np.sum(4.0 * C_L * h * np.sqrt(np.clip(t - t0, 0.0, None))))


def asymptote_cell(i: int, n: int, h: np.ndarray) -> tuple[int, float]:
    """(cell, its distance from the tip) where the tip asymptote is imposed for the tip at cell i:
    the next cell in (the tip cell's own mean opening is the mixed solve's least accurate value:
    a linear jump on the edge that ends at the tip; measured 25% too wide on KGD), the tip
    cell itself on a crack of fewer than 4 cells."""
    if n < 4:
        return i, 0.0
    return (1 if i == 0 else n - 2), float(h[i])


def tip_calibration(C: np.ndarray, h: np.ndarray, tip: int, K_unit: float, E_prime: float) -> tuple[int, float]:
    """(cell, factor): the cell where the asymptote of the tip at cell `tip` is imposed, and the
    ratio of its opening under a unit pressure (C's row sum) to the mean over the cell of the K
    field K_unit^' x^(1/2) / E', K_unit the interaction integral's K_I under that pressure. The
    elastic solve's error near a tip (linear jumps on a square-root opening: measured 6% too wide
    in the cell next to the tip on KGD's mesh, 18% in the tip cell) is thus taken out of the
    opening the asymptote is matched with, and K_I = K_Ic where viscosity does not matter."""
    j, x0 = asymptote_cell(tip, len(h), h)
    reference = tip_cell_mean(h[j], 0.0, K_unit, E_prime, 0.0, x0)
    factor = float(np.sum(C[j])) / reference if reference > 0 and K_unit > 0 else 1.0
    return j, factor


def scaled_guess(cells: Cells, t_old, t0_old, new_frac, schedule: Schedule, K_Ic, E_prime, mu, C_L,
                 shape=None) -> tuple[np.ndarray, float]:
    """A first (p, dt) for a step: the pressure of the given shape (uniform by default), scaled
    to hold the injected volume less the leaked one, and the dt that puts the first moving tip's
    cell on its asymptote."""
    from scipy.optimize import brentq

    shape = np.ones(len(cells.h)) if shape is None else shape
    unit = cells.C @ shape
    i, a = next((i, a) for i, a in cells.tips if a > 0)
    j, x0 = asymptote_cell(i, len(cells.h), cells.h)
    held = float(np.sum(cells.h * unit))
    new = np.isnan(t0_old)

    def pressure(dt):
        t0 = np.where(new, t_old + new_frac * dt, t0_old)
        volume = schedule.volume(t_old + dt) - leaked(t_old + dt, t0, cells.h, C_L)
        return (volume - np.sum(cells.h * cells.w_is)) / held

    def gap(log_dt):
        dt = math.exp(log_dt)
        w = unit[j] * pressure(dt) + cells.w_is[j]
        return w / cells.scale.get(j, 1.0) - tip_cell_mean(cells.h[j], a / dt, K_Ic, E_prime, mu, x0, C_L)

    lo, hi = -60.0, 60.0
    if gap(lo) * gap(hi) > 0:
        raise StepError("no time step puts the tip on its asymptote (the injection does not open the crack)")
    dt = math.exp(brentq(gap, lo, hi, xtol=1e-10))
    return shape * pressure(dt), dt


def _newton_step(cells: Cells, w_old: np.ndarray, t_old: float, t0_old: np.ndarray, new_frac: np.ndarray,
               schedule: Schedule, K_Ic: float, E_prime: float, mu: float, C_L: float,
               p_guess: np.ndarray | None = None, dt_guess: float | None = None, previous=None,
               p_old: np.ndarray | None = None) -> FluidState:
    """One implicit step (module docstring) on `cells`.

    w_old: the opening at the step's start on these cells (0 where the crack is new);
    t0_old: the tip's arrival time at each cell, NaN for cells the step's growth adds;
    new_frac: for those, where in the step the tip passes them (0 at its start, 1 at its
    end), so that t0 = t_old + new_frac dt. p_guess, dt_guess: where Newton starts (the
    uniform guess when None). previous: per tip of cells.tips, (advance, duration) of its last
    step, or None (the tip's speed, `tip_speed`). Returns the FluidState at the step's end.
    """
    n = len(cells.h)
    mu_p = 12.0 * mu
    h, s, C = cells.h, cells.s, cells.C
    ds = np.diff(s)
    # the moving tips: (cell, advance, the face into the cell, its mobility factor phi, the tip's last step,
    # the cell where the asymptote is imposed and its distance from the tip);
    # an arrested tip's cell keeps its mass balance, with no flux through the tip
    moving = []
    for k, (i, a) in enumerate(cells.tips):
        if a > 0:
            face, nxt = (0, 1) if i == 0 else (n - 2, n - 2)
            prev = None if previous is None or previous[k] is None else previous[k]
            j, x0 = asymptote_cell(i, n, h)
            moving.append((i, a, face, tip_face_factor(h[i], h[nxt], abs(s[nxt] - s[i])), prev, j, x0))
    if not moving:
        raise StepError("no tip advances in the step")
    p_guess, dt_guess = scaled_guess(cells, t_old, t0_old, new_frac, schedule, K_Ic, E_prime, mu, C_L, p_guess)
    new = np.isnan(t0_old)
    inj = np.zeros(n)
    inj[cells.inj] = 1.0
    w_scale = max(float(np.max(np.abs(C @ p_guess + cells.w_is))), 1e-300)
    p_scale = max(float(np.max(np.abs(p_guess))), 1e-300)
    length = float(np.sum(h))
    hC = h @ C
    calls = 0
    # the flux divergence at the step's start (on these cells), for the theta rule in time
    theta = 1.0 if p_old is None else THETA
    out_old = np.zeros(n)
    if p_old is not None:
        wf_old = np.clip(0.5 * (w_old[1:] + w_old[:-1]), 0.0, None)
        flux_old = -(wf_old ** 3 / mu_p) * np.diff(p_old) / ds
        out_old[:-1] += flux_old
        out_old[1:] -= flux_old

    def unpack(x):
        return x[:n] * p_scale, dt_guess * math.exp(float(np.clip(x[n], -math.log(DT_RANGE), math.log(DT_RANGE))))

    def residual(x, jacobian=False):
        nonlocal calls
        calls += 1
        p, dt = unpack(x)
        w = C @ p + cells.w_is
        t = t_old + dt
        t0 = np.where(new, t_old + new_frac * dt, t0_old)
        wf = np.clip(0.5 * (w[1:] + w[:-1]), 0.0, None)
        for i, a, face, phi, prev, _, _ in moving:  # the face into a moving tip's cell: the asymptote's flux
            wf[face] = phi ** (1 / 3) * float(tip_opening(h[i], tip_speed(a, dt, prev), K_Ic, E_prime, mu, C_L))
        dp = np.diff(p) / ds
        flux = -(wf ** 3 / mu_p) * dp  # from cell i to i + 1
        out = np.zeros(n)
        out[:-1] += flux
        out[1:] -= flux
        lk = 4.0 * C_L * h * (np.sqrt(np.clip(t - t0, 0.0, None)) - np.sqrt(np.clip(t_old - t0, 0.0, None)))
        dv = schedule.volume(t) - schedule.volume(t_old)
        r = (h * (w - w_old) + dt * (theta * out + (1 - theta) * out_old) + lk - dv * inj) / (h * w_scale)
        for _, a, _, _, prev, j, x0 in moving:
            r[j] = (w[j] / cells.scale.get(j, 1.0) - tip_cell_mean(h[j], tip_speed(a, dt, prev), K_Ic, E_prime, mu, x0, C_L)) / w_scale
        total = (np.sum(h * w) - schedule.volume(t) + leaked(t, t0, h, C_L)) / (length * w_scale)
        r = np.append(r, total)
        if not jacobian:
            return r
        # d flux_f / d p: the pressure difference and the mobility (through w = C p)
        dflux = np.zeros((n - 1, n))
        f = np.arange(n - 1)
        dflux[f, f + 1] -= wf ** 3 / mu_p / ds
        dflux[f, f] += wf ** 3 / mu_p / ds
        dflux -= ((3 * wf ** 2 / mu_p * (wf > 0) * dp * 0.5)[:, None]) * (C[1:] + C[:-1])
        for _, _, face, _, _, _, _ in moving:
            dflux[face] = 0.0
            dflux[face, face + 1] -= wf[face] ** 3 / mu_p / ds[face]
            dflux[face, face] += wf[face] ** 3 / mu_p / ds[face]
        dout = np.zeros((n, n))
        dout[:-1] += dflux
        dout[1:] -= dflux
        J = np.zeros((n + 1, n + 1))
        J[:n, :n] = (h[:, None] * C + dt * theta * dout) / (h * w_scale)[:, None] * p_scale
        for _, _, _, _, _, j, _ in moving:
            J[j, :n] = C[j] / cells.scale.get(j, 1.0) / w_scale * p_scale
        J[n, :n] = hC / (length * w_scale) * p_scale
        return r, dt_column(residual, x, r, J)

    x = damped_newton(residual, np.append(p_guess / p_scale, 0.0))
    p, dt = unpack(x)
    t = t_old + dt
    t0 = np.where(new, t_old + new_frac * dt, t0_old)
    return FluidState(t=t, p=p, w=C @ p + cells.w_is, t0=t0, injected=schedule.volume(t),
                      leaked=leaked(t, t0, h, C_L), dt=dt, calls=calls)


def dt_column(residual, x: np.ndarray, r: np.ndarray, J: np.ndarray) -> np.ndarray:
    """J with its last column, the residual's derivative in log(dt), by a forward difference of DT_EPS (the tip
    speed, the leak-off and the schedule all move with the time step)."""
    x2 = x.copy()
    x2[-1] += DT_EPS
    J[:, -1] = (residual(x2) - r) / DT_EPS
    return J


def damped_newton(residual, x: np.ndarray) -> np.ndarray:
    """The root of an implicit step's scaled residual (`residual(x)`, `residual(x, True)` -> (r, J)) from x,
    the last unknown log(dt): Newton's method with the time step's change capped at MAX_LOG_DT_STEP and a
    backtracking line search on the residual's 2-norm; where the search stalls above the round-off level
    STALL_RTOL, a Levenberg-Marquardt minimum from there. StepError where neither meets STALL_RTOL."""
    n = len(x) - 1
    r, J = residual(x, True)
    norm = float(np.max(np.abs(r)))
    for _ in range(MAX_NEWTON):
        if norm <= STEP_RTOL:
            break
        try:
            dx = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            dx = np.linalg.lstsq(J, -r, rcond=None)[0]
        if abs(dx[n]) > MAX_LOG_DT_STEP:  # at most a factor e^2 on dt in one Newton step
            dx *= MAX_LOG_DT_STEP / abs(dx[n])
        lam, merit = 1.0, float(np.linalg.norm(r))
        while lam > 1e-4:  # backtracking on the residual's 2-norm
            x_try = x + lam * dx
            n_try = float(np.linalg.norm(residual(x_try)))
            if np.isfinite(n_try) and n_try < (1 - 1e-4 * lam) * merit:
                break
            lam *= 0.5
        else:
            break
        x = x_try
        r, J = residual(x, True)
        norm = float(np.max(np.abs(r)))
    if not norm <= STALL_RTOL:  # a local minimum of the 2-norm, or round-off: a trust region instead
        x = _levenberg_marquardt(residual, x)
        norm = float(np.max(np.abs(residual(x))))
    if not norm <= STALL_RTOL:
        raise StepError(f"the implicit step did not converge in {MAX_NEWTON} Newton steps (largest scaled residual {norm:.2e})")
    return x


def _levenberg_marquardt(residual, x):
    """The least-squares minimum of the residual from x (MINPACK's Levenberg-Marquardt with the
    analytic Jacobian), where Newton's line search stalls."""
    from scipy.optimize import least_squares

    fit = least_squares(lambda z: residual(z), x, jac=lambda z: residual(z, True)[1], method="lm",
                        xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=100 * len(x))
    return fit.x


def solve_step(cells: Cells, w_old: np.ndarray, t_old: float, t0_old: np.ndarray, new_frac: np.ndarray,
               schedule: Schedule, K_Ic: float, E_prime: float, mu: float, C_L: float,
               p_guess: np.ndarray | None = None, dt_guess: float | None = None, previous=None,
               p_old: np.ndarray | None = None) -> FluidState:
    """One implicit step (`_newton_step`) from the pressure of the last step's shape, else from a
    uniform one; where Newton fails from both (a first step far from the uniform pressure), a
    continuation in the viscosity: from CONTINUATION_DECADES decades below
    `mu`, where the pressure is nearly uniform, up to `mu`, each solve starting from the last."""
    args = (cells, w_old, t_old, t0_old, new_frac, schedule, K_Ic, E_prime)
    for start in ([p_guess] if p_guess is not None else []) + [None]:  # the last step's shape, then uniform
        try:
            return _newton_step(*args, mu, C_L, start, dt_guess, previous, p_old)
        except StepError as exc:
            error = exc
    if mu <= 0:
        raise error
    state = None
    for k in range(CONTINUATION_DECADES, -1, -1):
        m = mu * 10.0 ** (-k)
        state = _newton_step(*args, m, C_L, None if state is None else state.p, None, previous, p_old)
    return state
