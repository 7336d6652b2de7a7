"""The hydraulic-fracture loop: pressure at propagation -> volume and time -> kink -> extend -> remesh.

Toughness-dominated, inviscid fluid: the fluid pressure p is uniform in the crack (no
pressure drop along it; the viscous regime, with the lubrication equation along the
crack, is a later step) and the fluid is incompressible with no leak-off, so the volume
injected at the rate Q0 (an area per unit time, per unit thickness) is the crack's
volume: t = V / Q0. The scene's own loads are the in-situ stress.

Each step, on the current crack:

1. the pressure at propagation: the smallest p at which a tip of the fluid-driven crack
   reaches the toughness, K_eq(p) = K_Ic (K_eq the MTS equivalent factor of the growth
   package, K_I taken as 0 where the faces at the tip touch). Without other loads the
   problem (contact included) is positively homogeneous of degree one in p: one solve at
   a trial pressure, scaled by K_Ic / K_eq. With an in-situ stress, two solves (p = 0
   and a trial p) give p by superposition, a third solve at that p checks it, and where
   contact makes the response nonlinear a regula falsi on K_eq(p) - K_Ic finishes it; every
   solve after the first reuses the step's factorization (only the load changes);
2. the volume V (`ngcrack.studies.volume.crack_volume`), the time t = V / Q0, the opening at
   the injection point;
3. the tips at propagation (K_eq within ADVANCE_RTOL of K_Ic; the pressure put the most
   loaded one there) advance by da, kinked by the MTS angle of their K; the others stay
   (a tip facing a band of higher in-situ stress is arrested while the other runs;
   `ngcrack.studies.growth.criteria`, `ngcrack.studies.growth.paths`); the grown scene is
   meshed afresh.

The run stops after `steps` steps, or when a tip would leave the body or meet another
crack (the reason is kept), or when the pressure no longer drives the tips.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
import shapely

from ...core.errors import InputError
from ...core.fields import is_number
from ...core.options import SolveOptions
from ...core.pipeline import Pipeline, SolveError
from ...planar.scene import SceneError
from ...planar.tips import effective_modulus
from ..growth.criteria import effective_K_I, mts_angle, mts_keq
from ..growth.loop import KINK_NOISE_RTOL, MAX_DA_FRACTION, MAX_STEPS, tip_values
from ..growth.paths import body_region, extend_tip, extended_cracks, tip_direction
from ..volume import crack_volume, with_pressure
from .propagation import pressure_at_propagation

#: K_eq at the pressure found is within this fraction of K_Ic (else the search goes on)
KIC_RTOL = 1e-8
#: a tip advances when its K_eq is within this fraction of K_Ic at the pressure found (the
#: most loaded tip is at K_Ic to KIC_RTOL); the others stay. The tips of a symmetric crack
#: differ by the mesh's asymmetry, measured below 1e-3 on the default meshes (KGD), and the
#: interaction integral's own error is of that order: a tip within 1% is at propagation
ADVANCE_RTOL = 1e-2
#: the most solves of one step's pressure search
MAX_SEARCH = 40
#: consecutive crack segments whose directions differ by less than this (radians, about)
#: are one straight segment
STRAIGHT_RTOL = 1e-9
#: solve options hydrofrac sets itself
_RESERVED = ("warm_start", "crack_mesh", "loads")
#: the crack models a fluid can drive (a bonded crack does not open)
CRACK_MODELS = ("contact", "free")
#: da at least this fraction of the tip mesh size: a smaller step moves the tip within its
#: own element, and remeshing changes the crack's volume by about as much as the growth
#: (measured on KGD at tip_h = l/20: the time of a step off by 25% at da = tip_h / 10, and
#: running backwards at tip_h / 50)
MIN_DA_TIP_FRACTION = 0.25
#: the largest strain scale the pressure at propagation may have, K_Ic / (E' sqrt(pi a)),
#: a the crack's half-length: beyond it small-strain elasticity does not describe the body
MAX_STRAIN = 0.1




def check_common_options(scene, rate, K_Ic, steps, crack, rate_unit: str) -> None:
    """The checks a plane and a radial fracture share: the rate (in rate_unit), the toughness, the steps and the
    fluid-driven crack's index, each refused by name before any work."""
    if not (is_number(rate) and math.isfinite(rate) and rate > 0):
        raise InputError(f"rate = {rate!r}: must be a finite number > 0 (the injection rate Q0, {rate_unit})")
    if not (is_number(K_Ic) and math.isfinite(K_Ic) and K_Ic > 0):
        raise InputError(f"K_Ic = {K_Ic!r}: must be a finite number > 0 (the fracture toughness)")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or not 1 <= steps <= MAX_STEPS:
        raise InputError(f"steps = {steps!r}: must be a whole number in [1, {MAX_STEPS}]")
    n = len(scene.cracks)
    if n == 0:
        raise InputError(f"scene {scene.name!r}: has no crack; hydrofrac drives a crack's faces apart")
    if isinstance(crack, bool) or not isinstance(crack, (int, np.integer)) or not 0 <= crack < n:
        raise InputError(f"crack = {crack!r}: must be a crack index 0..{n - 1} (the fluid-driven crack)")


