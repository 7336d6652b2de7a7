"""The growth loop: solve -> fracture parameters -> kink -> extend -> remesh, one row per step and tip.

Each step solves the static problem of the current scene (contact and friction
included; the previous step's contact set warm-starts the QP where the solve uses one),
takes K_I, K_II, G at every tip inside the body (`sol.tips`), and for the tips that grow
chooses the kink (criteria.py) and adds a segment of length da (paths.py). The next
step's solve meshes the grown scene afresh: the new tip is graded as a tip (tip_h), the
grown path meshed at crack_h.

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
once, until |K_II| <= PLS_RTOL K_eq at every new tip or PLS_MAX_TRIALS solves; the last
trial's solve is the next step's. The first trial angle (criteria.pls_predictor) is the MTS
angle at a tip's first kink, then the tip's previous kink corrected for the K_II left at
its tip; the next trials take Newton steps with the measured response dk_2/dtheta ~
PLS_SLOPE K_I, then secant steps.

Why PLS is the default (measured on the wings of a 45-degree crack with mu = 0.3 under
compression, da = a/10, bdm): the K_II at the tip of a new segment responds to its kink
angle at about 1.5 K_I per radian, three times the small-kink value K_I/2 that the MTS
angle -2 K_II/K_I assumes, so each explicit MTS step overcorrects about threefold and the
path zig-zags with a growing amplitude (kinks +7, -24, +22, -36, +40, -49 degrees), while
PLS turns smoothly (kinks -4.6, -4.1, -2.9, -2.5, -1.8 degrees) at about 1.5 solves per
step. On a straight path both agree: |K_II| below KINK_NOISE_RTOL K_eq is taken as 0.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import shapely

from ngcrack.options import SolveOptions
from ngcrack.pipeline import Pipeline, SolveError
from ngcrack.scene import SceneError, tip_label

from ..errors import InputError
from .criteria import (
    check_criterion,
    check_r_c,
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
from .paths import body_region, extend_tip, extended_cracks, tip_direction

#: the most steps a growth run may take
MAX_STEPS = 1000
#: da may be at most this fraction of the body's diameter
MAX_DA_FRACTION = 0.1
#: da must be at least this fraction of the mesh size at the tips: a shorter segment is below
#: what the mesh resolves (da = 1e-6 on a tip mesh of 5e-3 was taken for a cut-through)
MIN_DA_TIP_FRACTION = 0.1
#: tips whose load factor lies within this fraction of the smallest grow together
GROW_TOGETHER_RTOL = 0.02
#: PLS: |K_II| at every new tip at most this fraction of its K_eq ends the trials (about 1 degree
#: from the PLS angle at the measured response PLS_SLOPE; the next step corrects what is left)
PLS_RTOL = 0.03
#: PLS: the most trial solves per step (the last one is the next step's solve)
PLS_MAX_TRIALS = 3
#: PLS: the largest change of the angle between two trials (radians)
PLS_MAX_STEP = math.radians(30.0)
#: |K_II| at most this fraction of K_eq is noise of the computed K (measured: 5e-4 on the
#: Griffith plate, 1e-3 between the two symmetric tips of a wing crack): the kink is 0
#: (below 0.6 degrees), and a straight path on a symmetry line stays on it exactly
KINK_NOISE_RTOL = 5e-3
#: solve options grow sets itself
_RESERVED = ("warm_start", "crack_mesh", "loads")


def check_growth_options(scene, da, steps, K_Ic, criterion, solve_options) -> None:
    """Refuse bad input before any work, naming the field and what is allowed."""
    from ngcrack.tips import tip_labels

    check_criterion(criterion)
    if getattr(scene, "dimension", 2) == 3:
        raise InputError(f"scene {scene.name!r} is 3D: crack growth takes 2D scenes (3D growth is a later step)")

    def number(v):
        return not isinstance(v, bool) and isinstance(v, (int, float, np.floating, np.integer))

    check_growth_solve_options(scene, solve_options)

    if K_Ic is not None and not (number(K_Ic) and math.isfinite(K_Ic) and K_Ic > 0):
        raise InputError(f"K_Ic = {K_Ic!r}: must be a finite number > 0 (the fracture toughness), or None")
    limit = MAX_DA_FRACTION * scene.diameter
    if not (number(da) and math.isfinite(da) and 0 < da <= limit):
        raise InputError(f"da = {da!r}: must be a number in (0, {limit:.4g}] (at most {MAX_DA_FRACTION:g} of the "
                          f"body's diameter {scene.diameter:.4g})")
    shortest = min_da(scene, solve_options)
    if da < shortest:
        raise InputError(f"da = {da!r}: must be at least {MIN_DA_TIP_FRACTION:g} of the mesh size at the crack tips "
                         f"({shortest / MIN_DA_TIP_FRACTION:.4g}), i.e. >= {shortest:.4g}: a shorter segment is not "
                         f"resolved by the mesh; give a larger da or a smaller tip_h")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or not 1 <= steps <= MAX_STEPS:
        raise InputError(f"steps = {steps!r}: must be a whole number in [1, {MAX_STEPS}]")
    bad = [k for k in _RESERVED if k in solve_options]
    if bad:
        raise InputError(f"{bad[0]}: grow sets it for every step itself; give the scene and the mesh options only")
    if not tip_labels(scene):
        raise InputError(f"scene {scene.name!r}: has no crack tip inside the body (every crack end lies on the "
                          f"boundary or on another crack), so no crack can grow")


def min_da(scene, solve_options) -> float:
    """The shortest segment a step may add: MIN_DA_TIP_FRACTION of the mesh size at the tips (tip_h,
    else crack_h, else maxh, as the mesh resolves them from the options and the scene)."""
    from ngcrack.sizing import mesh_sizes

    sizes = {k: solve_options.get(k) for k in ("maxh", "tip_h", "crack_h", "grading")}
    try:
        maxh, tip_h, crack_h, _ = mesh_sizes(scene, **sizes)
    except (TypeError, ValueError):  # a bad size is refused, naming it, by the solve options' check
        return 0.0
    h = next(v for v in (tip_h, crack_h, maxh) if v is not None)
    return MIN_DA_TIP_FRACTION * float(h)


def check_growth_solve_options(scene, solve_options) -> None:
    """What a solve alone accepts but growth cannot use: friction on cracks that have no contact."""
    model = solve_options.get("crack_model") or "contact"
    if model != "contact":
        mu = max((float(getattr(c, "friction", 0.0) or 0.0) for c in scene.cracks), default=0.0)
        if mu:
            raise InputError(f"crack_model = {model!r}: the scene's cracks have friction {mu:g}, which acts only "
                             f"with crack_model 'contact' (free and bonded cracks have no contact); drop the friction "
                             f"(scene.with_(friction=0)) or use crack_model 'contact'")


@dataclass
class Solver:
    """The loop's solves: one Pipeline for the whole path and the solve options, checked once.

    Every step (and every PLS trial) is a new geometry, so the pipeline meshes and
    assembles it afresh; what it keeps is the contact set handed on as a warm start.
    """

    options: SolveOptions
    pipeline: Pipeline = field(default_factory=Pipeline)


def solve_step(scene, previous, solver: Solver):
    """One solve of the loop, warm-started from the previous one: the only place the loop solves."""
    return solver.pipeline.run(scene, solver.options, warm_start=previous)


def _closed_at(sol, tip) -> bool:
    """Whether the crack faces at the tip touch: the state of the crack sample nearest the tip."""
    if not sol.profiles:
        return False
    prof = sol.profiles[tip.crack]
    if prof.state is None or not len(prof.state):
        return False
    i = int(np.argmin((prof.x - tip.x) ** 2 + (prof.y - tip.y) ** 2))
    return str(prof.state[i]) != "open"


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
    (element, order, maxh, tip_h, crack_h, grading, qp_solver, crack_model, friction_method, ...).
    Tips stop at the boundary (the crack then cuts through) or before meeting a crack; the
    run stops after `steps` steps, when no tip is left inside the body, or when none can grow.
    """
    from ngcrack.scene import Scene
    from ngcrack.solve import as_scene

    from .result import GrowthResult

    if not isinstance(scene, (Scene, str)):
        raise InputError(f"scene = {scene!r}: must be a Scene (nc.Scene.from_toml, nc.scenes.load) or the name of a "
                         f"built-in scene")
    scene = as_scene(scene)
    if progress is not None and not callable(progress):
        raise InputError(f"progress = {progress!r}: must be None or a callable, called as progress(step, result) "
                         f"after every step")
    check_growth_options(scene, da, steps, K_Ic, criterion, solve_options)
    r_c = check_r_c(r_c, criterion)
    if not (isinstance(together, (int, float)) and 0 <= together < 1):
        raise InputError(f"together = {together!r}: must be a number in [0, 1)")
    da, steps = float(da), int(steps)
    region = body_region(scene)
    options = Solver(SolveOptions.of(**solve_options))
    result = GrowthResult(scene=scene, element=options.options.element, criterion=criterion, da=da,
                          K_Ic=None if K_Ic is None else float(K_Ic), r_c=r_c)
    t0 = time.perf_counter()
    sol = solve_step(scene, None, options)
    elapsed = time.perf_counter() - t0
    trials = 1
    frozen: dict[str, str] = {}
    grown_once: dict = {}  # tip -> its last kink after its first (radians), None after the first
    K_ref = K_Ic
    stopped = ""
    for n in range(steps + 1):
        values = tip_values(sol, criterion, r_c)
        if K_ref is None:
            drive = [v["K_eq"] for v in values if v["K_eq"] > 0]
            K_ref = max(drive) if drive else None
        for v in values:
            v["lambda"] = load_factor(K_ref, v["K_eq"]) if K_ref is not None else math.inf
        growing, extensions, next_scene, next_sol, cost, tried = [], [], None, None, 0.0, 0
        failed = ""
        if n < steps:
            while True:
                active = [v for v in values if v["label"] not in frozen and math.isfinite(v["lambda"])]
                if not active:
                    break
                lam_min = min(v["lambda"] for v in active)
                growing = [v for v in active if v["lambda"] <= lam_min * (1.0 + together)]
                t1 = time.perf_counter()
                try:
                    step = _advance(scene, sol, region, growing, da, criterion, options, frozen, grown_once)
                except (SolveError, InputError) as exc:  # e.g. the grown mesh above max_dof: keep what was done
                    failed = f"solve: the solve after step {n} failed ({exc})"
                    growing = []
                    break
                cost = time.perf_counter() - t1
                if step is None:  # every chosen tip froze: choose again among the others
                    growing = []
                    continue
                extensions, next_scene, next_sol, tried = step
                break
        grew = {tip_label(e.crack, e.end): e for e in extensions if e.point is not None}
        if criterion == "pls":  # the tips that did not grow: the first PLS trial's angle
            for v in values:
                if v["label"] not in grew:
                    v["kink"] = pls_predictor(effective_K_I(v["K_I"], v["closed"]), v["K_II_kink"],
                                              grown_once.get(v["label"]))
        lam_step = min((v["lambda"] for v in values if v["label"] in grew), default=None)
        if lam_step is None:
            lam_step = min((v["lambda"] for v in values if v["label"] not in frozen), default=math.inf)
        for v in values:  # a tip that stopped inside the body: why, in the step's row
            v["stopped"] = frozen.get(v["label"], "")
        result.add_step(n, scene, sol, values, lam_step, grew, elapsed, trials, frames=frames)
        result.solution = sol  # this step's solve, for the progress callback (ngcrack.vtk.SeriesWriter)
        if progress is not None:
            progress(n, result)
        for e in extensions:
            if e.outcome == "boundary":
                result.events.append((n, tip_label(e.crack, e.end), e.reason))
        if n == steps:
            stopped = f"steps: {steps} of {steps} steps done"
            break
        if failed:
            stopped = failed
            break
        if isinstance(next_scene, str):  # the grown scene was refused
            stopped = next_scene
            break
        if not grew:
            reasons = "; ".join(frozen.values())
            stopped = ("no tip can grow: " + reasons) if reasons else "no tip can grow: no tip has K_eq > 0"
            break
        # a tip's previous kink predicts its next one (PLS) only once it grows from a grown segment
        grown_once.update({v["label"]: v["kink"] if v["label"] in grown_once else None
                           for v in values if v["label"] in grew})
        scene = next_scene
        if next_sol is None:  # no tip left inside the body
            result.add_final(scene)
            stopped = "boundary: every tip reached the body's boundary (the cracks cut through)"
            break
        sol, elapsed, trials = next_sol, cost, tried
    result.stopped = stopped
    result.solution = sol
    result.frozen = dict(frozen)
    return result


