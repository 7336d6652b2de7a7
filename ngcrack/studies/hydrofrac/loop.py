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
3. both tips (every tip of the crack inside the body) advance by da, kinked by the MTS
   angle of their K (`ngcrack.studies.growth.criteria`, `ngcrack.studies.growth.paths`); the grown
   scene is meshed afresh.

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
from ...core.options import SolveOptions
from ...core.pipeline import Pipeline, SolveError
from ...core.scene import planar_only
from ...planar.scene import SceneError
from ..growth.criteria import effective_K_I, mts_angle, mts_keq
from ..growth.loop import KINK_NOISE_RTOL, MAX_DA_FRACTION, MAX_STEPS, tip_values
from ..growth.paths import body_region, extend_tip, extended_cracks, tip_direction
from ..volume import crack_volume, with_pressure

#: K_eq at the pressure found is within this fraction of K_Ic (else the search goes on)
KIC_RTOL = 1e-8
#: the most solves of one step's pressure search
MAX_SEARCH = 40
#: consecutive crack segments whose directions differ by less than this (radians, about)
#: are one straight segment
STRAIGHT_RTOL = 1e-9
#: solve options hydrofrac sets itself
_RESERVED = ("warm_start", "crack_mesh", "loads")


def _number(v) -> bool:
    return not isinstance(v, bool) and isinstance(v, (int, float, np.floating, np.integer))


def check_hydrofrac_options(scene, rate, K_Ic, da, steps, crack, injection, solve_options) -> None:
    """Refuse bad input before any work, naming the field and what is allowed."""
    from ...planar.tips import tip_labels

    if not (_number(rate) and math.isfinite(rate) and rate > 0):
        raise InputError(f"rate = {rate!r}: must be a finite number > 0 (the injection rate Q0, an area per unit "
                         "time per unit thickness)")
    if not (_number(K_Ic) and math.isfinite(K_Ic) and K_Ic > 0):
        raise InputError(f"K_Ic = {K_Ic!r}: must be a finite number > 0 (the fracture toughness)")
    limit = MAX_DA_FRACTION * scene.diameter
    if not (_number(da) and math.isfinite(da) and 0 < da <= limit):
        raise InputError(f"da = {da!r}: must be a number in (0, {limit:.4g}] (at most {MAX_DA_FRACTION:g} of the "
                         f"body's diameter {scene.diameter:.4g})")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or not 1 <= steps <= MAX_STEPS:
        raise InputError(f"steps = {steps!r}: must be a whole number in [1, {MAX_STEPS}]")
    n = len(scene.cracks)
    if n == 0:
        raise InputError(f"scene {scene.name!r}: has no crack; hydrofrac drives a crack's faces apart")
    if isinstance(crack, bool) or not isinstance(crack, (int, np.integer)) or not 0 <= crack < n:
        raise InputError(f"crack = {crack!r}: must be a crack index 0..{n - 1} (the fluid-driven crack)")
    if not any(lab.startswith(f"{crack},") for lab in tip_labels(scene)):
        raise InputError(f"crack = {crack}: has no tip inside the body, so it cannot grow")
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


def has_other_loads(scene, crack: int) -> bool:
    """Whether the scene loads the body besides the fluid-driven crack's pressure (an in-situ stress)."""
    if scene.body_force is not None and any(v != 0.0 for v in scene.body_force):
        return True
    if any(bc.value is not None and any(v != 0.0 for v in bc.value) for bc in scene.boundary.values()):
        return True
    if any(getattr(pc, "value", None) is not None and any(v != 0.0 for v in pc.value)
           for pc in getattr(scene, "points", ())):
        return True
    return any(c.pressure not in (None, 0.0) for k, c in enumerate(scene.cracks) if k != crack)


def _drive(sol, crack: int) -> float:
    """The largest K_eq over the crack's tips (K_I = 0 where the faces at a tip touch)."""
    values = [v["K_eq"] for v in tip_values(sol) if v["crack"] == crack]
    return max(values) if values else -math.inf


def propagation(scene, crack: int, K_Ic: float, pipe: Pipeline, options: SolveOptions, in_situ: bool):
    """(solution, pressure, factor, solves): the state at which the crack's first tip reaches K_Ic.

    The state is `factor` times `solution` (factor 1 unless the problem is homogeneous in p:
    `in_situ` False, no other loads, one solve scaled)."""
    a = 0.5 * scene.cracks[crack].length
    p_ref = K_Ic / math.sqrt(math.pi * a)  # Sneddon's pressure at propagation
    if not in_situ:
        sol = pipe.run(with_pressure(scene, [crack], p_ref), options)
        k = _drive(sol, crack)
        if not k > 0:
            raise SolveError(f"the pressure does not drive the tips of crack {crack} (K_eq = {k:.4g} at p = {p_ref:.4g})")
        return sol, p_ref * K_Ic / k, K_Ic / k, 1
    tried = []

    def run(p):
        sol = pipe.run(with_pressure(scene, [crack], p), options)
        tried.append((p, _drive(sol, crack) - K_Ic, sol))
        return tried[-1]

    _, g0, _ = run(0.0)
    if g0 >= 0:
        raise SolveError(f"crack {crack} is at propagation without fluid pressure (K_eq = {g0 + K_Ic:.4g} >= K_Ic)")
    p1 = p_ref
    for _ in range(MAX_SEARCH):  # a trial pressure that drives the tips (a compression may hold them closed)
        _, g1, _ = run(p1)
        if g1 > g0:
            break
        p1 *= 4.0
    else:
        raise SolveError(f"the pressure does not drive the tips of crack {crack} (up to p = {p1:.4g})")
    p = p1 * (0.0 - g0) / (g1 - g0)
    while len(tried) < MAX_SEARCH:
        p, g, sol = run(p)
        if abs(g) <= KIC_RTOL * K_Ic:
            return sol, p, 1.0, len(tried)
        lo = max((t for t in tried if t[1] < 0), key=lambda t: t[0])
        his = [t for t in tried if t[1] > 0]
        if not his:
            p = max(t[0] for t in tried) * 2.0
            continue
        hi = min(his, key=lambda t: t[0])
        # regula falsi, the interval's half as a safeguard
        p = (lo[0] * hi[1] - hi[0] * lo[1]) / (hi[1] - lo[1])
        if not lo[0] < p < hi[0] or len(tried) % 3 == 0:
            p = 0.5 * (lo[0] + hi[0])
    best = min(tried, key=lambda t: abs(t[1]))
    if abs(best[1]) <= 1e3 * KIC_RTOL * K_Ic:
        return best[2], best[0], 1.0, len(tried)
    raise SolveError(f"the pressure at propagation was not found in {MAX_SEARCH} solves (K_eq - K_Ic = {best[1]:.3g})")


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


