"""Kink criteria of quasi-static crack growth: pure functions of the stress intensity factors.

Frame and signs. The angles are measured in the tip frame of ngcrack.planar.tips: e1 the unit
tangent of the tip segment pointing out of the crack, e2 = e1 turned by +90 degrees, so
a positive kink angle turns the crack counter-clockwise (towards e2). K_I > 0 opens the
faces; K_II > 0 is the shear sigma_12 > 0 ahead of the tip in that frame. With K_II > 0
the crack kinks clockwise (theta < 0), with K_II < 0 counter-clockwise.

Maximum tangential stress (Erdogan and Sih 1963, `mts`). The hoop stress of the
singular field, sigma_tt ~ cos(theta/2) [K_I cos^2(theta/2) - 3/2 K_II sin(theta)] /
sqrt(2 pi r), is largest at

    theta = 2 atan((K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II))
          = -2 atan(2 K_II / (K_I + sqrt(K_I^2 + 8 K_II^2)))        (the form used: no 0/0 at K_II = 0)

and the crack grows when K_eq = cos^3(theta/2) K_I - 3/2 cos(theta/2) sin(theta) K_II
reaches the toughness K_Ic. Pure mode I: theta = 0, K_eq = K_I. Pure mode II:
theta = -sign(K_II) 2 atan(1/sqrt 2) = -sign(K_II) 70.53 degrees, K_eq = (2/sqrt 3) |K_II|.
Where the faces at the tip are closed the crack cannot open there: K_I is taken as 0
(`effective_K_I`), a closed sliding crack kinks at the pure mode II angle.

Principle of local symmetry (Goldstein and Salganik 1974, `pls`): the kink is the one
that makes K_II vanish at the new tip. It has no closed form for a finite extension;
ngcrack.studies.growth.loop finds it by trial extensions, solving for K_II at the new tip and
taking secant steps in the angle (`secant_angle`). To first order in the kink angle both
criteria agree (Cotterell and Rice 1980: k_2(theta) ~ K_II + theta K_I / 2 at the tip of
a small kink, zero at theta ~ -2 K_II / K_I, MTS's small-angle limit).

Kinked-crack relations (`kink_factors`, `kinked_K`, `pls_kink_angle`). The stress
intensity factors k_1, k_2 at the tip of an infinitesimal straight kink of angle theta
are linear in the parent tip's K: k_p(theta) = F_p1(theta) K_I + F_p2(theta) K_II. To
first order (Cotterell and Rice 1980) F is the singular field's stresses in the
direction theta, sqrt(2 pi r) (sigma_tt, sigma_rt):

    k_1 = cos(theta/2) [K_I cos^2(theta/2) - 3/2 K_II sin(theta)]
    k_2 = 1/2 cos(theta/2) [K_I sin(theta) + K_II (3 cos(theta) - 1)]

(`cotterell_rice`), whose k_2 = 0 is exactly the MTS angle. The exact F of Amestoy and
Leblond (1992) differ at second order; `kink_factors` uses their series in m = theta/pi
truncated after m^6 (F_11, F_22 even, F_12, F_21 odd), within about 1 degree of their
exact PLS angles up to the pure mode II angle (77.3 degrees exact, 76.7 from the series).
The kink of a finite segment da also feels the T-stress and the field's gradients; the
loop checks the predicted angle by a solve of the grown scene.

Generalized maximum tangential stress (`gmts`; Williams and Ewing 1972, Smith, Ayatollahi
and Pavier 2001): the hoop stress with the T-stress, taken at a critical distance r_c
(a material length) instead of its singular limit,

    sqrt(2 pi r_c) sigma_tt(r_c, theta) = cos(theta/2) [K_I cos^2(theta/2) - 3/2 K_II sin(theta)]
                                          + sqrt(2 pi r_c) T sin^2(theta),

is largest at the kink angle (`gmts_angle`, a global search refined by Brent's method), and
its value there is the K_eq that the toughness K_Ic is set against (`gmts_keq`). T = 0 gives
MTS. In pure mode I the straight path stays a maximum while T < 3 K_I / (8 sqrt(2 pi r_c));
above, the two kinks +-theta with cos(theta) / cos(theta/2) = 3 K_I / (8 sqrt(2 pi r_c) T)
take over (the straight path turns unstable; with K_II = 0 exactly the counter-clockwise
one is returned, otherwise the one MTS would take).
"""

