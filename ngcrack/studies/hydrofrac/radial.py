"""Radial (penny-shaped) hydraulic fractures in 3D: a disc crack fed at its centre, toughness-dominated.

A disc crack of a 3D scene (a penny in a box; the scene's loads are the in-situ stress) is
fed at its centre at the rate Q0 (or a schedule). The fluid is inviscid (its pressure p is
uniform in the crack: the toughness-dominated limit, the K-vertex of Savitski and
Detournay 2002) and incompressible; with leak-off (Carter, C_L) the injected volume is the
crack's plus what leaked through its faces. Each step, on a disc of radius R:

1. the pressure at propagation: the p at which the front's mean K_I reaches K_Ic (K_I taken
   as 0 where the faces at a front point touch). Without other loads the problem, contact
   included, is positively homogeneous in p: one solve, scaled. With an in-situ stress,
   solves at p = 0 and a trial p, then secants (exact while the front is open: the response
   is affine there) inside a regula falsi bracket where contact makes it nonlinear;
2. the volume V (the integral of the solve's normal jump over the crack's faces), the time
   at which the schedule has injected V plus the leaked volume, the opening at the centre;
3. the front points at propagation (K_I within RADIAL_ADVANCE_RTOL of K_Ic) advance. The
   crack is kept a disc: the radius grows by da where every front point is at propagation
   (a radially symmetric case: all of them are, to the front integral's scatter); where some
   are not (a stress gradient, a free face nearby) the run stops and says so: a non-circular
   front is the business of general 3D front growth, not of this model.

The mesh sizes at the crack (crack_h, front_h) scale with R (the first step's, resolved from the
options, the scene and the defaults): every step is the same problem at the same relative
resolution, and costs about the same. The body's maxh stays.

Closed forms (an infinite body; Sneddon's penny under a uniform pressure p):
V = 16 p R^3 / (3 E'), K_I = 2 p (R / pi)^(1/2), w(0) = 8 p R / (pi E'), E' = E / (1 - nu^2).
At propagation p = K_Ic (pi / R)^(1/2) / 2 and V = 8 pi^(1/2) K_Ic R^(5/2) / (3 E'), so
with V = Q0 t: R = (3 E' Q0 t / (8 pi^(1/2) K_Ic))^(2/5) = 0.8546 (E' Q0 t / K')^(2/5),
K' = 4 (2 / pi)^(1/2) K_Ic (Savitski-Detournay's K-vertex). With leak-off dominating (no
storage), Q0 t = 4 C_L int sqrt(t - t0(r)) dA over the disc, t0(r) = t (r / R)^4, gives
R = (Q0^2 t / C_L^2)^(1/4) / pi (their leak-off vertex, C' = 2 C_L).
"""

from __future__ import annotations

import math
import time

import numpy as np

from ...core.errors import InputError
from ...core.fields import SceneError
from ...core.pipeline import Pipeline, SolveError
from .propagation import pressure_at_propagation

#: a front point is at propagation when its K_I is at least (1 - RADIAL_ADVANCE_RTOL) K_Ic, the
#: front's mean being at K_Ic: the order-1 front integral scatters from point to point, by about 1%
#: on the default penny mesh (K_I within -1.8% and +0.2% of Sneddon's, BENCHMARKS) and by 3.3% on a
#: coarse one (front_h = 0.4 R, measured), so a front within 5% is uniformly at propagation
RADIAL_ADVANCE_RTOL = 0.05
#: the mean K_I at the pressure found is within this fraction of K_Ic
RADIAL_KIC_RTOL = 1e-6
#: the most solves of one step's pressure search
RADIAL_MAX_SEARCH = 16
#: R of the K-vertex: R = R_K (E' Q0 t / K')^(2/5), (3 sqrt(2) / (2 pi))^(2/5) (module docstring)
R_K = (3.0 * math.sqrt(2.0) / (2.0 * math.pi)) ** 0.4
#: Savitski-Detournay's regimes of the radial fracture in the dimensionless toughness
#: K = K' (t^2 / (mu'^5 Q0^3 E'^13))^(1/18): near the K-vertex above K_RADIAL_TOUGHNESS, near the
#: M-vertex below K_RADIAL_VISCOUS
K_RADIAL_TOUGHNESS, K_RADIAL_VISCOUS = 3.5, 1.0
#: the first state is taken as grown from the injection point at the K-vertex's R ~ t^(2/5) (the
#: arrival times behind it, for leak-off): t0(r) = t1 (r / R1)^(1 / FIRST_GROWTH_EXPONENT)
FIRST_GROWTH_EXPONENT = 0.4
#: Gauss points per ring of the leak-off integral over the disc
LEAKOFF_GAUSS = 48
#: samples of the opening along a radius in the step's profile
PROFILE_POINTS = 24
#: da at least this fraction of the front mesh size (as the 2D loop's tip fraction)
MIN_DA_FRONT_FRACTION = 0.25
#: at most this fraction of the body's diameter
MAX_DA_BODY_FRACTION = 0.5
#: the largest strain scale of the pressure at propagation, p / E' (small strains)
MAX_STRAIN = 0.1


