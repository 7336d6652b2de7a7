"""The growth loop: solve -> fracture parameters -> kink -> extend -> remesh, one row per step and tip.

Each step solves the static problem of the current scene (contact and friction
included; the previous step's contact set warm-starts the QP where the solve uses one),
takes K_I, K_II, G at every tip inside the body (`sol.tips`), and for the tips that grow
chooses the kink (criteria.py) and adds a segment of length da (paths.py). The next
step's solve meshes the grown scene afresh: the new tip is graded as a tip (tip_h), the
path from crack_h at the tips coarser with the distance from them (path_grading).

Load. Under one proportional load, unilateral contact and Coulomb friction make the static
problem positively homogeneous of degree one in the load: the solution at lambda times
the scene's load is lambda times the solution at the scene's load. So each step gives
the load factor at which a tip grows exactly: lambda = K_Ic / K_eq, K_eq the MTS
equivalent factor at the scene's load (criteria.mts_keq, K_I = 0 where the faces at the
tip are closed). This is the static, proportional-loading answer: the path dependence of
friction within a step (the slip history between two load levels) is not modelled. The
step's load factor is the smallest over its tips; tips whose lambda lies within
GROW_TOGETHER_RTOL of it grow together, the others wait. Without K_Ic, lambda is
relative to the first step: K_Ic is taken as the largest K_eq of step 0 (lambda_0 = 1).
The same K_eq gives the load factor under both criteria (PLS chooses only the direction).

Kink. `criterion="mts"` kinks each growing tip by the MTS angle of its K; `"pls"` by the
angle that makes K_II vanish at the new tip: trial extensions of every growing tip at
once, until every new tip's K_II is within PLS_ANGLE_TOL of the PLS angle (|K_II| at most
PLS_ANGLE_TOL times dk_2/dtheta) or MAX_TRIALS solves; the last trial's solve is the next
step's. The first trial angle (criteria.pls_predictor) is the PLS angle of the kinked-crack
relations for the tip's K (criteria.pls_kink_angle) at a tip's first kink or after a large
one, else the tip's previous kink (a smooth path's curvature) corrected for the K_II left
at its tip by the slope dk_2/dtheta measured at its last trials; the next trials take
Newton steps with that slope (PLS_SLOPE K_I before any is measured), then secant steps
within a bracket of K_II = 0. Most steps of a smooth path take one solve.

Open tips only. Both criteria assume that the new tip is open: MTS maximises a tensile hoop
stress, PLS asks K_II = 0 of a tip that opens (a tip closed and stuck by friction has
K_II = 0 at any angle, which says nothing of the direction). A trial whose new tip comes out
closed (faces touching at the tip, or K_I <= 0) is not kept: the tip is tried again at half
the kink, towards straight ahead; a tip still closed after MAX_TRIALS solves, or closed
straight ahead, stops (`frozen`, with the reason) and the others grow on. When no tip is
left to grow the run stops, naming why. A tip whose K_eq is at the noise level of the
computed K, measured on the load's scale at its crack (drive.py), or below DRIVE_NOISE_RTOL of
the run's largest, has no driving force: it neither grows nor kinks.

Why PLS is the default (measured on the wings of a 45-degree crack with mu = 0.3 under
compression, da = a/10, bdm): the K_II at the tip of a new segment responds to its kink
angle at about 1.5 K_I per radian, three times the small-kink value K_I/2 that the MTS
angle -2 K_II/K_I assumes, so each explicit MTS step overcorrects about threefold and the
path zig-zags with a growing amplitude (kinks +7, -24, +22, -36, +40, -49 degrees), while
PLS turns smoothly (kinks -4.6, -4.1, -2.9, -2.5, -1.8 degrees), at 1.25 solves per step
on the README's teaching scene (benchmarks/growth.py). On a straight path both agree: |K_II| below KINK_NOISE_RTOL K_eq is taken as 0.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import shapely

from ngcrack.core.pipeline import SolveError
from ngcrack.planar.scene import SceneError, tip_label

from ...core.errors import InputError
from .checks import MAX_DA_FRACTION as MAX_DA_FRACTION
from .checks import MAX_STEPS as MAX_STEPS
from .checks import check_grow_call
from .checks import check_growth_options as check_growth_options
from .criteria import (
    PLS_SLOPE,
    effective_K_I,
    gmts_angle,
    gmts_keq,
    load_factor,
    mts_angle,
    mts_keq,
    newton_angle,
    pls_predictor,
    secant_angle,
)
from .drive import noise_reasons
from .fatigue import Cycles
from .holes import HOLE_REASON, leave_holes
from .paths import body_region, cut_through, extend_tip, extended_cracks, pieces, tip_direction
from .solves import COST_PARTS, Solver, on_rank_zero, solve_step

#: tips whose load factor lies within this fraction of the smallest grow together
GROW_TOGETHER_RTOL = 0.02
#: PLS: a trial is kept where its new tip's K_II is at most this angle (radians) times dk_2/dtheta
#: (the tip's measured slope, else PLS_SLOPE K_I): the angle is within it of the PLS angle. The K_II
#: left is corrected at the next step's first trial (pls_predictor), so the path does not drift;
#: the K_II of a new tip scatters by about 3% of its K_I from one mesh to the next (measured on the
#: wings of the inclined-compression scene), about 1 degree
PLS_ANGLE_TOL = math.radians(1.5)
#: a new tip that comes out closed at a kink below this (radians) closes straight ahead too: it stops
#: without halving the kink further
CLOSED_STRAIGHT = math.radians(1.0)
#: the most trial solves per step (PLS trials, and new tips that came out closed; the last one is the
#: next step's solve); a tip still closed after them stops, and one more solve grows the others
MAX_TRIALS = 4
#: PLS: the largest change of the angle between two trials (radians)
PLS_MAX_STEP = math.radians(30.0)
#: |K_II| at most this fraction of K_eq is noise of the computed K (measured: 5e-4 on the
#: Griffith plate, 1e-3 between the two symmetric tips of a wing crack): the kink is 0
#: (below 0.6 degrees), and a straight path on a symmetry line stays on it exactly
KINK_NOISE_RTOL = 5e-3
#: a tip whose K_eq is below this fraction of the largest K_eq of the run so far has no driving
#: force (its K is the noise of the computed K, its load factor would be a thousand times the others')
DRIVE_NOISE_RTOL = 1e-3


def _closed_at(sol, tip) -> bool:
    """Whether the crack faces at the tip touch: the tip's own `closed` (ngcrack.planar.tips.tip_closed;
    with contact its K_I is then 0)."""
    return bool(tip.closed)


def tip_values(sol, criterion: str = "mts", r_c: float | None = None) -> list[dict]:
    """Per tip inside the body: K_I, K_II, G, T, closed, the kink angle and K_eq at the scene's load
    (MTS; with criterion "gmts" the generalized MTS at the critical distance r_c, with T)."""
    out = []
    for t in sol.tips:
        closed = _closed_at(sol, t)
        k1 = effective_K_I(t.K_I, closed)
        K_II = float(t.K_II)
        if abs(K_II) <= KINK_NOISE_RTOL * abs(mts_keq(k1, K_II)):
            K_II = 0.0  # noise: no kink
        T = float(getattr(t, "T", 0.0))
        if criterion == "gmts":
            theta = gmts_angle(k1, K_II, T, r_c)
            K_eq = gmts_keq(k1, K_II, T, r_c, theta)
        else:
            theta = mts_angle(k1, K_II)
            K_eq = mts_keq(k1, K_II, theta)
        out.append({"label": t.label, "crack": int(t.crack), "end": t.end, "x": float(t.x), "y": float(t.y),
                    "K_I": float(t.K_I), "K_II": float(t.K_II), "G": float(t.G), "T": T, "closed": bool(closed),
                    "theta": theta, "K_eq": float(K_eq), "K_II_kink": K_II})
    return out


def grow(scene, da: float, steps: int, K_Ic: float | None = None, criterion: str = "pls", *,
         together: float = GROW_TOGETHER_RTOL, frames: bool = True, progress=None, r_c: float | None = None,
         paris=None, R: float = 0.0, at_hole="stop", estimate: bool = False,
         **solve_options):
    """Grow the cracks of `scene` quasi-statically by segments of length `da`; a GrowthResult.

    criterion: "pls" (principle of local symmetry by trial extensions, the default: smooth
    paths), "mts" (maximum tangential stress, one solve per step; zig-zags where the path
    curves, see the module docstring) or "gmts" (the generalized MTS with the T-stress at the
    critical distance r_c, a material length: criteria.gmts_angle; one solve per step). K_Ic: the fracture toughness (None: load factors relative
    to the first step). steps: at most MAX_STEPS. together: tips whose load factor lies
    within this fraction of the step's smallest grow together. frames: keep the deformed
    body of every step for `GrowthResult.animate`. progress: called as progress(step,
    result_so_far) after every step. The other keywords go to every solve
    (element, order, maxh, tip_h, crack_h, grading, qp_solver, crack_model, friction_method, ...);
    path_grading and, with friction, friction_method: growth's own defaults unless given (solves.py).
    paris: (C, m) for fatigue (fatigue.py): the load is the scene's (the cycle's maximum, load
    factor 1), R the load ratio; every step advances the leading tip by da and every other tip
    by its share of the same cycles, da (Delta K_i / Delta K_max)^m (paris=(C, m, dK_th): none
    at or below the threshold dK_th); the `cycles` column counts the cycles (Paris law
    da/dN = C Delta_K^m integrated over the step), and the run stops when K_max reaches K_Ic.
    A tip reaching the boundary stops there; where the cracks then cut the body in pieces the
    run ends ("cut through", the last segment kept in `paths`). A tip reaching a hole joins it
    (the crack ends on the hole's edge, the ligament is cut, the other tips grow on; a body
    that comes apart so ends the run "cut through" too); at_hole: "stop" (the default), or a
    length L0: a new crack of that length leaves the hole where its hoop stress is largest (holes.py). Tips stop before meeting a
    crack, or where their new tip would close (frozen, with the reason); the run stops after
    `steps` steps, when no tip is left inside the body, or when none can grow.
    estimate: also compute every step's error estimate (the table's `error_estimate` column,
    empty otherwise; it costs about 5% of a step).
    A 3D scene grows its fronts in their planes (loop3d.grow_solid: da, steps, K_Ic, paris, R, corrector and the solve options).
    Under `mpiexec -n N` (N > 1) growth is not distributed: rank 0 grows and returns the result, the other
    ranks return None after the same input checks (as `nc.solve` returns None there).
    """
    from .result import GrowthResult

    if isinstance(scene, str):  # a built-in scene's name: its kind decides the loop
        from ngcrack.core.solve import as_scene

        scene = as_scene(scene)
    if getattr(scene, "dimension", 2) == 3:  # planar growth of 3D fronts (loop3d.py)
        from .loop3d import grow_solid, planar_options

        return grow_solid(scene, da, steps, K_Ic, paris=paris, R=R, together=together, progress=progress, frames=frames,
                          planar=planar_options(criterion, r_c, at_hole, estimate), **solve_options)
    if "corrector" in solve_options:
        raise InputError(f"corrector = {solve_options['corrector']!r}: an option of 3D growth (Heun's step of surface "
                         f"cracks); scene {getattr(scene, 'name', scene)!r} is 2D: leave it out")
    scene, r_c, fatigue, hole_crack = check_grow_call(scene, da, steps, K_Ic, criterion, together, progress, r_c,
                                                    paris, R, at_hole, solve_options, estimate, frames)
    da, steps = float(da), int(steps)
    options = Solver.of(scene, solve_options)
    if not on_rank_zero():  # not distributed: under mpiexec rank 0 grows, the others return None at once
        return None
    result = GrowthResult(scene=scene, element=options.options.element, criterion=criterion, da=da,
                          K_Ic=None if K_Ic is None else float(K_Ic), r_c=r_c, estimates=bool(estimate))
    t0 = time.perf_counter()
    sol = solve_step(scene, None, options)
    elapsed = time.perf_counter() - t0
    run = _Run(scene=scene, sol=sol, solver=options, result=result, region=body_region(scene), criterion=criterion,
               da=da, together=together, r_c=r_c, K_Ic=K_Ic, hole_crack=hole_crack,
               cycles=Cycles(*fatigue, R=float(R)) if fatigue else None, elapsed=elapsed,
               parts=options.since(dict.fromkeys(COST_PARTS, 0.0)), K_ref=K_Ic)
    stopped = ""
    for n in range(steps + 1):
        values = _fracture_parameters(run)
        step = _Step()
        if run.cycles is not None:
            run.cycles.grown(run.scene, values, run.last_grew)
            step.fractured = run.cycles.fracture(values, K_Ic)
        if n < steps and not step.fractured:
            _direction_and_extension(run, values, step, n)
            if run.cycles is not None:
                run.cycles.growing(run.scene, values, {v["label"] for v in step.growing})
        _record_step(run, n, values, step, frames, progress)
        reason = _stop_reason(run, n, steps, step)
        if reason is None and run.hole_crack is not None:
            reason = _leave_holes(run, n, values, step)
        if reason is None:
            reason = _next_step(run, values, step)
        if reason is not None:
            stopped = reason
            break
    result.stopped = stopped
    result.solution = run.sol
    result.frozen = dict(run.frozen)
    return result


@dataclass
class _Run:
    """What a growth run carries from one step to the next: the current scene and its solve, and the
    tips' history (frozen tips with their reasons, previous kinks, measured PLS slopes)."""

    scene: object
    sol: object
    solver: Solver
    result: object
    region: object
    criterion: str
    da: float
    together: float
    r_c: float | None
    K_Ic: float | None
    hole_crack: object
    cycles: Cycles | None
    #: the seconds, cost parts and solves of the current solve (the step's row)
    elapsed: float
    parts: dict
    trials: int = 1
    frozen: dict = field(default_factory=dict)
    #: tip -> its last kink after its first (radians), None after the first
    grown_once: dict = field(default_factory=dict)
    #: tip -> dk_2/dtheta measured at its last step's trials (PLS)
    slopes: dict = field(default_factory=dict)
    #: the holes a new crack has left, and the tips that reached them
    passed: set = field(default_factory=set)
    last_grew: set = field(default_factory=set)
    K_ref: float | None = None
    #: the largest K_eq of the run so far: a K_eq below DRIVE_NOISE_RTOL of it is no drive
    K_top: float = 0.0
    #: tip -> why the current step's load does not drive it (drive.py: its K_eq is noise)
    undriven: dict = field(default_factory=dict)