from __future__ import annotations

import math

from ...core.errors import InputError

#: the kink criteria
CRITERIA = ("mts", "pls", "gmts")


def check_criterion(criterion) -> str:
    if criterion not in CRITERIA:
        raise InputError(f"criterion = {criterion!r}: allowed values are {', '.join(CRITERIA)}")
    return criterion


def effective_K_I(K_I: float, closed: bool) -> float:
    """K_I as the criteria use it: 0 where the faces at the tip are closed (they touch and
    cannot open there), else K_I; a negative K_I (interpenetration, which contact rules out)
    counts as 0 too."""
    return 0.0 if closed else max(float(K_I), 0.0)


def mts_angle(K_I: float, K_II: float) -> float:
    """The maximum tangential stress kink angle theta in radians (tip frame, counter-clockwise
    positive), in [-70.53, 70.53] degrees for K_I >= 0. K_I = K_II = 0: 0 (no direction)."""
    K_I, K_II = float(K_I), float(K_II)
    root = math.sqrt(K_I * K_I + 8.0 * K_II * K_II)
    den = K_I + root
    if den <= 0.0:  # K_II = 0 and K_I <= 0: no driving force, no kink
        return 0.0
    return -2.0 * math.atan(2.0 * K_II / den)


def hoop_factor(theta: float, K_I: float, K_II: float) -> float:
    """sqrt(2 pi r) sigma_thetatheta of the singular field in the direction theta:
    cos(theta/2) [K_I cos^2(theta/2) - 3/2 K_II sin(theta)]."""
    c = math.cos(0.5 * theta)
    return c * (K_I * c * c - 1.5 * K_II * math.sin(theta))


def mts_keq(K_I: float, K_II: float, theta: float | None = None) -> float:
    """K_eq = cos^3(theta/2) K_I - 3/2 cos(theta/2) sin(theta) K_II at theta (default: the MTS angle)."""
    if theta is None:
        theta = mts_angle(K_I, K_II)
    return hoop_factor(theta, K_I, K_II)


def load_factor(K_Ic: float, K_eq: float) -> float:
    """lambda = K_Ic / K_eq: the load factor at which the tip grows (inf where K_eq <= 0).

    The static problem with unilateral contact and Coulomb friction under one proportional
    load is positively homogeneous of degree one in the load, so K scales with lambda.
    """
    return float(K_Ic) / float(K_eq) if K_eq > 0 else math.inf


def secant_angle(theta0: float, g0: float, theta1: float, g1: float, limit: float) -> float:
    """The secant step for g(theta) = 0 from (theta0, g0), (theta1, g1), the step kept within
    +-limit of theta1 (a flat secant would jump far)."""
    if g1 == g0 or theta1 == theta0:
        return theta1
    step = -g1 * (theta1 - theta0) / (g1 - g0)
    return theta1 + max(-limit, min(limit, step))


#: dk_2/dtheta at the tip of a grown segment of length da, in units of its K_I: measured
#: 1.46 to 1.60 on wing cracks (da = a/10; three times the small-kink value 1/2)
PLS_SLOPE = 1.5


def newton_angle(theta: float, K_II_new: float, K_I_new: float, limit: float, slope: float = PLS_SLOPE) -> float:
    """A PLS correction from one trial: theta - K_II / (slope K_I) at the trial tip, kept
    within +-limit; K_I <= 0 leaves theta."""
    if K_I_new <= 0:
        return theta
    step = -K_II_new / (slope * K_I_new)
    return theta + max(-limit, min(limit, step))


#: a previous kink larger than this (radians) is a kink, not the curvature of a smooth path:
#: the next step's first trial does not carry it over (the K at the tip says where to go)
PLS_CARRY_MAX = math.radians(10.0)


