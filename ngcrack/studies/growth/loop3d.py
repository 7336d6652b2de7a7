"""Planar growth of 3D cracks: solve -> K along every front -> advance every point -> a new curve crack.

`nc.grow(scene3d, da=..., steps=..., K_Ic=..., paris=(C, m[, dK_th]), R=...)` comes here (loop.grow
dispatches on the scene's dimension). Each step solves the scene once, takes K_I, K_II, K_III at the
points of every front (ngcrack.solid.front), and advances every point in the crack's plane along the
front's outward normal by da times its rule (fronts3d.py: quasi-static, the points at K_Ic; fatigue,
Paris's law); `da` is the largest advance of a point in a step. The grown front is smoothed and the
crack becomes a `curve` crack (ngcrack.solid.curve) in the same plane, meshed afresh at the next solve:
one solve per step.

Load. As in 2D (loop.py), the solution scales with a proportional load: the quasi-static step's load
factor is K_Ic / max K_eq (without K_Ic, relative to step 0's), and a fatigue cycle's maximum is the
scene's load (load factor 1).

Cycles (fatigue). The leading point advances by da per step; the cycles of a step are the integral
of ds / (C Delta K_max(s)^m) over it, with ln Delta K_max interpolated in ln L through the last two or
three steps (L the crack's equivalent radius sqrt(area / pi), fatigue.step_cycles): exact where K grows
as a power of the size (a penny: K ~ sqrt(a)), second order otherwise; so the count does not depend on
da (a first-order da / (C Delta K_max^m) per step is 6.6% high on a penny after four steps of 0.1 a, m = 3). The
run stops when K_max reaches K_Ic (fracture).

Surface cracks (a disc, an ellipse or a curve crossing a face, its front from surface to surface): the
same rules along the open front, the surface points growing with K taken SURFACE_K_FRACTION of the
front's length in from the surface and moving along the face. A disc or an ellipse grows as the ellipse
with the same centre and axes fitted to the advanced points (surface3d.py), the leading point's advance
in the cycle count being what the fitted ellipse gives it; a curve grows as the curve through the
advanced points, a free front shape (surface_curve.py).

Break-through (breakthrough.py): a grown embedded front whose ligament to a face falls below 0.4 of
its half-height (ASME XI's proximity rule), or that comes within the scene's clearance of the face or
crosses it, is re-characterised as a surface crack of depth 2a + S centred on the face and grows on
as one; the event is in `result.events` and `result.transitions` (the JSON's `events`). The step
that brought it there is counted as the embedded crack's, the break-through takes no cycles.

Through the back face (through.py): a grown surface or corner crack whose depth reaches 0.95 of the
plate's thickness (NASGRO's transition), whose ligament to the back face falls below 1.5 front_h, or
whose front crosses it, becomes a through crack of its area (a polygon crossing both faces, straight
fronts from face to face); the event is in `result.transitions` as a break-through's, the step that
brought it there counted as the surface crack's, the transition none, and the run stops after the
through crack's solve ("through: ...": its growth is not supported yet).

Heun's step (`corrector=True`): a surface crack's step is solved twice, on the crack and on the
crack its advance predicts, and grown by the mean of the two advances (the second matched at the
same fraction of the front's length): second order in da where the one-solve step is first order
(the rule fed Newman and Raju's K: 0.5% off their a/c at da = 0.1 against 2.7%). Embedded fronts and
the step of a break-through keep the one-solve step.

Stops: after `steps` steps; at fracture; where a grown embedded front nears a face and cannot be
re-characterised (parallel to it, the surface crack not admissible: a sliver to the back face, a held
face; "boundary: ..."), a grown surface crack becomes a through crack ("through: ...", after its solve)
or nears another face (the scene's sliver check, "boundary: ...") or a front nears another crack ("crack: ..."); where the grown crack makes no
valid scene or its solve fails. A scene whose crack comes near a face without crossing it, a surface crack whose centre is off
the surface, or a polygon (its corners have no K), is refused before any meshing.
"""

from __future__ import annotations

import gc
import math
import time
from types import SimpleNamespace

import numpy as np

from ...core.errors import InputError
from ...core.fields import is_finite
from .breakthrough import recharacterise
from .checks import MAX_DA_FRACTION, MAX_STEPS, MIN_DA_TIP_FRACTION, check_corrector, check_flag
from .fatigue import check_paris, delta_K, step_cycles
from .fronts3d import (
    CLEARANCE_RTOL,
    GROW_TOGETHER_RTOL,
    check_growable,
    clearance_reason,
    equivalent_radius,
    grown_crack,
    new_front,
    paris_advance,
    point_values,
    quasi_static_advance,
)
from .surface3d import check_surface_growable, grown_surface_crack, is_surface_crack
from .through import stop_reason, through_crack, through_values