# ------------------------------------------------------------------------------ closed forms
def k_vertex_radial(t, E_prime: float, K_Ic: float, Q0: float):
    """(radius, pressure, opening at the centre) of the radial K-vertex (uniform pressure) at time t."""
    t = np.asarray(t, dtype=float)
    R = (3.0 * E_prime * Q0 * t / (8.0 * math.sqrt(math.pi) * K_Ic)) ** 0.4
    p = 0.5 * K_Ic * np.sqrt(math.pi / R)
    return R, p, 8.0 * p * R / (math.pi * E_prime)


def sneddon_penny(p: float, R: float, E_prime: float) -> dict:
    """Sneddon's penny of radius R under the uniform pressure p: volume, K_I, centre opening."""
    return {"volume": 16.0 * p * R ** 3 / (3.0 * E_prime), "K_I": 2.0 * p * math.sqrt(R / math.pi),
            "opening": 8.0 * p * R / (math.pi * E_prime)}


def carter_radius(t, Q0: float, C_L: float):
    """The storage-free (leak-off-dominated) radius (Q0^2 t / C_L^2)^(1/4) / pi."""
    return (Q0 ** 2 * np.asarray(t, dtype=float) / C_L ** 2) ** 0.25 / math.pi


def k_m_radial(t: float, K_Ic: float, E_prime: float, mu: float, Q0: float) -> float:
    """Savitski-Detournay's dimensionless toughness of the radial fracture at time t (it grows as t^(1/9))."""
    from .flow import k_prime

    return k_prime(K_Ic) * (t ** 2 / ((12.0 * mu) ** 5 * Q0 ** 3 * E_prime ** 13)) ** (1.0 / 18.0)


def e_prime_3d(scene) -> float:
    mat = scene.material
    return mat.E / (1.0 - mat.nu ** 2)


# ------------------------------------------------------------------------------ the checks
def check_radial_options(scene, rate, K_Ic, da, steps, crack, injection, solve_options, progress=None) -> None:
    """Refuse bad input of a radial fracture before any meshing, naming the field and what is allowed."""
    from ...core.fields import is_number
    from .loop import _RESERVED, CRACK_MODELS, check_common_options

    check_common_options(scene, rate, K_Ic, steps, crack, "a volume per unit time")
    if scene.cracks[crack].shape != "disc":
        raise InputError(f"crack = {crack}: a {scene.cracks[crack].shape}; a radial fracture (3D) grows a disc crack "
                         "(shape = \"disc\")")
    if injection is not None:
        raise InputError(f"injection = {injection!r}: a radial fracture (3D) is fed at its disc's centre; leave "
                         "injection out")
    bad = [k for k in _RESERVED if k in solve_options]
    if bad:
        raise InputError(f"{bad[0]}: hydrofrac sets it for every step itself; give the scene and the mesh options only")
    model = solve_options.get("crack_model", "contact")
    if model not in CRACK_MODELS:
        raise InputError(f"crack_model = {model!r}: allowed values are {', '.join(CRACK_MODELS)} (a fluid cannot open "
                         "a bonded crack)")
    R = scene.cracks[crack].radius
    strain = 0.5 * K_Ic * math.sqrt(math.pi / R) / e_prime_3d(scene)
    if strain > MAX_STRAIN:
        raise InputError(f"K_Ic = {K_Ic!r}: the pressure at propagation would be {strain:.3g} E' (K_Ic (pi / R)^(1/2) "
                         f"/ 2, R the radius); at most {MAX_STRAIN:g} E' keeps the strains small")
    sizes = {k: solve_options.get(k) for k in ("maxh", "crack_h", "front_h")}
    front_h = None
    if all(v is None or (is_number(v) and v > 0) for v in sizes.values()):
        front_h = scene.mesh_sizes(**sizes)["front_h"]
    low = MIN_DA_FRONT_FRACTION * front_h if front_h else 0.0
    limit = MAX_DA_BODY_FRACTION * scene.diameter
    if not (is_number(da) and math.isfinite(da) and da > 0 and low <= da <= limit):
        raise InputError(f"da = {da!r}: must be a number in [{low:.4g}, {limit:.4g}] (at least {MIN_DA_FRONT_FRACTION:g} "
                         f"of the front mesh size {front_h or 0:.4g}, at most {MAX_DA_BODY_FRACTION:g} of the body's "
                         f"diameter {scene.diameter:.4g})")
    if progress is not None and not callable(progress):
        raise InputError(f"progress = {progress!r}: must be None or a callable progress(step, result)")