@dataclass
class _Step:
    """What one step does: the tips chosen to grow, their extensions, the next scene and its solve
    (with its cost and solves), and why the run stops here if it does (failed, fractured)."""

    growing: list = field(default_factory=list)
    extensions: list = field(default_factory=list)
    next_scene: object = None
    next_sol: object = None
    cost: float = 0.0
    tried: int = 0
    cost_parts: dict = field(default_factory=lambda: dict.fromkeys(COST_PARTS, 0.0))
    failed: str = ""
    fractured: str = ""
    #: label -> extension of the tips that grew
    grew: dict = field(default_factory=dict)


def _fracture_parameters(run: _Run) -> list[dict]:
    """The tips' values at the current solve, with each tip's load factor `lambda` (inf: no drive)."""
    values = tip_values(run.sol, run.criterion, run.r_c)
    run.undriven = noise_reasons(run.sol, run.scene, values)
    for v in values:
        if v["label"] in run.undriven:  # noise: no kink either
            v["theta"], v["K_II_kink"] = 0.0, 0.0
    drive = [v["K_eq"] for v in values if v["K_eq"] > 0 and v["label"] not in run.undriven]
    run.K_top = max([run.K_top] + drive)
    if run.K_ref is None:
        run.K_ref = max(drive) if drive else None
    for v in values:
        driven = run.K_ref is not None and v["label"] not in run.undriven and v["K_eq"] > DRIVE_NOISE_RTOL * run.K_top
        v["lambda"] = load_factor(run.K_ref, v["K_eq"]) if driven else math.inf
    return values