def check_hydrofrac_options(scene, rate, K_Ic, da, steps, crack, injection, solve_options, progress=None) -> None:
    """Refuse bad input before any work, naming the field and what is allowed."""
    from ...planar.sizing import mesh_sizes
    from ...planar.tips import tip_labels

    check_common_options(scene, rate, K_Ic, steps, crack, "an area per unit time per unit thickness")
    if not any(lab.startswith(f"{crack},") for lab in tip_labels(scene)):
        raise InputError(f"crack = {crack}: has no tip inside the body, so it cannot grow")
    mat = scene.material
    strain = K_Ic / (effective_modulus(mat.E, mat.nu, mat.plane) * math.sqrt(0.5 * math.pi * scene.cracks[crack].length))
    if strain > MAX_STRAIN:
        raise InputError(f"K_Ic = {K_Ic!r}: the pressure at propagation would be {strain:.3g} E' (K_Ic / (E' sqrt(pi a)), "
                         f"a the half-length); at most {MAX_STRAIN:g} E' keeps the strains small")
    opts = {k: solve_options.get(k) for k in ("maxh", "tip_h", "crack_h")}
    tip_h = mesh_sizes(scene, **opts)[1] if all(v is None or (is_number(v) and v > 0) for v in opts.values()) else None
    limit = MAX_DA_FRACTION * scene.diameter
    low = MIN_DA_TIP_FRACTION * tip_h if tip_h else 0.0
    if not (is_number(da) and math.isfinite(da) and low <= da <= limit and da > 0):
        raise InputError(f"da = {da!r}: must be a number in [{low:.4g}, {limit:.4g}] (at least {MIN_DA_TIP_FRACTION:g} "
                         f"of the tip mesh size {tip_h or 0:.4g}, at most {MAX_DA_FRACTION:g} of the body's diameter "
                         f"{scene.diameter:.4g})")
    if injection is not None:
        try:
            x, y = (float(v) for v in injection)
        except (TypeError, ValueError):
            raise InputError(f"injection = {injection!r}: must be a point [x, y] on the crack") from None
        line = shapely.LineString(scene.cracks[crack].points)
        if not (math.isfinite(x) and math.isfinite(y)) or line.distance(shapely.Point(x, y)) > 1e-6 * scene.diameter:
            raise InputError(f"injection = {injection!r}: must be a point [x, y] on crack {crack}")
    bad = [k for k in _RESERVED if k in solve_options]
    if bad:
        raise InputError(f"{bad[0]}: hydrofrac sets it for every step itself; give the scene and the mesh options only")
    model = solve_options.get("crack_model", "contact")
    if model not in CRACK_MODELS:
        raise InputError(f"crack_model = {model!r}: allowed values are {', '.join(CRACK_MODELS)} (a fluid cannot open "
                         "a bonded crack)")
    if progress is not None and not callable(progress):
        raise InputError(f"progress = {progress!r}: must be None or a callable progress(step, result)")


def has_other_loads(scene, crack) -> bool:
    """Whether the scene loads the body besides the fluid-driven crack's pressure (an in-situ stress);
    `crack`: its index, or the indices of several fluid-driven cracks."""
    fluid = {crack} if isinstance(crack, (int, np.integer)) else set(crack)
    if scene.body_force is not None and any(v != 0.0 for v in scene.body_force):
        return True
    if any(bc.value is not None and any(v != 0.0 for v in bc.value) for bc in scene.boundary.values()):
        return True
    if any(getattr(pc, "value", None) is not None and any(v != 0.0 for v in pc.value)
           for pc in getattr(scene, "points", ())):
        return True
    return any(c.pressure not in (None, 0.0) for k, c in enumerate(scene.cracks) if k not in fluid)