# ------------------------------------------------------------------------------ the disc
def disc_scene(scene, crack: int, radius: float, pressure: float):
    """The scene with crack `crack` a disc of `radius` under the uniform `pressure` (validated: a
    SceneError where it would reach the boundary or another crack)."""
    d = scene.to_dict()
    d["crack"][crack]["radius"] = float(radius)
    d["crack"][crack]["pressure"] = float(pressure)
    return type(scene).from_dict(d)


def grown_disc(scene, crack: int, R: float, da: float):
    """(scene, radius, None) with crack `crack` a disc of radius R + da, or (scene, R, the reason) where it does
    not fit the body: the growth step of the radial loops."""
    try:
        return disc_scene(scene, crack, R + da, 0.0), R + da, None
    except SceneError as exc:
        return scene, R, f"boundary: the disc of radius {R + da:.6g} does not fit the body ({exc})"


def scaled_options(options, sizes: dict, R0: float, R: float):
    """The solve options with the crack's mesh sizes scaled by R / R0 (the body's maxh kept)."""
    f = R / R0
    return options.replace(maxh=sizes["maxh"], crack_h=min(sizes["crack_h"] * f, sizes["maxh"]),
                           front_h=min(sizes["front_h"] * f, sizes["maxh"]), grading=sizes["grading"])


def front_of(sol, crack: int):
    for f in sol.fronts:
        if f.crack == crack:
            return f
    raise SolveError(f"the solve gave no front for crack {crack}")


def opening_along(sol, crack: int, radii) -> np.ndarray:
    """The normal jump at distances `radii` from the disc's centre along its in-plane axis e_a."""
    import ngsolve as ngs

    c = sol.scene.cracks[crack]
    mesh = sol.smesh.mesh
    jn = sol.gf.components[sol.disc.jn]
    out = []
    for r in radii:
        x = c.center + r * c.e_a
        out.append(float(np.asarray(jn(mesh(float(x[0]), float(x[1]), float(x[2]), ngs.BND))).ravel()[0]))
    return np.array(out)


# ------------------------------------------------------------------------------ one step
def _drive(sol, crack: int) -> float:
    """The front's mean K_I (0 where the faces at a front point touch)."""
    f = front_of(sol, crack)
    return float(np.mean(np.where(f.closed, 0.0, f.K_I)))


def propagation_radial(scene, crack: int, R: float, K_Ic: float, pipe: Pipeline, options, in_situ: bool):
    """(solution, pressure, factor, solves): the state at which the front's mean K_I is K_Ic; the state is
    `factor` times `solution` (factor 1 unless the problem is homogeneous in p: no other load, one solve scaled)."""
    from ...core.solve import solve

    p_ref = 0.5 * K_Ic * math.sqrt(math.pi / R)  # Sneddon's pressure at propagation
    if not in_situ:
        sol = solve(disc_scene(scene, crack, R, p_ref), options=options, pipeline=pipe)
        k = _drive(sol, crack)
        if not k > 0:
            raise SolveError(f"the pressure does not drive the front of crack {crack} (mean K_I = {k:.4g} at p = {p_ref:.4g})")
        return sol, p_ref * K_Ic / k, K_Ic / k, 1
    def run(p):
        sol = solve(disc_scene(scene, crack, R, p), options=options, pipeline=pipe)
        return p, _drive(sol, crack) - K_Ic, sol

    sol, p, solves = pressure_at_propagation(run, p_ref, K_Ic, RADIAL_KIC_RTOL, RADIAL_MAX_SEARCH, f"the front of crack {crack}")
    return sol, p, 1.0, solves