def _direction_and_extension(run: _Run, values: list[dict], step: _Step, n: int) -> None:
    """Choose the tips that grow (the smallest load factor, and those within `together` of it), kink
    and extend them and solve the grown scene (_advance), into `step`; where every chosen tip
    freezes, choose again among the others."""
    while True:
        active = [v for v in values if v["label"] not in run.frozen and math.isfinite(v["lambda"])]
        if not active:
            return
        lam_min = min(v["lambda"] for v in active)
        step.growing = [v for v in active if v["lambda"] <= lam_min * (1.0 + run.together)]
        if run.cycles is not None:  # fatigue: every driven tip by its share of the step's cycles
            step.growing = run.cycles.increments(active, run.da)
            if not step.growing:
                return
        t1, before = time.perf_counter(), dict(run.solver.spent)
        try:
            out = _advance(run.scene, run.sol, run.region, step.growing, run.da, run.criterion, run.solver,
                           run.frozen, run.grown_once, run.slopes)
        except (SolveError, InputError) as exc:  # e.g. the grown mesh above max_dof: keep what was done
            step.failed = f"solve: the solve after step {n} failed ({exc})"
            step.growing = []
            return
        step.cost, step.cost_parts = time.perf_counter() - t1, run.solver.since(before)
        if out is None:  # every chosen tip froze: choose again among the others
            step.growing = []
            continue
        step.extensions, step.next_scene, step.next_sol, step.tried = out
        return


