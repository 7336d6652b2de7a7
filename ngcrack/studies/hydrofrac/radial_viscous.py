"""The viscous radial (penny) fracture in 3D: fixed radius increments, the time step solved for.

The front stays a circle about the injection point: the model assumes radial symmetry (an
isotropic, homogeneous body whose loads are symmetric about the disc's axis, the body far
enough for its faces not to break the symmetry; the front's K_I scatter of the calibration
solve is recorded). Each step, on the disc of radius R (meshed afresh, the crack's mesh
sizes scaled with R as in the toughness-only model):

1. the ring compliance from the 3D mixed solve (`radial_elastic`: one mesh, one
   factorization, RADIAL_RINGS + 1 solves with it, the tip calibration by the interaction
   integral on the unit pressure's solution);
2. the implicit flow step on the rings (`radial_flow`): the ring pressures and the step's
   duration at which the front has advanced by da (at step 0 the disc is taken as grown
   from the injection point, its front at the speed FIRST_GROWTH R / t of the M-vertex's
   R ~ t^(4/9)), the opening and pressure carried over from the last step's rings;
3. the record: the centre's opening from the 3D solution under the rings' pressures (one
   expansion, no new solve), the fluid's profile (ring mid radii, mean openings, pressures),
   per front point the K_I the opening next to the front shows (the asymptote's K part).
"""

from __future__ import annotations

import time

import numpy as np

from ...core.pipeline import Pipeline, SolveError
from .flow import StepError, tip_opening
from .radial import (
    disc_scene,
    e_prime_3d,
    grown_disc,
    k_m_radial,
    scaled_options,
)
from .radial_elastic import ring_elastic
from .radial_flow import Rings, carried_over, radial_step, ring_tip_mean

#: the fluid's rings over the disc (equal widths): the M-vertex's R within 0.42% with 10 rings and Sneddon's exact
#: axisymmetric compliance, 0.28-0.56% with 6, from the second step on (measured); the 3D compliance needs the
#: crack's mesh to resolve them (on the default penny mesh, 2-3 elements along the radius, their mean openings
#: under a uniform pressure scatter by -9..+1% about Sneddon's)
RADIAL_RINGS = 10
#: the first step's front speed FIRST_GROWTH R / t (the M-vertex's R ~ t^(4/9); at the K-vertex the speed
#: does not enter the tip asymptote)
FIRST_GROWTH = 4.0 / 9.0


def apparent_K(rings: Rings, w: np.ndarray, E_prime: float) -> float:
    """The K_I the opening in the ring next to the front ring shows (calibrated): its ratio to the K field's
    mean opening there per unit K_I."""
    h = rings.width
    unit = ring_tip_mean(rings.R, float(h[-1]), float(h[-2]), 0.0, 1.0, E_prime, 0.0)
    return float(w[-2] / rings.scale / unit)


def march(rings: Rings, state, rings_old: Rings | None, previous, schedule, fluid, da: float):
    """The flow step onto `rings` from the last step's `state` on `rings_old` (None: the first step, the disc
    grown from the injection point), the front advanced by da; `previous` the last step's (da, dt) or None."""
    if state is None:
        mid = rings.mid
        frac = (mid / rings.R) ** (1.0 / FIRST_GROWTH)  # the front passed r at t (r / R)^(9/4)
        return radial_step(rings, np.zeros(len(mid)), None, 0.0, np.full(len(mid), np.nan), frac, schedule,
                           FIRST_GROWTH * rings.R, None, fluid)
    w_old, p_old, t0_old, frac = carried_over(rings_old.edges, state.w, state.p, state.t0, rings.edges)
    return radial_step(rings, w_old, p_old, state.t, t0_old, frac, schedule, da, previous, fluid, p_guess=p_old)