#: da may be at most this fraction of the smallest crack's size (its diameter): a longer step outruns the
#: front's curvature
MAX_DA_CRACK_FRACTION = 0.25
#: a crack whose largest advance is below this fraction of da keeps its shape (it does not grow this step)
STILL_RTOL = 1e-6
#: the options of 2D growth that planar 3D growth has no use for, and why
PLANAR_GROWTH_ONLY = {"criterion": "3D growth is planar (kink_deg reports the MTS kink a non-planar code would take)",
                      "r_c": "the gmts criterion's critical distance is 2D only",
                      "at_hole": "3D bodies have no holes", "estimate": "3D growth computes no error estimate"}
#: the power of the size K grows with over the step of a break-through when only one step of the crack is known
#: (an embedded crack's K ~ sqrt(size))
BREAKTHROUGH_K_POWER = 0.5
#: solve options grow sets itself
_RESERVED = ("warm_start", "crack_mesh", "loads")


def planar_options(criterion, r_c, at_hole, estimate) -> dict:
    """The 2D-only options of grow given other values than their defaults (grow_solid refuses them by name)."""
    given = {"criterion": criterion if criterion != "pls" else None, "r_c": r_c,
             "at_hole": at_hole if not (isinstance(at_hole, str) and at_hole == "stop") else None,
             "estimate": estimate if estimate is not False else None}
    return {k: v for k, v in given.items() if v is not None}




def check_solid_grow(scene, da, steps, K_Ic, paris, R, together, progress, solve_options, planar: dict):
    """grow's checks on a 3D scene, before any meshing; the Paris law (C, m, dK_th) or None."""
    from ngcrack.core.options import SolveOptions
    from ngcrack.solid.options import solid_options
    from ngcrack.solid.stages import check_request

    for key, value in planar.items():
        raise InputError(f"{key} = {value!r}: not an option of 3D growth ({PLANAR_GROWTH_ONLY[key]}); leave it out")
    check_growable(scene)
    if K_Ic is not None and not (is_finite(K_Ic) and K_Ic > 0):
        raise InputError(f"K_Ic = {K_Ic!r}: must be a finite number > 0 (the fracture toughness), or None")
    crack = min(c.size for c in scene.cracks)
    limit = min(MAX_DA_FRACTION * scene.diameter, MAX_DA_CRACK_FRACTION * crack)
    if not (is_finite(da) and 0 < da <= limit):
        raise InputError(f"da = {da!r}: must be a number in (0, {limit:.4g}] (at most {MAX_DA_CRACK_FRACTION:g} of the "
                         f"smallest crack's size {crack:.4g} and {MAX_DA_FRACTION:g} of the body's diameter)")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or not 1 <= steps <= MAX_STEPS:
        raise InputError(f"steps = {steps!r}: must be a whole number in [1, {MAX_STEPS}]")
    if progress is not None and not callable(progress):
        raise InputError(f"progress = {progress!r}: must be None or a callable, called as progress(step, result)")
    if isinstance(together, bool) or not (isinstance(together, (int, float)) and 0 < together < 0.5):
        raise InputError(f"together = {together!r}: must be a number in (0, 0.5) (the points within it of the largest "
                         f"K_eq advance)")
    if solve_options.get("fronts", True) is not True:  # every step advances the fronts by their K
        raise InputError(f"fronts = {solve_options['fronts']!r}: growth computes the fronts' K at every step itself; "
                         f"leave it out")
    bad = [k for k in _RESERVED if k in solve_options]
    if bad:
        raise InputError(f"{bad[0]}: grow sets it for every step itself; give the scene and the mesh options only")
    try:
        options = SolveOptions.of(None, **solve_options)
    except TypeError as exc:
        raise InputError(str(exc)) from None
    options.check_for(scene)
    check_request(scene, solid_options(options, scene), options.max_dof)  # the first solve's size guard, before any run
    front_h = scene.mesh_sizes(solve_options.get("maxh"), solve_options.get("crack_h"), solve_options.get("front_h"),
                               solve_options.get("grading"))["front_h"]
    if da < MIN_DA_TIP_FRACTION * front_h:
        raise InputError(f"da = {da!r}: must be at least {MIN_DA_TIP_FRACTION:g} of the mesh size at the fronts "
                         f"({front_h:.4g}): a shorter advance is not resolved by the mesh; give a larger da")
    return check_paris(paris, R)