def _record_step(run: _Run, n: int, values: list[dict], step: _Step, frames: bool, progress) -> None:
    """The step's row in the result (its tips, load factor, cost and events), then the progress callback."""
    grew = {tip_label(e.crack, e.end): e for e in step.extensions if e.point is not None}
    for e in step.extensions:  # a tip that has grown up to a hole stops there
        if e.outcome == "hole":
            run.frozen[tip_label(e.crack, e.end)] = e.reason
    if run.criterion == "pls":  # the tips that did not grow: the first PLS trial's angle
        for v in values:
            if v["label"] not in grew:
                v["kink"] = pls_predictor(effective_K_I(v["K_I"], v["closed"]), v["K_II_kink"],
                                          run.grown_once.get(v["label"]), run.slopes.get(v["label"]))
    lam_step = min((v["lambda"] for v in values if v["label"] in grew), default=None)
    if lam_step is None:
        lam_step = min((v["lambda"] for v in values if v["label"] not in run.frozen), default=math.inf)
    if run.cycles is not None:  # fatigue: the scene's load, the cycle's maximum
        lam_step = 1.0
    for v in values:  # a tip that stopped inside the body: why, in the step's row
        v["stopped"] = run.frozen.get(v["label"], "")
    result = run.result
    result.add_step(n, run.scene, run.sol, values, lam_step, grew, run.elapsed, run.trials, frames=frames,
                    parts=run.parts, cycles=None if run.cycles is None else run.cycles.total)
    result.solution = run.sol  # this step's solve, for the progress callback (ngcrack.planar.vtk.SeriesWriter)
    if progress is not None:
        progress(n, result)
    for e in step.extensions:
        if e.outcome in ("boundary", "hole"):
            result.events.append((n, tip_label(e.crack, e.end), e.reason))
    step.grew = grew