def viscous_radial_run(scene, schedule, K_Ic: float, da: float, steps: int, t_end, crack: int, progress, options,
                       result, mu: float, C_L: float):
    """The viscous radial loop (module docstring) into `result`; returns it."""
    E_prime = e_prime_3d(scene)
    fluid = (K_Ic, E_prime, mu, C_L)
    R0 = float(scene.cracks[crack].radius)
    sizes = scene.mesh_sizes(maxh=options.maxh, crack_h=options.crack_h, front_h=options.front_h, grading=options.grading)
    xi = np.linspace(0.0, 1.0, RADIAL_RINGS + 1)
    current, R = disc_scene(scene, crack, R0, 0.0), R0
    state, rings_old, previous, stopped = None, None, None, ""
    for n in range(steps + 1):
        t_cpu = time.process_time()
        edges = R * xi
        h = np.diff(edges)
        try:
            el = ring_elastic(Pipeline(), current, crack, edges, scaled_options(options, sizes, R0, R), E_prime,
                              lambda K, R=R, h=h: ring_tip_mean(R, float(h[-1]), float(h[-2]), 0.0, K, E_prime, 0.0))
        except SolveError as exc:
            stopped = f"solve: step {n}: {exc}"
            break
        rings = Rings(edges=edges, C=el.C, w_is=el.w_is, scale=el.scale)
        try:
            st = march(rings, state, rings_old, previous, schedule, fluid, da)
        except StepError as exc:
            stopped = f"flow: step {n}: {exc}"
            break
        K_m = k_m_radial(st.t, K_Ic, E_prime, mu, schedule.largest_rate)
        row, frame = viscous_radial_record(n, el, rings, st, R, K_m, K_Ic, E_prime, fluid, da if state else FIRST_GROWTH * R,
                                           previous, time.process_time() - t_cpu, crack)
        result.add(row, frame, current)
        if progress is not None:
            progress(n, result)
        previous = (da, st.dt) if state is not None else None
        state, rings_old = st, rings
        if t_end is not None and st.t >= t_end:
            stopped = f"time: t = {st.t:.6g} reached the end time {t_end:.6g} at step {n}"
            break
        if n == steps:
            stopped = f"steps: {steps} of {steps} steps done"
            break
        current, R, stopped = grown_disc(current, crack, R, da)
        if stopped:
            break
    result.stopped = stopped
    result.final = current
    return result


def viscous_radial_record(n, el, rings: Rings, st, R, K_m, K_Ic, E_prime, fluid, a, previous, elapsed, crack=0) -> tuple:
    """The step's JSON row and its frame (a section through the disc's centre along e_a: the rings' openings).
    `kkt` is 0: the faces are open, no contact problem is solved (the flow's compliance is the free crack's);
    `front` K_I is the asymptote's (`apparent_K`, the same at every point), `K_I_calibration_spread` the
    front integral's scatter under the calibration's unit pressure (how far the front is from symmetric)."""
    from .flow import tip_speed

    c = el.crack
    w3d = el.opening_at(st.p, np.concatenate([[0.0], rings.mid]))
    K_app = apparent_K(rings, st.w, E_prime)
    V = tip_speed(a, st.dt, previous)
    tips = [{"crack": crack, "end": k, "x": float(pt[0]), "y": float(pt[1]), "z": float(pt[2]), "K_I": K_app, "K_II": 0.0,
             "K_III": 0.0, "kink_deg": 0.0, "advanced": True} for k, pt in enumerate(el.front_points)]
    radius = float(np.mean(np.linalg.norm(el.front_points - c.center, axis=1)))
    volume = float(rings.area @ st.w)
    row = {"step": n, "time": st.t, "half_length": float(R), "pressure": float(st.p[0]),
           "opening_at_injection": float(w3d[0]), "volume": volume, "ndof": el.ndof, "time_s": float(elapsed),
           "kkt": 0.0, "solves": len(rings.mid) + 1, "K_m": K_m, "efficiency": st.efficiency, "radius": radius,
           "leaked": float(st.leaked), "injected": float(st.injected), "dt": float(st.dt), "speed": float(V),
           "front": {"K_I_mean": K_app, "K_I_min": K_app, "K_I_max": K_app, "spread": 0.0,
                     "K_I_calibration_spread": el.K_spread},
           "tip_opening": float(tip_opening(float(rings.width[-1]), V, *fluid[:3], fluid[3])),
           "profile": {"s": rings.mid.tolist(), "opening": st.w.tolist(), "pressure": st.p.tolist(),
                       "opening_3d": w3d[1:].tolist()},
           "tips": tips}
    s = rings.mid
    xs = np.concatenate([-s[::-1], s])
    frame = {"points": [[-R, 0.0], [R, 0.0]], "x": xs.tolist(), "y": [0.0] * len(xs), "normal": [[0.0, 1.0]] * len(xs),
             "opening": np.concatenate([st.w[::-1], st.w]).tolist()}
    return row, frame