# ------------------------------------------------------------------------------ time and leak-off
def _ring_integral(r0: float, r1: float, t0a: float, t0b: float, t: float) -> float:
    """int over r0 < r < r1 of sqrt(t - t0(r)) 2 pi r dr, t0 linear from t0a to t0b."""
    if r1 <= r0:
        return 0.0
    u, wts = np.polynomial.legendre.leggauss(LEAKOFF_GAUSS)
    # r = r1 - (r1 - r0) s^2: the square root at the ring's outer edge (where t0 -> t) integrated smoothly
    s = 0.5 * (u + 1.0)
    r = r1 - (r1 - r0) * s * s
    t0 = t0b + (t0a - t0b) * s * s
    f = np.sqrt(np.maximum(t - t0, 0.0)) * 2.0 * math.pi * r * 2.0 * (r1 - r0) * s
    return float(0.5 * np.sum(wts * f))


def leaked_volume(t: float, rings: list, R1: float, t1: float, C_L: float) -> float:
    """The volume leaked by t through both faces, 4 C_L int sqrt(t - t0(r)) dA: `rings` are (r0, r1, t0 at r0,
    t0 at r1) beyond the first radius R1, reached at t1 (the first disc grown at R ~ t^(2/5) before)."""
    if C_L == 0.0:
        return 0.0
    u, wts = np.polynomial.legendre.leggauss(LEAKOFF_GAUSS)
    s = 0.5 * (u + 1.0)
    r = R1 * (1.0 - s * s)
    t0 = t1 * (r / R1) ** (1.0 / FIRST_GROWTH_EXPONENT)
    inner = float(0.5 * np.sum(wts * np.sqrt(np.maximum(t - t0, 0.0)) * 2.0 * math.pi * r * 2.0 * R1 * s))
    return 4.0 * C_L * (inner + sum(_ring_integral(a, b, ta, tb, t) for a, b, ta, tb in rings))


def step_time(volume: float, schedule, C_L: float, history: list, R: float):
    """(t, injected, leaked) at which the schedule has injected `volume` plus the leak-off (None where it never does).

    history: the accepted steps' (R, t); the current disc of radius R was reached at the unknown t."""
    from scipy.optimize import brentq

    if C_L == 0.0:
        t = schedule.time_of(volume)
        return (None, None, 0.0) if t is None else (t, schedule.volume(t), 0.0)

    def leaked(t):
        if not history:  # the first disc: arrival times t (r / R)^(5/2) scale with t itself
            return leaked_volume(t, [], R, t, C_L)
        rings = [(a[0], b[0], a[1], b[1]) for a, b in zip(history, history[1:])] + [(history[-1][0], R, history[-1][1], t)]
        return leaked_volume(t, rings, history[0][0], history[0][1], C_L)

    def f(t):
        return schedule.volume(t) - volume - leaked(t)

    t_stored = schedule.time_of(volume)  # the time without leak-off: a lower bound
    if t_stored is None:
        return None, None, 0.0
    lo = max(history[-1][1] if history else 0.0, t_stored)
    if f(lo) >= 0:  # no later than the last step: the caller stops on it
        return lo, schedule.volume(lo), leaked(lo)
    hi = 1.5 * lo
    for _ in range(200):
        if f(hi) > 0:
            break
        hi *= 2.0
    else:
        return None, None, 0.0
    t = brentq(f, lo, hi, xtol=1e-14 * hi, rtol=1e-12)
    return t, schedule.volume(t), leaked(t)