def _stop_reason(run: _Run, n: int, steps: int, step: _Step) -> str | None:
    """Why the run stops after this step (fracture, the last step, a failed solve, a cut-through, a
    refused grown scene), or None."""
    if step.fractured:
        return step.fractured
    if n == steps:
        return f"steps: {steps} of {steps} steps done"
    if step.failed:
        return step.failed
    if isinstance(step.next_scene, CutThrough):  # failure: the run ends with the last segment kept
        run.result.add_final(step.next_scene.scene, cracks=step.next_scene.cracks)
        return step.next_scene.reason
    if isinstance(step.next_scene, str):  # the grown scene was refused
        return step.next_scene
    return None


def _leave_holes(run: _Run, n: int, values: list[dict], step: _Step) -> str | None:
    """New cracks leaving the holes that tips reached (holes.py), and the solve of the scene with
    them, into `step`; the reason if that solve fails, else None. Where a tip joined a hole, the hoop
    stress is that of the joined scene (the hole is then the crack's blunt end): its solve, made here
    where no tip was left to solve it for."""
    scene, sol = (run.scene, run.sol) if step.next_scene is None else (step.next_scene, step.next_sol)
    if sol is None:
        joined = any(HOLE_REASON.search(why) and "joined it" in why and lab not in run.passed
                     for lab, why in run.frozen.items())
        sol = run.sol
        if joined and not isinstance(scene, (str, CutThrough)):
            try:
                sol = solve_step(scene, run.sol, run.solver)
            except (SolveError, InputError) as exc:
                return f"solve: the solve after step {n} failed ({exc})"
            step.tried += 1
    left = leave_holes(scene, sol, values, run.frozen, run.passed, run.hole_crack)
    for lab, what in left.events:
        run.result.events.append((n, lab, what))
    if left.scene is None:
        return None
    t1, before = time.perf_counter(), dict(run.solver.spent)
    try:
        step.next_sol = solve_step(left.scene, step.next_sol or run.sol, run.solver)
    except (SolveError, InputError) as exc:
        return f"solve: the solve after step {n} failed ({exc})"
    step.next_scene, step.tried = left.scene, step.tried + 1
    step.cost += time.perf_counter() - t1
    step.cost_parts = {k: step.cost_parts[k] + v for k, v in run.solver.since(before).items()}
    step.grew = step.grew or {"new crack": None}
    return None


