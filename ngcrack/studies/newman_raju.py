"""Newman and Raju's empirical stress-intensity factors of surface and corner cracks in plates in tension.

J. C. Newman Jr. and I. S. Raju, "An empirical stress-intensity factor equation for the surface
crack", Engineering Fracture Mechanics 15 (1981) 185-192; the corner crack's equation from their
NASA TM-83200 (1981), "Stress-intensity factor equations for cracks in three-dimensional finite
bodies". The equations were fitted to their own finite-element results (Raju and Newman 1979);
they state them generally within 5 percent of those results for 0.2 <= a/c <= 2 and a/t < 0.8
(`STATED_ACCURACY`). The formulas are written here from the published equations, for remote uniform
tension S (the bending terms are left out).

Notation: a the crack's depth, c its half-length on the surface, t the plate's thickness, b the
plate's half-width (its full width for the corner crack), phi the parametric angle of the ellipse
measured from the free surface (phi = 90 deg at the deepest point): a point of the front is
(c cos phi, a sin phi) from the crack's centre.

    K = S sqrt(pi a / Q) F(a/c, a/t, c/b, phi),   Q = 1 + 1.464 (a/c)^1.65  (a/c <= 1)

    >>> round(float(surface_crack_K(1.0, a=0.6, c=1.0, t=1.5, b=5.0, phi=math.pi / 2)), 3)
    1.26
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..core.errors import InputError

#: Newman and Raju's stated accuracy of their equations against their finite-element results (a fraction)
STATED_ACCURACY = 0.05
#: the window of distances behind a front point, in the crack's depth, over which `opening_K_I` fits the opening
OPENING_WINDOW = (0.1, 0.4)
#: the points sampled in that window
OPENING_SAMPLES = 31
#: the offset (in the depth) of the points on either face from the crack's plane where the opening is read
OPENING_OFFSET = 1e-4
#: the ranges of a/c and a/t their surface-crack equation covers for a/c <= 1 (a/t below 0.8 for the stated accuracy)
A_OVER_C_RANGE, A_OVER_T_RANGE = (0.0, 1.0), (0.0, 0.8)


def shape_factor(a_over_c: float) -> float:
    """Q: the square of the complete elliptic integral of the second kind, in their approximation (a/c <= 1)."""
    return 1.0 + 1.464 * a_over_c ** 1.65


def _f_phi(r: float, phi):
    return ((r * np.cos(phi)) ** 2 + np.sin(phi) ** 2) ** 0.25


def surface_crack_F(a_over_c: float, a_over_t: float, c_over_b: float, phi) -> np.ndarray:
    """The boundary-correction factor F of a semi-elliptical surface crack in tension (a/c <= 1)."""
    r, s = a_over_c, a_over_t
    if not 0.0 < r <= 1.0:
        raise ValueError(f"a/c = {r!r}: the equation used here covers 0 < a/c <= 1")
    m1 = 1.13 - 0.09 * r
    m2 = -0.54 + 0.89 / (0.2 + r)
    m3 = 0.5 - 1.0 / (0.65 + r) + 14.0 * (1.0 - r) ** 24
    g = 1.0 + (0.1 + 0.35 * s ** 2) * (1.0 - np.sin(phi)) ** 2
    f_w = 1.0 / math.sqrt(math.cos(0.5 * math.pi * c_over_b * math.sqrt(s)))
    return (m1 + m2 * s ** 2 + m3 * s ** 4) * _f_phi(r, np.asarray(phi, dtype=float)) * g * f_w


def surface_crack_K(S: float, a: float, c: float, t: float, b: float, phi) -> np.ndarray:
    """K_I of a semi-elliptical surface crack (depth a, half-length c) in a plate (thickness t, half-width b)
    under remote tension S, at the parametric angle(s) phi."""
    return S * math.sqrt(math.pi * a / shape_factor(a / c)) * surface_crack_F(a / c, a / t, c / b, phi)


def corner_crack_F(a_over_c: float, a_over_t: float, c_over_b: float, phi) -> np.ndarray:
    """The boundary-correction factor F of a quarter-elliptical corner crack in tension (a/c <= 1; b the
    plate's width)."""
    r, s = a_over_c, a_over_t
    if not 0.0 < r <= 1.0:
        raise ValueError(f"a/c = {r!r}: the equation used here covers 0 < a/c <= 1")
    phi = np.asarray(phi, dtype=float)
    m1 = 1.08 - 0.03 * r
    m2 = -0.44 + 1.06 / (0.3 + r)
    m3 = -0.5 + 0.25 * r + 14.8 * (1.0 - r) ** 15
    g1 = 1.0 + (0.08 + 0.4 * s ** 2) * (1.0 - np.sin(phi)) ** 3
    g2 = 1.0 + (0.08 + 0.15 * s ** 2) * (1.0 - np.cos(phi)) ** 3
    lam = c_over_b * math.sqrt(s)
    f_w = 1.0 - 0.2 * lam + 9.4 * lam ** 2 - 19.4 * lam ** 3 + 27.1 * lam ** 4
    return (m1 + m2 * s ** 2 + m3 * s ** 4) * g1 * g2 * _f_phi(r, phi) * f_w


def corner_crack_K(S: float, a: float, c: float, t: float, b: float, phi) -> np.ndarray:
    """K_I of a quarter-elliptical corner crack (depth a into the thickness t, length c along the width b)."""
    return S * math.sqrt(math.pi * a / shape_factor(a / c)) * corner_crack_F(a / c, a / t, c / b, phi)


# ---------------------------------------------------------------------------------- cracks at a hole
def bowie_F(a_over_r):
    """Bowie's boundary-correction factor F of one through crack of length a at a circular hole of radius r in an
    infinite plate under remote tension S normal to the crack: K = S sqrt(pi a) F (O. L. Bowie, J. Math. Phys. 35
    (1956) 60-71). Newman's fit to Bowie's values, as the Tada-Paris-Irwin handbook quotes it, in lambda =
    1 / (1 + a/r): F = 0.707 - 0.18 lambda + 6.55 lambda^2 - 10.54 lambda^3 + 6.85 lambda^4 (3.39 = 1.12 Kt at
    a = 0, 1.73 at a/r = 0.5, 1.37 at 1, 0.707 as a/r grows: the crack of length 2r + a without the hole).

    >>> round(float(bowie_F(0.5)), 3)
    1.728
    """
    lam = 1.0 / (1.0 + np.asarray(a_over_r, dtype=float))
    return 0.707 - 0.18 * lam + 6.55 * lam ** 2 - 10.54 * lam ** 3 + 6.85 * lam ** 4


def hole_corner_cracks_F(a_over_c: float, a_over_t: float, c_over_r: float, r_over_b: float, phi) -> np.ndarray:
    """The boundary-correction factor F of two symmetric quarter-elliptical corner cracks at a circular hole in a
    plate in tension (Newman and Raju, NASA TM-83200, 1981, and the 1986 chapter "Stress-intensity factor equations
    for cracks in three-dimensional finite bodies subjected to tension and bending loads"; a/c <= 1): a the depth
    along the bore, c the length along the plate's face, r the hole's radius, b the plate's half-width, phi the
    parametric angle from the plate's face (0) to the bore (pi/2):

        F = (M1 + M2 (a/t)^2 + M3 (a/t)^4) g1 g2 g3 f_phi f_w,   M1, M2, M3, f_phi as the surface crack's,
        g1 = 1 + (0.1 + 0.35 (a/t)^2) (1 - sin phi)^2,          lambda = 1 / (1 + (c/r) cos(0.85 phi)),
        g2 = (1 - 0.15 lambda + 3.46 lambda^2 - 4.47 lambda^3 + 3.52 lambda^4) / (1 + 0.13 lambda^2),
        g3 = (1 + 0.04 a/c) (1 + 0.1 (1 - cos phi)^2) (0.8 + 0.2 (a/t)^(1/4)),
        f_w = [sec(pi r / 2b) sec(pi (2r + 2c) / (4 (b - c) + 4c) sqrt(a/t))]^(1/2).

    g2 is Newman's fit to Bowie's two cracks at a hole in lambda; f_w the finite-width correction for n = 2 cracks
    (about 1.01 on a plate 24 hole radii wide). They state the equations generally within STATED_ACCURACY of their
    finite-element results."""
    r, s = a_over_c, a_over_t
    if not 0.0 < r <= 1.0:
        raise ValueError(f"a/c = {r!r}: the equation used here covers 0 < a/c <= 1")
    phi = np.asarray(phi, dtype=float)
    m1 = 1.13 - 0.09 * r
    m2 = -0.54 + 0.89 / (0.2 + r)
    m3 = 0.5 - 1.0 / (0.65 + r) + 14.0 * (1.0 - r) ** 24
    g1 = 1.0 + (0.1 + 0.35 * s ** 2) * (1.0 - np.sin(phi)) ** 2
    lam = 1.0 / (1.0 + c_over_r * np.cos(0.85 * phi))
    g2 = (1.0 - 0.15 * lam + 3.46 * lam ** 2 - 4.47 * lam ** 3 + 3.52 * lam ** 4) / (1.0 + 0.13 * lam ** 2)
    g3 = (1.0 + 0.04 * r) * (1.0 + 0.1 * (1.0 - np.cos(phi)) ** 2) * (0.8 + 0.2 * s ** 0.25)
    c_over_b, n = c_over_r * r_over_b, 2
    f_w = math.sqrt(1.0 / math.cos(0.5 * math.pi * r_over_b)
                    / math.cos(math.pi * (2 * r_over_b + n * c_over_b) / (4 * (1 - c_over_b) + 2 * n * c_over_b) * math.sqrt(s)))
    return (m1 + m2 * s ** 2 + m3 * s ** 4) * g1 * g2 * g3 * _f_phi(r, phi) * f_w


def hole_corner_cracks_K(S: float, a: float, c: float, t: float, radius: float, b: float, phi) -> np.ndarray:
    """K_I of each of two symmetric corner cracks (depth a along the bore, length c along the face) at a hole of
    radius `radius` in a plate of thickness t and half-width b under remote tension S (`hole_corner_cracks_F`)."""
    return S * math.sqrt(math.pi * a / shape_factor(a / c)) * hole_corner_cracks_F(a / c, a / t, c / radius, radius / b, phi)


# ---------------------------------------------------------------------------------- published tables
#: a/c of the published tables' columns (their a/c = 2 columns and ASME's a/c = 0 column are left out: the
#: equations here cover 0 < a/c <= 1, and for a > c their normalisation is not the one below)
TABLE_A_OVER_C = (0.2, 0.4, 0.6, 0.8, 1.0)
#: Shiratori's rows (a/t) and his columns, a subset of TABLE_A_OVER_C (he gives no a/c = 0.8)
SHIRATORI_A_OVER_T, SHIRATORI_A_OVER_C = (0.1, 0.2, 0.4, 0.6, 0.8), (0.2, 0.4, 0.6, 1.0)
#: ASME's rows (a/t)
ASME_A_OVER_T = (0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8)

#: The influence coefficient F0 of uniform stress (K = S sqrt(pi a / Q) F0, Q = `shape_factor`) of a
#: semi-elliptical surface crack in a flat plate, at the deepest point ("deepest", phi = 90 deg) and where the
#: front meets the surface ("surface", phi = 0), rows a/t and columns a/c as in the constants above. Numbers
#: only, as tabulated in the data files of the FFSeval package (S. Sakai, PyPI, version 1.4.1, MIT licence):
#:
#: - "shiratori": FFSeval/data/K-1-a-3.csv, tables 1 (F0 at the deepest point) and 5 (F0 at the surface);
#:   its citation: M. Shiratori, analysis of stress-intensity factors by the influence-function method,
#:   JSME course text "Surface cracks: their analysis and evaluation", No. 900-2 (1990) p. 1 (in Japanese),
#:   reproduced in the Japanese handbook of structural integrity assessment (Kyoritsu), solution K-1-a-3. Range
#:   stated there 0.1 <= a/t <= 0.8, 0.2 <= a/c <= 2; the method's accuracy is not stated in the data.
#: - "asme": FFSeval/data/K-1-a-2.csv, tables 1 and 5 (F0 at the deepest point and at the surface); its
#:   citation: ASME Boiler and Pressure Vessel Code, Section XI, Appendix A (2004), with R. C. Cipolla, ASME
#:   PVP vol. 313-1 (1995) p. 105 for the technical basis. Range 0 < a/t <= 0.8, 0 < a/c <= 1; accuracy not
#:   stated in the data. (Its a/c = 0 column, left out, is Tada's single-edge-cracked strip free to bend:
#:   11.99 at a/t = 0.8.)
#:
#: Neither table has a width: both are for wide plates (FFSeval calls them with a, c, t alone); `published_K`
#: applies Newman and Raju's finite-width factor f_w to compare with a plate of half-width b. At their common
#: points the two agree within 1.1% at the deepest point (0.2% at a/t = 0.8) and 2.6% at the surface, closer
#: than two independent analyses usually do: they are taken here as one family of results, not as two
#: confirmations. They give the deepest and surface points only; values along the front between them were not
#: found.
PUBLISHED_F0 = {
    "shiratori": {
        "deepest": ((1.119, 1.087, 1.069, 1.039),
                    (1.162, 1.119, 1.090, 1.047),
                    (1.371, 1.216, 1.143, 1.083),
                    (1.651, 1.327, 1.206, 1.106),
                    (1.787, 1.379, 1.228, 1.107)),
        "surface": ((0.512, 0.794, 0.933, 1.133),
                    (0.582, 0.810, 0.954, 1.145),
                    (0.688, 0.911, 1.025, 1.220),
                    (0.882, 1.060, 1.192, 1.318),
                    (1.201, 1.320, 1.366, 1.441)),
    },
    "asme": {
        "deepest": ((1.0949, 1.0856, 1.0727, 1.0564, 1.0366),
                    (1.1000, 1.0879, 1.0740, 1.0575, 1.0373),
                    (1.1152, 1.0947, 1.0779, 1.0609, 1.0396),
                    (1.1402, 1.1058, 1.0842, 1.0664, 1.0432),
                    (1.1744, 1.1210, 1.0928, 1.0739, 1.0482),
                    (1.2170, 1.1399, 1.1035, 1.0832, 1.0543),
                    (1.2670, 1.1621, 1.1160, 1.0940, 1.0614),
                    (1.3840, 1.2135, 1.1448, 1.1190, 1.0772),
                    (1.5128, 1.2693, 1.1757, 1.1457, 1.0931),
                    (1.6372, 1.3216, 1.2039, 1.1699, 1.1058),
                    (1.7373, 1.3610, 1.2237, 1.1868, 1.1112),
                    (1.7899, 1.3761, 1.2285, 1.1902, 1.1045)),
        "surface": ((0.5450, 0.7492, 0.9024, 1.0297, 1.1406),
                    (0.5514, 0.7549, 0.9070, 1.0330, 1.1427),
                    (0.5610, 0.7636, 0.9144, 1.0391, 1.1473),
                    (0.5738, 0.7756, 0.9249, 1.0479, 1.1545),
                    (0.5900, 0.7908, 0.9385, 1.0596, 1.1641),
                    (0.6099, 0.8095, 0.9551, 1.0740, 1.1763),
                    (0.6338, 0.8318, 0.9750, 1.0913, 1.1909),
                    (0.6949, 0.8881, 1.0250, 1.1347, 1.2278),
                    (0.7772, 0.9619, 1.0896, 1.1902, 1.2746),
                    (0.8859, 1.0560, 1.1701, 1.2585, 1.3315),
                    (1.0283, 1.1740, 1.2686, 1.3401, 1.3984),
                    (1.2144, 1.3208, 1.3871, 1.4361, 1.4753)),
    },
}
#: the grid (a/t rows, a/c columns) of each table
PUBLISHED_GRID = {"shiratori": (SHIRATORI_A_OVER_T, SHIRATORI_A_OVER_C), "asme": (ASME_A_OVER_T, TABLE_A_OVER_C)}
#: a ratio within this fraction of the grid's largest value outside the grid's ends is taken at the end
GRID_RTOL = 1e-9
#: the front points the tables give, as Newman and Raju's parametric angle
PUBLISHED_PHI = {"deepest": 0.5 * math.pi, "surface": 0.0}


def published_F(source: str, point: str, a_over_c: float, a_over_t: float) -> float:
    """The published F0 (wide plate) of `source` ("shiratori" or "asme") at `point` ("deepest" or "surface"):
    the tabulated value at a grid point, bilinear in (a/t, a/c) between them (no extrapolation).

    >>> published_F("shiratori", "deepest", 0.6, 0.8)
    1.228
    """
    if source not in PUBLISHED_F0:
        raise InputError(f"source = {source!r}: the published tables are {sorted(PUBLISHED_F0)}")
    if point not in PUBLISHED_PHI:
        raise InputError(f"point = {point!r}: the tables give {sorted(PUBLISHED_PHI)}")
    rows, cols = PUBLISHED_GRID[source]
    for name, value, grid in (("a/t", a_over_t, rows), ("a/c", a_over_c, cols)):
        tol = GRID_RTOL * grid[-1]  # a ratio computed from lengths (0.6 / 3 = 0.19999999999999998) is on the grid
        if isinstance(value, bool) or not (isinstance(value, numbers.Real) and grid[0] - tol <= value <= grid[-1] + tol):
            raise InputError(f"{name} = {value!r}: the {source} table covers {grid[0]} <= {name} <= {grid[-1]}")
    table = np.asarray(PUBLISHED_F0[source][point], dtype=float)
    along_c = np.array([np.interp(a_over_c, cols, row) for row in table])
    return float(np.interp(a_over_t, rows, along_c))


def published_K(source: str, point: str, S: float, a: float, c: float, t: float, b: float) -> float:
    """K_I from `published_F` in a plate of half-width b under remote tension S: S sqrt(pi a / Q) F0 f_w, with
    Newman and Raju's finite-width factor f_w = [sec(pi c / 2b sqrt(a/t))]^(1/2) (the tables are for wide
    plates; f_w is 1.02 at c/b = 0.2, a/t = 0.8)."""
    f_w = 1.0 / math.sqrt(math.cos(0.5 * math.pi * (c / b) * math.sqrt(a / t)))
    return S * math.sqrt(math.pi * a / shape_factor(a / c)) * published_F(source, point, a / c, a / t) * f_w


# ---------------------------------------------------------------------------------- an independent check
def opening_K_I(sol, point, inward, depth: float, crack: int = 0, window=OPENING_WINDOW,
                samples: int = OPENING_SAMPLES) -> float:
    """K_I at a front point from the crack's opening behind it, independent of the domain integral.

    The opening delta(r) at the distance r behind the front (along `inward`, in the crack's plane) is read from
    the displacement on either face (OPENING_OFFSET depth off the plane); near a straight front in plane strain
    delta = (8 / E') K_I sqrt(r / 2 pi), so K(r) = E' delta sqrt(2 pi / r) / 8 tends to K_I as r -> 0. K(r) is
    fitted by a straight line over r in `window` (fractions of `depth`: past the elements at the front, whose
    polynomials do not follow sqrt(r), within the part where K(r) is linear in r) and its value at r = 0
    returned. A check, not the reported K: it rests on the sampled faces' displacements alone (on the
    built-in surface crack and a/c = 1, a/t = 0.8 it agrees with the domain integral within 1-2% at order 2).
    `sol` a 3D solution (``sol.fields["u"]``, ``sol.smesh.mesh``, ``sol.scene.material``, the normal of
    ``sol.scene.cracks[crack]``)."""
    E, nu = sol.scene.material.E, sol.scene.material.nu
    e_prime = E / (1.0 - nu * nu)
    n = np.asarray(sol.scene.cracks[crack].normal, dtype=float)
    inward = np.asarray(inward, dtype=float) / np.linalg.norm(inward)
    r = depth * np.linspace(window[0], window[1], samples)
    p = np.asarray(point, dtype=float) + np.outer(r, inward)
    mesh, u = sol.smesh.mesh, sol.fields["u"]

    def normal_u(q):
        return np.asarray(u(mesh(q[:, 0], q[:, 1], q[:, 2]))) @ n

    eps = OPENING_OFFSET * depth
    delta = normal_u(p + eps * n) - normal_u(p - eps * n)
    k_r = e_prime * delta * np.sqrt(2.0 * np.pi / r) / 8.0
    return float(np.polyfit(r, k_r, 1)[-1])


#: `front_opening_K_I`'s window ends at most this fraction of the station's reach behind it (the distance inwards to
#: the crack's medial axis: on a surface crack the free face, near its ends)
OPENING_REACH_FRACTION = 0.8


def front_opening_K_I(sol, crack: int = 0, window=OPENING_WINDOW) -> np.ndarray:
    """`opening_K_I` at every station of a disc's or an ellipse's front (``sol.fronts``), read along the station's
    in-plane normal behind it over `window` fractions of the crack's smaller semi-axis, the window's far end at most
    OPENING_REACH_FRACTION of the station's reach (NaN where the window closes)."""
    c = sol.scene.cracks[crack]
    a, b = c.semi_axes
    front = next(f for f in sol.fronts if f.crack == crack)
    phi = np.asarray(front.angle, dtype=float)  # the ellipse's angle (the fronts' `angle` of a disc or an ellipse)
    tangent = np.multiply.outer(-a * np.sin(phi), c.e_a) + np.multiply.outer(b * np.cos(phi), c.e_b)
    e1 = np.cross(tangent, c.normal)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)  # outward, in the crack's plane
    reach = b / a * np.hypot(a * np.sin(phi), b * np.cos(phi))  # to the medial axis (`solid.front.FrontGeometry.reach`)
    ell = min(a, b)
    far = np.minimum(window[1] * ell, OPENING_REACH_FRACTION * reach)
    out = np.full(len(front.angle), np.nan)
    for k, p in enumerate(front.points):
        lo = window[0] * ell
        if far[k] > 1.5 * lo:
            out[k] = opening_K_I(sol, p, -e1[k], 1.0, crack, (lo, far[k]))
    return out