class _Cycles:
    """The cumulative cycles of a 3D fatigue run (module docstring): (L, K_max) of the steps so far."""

    def __init__(self, C, m, dK_th, R):
        self.C, self.m, self.dK_th, self.R = C, m, dK_th, R
        self.total = 0.0
        self.history: list[tuple[float, float]] = []

    def step(self, L: float, K_max: float, da: float | None) -> float:
        """The total after a step whose leading point advanced by `da` (None: step 0) to a crack of size L."""
        if da is not None and self.history:
            L0, K0 = self.history[-1]
            if L > L0 and K0 > 0 and K_max > 0:
                pts = (self.history + [(L, K_max)])[-3:]
                try:
                    self.total += step_cycles([p[0] for p in pts], [p[1] for p in pts], self.C, self.m, self.R, da)
                except ValueError:  # not monotone: the trapezoid rule
                    self.total += 0.5 * da * sum(1.0 / (self.C * delta_K(k, self.R) ** self.m) for k in (K0, K_max))
            else:
                self.history = []
        self.history.append((L, K_max))
        return self.total

    def breakthrough(self, L: float, da: float) -> float:
        """The total after the step in which the leading crack, grown by `da` to the size L, broke through a face
        (breakthrough.py): K at L extrapolated as the power of the size through the last two steps (K ~ sqrt(L) with
        one); the history starts afresh with the surface crack."""
        if self.history and L > self.history[-1][0]:
            (L1, K1), p = self.history[-1], BREAKTHROUGH_K_POWER
            if len(self.history) > 1 and self.history[-2][0] < L1 and self.history[-2][1] > 0:
                L0, K0 = self.history[-2]
                p = math.log(K1 / K0) / math.log(L1 / L0)
            if K1 > 0:
                self.total += step_cycles([L1, L], [K1, K1 * (L / L1) ** p], self.C, self.m, self.R, da)
        self.history = []
        return self.total