def _extend(scene, region, angles: dict, growing: list[dict], da: float, frozen: dict) -> list:
    """The extensions of the growing tips at the absolute angles `angles` (label -> radians);
    tips that would meet a crack are frozen (their reason kept)."""
    out, new_segments = [], []
    for v in growing:
        if v["label"] in frozen:
            continue
        ext = extend_tip(scene, region, v["crack"], v["end"], angles[v["label"]], da, new_segments)
        if ext.outcome in ("crack", "hole"):
            frozen[v["label"]] = ext.reason
            continue
        p = (v["x"], v["y"])
        new_segments.append((v["label"], shapely.LineString([p, ext.point])))
        out.append(ext)
    return out


def _grown(scene, extensions):
    """The grown scene, or the reason (a string) why the grown cracks make no valid scene."""
    try:
        return scene.with_(cracks=extended_cracks(scene, extensions))
    except SceneError as exc:
        return f"scene: the grown cracks make an invalid scene ({exc})"


def _advance(scene, sol, region, growing, da, criterion, options, frozen, grown=None):
    """Extend the growing tips by the criterion: (extensions, next scene, next solution or None, solves),
    or None if every growing tip froze. The next scene is a string (the reason) if refused."""
    from ngcrack.tips import tip_labels

    base = {v["label"]: tip_direction(scene.cracks[v["crack"]], v["end"]) for v in growing}
    grown = grown or {}
    if criterion == "pls":
        theta = {v["label"]: pls_predictor(effective_K_I(v["K_I"], v["closed"]), v["K_II_kink"], grown.get(v["label"]))
                 for v in growing}
    else:
        theta = {v["label"]: v["theta"] for v in growing}
    history: dict[str, list] = {lab: [] for lab in theta}
    solves = 0
    while True:
        extensions = _extend(scene, region, {lab: base[lab] + theta[lab] for lab in theta}, growing, da, frozen)
        if not extensions:
            return None
        for e in extensions:
            v = next(v for v in growing if v["label"] == tip_label(e.crack, e.end))
            v["kink"] = theta[v["label"]]
        new = _grown(scene, extensions)
        if isinstance(new, str):
            return extensions, new, None, solves
        if not tip_labels(new):
            return extensions, new, None, solves
        new_sol = solve_step(new, sol, options)
        solves += 1
        if criterion != "pls" or solves >= PLS_MAX_TRIALS:
            return extensions, new, new_sol, solves
        new_tips = {t.label: t for t in new_sol.tips}
        done = True
        for e in extensions:
            lab = tip_label(e.crack, e.end)
            t = new_tips.get(lab)
            if e.outcome != "grew" or t is None:
                continue
            v = next(v for v in growing if v["label"] == lab)
            g, scale = float(t.K_II), max(abs(v["K_eq"]), abs(t.K_I), abs(t.K_II))
            history[lab].append((theta[lab], g))
            if abs(g) <= PLS_RTOL * scale:
                continue
            done = False
            if len(history[lab]) == 1:
                theta[lab] = newton_angle(theta[lab], g, float(t.K_I), PLS_MAX_STEP)
            else:
                (a0, g0), (a1, g1) = history[lab][-2:]
                theta[lab] = secant_angle(a0, g0, a1, g1, PLS_MAX_STEP)
        if done:
            return extensions, new, new_sol, solves