def _drive(sol, cracks: list) -> float:
    """The largest K_eq over the tips of the cracks (K_I = 0 where the faces at a tip touch)."""
    values = [v["K_eq"] for v in tip_values(sol) if v["crack"] in cracks]
    return max(values) if values else -math.inf


def propagation(scene, crack, K_Ic: float, pipe: Pipeline, options: SolveOptions, in_situ: bool):
    """(solution, pressure, factor, solves): the state at which the crack's first tip reaches K_Ic.

    The state is `factor` times `solution` (factor 1 unless the problem is homogeneous in p:
    `in_situ` False, no other loads, one solve scaled). `crack`: an index, or the indices of
    several cracks filled by one fluid at one pressure (the first tip of any of them)."""
    cracks = [int(crack)] if isinstance(crack, (int, np.integer)) else [int(k) for k in crack]
    a = 0.5 * max(scene.cracks[k].length for k in cracks)
    p_ref = K_Ic / math.sqrt(math.pi * a)  # Sneddon's pressure at propagation
    if not in_situ:
        sol = pipe.run(with_pressure(scene, cracks, p_ref), options)
        k = _drive(sol, cracks)
        if not k > 0:
            raise SolveError(f"the pressure does not drive the tips of crack {crack} (K_eq = {k:.4g} at p = {p_ref:.4g})")
        return sol, p_ref * K_Ic / k, K_Ic / k, 1
    def run(p):
        sol = pipe.run(with_pressure(scene, cracks, p), options)
        return p, _drive(sol, cracks) - K_Ic, sol

    sol, p, solves = pressure_at_propagation(run, p_ref, K_Ic, KIC_RTOL, MAX_SEARCH, f"the tips of crack {crack}")
    return sol, p, 1.0, solves


def step_stop(n: int, row: dict, result, frame, current, progress, t_end, steps: int) -> str | None:
    """Record step n's row in `result` unless it cannot be (the schedule never injects its fluid, or it holds no
    more than the step before); the reason the loop stops after it (the end time, the last step), else None."""
    if row["time"] is None:
        return f"shut-in: step {n} holds more fluid ({row['volume']:.6g}) than the schedule ever injects"
    if result.steps and row["time"] <= result.steps[-1]["time"]:
        return (f"time: step {n} holds no more fluid than step {n - 1} (t = {row['time']:.6g} <= "
                f"{result.steps[-1]['time']:.6g}); the growth da is below what the mesh resolves")
    result.add(row, frame, current)
    if progress is not None:
        progress(n, result)
    if t_end is not None and row["time"] >= t_end:
        return f"time: t = {row['time']:.6g} reached the end time {t_end:.6g} at step {n}"
    if n == steps:
        return f"steps: {steps} of {steps} steps done"
    return None


def straightened(points) -> tuple:
    """The polyline without its interior points where it runs straight on (collinear to
    STRAIGHT_RTOL): a tip that grew straight keeps one long tip segment, so that its
    domain integral's radius (limited by the tip segment's far end) grows with the crack."""
    pts = [tuple(p) for p in points]
    out = [pts[0]]
    for i in range(1, len(pts) - 1):
        a, b, c = np.asarray(out[-1]), np.asarray(pts[i]), np.asarray(pts[i + 1])
        u, v = b - a, c - b
        if abs(u[0] * v[1] - u[1] * v[0]) <= STRAIGHT_RTOL * np.linalg.norm(u) * np.linalg.norm(v) and u @ v > 0:
            continue
        out.append(pts[i])
    out.append(pts[-1])
    return tuple(out)


def injection_arclength(crack_points, injection) -> float:
    """The arc length of the injection point along the crack (its centre when None)."""
    line = shapely.LineString(crack_points)
    if injection is None:
        return 0.5 * line.length
    return float(line.project(shapely.Point(*injection)))