def grow_solid(scene, da: float, steps: int, K_Ic: float | None = None, *, paris=None, R: float = 0.0,
               together: float = GROW_TOGETHER_RTOL, progress=None, frames: bool = True, planar: dict | None = None,
               corrector: bool = False, **solve_options):
    """Grow the planar cracks of a 3D scene (module docstring); a SolidGrowthResult. `planar`: the 2D-only
    options the caller was given (refused by name). `corrector`: the surface cracks' steps by Heun's
    predictor-corrector (module docstring: two solves a step, second order in da)."""
    from ngcrack.core.solve import solve

    from .result3d import SolidGrowthResult

    corrector = check_corrector(corrector, scene)
    check_flag(frames, "frames", "keep every step's deformed body for the animation")
    fatigue = check_solid_grow(scene, da, steps, K_Ic, paris, R, together, progress, solve_options, planar or {})
    da, steps = float(da), int(steps)
    cycles = None if fatigue is None else _Cycles(*fatigue, R=float(R))
    result = SolidGrowthResult(scene=scene, element=solve_options.get("element") or "tdnns", da=da,
                               K_Ic=None if K_Ic is None else float(K_Ic), paris=fatigue, R=float(R))
    nu = scene.material.nu
    t0 = time.perf_counter()
    sol = solve(scene, **solve_options)
    elapsed, K_ref, leader_da, solves = time.perf_counter() - t0, K_Ic, None, 1
    through_stop = ""  # set once a crack became a through crack (through.py): the run stops after its solve

    def rule(values):
        """The advance of every front's points at a solve's K (fatigue: Paris; else quasi-static)."""
        top = max(float(np.max(v["K_drive"])) for v in values)
        if cycles is not None:
            return [paris_advance(v["K_drive"], da, cycles.m, cycles.R, cycles.dK_th, top=top) for v in values]
        return [quasi_static_advance(v["K_drive"], da, together, top=top) for v in values]

    for n in range(steps + 1):
        values = [through_values(f, nu) if scene.cracks[f.crack].shape == "polygon" else point_values(f, nu, scene)
                  for f in sol.fronts]
        K_top = max(float(np.max(v["K_drive"])) for v in values)
        lead = int(np.argmax([np.max(v["K_drive"]) for v in values]))
        crack_of_lead = sol.fronts[lead].crack
        total = None
        if cycles is not None:
            total = cycles.step(equivalent_radius(scene.cracks[crack_of_lead]), K_top, leader_da)
        if K_ref is None:
            K_ref = K_top  # relative load factors: 1 at step 0
        load_factor = 1.0 if cycles is not None else (K_ref / K_top if K_top > 0 else math.inf)
        reason = ""
        if K_top <= 0:
            reason = "no front can grow: K_eq = 0 at every front point (the faces closed or unloaded)"
        elif cycles is not None and K_Ic is not None and K_top >= K_Ic:
            reason = (f"fracture: K_max = {K_top:.4g} on crack[{crack_of_lead}] reached K_Ic = {K_Ic:.4g} (the crack runs "
                      f"on the next cycle)")
        if not reason and through_stop:
            reason = through_stop
        advances = rule(values)
        if cycles is not None and not reason and n < steps and not any(np.max(a) > 0 for a in advances):
            reason = f"threshold: Delta K is at or below Delta K_th = {cycles.dK_th:g} at every front point"
        grows = not reason and n < steps
        result.add_step(n, scene, sol, values, advances if grows else None, load_factor, elapsed, total, solves)
        if progress is not None:
            progress(n, result)
        if n == steps:
            reason = f"steps: {steps} of {steps} steps done"
        if reason:
            result.stopped = reason
            break
        broke: list[dict] = []
        front_h = scene.mesh_sizes(solve_options.get("maxh"), solve_options.get("crack_h"), solve_options.get("front_h"),
                                   solve_options.get("grading"))["front_h"]
        new_scene, reason, lead_advance = _grown_scene(scene, sol, values, advances, da, cycles is not None, lead, broke,
                                                       front_h)
        elapsed, solves = 0.0, 1
        surface = [k for k, f in enumerate(sol.fronts) if is_surface_crack(scene.domain, scene.cracks[f.crack])]
        if corrector and not reason and not broke and surface:  # Heun: the step again with the mean advance
            fronts = SimpleNamespace(fronts=[SimpleNamespace(crack=f.crack, angle=np.asarray(f.angle)) for f in sol.fronts])
            sol = None
            gc.collect()
            t0 = time.perf_counter()
            try:
                sol = solve(new_scene, **solve_options)
            except (RuntimeError, InputError) as exc:
                result.stopped = f"solve: the predictor's solve after step {n} failed ({exc})"
                break
            elapsed, solves = time.perf_counter() - t0, 2
            mean = corrected(scene, new_scene, fronts, advances, sol, rule([point_values(f, nu, new_scene) for f in sol.fronts]),
                             surface)
            sol = None
            new_scene, reason, lead_advance = _grown_scene(scene, fronts, values, mean, da, cycles is not None, lead, broke,
                                                           front_h)
        if reason:
            result.stopped = reason
            result.events.append((n, reason))
            break
        for info in broke:  # an embedded crack became a surface crack (breakthrough.py), a surface one a through crack
            result.events.append((n + 1, info["what"]))
            result.transitions.append({"step": n + 1, **info})
            if info["event"] == "through":
                through_stop = stop_reason(info)
            if cycles is not None and info["crack"] == crack_of_lead:
                cycles.breakthrough(info["embedded_size"], da if info["event"] == "surface" else lead_advance)
                lead_advance = None  # the new crack's cycles count from its first solve
        sol = None  # the old solve's memory goes before the new one's mesh is made (a 3D solve is GBs;
        gc.collect()  # NGSolve's objects hold reference cycles, which only the collector frees)
        t0 = time.perf_counter()
        try:
            sol = solve(new_scene, **solve_options)
        except (RuntimeError, InputError) as exc:  # SolveError, a mesh failure: keep what was done
            result.stopped = f"solve: the solve after step {n} failed ({exc})"
            break
        scene, elapsed, leader_da = new_scene, elapsed + time.perf_counter() - t0, lead_advance
    result.solution = sol
    return result