def _next_step(run: _Run, values: list[dict], step: _Step) -> str | None:
    """Move the run on to the grown scene and its solve; the reason the run stops if no tip grew or
    none is left inside the body, else None."""
    if not step.grew:
        reasons = "; ".join([*run.frozen.values(), *(why for lab, why in run.undriven.items() if lab not in run.frozen)])
        return ("no tip can grow: " + reasons) if reasons else "no tip can grow: no tip has K_eq > 0"
    # a tip's previous kink predicts its next one (PLS) only once it grows from a grown segment
    run.grown_once.update({v["label"]: v["kink"] if v["label"] in run.grown_once else None
                           for v in values if v["label"] in step.grew})
    run.scene = step.next_scene
    if step.next_sol is None:  # no tip left inside the body
        run.result.add_final(run.scene)
        joined = any("joined it" in why for why in run.frozen.values())
        return ("boundary: every tip reached the body's boundary or joined a hole" if joined
                else "boundary: every tip reached the body's boundary (the cracks cut through)")
    run.sol, run.elapsed, run.trials, run.parts = step.next_sol, step.cost, step.tried, step.cost_parts
    run.last_grew = set(step.grew)
    return None


def _extend(scene, region, angles: dict, growing: list[dict], da: float, frozen: dict) -> list:
    """The extensions of the growing tips at the absolute angles `angles` (label -> radians);
    tips that would meet a crack are frozen (their reason kept)."""
    out, new_segments = [], []
    for v in growing:
        if v["label"] in frozen:
            continue
        ext = extend_tip(scene, region, v["crack"], v["end"], angles[v["label"]], v.get("da", da), new_segments)
        if ext.point is None:  # a crack in the way, or a hole right ahead: the tip stops where it is
            frozen[v["label"]] = ext.reason
            continue
        p = (v["x"], v["y"])
        new_segments.append((v["label"], shapely.LineString([p, ext.point])))
        out.append(ext)
    return out