# ------------------------------------------------------------------------------ the loop
def step_row(n, scene, sol, crack, R, p, factor, solves, elapsed, K_Ic, t, injected, leaked, volume, K_m) -> tuple:
    """The step's JSON row and its frame (a section through the disc's centre along e_a)."""
    f = front_of(sol, crack)
    K_I = factor * np.where(f.closed, 0.0, f.K_I)
    mean = float(np.mean(K_I))
    c = sol.scene.cracks[crack]
    tips = []
    for k, pt in enumerate(f.points):
        tips.append({"crack": crack, "end": k, "x": float(pt[0]), "y": float(pt[1]), "z": float(pt[2]),
                     "K_I": float(K_I[k]), "K_II": float(factor * f.K_II[k]), "K_III": float(factor * f.K_III[k]),
                     "kink_deg": 0.0, "advanced": bool(K_I[k] >= (1.0 - RADIAL_ADVANCE_RTOL) * K_Ic)})
    radius = float(np.mean(np.linalg.norm(f.points - c.center, axis=1)))
    s = (np.arange(PROFILE_POINTS) + 0.5) / PROFILE_POINTS * R
    opening = factor * opening_along(sol, crack, s)
    w0 = float(factor * opening_along(sol, crack, [0.0])[0])
    row = {"step": n, "time": t, "half_length": float(R), "pressure": float(p), "opening_at_injection": w0,
           "volume": float(volume), "ndof": int(sol.ndof["total"]), "time_s": float(elapsed),
           "kkt": float(max(sol.kkt.values(), default=0.0)), "solves": solves, "K_m": K_m,
           "efficiency": float(volume / injected) if injected else 1.0, "radius": radius,
           "leaked": float(leaked),
           "front": {"K_I_mean": mean, "K_I_min": float(K_I.min()), "K_I_max": float(K_I.max()),
                     "spread": float((K_I.max() - K_I.min()) / mean) if mean > 0 else math.inf},
           "profile": {"s": s.tolist(), "opening": opening.tolist(), "pressure": [float(p)] * len(s)},
           "tips": tips}
    xs = np.concatenate([-s[::-1], s])
    frame = {"points": [[-R, 0.0], [R, 0.0]], "x": xs.tolist(), "y": [0.0] * len(xs), "normal": [[0.0, 1.0]] * len(xs),
             "opening": np.concatenate([opening[::-1], opening]).tolist()}
    return row, frame


def radial_run(scene, schedule, K_Ic: float, da: float, steps: int, t_end, crack: int, progress, options, result,
               viscosity, leakoff: float, warn):
    """The radial loop (module docstring) into `result`; returns it. `warn(K_m)` is called once, at the first
    step whose dimensionless toughness says viscosity matters."""
    from ...solid.volume import crack_volume
    from .loop import has_other_loads

    in_situ = has_other_loads(scene, crack)
    R0 = float(scene.cracks[crack].radius)
    E_prime = e_prime_3d(scene)
    sizes = scene.mesh_sizes(maxh=options.maxh, crack_h=options.crack_h, front_h=options.front_h, grading=options.grading)
    current, R = disc_scene(scene, crack, R0, 0.0), R0
    history, stopped, warned = [], "", False
    for n in range(steps + 1):
        t0 = time.process_time()
        opts = scaled_options(options, sizes, R0, R)
        try:
            sol, p, factor, solves = propagation_radial(current, crack, R, K_Ic, Pipeline(), opts, in_situ)
        except SolveError as exc:
            stopped = f"solve: step {n}: {exc}"
            break
        volume = factor * crack_volume(sol, crack)
        t, injected, leaked = step_time(volume, schedule, leakoff, history, R)
        if t is None:
            stopped = f"shut-in: step {n} holds more fluid ({volume:.6g}) than the schedule ever injects"
            break
        if history and t <= history[-1][1]:
            stopped = (f"time: step {n} holds no more fluid than step {n - 1} (t = {t:.6g} <= {history[-1][1]:.6g}); "
                       "the growth da is below what the mesh resolves")
            break
        K_m = None if viscosity is None else k_m_radial(t, K_Ic, E_prime, viscosity, schedule.largest_rate)
        if K_m is not None and K_m < K_RADIAL_TOUGHNESS and not warned:
            warned = True
            warn(K_m, t)
        row, frame = step_row(n, current, sol, crack, R, p, factor, solves, time.process_time() - t0, K_Ic, t,
                              injected, leaked, volume, K_m)
        result.add(row, frame, current)
        history.append((R, t))
        if progress is not None:
            progress(n, result)
        if t_end is not None and t >= t_end:
            stopped = f"time: t = {t:.6g} reached the end time {t_end:.6g} at step {n}"
            break
        if n == steps:
            stopped = f"steps: {steps} of {steps} steps done"
            break
        held = [tp for tp in row["tips"] if not tp["advanced"]]
        if held:
            worst = min(tp["K_I"] for tp in held) / K_Ic
            stopped = (f"front: step {n}: {len(held)} of {len(row['tips'])} front points below K_Ic (down to "
                       f"{worst:.3f} K_Ic, the mean at K_Ic); the radial model keeps the crack a disc and cannot "
                       "follow a front that grows in part")
            break
        current, R, stopped = grown_disc(current, crack, R, da)
        if stopped:
            break
    result.stopped = stopped
    result.final = current
    return result