#: Savitski and Detournay (2002), the radial M-vertex R = gamma (E' Q0^3 t^4 / mu')^(1/9): gamma of their
#: first-order solution (accurate to 1e-3, the reference here) and of the zero-order one
M_GAMMA, M_GAMMA_0 = 0.6976, 0.6955
#: their first-order opening Omega(rho) = (1 - rho)^(2/3) sum_i A_i P_i(v) + B (sqrt(1 - rho^2) - rho arccos rho),
#: v = 2 (rho - 1): the published coefficients A_i, B and the polynomials P_i (highest power first)
M_OPENING_A = (1.89201, 0.000663163, 0.00314291, 0.000843517)
M_OPENING_P = ((1.0,), (38 / 9, 80 / 9, 35 / 9), (5225 / 648, 2717 / 108, 1235 / 54, 455 / 81),
               (59675 / 3888, 15400 / 243, 7150 / 81, 11440 / 243, 1820 / 243))
M_OPENING_LINEAR = 0.102366  # times (1 - rho)^(2/3) (1/3 + 13/3 (2 rho - 1))
M_OPENING_B = 0.237267
#: their first-order pressure Pi(rho) = c (q(rho) + s^(1/3) ln(1 / rho) + d s^(1/3)) / s^(1/3), s = 1 - rho,
#: q a cubic (highest power first)
M_PRESSURE_C, M_PRESSURE_D = 0.0931746, 8.81828
M_PRESSURE_Q = (-0.103558, -0.171565, -0.0195787, -2.20161)


def m_opening(rho) -> np.ndarray:
    """Omega(rho): the M-vertex opening in the scale eps L gamma (module constants)."""
    rho = np.asarray(rho, dtype=float)
    v = 2.0 * (rho - 1.0)
    tip = np.clip(1.0 - rho, 0.0, None) ** (2.0 / 3.0)
    series = sum(a * np.polyval(poly, v) for a, poly in zip(M_OPENING_A, M_OPENING_P))
    series = series + M_OPENING_LINEAR * (1.0 / 3.0 + 13.0 / 3.0 * (2.0 * rho - 1.0))
    outer = np.sqrt(np.clip(1.0 - rho ** 2, 0.0, None)) - rho * np.arccos(np.clip(rho, -1.0, 1.0))
    return tip * series + M_OPENING_B * outer


def m_pressure(rho) -> np.ndarray:
    """Pi(rho): the M-vertex pressure in the scale eps E' (log-singular at the centre, -s^(-1/3) at the front)."""
    rho = np.asarray(rho, dtype=float)
    s3 = np.cbrt(1.0 - rho)
    with np.errstate(divide="ignore", invalid="ignore"):
        return M_PRESSURE_C * (np.polyval(M_PRESSURE_Q, rho) + s3 * (np.log(1.0 / rho) + M_PRESSURE_D)) / s3


def m_vertex_radial(t, E_prime: float, mu: float, Q0: float) -> dict:
    """Savitski and Detournay's radial M-vertex at time t: R (first order), R0 (zero order), the centre's opening
    w0, and the scales eps = (mu' / (E' t))^(1/3), L = (E' Q0^3 t^4 / mu')^(1/9) of the profiles: w(rho) = eps L
    gamma m_opening(rho), p(rho) = eps E' m_pressure(rho), rho = r / R."""
    mu_p = 12.0 * mu
    t = np.asarray(t, dtype=float)
    L = (E_prime * Q0 ** 3 * t ** 4 / mu_p) ** (1.0 / 9.0)
    eps = (mu_p / (E_prime * t)) ** (1.0 / 3.0)
    return {"R": M_GAMMA * L, "R0": M_GAMMA_0 * L, "w0": eps * L * M_GAMMA * float(m_opening(0.0)), "eps": eps, "L": L}