def pls_predictor(K_I: float, K_II: float, previous: float | None, slope: float | None = None) -> float:
    """The first trial angle of a PLS step. At a tip's first kink (previous None), where its
    faces are closed, or where its previous kink was larger than PLS_CARRY_MAX: the PLS angle
    of the kinked-crack relations for its K (`pls_kink_angle`). At a grown tip on a smooth
    path: its previous kink (the path's curvature carried on) corrected by
    -K_II / slope for the K_II left at its tip (slope: dk_2/dtheta measured at the tip's last
    step, default PLS_SLOPE K_I)."""
    if previous is None or K_I <= 0 or abs(float(previous)) > PLS_CARRY_MAX:
        return pls_kink_angle(K_I, K_II)
    slope = PLS_SLOPE * float(K_I) if slope is None or slope <= 0 else float(slope)
    return float(previous) - float(K_II) / slope


# ---------------------------------------------------------------------- kinked-crack relations
def cotterell_rice(theta: float) -> tuple[float, float, float, float]:
    """First-order kinked-crack factors (F_11, F_12, F_21, F_22) at theta (radians): the
    singular field's sqrt(2 pi r) sigma_tt and sigma_rt in the direction theta per unit K_I, K_II."""
    c, s = math.cos(0.5 * theta), math.sin(theta)
    return c ** 3, -1.5 * c * s, 0.5 * c * s, 0.5 * c * (3.0 * math.cos(theta) - 1.0)


def kink_factors(theta: float) -> tuple[float, float, float, float]:
    """Amestoy-Leblond kinked-crack factors (F_11, F_12, F_21, F_22) at theta (radians, |theta| < pi/2
    where the series holds): k_1 = F_11 K_I + F_12 K_II, k_2 = F_21 K_I + F_22 K_II at the tip of
    an infinitesimal kink. Their series in m = theta / pi, truncated after m^6."""
    m = float(theta) / math.pi
    p2, p4, p6 = math.pi ** 2, math.pi ** 4, math.pi ** 6
    f11 = 1 - 3 * p2 / 8 * m ** 2 + (p2 - 5 * p4 / 128) * m ** 4 + (p2 / 9 - 11 * p4 / 72 + 119 * p6 / 15360) * m ** 6
    f12 = math.pi * (-1.5 * m + (10 / 3 + p2 / 16) * m ** 3 + (-2 - 133 * p2 / 180 + 59 * p4 / 1280) * m ** 5)
    f21 = math.pi * (0.5 * m - (4 / 3 + p2 / 48) * m ** 3 + (-2 / 3 + 13 * p2 / 30 - 59 * p4 / 3840) * m ** 5)
    f22 = (1 - (4 + 3 * p2 / 8) * m ** 2 + (8 / 3 + 29 * p2 / 18 - 5 * p4 / 128) * m ** 4
           + (-32 / 15 - 4 * p2 / 9 - 1159 * p4 / 7200 + 119 * p6 / 15360) * m ** 6)
    return f11, f12, f21, f22


def kinked_K(K_I: float, K_II: float, theta: float) -> tuple[float, float]:
    """(k_1, k_2) at the tip of an infinitesimal kink of angle theta (Amestoy-Leblond)."""
    f11, f12, f21, f22 = kink_factors(theta)
    return f11 * K_I + f12 * K_II, f21 * K_I + f22 * K_II


def pls_kink_angle(K_I: float, K_II: float) -> float:
    """The kink angle (radians) with k_2 = 0 at the tip of an infinitesimal kink (Amestoy-Leblond),
    the one with k_1 > 0, between 0 and the pure mode II angle; K_II = 0: 0. Bisection on
    k_2(theta), monotone on that interval for K_I >= 0."""
    K_I, K_II = max(float(K_I), 0.0), float(K_II)
    if K_II == 0.0:
        return 0.0
    sign = -1.0 if K_II > 0 else 1.0  # K_II > 0 kinks clockwise
    lo, hi = 0.0, sign * math.radians(85.0)

    def k2(t):
        return kinked_K(K_I, K_II, t)[1]

    g_lo = k2(lo)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        g = k2(mid)
        if (g > 0) == (g_lo > 0):
            lo, g_lo = mid, g
        else:
            hi = mid
    return 0.5 * (lo + hi)


# ------------------------------------------------------------------ generalized MTS
#: samples of the kink angle in (-pi, pi) of the global search, before Brent's refinement
GMTS_SAMPLES = 721
#: the search stays this far (radians) inside +-pi, the crack faces
GMTS_EDGE = 1e-6
#: Newton steps on the hoop stress's slope after Brent's refinement
GMTS_NEWTON = 4