@dataclass(frozen=True)
class CutThrough:
    """The grown cracks cut the body in two (or more): the end of the run. `cracks`: the grown
    cracks' points; `scene`: the grown scene where it is a valid one (every piece still held), else None."""

    reason: str
    cracks: list
    scene: object = None


def _cut(scene, region, extensions) -> CutThrough | None:
    """A CutThrough where a tip reaching the boundary or joining a hole separates a piece of the body, else None."""
    ends = [e for e in extensions if e.outcome in ("boundary", "hole") and e.point is not None]
    if not ends:
        return None
    cracks = extended_cracks(scene, extensions)
    after = [c.points for c in cracks]
    if not cut_through(region, [c.points for c in scene.cracks], after):
        return None
    new = _grown(scene, extensions)
    where = ", ".join(f"tip {tip_label(e.crack, e.end)} at ({e.point[0]:.4g}, {e.point[1]:.4g})" for e in ends)
    what = "the boundary" if all(e.outcome == "boundary" for e in ends) else (
        "a hole" if all(e.outcome == "hole" for e in ends) else "the boundary or a hole")
    return CutThrough(f"cut through: {where} reached {what} and the cracks cut the body in "
                      f"{pieces(region, after)} pieces", after, None if isinstance(new, str) else new)


def _grown(scene, extensions):
    """The grown scene, or the reason (a string) why the grown cracks make no valid scene."""
    try:
        return scene.with_(cracks=extended_cracks(scene, extensions))
    except SceneError as exc:
        return f"scene: the grown cracks make an invalid scene ({exc})"


def _open_tip(sol, t) -> bool:
    """Whether the tip `t` of `sol` is open: faces apart at the tip and K_I > 0 (the state MTS and PLS assume)."""
    return float(t.K_I) > 0.0 and not _closed_at(sol, t)


def _closes_reason(lab: str, tried: list, criterion: str) -> str:
    angles = ", ".join(f"{math.degrees(a):+.1f}" for a in tried)
    return (f"tip {lab}: the new tip's faces close at every kink tried ({angles} degrees); {criterion} assumes an "
            "open tip, and a closed tip would grow only in shear, by a criterion ngcrack does not have")


def _measured_slope(history: list) -> float | None:
    """dk_2/dtheta from the last two open trials of a tip (None with fewer, or a slope <= 0,
    which the kinked-crack relations rule out near the PLS angle)."""
    if len(history) < 2:
        return None
    (a0, g0), (a1, g1) = history[-2:]
    if a1 == a0 or (g1 - g0) / (a1 - a0) <= 0:
        return None
    return (g1 - g0) / (a1 - a0)


def _next_angle(history: list, slope: float) -> float:
    """The next PLS trial angle from the open trials (angle, K_II at the new tip) so far: the
    secant within the closest pair that brackets K_II = 0 where one does, else the secant of
    the last two, else a Newton step with `slope` (dk_2/dtheta: the tip's measured one
    from its last step, else PLS_SLOPE times the new tip's K_I or the parent tip's K_eq)."""
    a1, g1 = history[-1]
    pos = [(a, g) for a, g in history if g > 0]
    neg = [(a, g) for a, g in history if g < 0]
    if pos and neg:
        (a0, g0), (a1, g1) = min(((p, q) for p in pos for q in neg), key=lambda pq: abs(pq[0][0] - pq[1][0]))
        return a0 - g0 * (a1 - a0) / (g1 - g0)
    if len(history) > 1:
        a0, g0 = history[-2]
        return secant_angle(a0, g0, a1, g1, PLS_MAX_STEP)
    return newton_angle(a1, g1, slope, PLS_MAX_STEP, slope=1.0)