def step_record(n, scene, sol, crack, pressure, factor, rate, injection, solves, elapsed) -> tuple[dict, dict]:
    """The step's JSON row and its frame (points, opening profile) from the state factor * sol."""
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
                     "kink_deg": math.degrees(mts_angle(k1, kink_II)) + 0.0})
    row = {"step": n, "time": volume / rate, "half_length": 0.5 * scene.cracks[crack].length,
           "pressure": float(pressure), "opening_at_injection": w0, "volume": volume,
           "ndof": int(sol.ndof["total"]), "time_s": float(elapsed), "kkt": float(max(sol.kkt.values(), default=0.0)),
           "solves": solves, "tips": tips}
    frame = {"points": [list(p) for p in scene.cracks[crack].points], "x": prof.x.tolist(), "y": prof.y.tolist(),
             "normal": sol.crack_mesh.cracks[crack].normal.tolist(), "opening": (factor * prof.normal_jump).tolist()}
    return row, frame


def hydrofrac(scene, rate: float, K_Ic: float, da: float, steps: int, *, crack: int = 0, injection=None,
              progress=None, **solve_options):
    """Grow a fluid-driven crack of `scene` under the injection rate `rate` (module docstring).

    rate: Q0, the injected area per unit time (per unit thickness); K_Ic: the toughness;
    da: the growth of each tip per step; steps: at most MAX_STEPS. crack: the index of the
    fluid-driven crack; injection: the injection point [x, y] on it (its centre by
    default), where `opening_at_injection` is read. progress: called as progress(step,
    result_so_far) after every step. The other keywords go to every solve (element,
    order, maxh, tip_h, crack_h, grading, crack_model, ...). Returns a HydrofracResult.
    """
    from ...core.solve import as_scene
    from .result import HydrofracResult

    scene = as_scene(scene)
    planar_only(scene, "hydraulic fracture")
    check_hydrofrac_options(scene, rate, K_Ic, da, steps, crack, injection, solve_options)
    options = SolveOptions.of(**solve_options)
    options.check_for(scene)
    rate, K_Ic, da, steps, crack = float(rate), float(K_Ic), float(da), int(steps), int(crack)
    region = body_region(scene)
    in_situ = has_other_loads(scene, crack)
    result = HydrofracResult(scene=scene, element=options.element, rate=rate, K_Ic=K_Ic, da=da)
    current = with_pressure(scene, [crack], 0.0)
    stopped = ""
    for n in range(steps + 1):
        t0 = time.perf_counter()
        pipe = Pipeline()  # a new geometry every step: nothing to keep but the code path
        try:
            sol, p, factor, solves = propagation(current, crack, K_Ic, pipe, options, in_situ)
        except SolveError as exc:
            stopped = f"solve: step {n}: {exc}"
            break
        row, frame = step_record(n, current, sol, crack, p, factor, rate, injection, solves, time.perf_counter() - t0)
        result.add(row, frame, current)
        if progress is not None:
            progress(n, result)
        if n == steps:
            stopped = f"steps: {steps} of {steps} steps done"
            break
        extensions, new_segments, reason = [], [], ""
        for tip in row["tips"]:
            phi = tip_direction(current.cracks[crack], tip["end"]) + math.radians(tip["kink_deg"])
            ext = extend_tip(current, region, crack, tip["end"], phi, da, new_segments)
            if ext.outcome != "grew":
                reason = f"{ext.outcome}: {ext.reason}"
                break
            new_segments.append((f"{crack},{tip['end']}", shapely.LineString([(tip["x"], tip["y"]), ext.point])))
            extensions.append(ext)
        if reason:
            stopped = reason
            break
        grown = [dataclasses.replace(c, points=straightened(c.points), pressure=old.pressure)
                 for c, old in zip(extended_cracks(current, extensions), current.cracks)]
        try:
            current = current.with_(cracks=grown)
        except SceneError as exc:
            stopped = f"scene: the grown crack makes an invalid scene ({exc})"
            break
    result.stopped = stopped
    result.final = current
    return result