def _grown_scene(scene, sol, values, advances, da, smooth, lead: int = 0, events: list | None = None,
                 front_h: float | None = None):
    """(the scene with every front advanced, "", the advance of the leading point), or (None, why the run stops,
    None). The leading point (the largest K_drive of front `lead`) advanced by da, or, on a surface crack,
    by what the fitted ellipse gives it (surface3d.py; a curve: da). An embedded crack that nears a face becomes a surface
    crack (breakthrough.py): what happened is appended to `events` (dictionaries)."""
    from ngcrack.core.fields import SceneError
    from ngcrack.solid.scene import SolidScene, crack_from_dict

    d = scene.to_dict()
    grown, lead_advance, surface, broke = {}, da, set(), []
    for k, (f, adv) in enumerate(zip(sol.fronts, advances)):
        if np.max(adv) <= STILL_RTOL * da:
            continue
        crack = scene.cracks[f.crack]
        if is_surface_crack(scene.domain, crack):  # the ellipse (or the curve) through the advanced points
            top = int(np.argmax(values[k]["K_drive"])) if values is not None else int(np.argmax(adv))
            d["crack"][f.crack], moved = grown_surface_crack(scene.domain, crack, f.angle, adv, top)
            if k == lead:
                lead_advance = moved
            if front_h is not None:  # near the back face: re-characterised as a through crack (through.py)
                try:
                    through_d, info, why = through_crack(scene.domain, crack, crack_from_dict(d["crack"][f.crack], f.crack),
                                                         f.crack, front_h)
                except SceneError:
                    through_d, info, why = None, None, ""
                if why:
                    return None, why, None
                if through_d is not None:
                    d["crack"][f.crack] = through_d
                    broke.append(info)
                    continue
            grown[f.crack] = None
            surface.add(f.crack)
            continue
        points = new_front(crack, adv, f.angle, smooth)
        d["crack"][f.crack] = grown_crack(crack, points)
        grown[f.crack] = points
        try:  # near a face: re-characterised as a surface crack (breakthrough.py)
            surface_d, info, why = recharacterise(scene.domain, crack_from_dict(d["crack"][f.crack], f.crack), f.crack,
                                                  CLEARANCE_RTOL)
        except SceneError:
            surface_d, info, why = None, None, ""
        if why:
            return None, why, None
        if surface_d is not None:
            d["crack"][f.crack] = surface_d
            grown[f.crack] = None
            broke.append(info)
    try:
        new = SolidScene.from_dict(d)
        for info in broke:
            if info["event"] == "surface":
                check_surface_growable(new.domain, info["crack"], new.cracks[info["crack"]])
    except (SceneError, InputError) as exc:
        if broke and broke[0]["event"] == "through":
            return None, f"boundary: {broke[0]['what']}, but the through crack is no admissible crack: {exc}", None
        if broke:
            info = broke[0]
            return None, (f"boundary: crack[{info['crack']}] nears face {info['face']} (ligament {max(info['ligament'], 0):.3g}"
                          f", half-height {info['half_height']:.3g}), but the surface crack it is re-characterised as "
                          f"(depth {info['depth']:.4g}, half-length {info['surface_half_length']:.4g}) is no admissible "
                          f"crack: {exc}"), None
        for i in grown:  # the named reasons first: a face or another crack reached
            try:
                why = clearance_reason(scene, i, crack_from_dict(d["crack"][i], i))
            except SceneError:
                why = ""
            if why:
                return None, why, None
        if surface:
            return None, (f"boundary: the grown surface crack is no valid crack ({exc}); a surface crack's front that "
                          f"nears another face (the body's back face or its sides) stops the growth"), None
        return None, f"scene: the grown fronts make no valid scene ({exc})", None
    for i in grown:
        why = clearance_reason(new, i, new.cracks[i])
        if why:
            return None, why, None
    if events is not None:
        events.extend(broke)
    return new, "", lead_advance


def corrected(scene, predicted, fronts, advances, sol_p, advances_p, surface: list) -> list:
    """Heun's advance: on the surface cracks' fronts (indices `surface` of `fronts`), the mean of each station's
    advance on the scene and of the advance at the same fraction of the front's length on the predicted crack (its
    solve `sol_p`, advances `advances_p`); the other fronts keep theirs."""
    from .surface3d import ellipse_arc

    out = [np.asarray(a, dtype=float) for a in advances]
    for k in surface:
        crack = fronts.fronts[k].crack
        match = [j for j, f in enumerate(sol_p.fronts) if f.crack == crack]
        if len(match) != 1:
            continue
        f_p = sol_p.fronts[match[0]]
        s = ellipse_arc(scene.cracks[crack], np.asarray(fronts.fronts[k].angle, dtype=float))
        s_p = ellipse_arc(predicted.cracks[crack], np.asarray(f_p.angle, dtype=float))
        out[k] = 0.5 * (out[k] + np.interp(s / s[-1], s_p / s_p[-1], np.asarray(advances_p[match[0]], dtype=float)))
    return out