def step_record(n, scene, sol, crack, pressure, factor, schedule, injection, solves, elapsed, K_Ic, K_m) -> tuple[dict, dict]:
    """The step's JSON row and its frame (points, opening profile) from the state factor * sol
    (the row's time None where the schedule never injects the crack's volume)."""
    prof = sol.profiles[crack]
    volume = factor * crack_volume(sol, [crack])
    s_inj = injection_arclength(scene.cracks[crack].points, injection)
    w0 = factor * float(np.interp(s_inj, prof.s, prof.normal_jump))
    tips = []
    for v in tip_values(sol):
        if v["crack"] != crack:
            continue
        K_I, K_II = factor * v["K_I"], factor * v["K_II"]
        k1 = effective_K_I(K_I, v["closed"])
        kink_II = 0.0 if abs(K_II) <= KINK_NOISE_RTOL * abs(mts_keq(k1, K_II)) else K_II
        tips.append({"crack": crack, "end": v["end"], "x": v["x"], "y": v["y"], "K_I": K_I, "K_II": K_II,
                     "kink_deg": math.degrees(mts_angle(k1, kink_II)) + 0.0,
                     "advanced": bool(mts_keq(k1, K_II) >= (1.0 - ADVANCE_RTOL) * K_Ic)})
    row = {"step": n, "time": schedule.time_of(volume), "half_length": 0.5 * scene.cracks[crack].length,
           "pressure": float(pressure), "opening_at_injection": w0, "volume": volume,
           "ndof": int(sol.ndof["total"]), "time_s": float(elapsed), "kkt": float(max(sol.kkt.values(), default=0.0)),
           "solves": solves, "K_m": K_m, "efficiency": 1.0,
           "profile": {"s": prof.s.tolist(), "opening": (factor * prof.normal_jump).tolist(),
                       "pressure": [float(pressure)] * len(prof.s)},
           "tips": tips}
    frame = {"points": [list(p) for p in scene.cracks[crack].points], "x": prof.x.tolist(), "y": prof.y.tolist(),
             "normal": sol.crack_mesh.cracks[crack].normal.tolist(), "opening": (factor * prof.normal_jump).tolist()}
    return row, frame


def grow_tips(current, region, crack: int, tips: list, da: float):
    """(the grown scene, "") with every tip of `tips` marked "advanced" extended by da along its
    kink, or (the scene unchanged, why not) where a tip would leave the body or meet a crack."""
    extensions, new_segments = [], []
    for tip in tips:
        if not tip["advanced"]:
            continue
        phi = tip_direction(current.cracks[crack], tip["end"]) + math.radians(tip["kink_deg"])
        ext = extend_tip(current, region, crack, tip["end"], phi, da, new_segments)
        if ext.outcome != "grew":
            return current, f"{ext.outcome}: {ext.reason}"
        new_segments.append((f"{crack},{tip['end']}", shapely.LineString([(tip["x"], tip["y"]), ext.point])))
        extensions.append(ext)
    grown = [dataclasses.replace(c, points=straightened(c.points), pressure=old.pressure)
             for c, old in zip(extended_cracks(current, extensions), current.cracks)]
    try:
        return current.with_(cracks=grown), ""
    except SceneError as exc:
        return current, f"scene: the grown crack makes an invalid scene ({exc})"


def toughness_run(scene, schedule, K_Ic: float, da: float, steps: int, t_end, crack: int, injection, progress,
                  options: SolveOptions, result, K_m):
    """The toughness-dominated loop (module docstring) into `result`; returns it."""
    region = body_region(scene)
    in_situ = has_other_loads(scene, crack)
    current = with_pressure(scene, [crack], 0.0)
    stopped = ""
    for n in range(steps + 1):
        t0 = time.process_time()
        pipe = Pipeline()  # a new geometry every step: nothing to keep but the code path
        try:
            sol, p, factor, solves = propagation(current, crack, K_Ic, pipe, options, in_situ)
        except SolveError as exc:
            stopped = f"solve: step {n}: {exc}"
            break
        row, frame = step_record(n, current, sol, crack, p, factor, schedule, injection, solves,
                                 time.process_time() - t0, K_Ic, K_m)
        stopped = step_stop(n, row, result, frame, current, progress, t_end, steps)
        if stopped:
            break
        current, stopped = grow_tips(current, region, crack, row["tips"], da)
        if stopped:
            break
    result.stopped = stopped
    result.final = current
    return result