def _advance(scene, sol, region, growing, da, criterion, options, frozen, grown=None, slopes=None):
    """Extend the growing tips by the criterion: (extensions, next scene, next solution or None, solves),
    or None if every growing tip froze. The next scene is a string (the reason) if refused.

    Every trial is a solve of the grown scene. A kink is kept only where the new tip is
    open (K_I > 0, faces apart), the state both criteria assume: a tip whose new tip comes
    out closed is tried again at half its kink (towards straight ahead), and one still
    closed after MAX_TRIALS solves stops (frozen, with the reason), the others grow on."""
    from ngcrack.planar.tips import tip_labels

    base = {v["label"]: tip_direction(scene.cracks[v["crack"]], v["end"]) for v in growing}
    grown = grown if grown is not None else {}
    slopes = slopes if slopes is not None else {}
    if criterion == "pls":
        theta = {v["label"]: pls_predictor(effective_K_I(v["K_I"], v["closed"]), v["K_II_kink"], grown.get(v["label"]),
                                           slopes.get(v["label"]))
                 for v in growing}
    else:
        theta = {v["label"]: v["theta"] for v in growing}
    history: dict[str, list] = {lab: [] for lab in theta}
    closed_at: dict[str, list] = {lab: [] for lab in theta}
    solves = 0
    while True:
        extensions = _extend(scene, region, {lab: base[lab] + theta[lab] for lab in theta}, growing, da, frozen)
        if not extensions:
            return None
        for e in extensions:
            v = next(v for v in growing if v["label"] == tip_label(e.crack, e.end))
            v["kink"] = theta[v["label"]]
        cut = _cut(scene, region, extensions)
        if cut is not None:
            return extensions, cut, None, solves
        new = _grown(scene, extensions)
        if isinstance(new, str):
            return extensions, new, None, solves
        if not tip_labels(new):
            return extensions, new, None, solves
        new_sol = solve_step(new, sol, options)
        solves += 1
        new_tips = {t.label: t for t in new_sol.tips}
        done, closing = True, []
        for e in extensions:
            lab = tip_label(e.crack, e.end)
            t = new_tips.get(lab)
            if e.outcome != "grew" or t is None:
                continue
            if not _open_tip(new_sol, t):
                closing.append(lab)
                closed_at[lab].append(theta[lab])
                if abs(theta[lab]) < CLOSED_STRAIGHT:  # straight ahead closes: no kink opens it
                    frozen[lab] = _closes_reason(lab, closed_at[lab], criterion)
                theta[lab] = 0.5 * theta[lab]
                continue
            if criterion != "pls":
                continue
            v = next(v for v in growing if v["label"] == lab)
            g = float(t.K_II)
            history[lab].append((theta[lab], g))
            measured = _measured_slope(history[lab])
            if measured is not None:
                slopes[lab] = measured
            slope = slopes.get(lab) or PLS_SLOPE * max(float(t.K_I), abs(v["K_eq"]))
            if abs(g) <= PLS_ANGLE_TOL * slope:  # within PLS_ANGLE_TOL of the PLS angle
                continue
            done = False
            theta[lab] = _next_angle(history[lab], slope)
        if solves >= MAX_TRIALS:
            if not closing:
                return extensions, new, new_sol, solves
            for lab in closing:  # out of trials: these tips stop, the others grow without them
                frozen[lab] = _closes_reason(lab, closed_at[lab], criterion)
        elif done and not closing:
            return extensions, new, new_sol, solves