def check_r_c(r_c, criterion: str) -> float | None:
    """The critical distance of `gmts`: a finite number > 0, required by gmts and refused by the others."""
    if criterion != "gmts":
        if r_c is not None:
            raise InputError(f"r_c = {r_c!r}: only criterion = 'gmts' uses a critical distance; remove it or "
                             f"choose gmts")
        return None
    if isinstance(r_c, bool) or not isinstance(r_c, (int, float)) or not math.isfinite(r_c) or r_c <= 0:
        raise InputError(f"r_c = {r_c!r}: criterion = 'gmts' needs the critical distance r_c, a finite number > 0 "
                         f"(a material length, in the scene's units)")
    return float(r_c)


def gmts_hoop(theta: float, K_I: float, K_II: float, T: float, r_c: float) -> float:
    """sqrt(2 pi r_c) sigma_thetatheta(r_c, theta): the singular hoop stress plus T sin^2(theta)."""
    return hoop_factor(theta, K_I, K_II) + math.sqrt(2.0 * math.pi * r_c) * T * math.sin(theta) ** 2


def gmts_angle(K_I: float, K_II: float, T: float, r_c: float) -> float:
    """The generalized MTS kink angle in radians (tip frame, counter-clockwise positive):
    the theta in (-pi, pi) where `gmts_hoop` is largest. No driving stress (K_I = K_II = 0 and
    T <= 0): 0."""
    import numpy as np
    from scipy.optimize import minimize_scalar

    K_I, K_II, T, r_c = float(K_I), float(K_II), float(T), float(r_c)
    if K_I == 0.0 and K_II == 0.0 and T <= 0.0:
        return 0.0
    grid = np.linspace(-math.pi + GMTS_EDGE, math.pi - GMTS_EDGE, GMTS_SAMPLES)
    A = math.sqrt(2.0 * math.pi * r_c)
    c = np.cos(0.5 * grid)
    values = c * (K_I * c * c - 1.5 * K_II * np.sin(grid)) + A * T * np.sin(grid) ** 2
    k = int(np.argmax(values))
    step = grid[1] - grid[0]
    lo, hi = max(grid[0], grid[k] - step), min(grid[-1], grid[k] + step)
    res = minimize_scalar(lambda t: -gmts_hoop(t, K_I, K_II, T, r_c), bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-12})
    theta = float(res.x) if -res.fun >= values[k] else float(grid[k])
    for _ in range(GMTS_NEWTON):  # Brent's maximum is good to sqrt(eps); Newton on the slope to round-off
        d1, d2 = _gmts_slopes(theta, K_I, K_II, A * T)
        if d2 >= 0.0:
            break
        new = theta - d1 / d2
        if not lo <= new <= hi:
            break
        theta = new
    if K_II == 0.0:  # symmetric: +-theta are equal maxima; the counter-clockwise one
        theta = abs(theta)
    return theta


def _gmts_slopes(theta: float, K_I: float, K_II: float, AT: float) -> tuple[float, float]:
    """The first and second derivatives of `gmts_hoop` in theta (AT = sqrt(2 pi r_c) T)."""
    c, s = math.cos(0.5 * theta), math.sin(0.5 * theta)
    st, ct = math.sin(theta), math.cos(theta)
    d1 = -1.5 * K_I * c * c * s - 1.5 * K_II * (-0.5 * s * st + c * ct) + AT * 2.0 * st * ct
    d2 = -1.5 * K_I * (0.5 * c ** 3 - c * s * s) - 1.5 * K_II * (-1.25 * c * st - s * ct) + 2.0 * AT * math.cos(2.0 * theta)
    return d1, d2


def gmts_keq(K_I: float, K_II: float, T: float, r_c: float, theta: float | None = None) -> float:
    """K_eq = sqrt(2 pi r_c) sigma_tt(r_c, theta) at theta (default: the GMTS angle); the tip grows
    when it reaches K_Ic (sigma_tt(r_c) reaches the material's K_Ic / sqrt(2 pi r_c))."""
    if theta is None:
        theta = gmts_angle(K_I, K_II, T, r_c)
    return gmts_hoop(theta, K_I, K_II, T, r_c)
