"""KGD between its vertices: the universal tip asymptote and a global approximate solution.

**The universal tip asymptote** (Dontsov and Peirce 2015, "A non-singular integral equation
formulation to analyse multiscale behaviour in semi-infinite hydraulic fractures", JFM 781 R1;
no leak-off, their first-order "delta correction"): the opening at distance s behind a tip moving
at speed V, between the toughness asymptote w = K' s^(1/2) / E' and the viscosity one
w = beta_m (mu' V / E')^(1/3) s^(2/3),

    w = (K' s^(1/2) / E') (1 + 3 C1(delta) x)^(1/3),   x = (s / l_mk)^(1/2),  l_mk = (K'^3 / (E'^2 mu' V))^2,
    delta = (beta_m^3 / 3) x / (1 + beta_m^3 x),      C1(d) = 4 (1 - 2 d) tan(pi d) / (d (1 - d)),

C1 running from 4 pi at the toughness end (delta -> 0) to beta_m^3 / 3 = 6 sqrt(3) at the viscosity
end (delta = 1/3), so that it is exact at both vertices and within about 1% of the numerical
solution of the semi-infinite fracture between them (their estimate). The "sum of cubes"
(w_k^3 + w_m^3)^(1/3) is its zeroth order (C1 held at beta_m^3 / 3): up to 1.2% narrower in between.

**The global approximate solution** (after Dontsov 2017, "An approximate solution for a plane
strain hydraulic fracture that accounts for fracture toughness, fluid viscosity, and leak-off",
Int J Fract 205: the tip asymptote used over the whole crack with the global volume balance; the
construction here is this module's own, no leak-off): the opening of the KGD crack of half-length l
is the universal asymptote at the tip's speed V = dl/dt evaluated at the "elliptic distance"

    s(x) = (l^2 - x^2) / (2 l),

(the toughness asymptote at that distance is exactly the uniform-pressure crack's opening, so the
K-vertex is reproduced exactly), and l(t) meets the volume balance 2 int_0^l w dx = Q0 t with the
self-similar speed V = 2 l / (3 t) (K_m is constant in time for KGD at a constant rate, so the
solution is l = gamma(K_m) L_m(t)). At the M-vertex the shape (1 - x^2/l^2)^(2/3) holds a little
more than Adachi and Detournay's solution does (l 1.5% long, w0 4% low); the viscosity term's
scale is therefore calibrated by one constant (VISCOUS_CALIBRATION) so that l is exact at the
M-vertex too. The result is a smooth reference that reduces to both vertices' closed forms;
between them it is an approximation (not Garagash's numerical solution), whose own error is of
the order of the calibration it needed (1.5% in l at the M-vertex without it).
"""

from __future__ import annotations

import math

import numpy as np

from .flow import K_PRIME, L_M, W_M, c1, km_opening

#: Gauss-Legendre points of the volume integral (in u: x = l (1 - u^2), the tip's square root integrated exactly)
_GAUSS = np.polynomial.legendre.leggauss(64)
#: the viscosity term's scale (mu' multiplied by it in the global solution only) that makes its
#: M-vertex length Adachi and Detournay's 0.6152: found by `calibrate()` ((0.6249 / 0.6152)^6)
VISCOUS_CALIBRATION = 1.0987


def universal_opening(s, V: float, K_prime: float, E_prime: float, mu_prime: float):
    """The universal tip asymptote (module docstring) at distances s behind a tip moving at V."""
    return km_opening(s, V, K_prime, E_prime, mu_prime, universal=True)


def _volume(l: float, t: float, K_prime: float, E_prime: float, mu_prime: float) -> float:
    """2 int_0^l w dx of the global solution at half-length l and time t (x = l (1 - u^2))."""
    u, wts = _GAUSS
    u = 0.5 * (u + 1.0)
    x = l * (1.0 - u * u)
    s = (l * l - x * x) / (2.0 * l)
    w = universal_opening(s, 2.0 * l / (3.0 * t), K_prime, E_prime, mu_prime)
    return float(2.0 * np.sum(0.5 * wts * w * 2.0 * l * u))


def _balance(l, t, K_prime, E_prime, mu_prime, Q0) -> float:
    return _volume(l, t, K_prime, E_prime, mu_prime) - Q0 * t


def kgd_transition(t, E_prime: float, K_Ic: float, mu: float, Q0: float, calibration: float = VISCOUS_CALIBRATION):
    """(half-length l, opening at the injection point w0) of the KGD fracture at times t, for any K_m
    (the global approximate solution of the module docstring; mu = 0 is the K-vertex, K_Ic = 0 the
    M-vertex's length)."""
    from scipy.optimize import brentq

    K_prime = K_PRIME * K_Ic
    mu_prime = 12.0 * mu * calibration
    out_l, out_w = [], []
    for tt in np.atleast_1d(np.asarray(t, dtype=float)):
        if mu > 0:
            guess = L_M * (E_prime * Q0 ** 3 * tt ** 4 / (12.0 * mu)) ** (1 / 6)
        else:
            guess = (E_prime * Q0 * tt / (2.0 * math.sqrt(math.pi) * K_Ic)) ** (2 / 3)
        lo, hi = 1e-3 * guess, 1e3 * guess
        l = brentq(_balance, lo, hi, args=(tt, K_prime, E_prime, mu_prime, Q0), xtol=1e-14 * guess, rtol=1e-13)
        out_l.append(l)
        out_w.append(float(universal_opening(0.5 * l, 2.0 * l / (3.0 * tt), K_prime, E_prime, mu_prime)))
    if np.ndim(t) == 0:
        return out_l[0], out_w[0]
    return np.array(out_l), np.array(out_w)


def gamma(K_m: float, calibration: float = VISCOUS_CALIBRATION) -> tuple[float, float]:
    """(l / L_m, w0 / W_m) of the global solution at the dimensionless toughness K_m, L_m =
    (E' Q0^3 t^4 / mu')^(1/6), W_m = (mu' Q0^3 t^2 / E')^(1/6) (0.6152, 1.1265 at the M-vertex)."""
    E_prime, Q0, t, mu = 1.0, 1.0, 1.0, 1.0 / 12.0  # mu' = 1: the M scales are 1
    K_Ic = K_m / K_PRIME  # K_m = K' / (E'^3 mu' Q0)^(1/4) = K'
    return kgd_transition(t, E_prime, K_Ic, mu, Q0, calibration)


def calibrate() -> float:
    """The VISCOUS_CALIBRATION that makes the M-vertex length Adachi and Detournay's L_M."""
    # at K_m = 0 the length goes as calibration^(-1/6): one evaluation gives it
    l0 = gamma(0.0, 1.0)[0]
    return (l0 / L_M) ** 6


__all__ = ["VISCOUS_CALIBRATION", "W_M", "c1", "calibrate", "gamma", "kgd_transition", "universal_opening"]
