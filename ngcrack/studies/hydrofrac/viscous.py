"""The hydraulic-fracture loop with a viscous fluid: fixed length increments, the time step solved for.

Each step, on the current crack (meshed afresh):

1. the compliance of the crack over its edges (the fluid cells) from ngcrack's mixed solve
   (`elastic.py`: one mesh, one factorization, two load vectors);
2. the implicit flow step (`flow.solve_step`): the cell pressures and the step's duration
   at which every tip has advanced by its increment (da; at step 0 the crack is taken as
   grown from the injection point, so that its first state is a propagating one), the
   fluid's opening and pressure carried over from the last step by arc length (the crack's
   first point moves back by the first tip's increment);
3. the mixed solve with that pressure on the faces (a piecewise-constant table) and
   contact: the tips' K (MTS kink), the KKT residuals, the opening the fluid sees checked;
4. the tips that grow after the step advance by da along their kink (`loop.grow_tips`): every
   tip that moved, and an arrested one whose opening next to the tip (calibrated) shows
   K_Ic (`apparent_K`).

A moving tip is arrested when the fluid no longer flows towards it (`fed`): driven into a
band of higher in-situ stress, the fixed increment forces it open and the pressure rises
towards it. The step is then solved again on the geometry grown by the other tips only.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from ...core.options import SolveOptions
from ...core.pipeline import Pipeline, SolveError
from ...planar.tips import effective_modulus, tip_labels
from ..growth.criteria import effective_K_I, mts_angle, mts_keq
from ..growth.loop import KINK_NOISE_RTOL, tip_values
from ..growth.paths import body_region
from .elastic import crack_compliance, pressure_table
from .flow import Cells, StepError, asymptote_cell, solve_step, tip_calibration, tip_cell_mean
from .loop import ADVANCE_RTOL, grow_tips, injection_arclength

#: a tip is fed unless the pressure rises towards it by more than this fraction of the largest
#: pressure (a nearly inviscid fluid's pressure is uniform but for round-off and the time
#: rule's small oscillations: an exact sign test stopped a tip of the symmetric KGD at random;
#: a tip driven into the test's stress band sees a rise of 3-6%)
FED_RTOL = 1e-2
#: the first state's growth law l ~ t^GROWTH_EXPONENT, for the tip's arrival times (leak-off)
GROWTH_EXPONENT = 2.0 / 3.0


@dataclasses.dataclass
class FluidHistory:
    """What a step hands to the next: the cells' arc lengths (mid points and ends), the opening,
    pressure and tip arrival times on them, the time, the injection's arc length, and per tip end
    (advance, duration) of its last step."""

    s: np.ndarray
    length: float
    w: np.ndarray
    p: np.ndarray
    t0: np.ndarray
    t: float
    s_inj: float
    last: dict


def carried_over(old: FluidHistory | None, s: np.ndarray, advance: dict):
    """(w_old, p_old, t0_old, new_frac) on cells at arc lengths `s` of the grown crack: the old
    state shifted by the first tip's advance; cells beyond the old ends are new (NaN arrival,
    new_frac where in the step the tip passed them)."""
    if old is None:
        raise ValueError("no state to carry over")
    a_first, a_last = advance.get("first", 0.0), advance.get("last", 0.0)
    x = s - a_first  # old arc length
    inside = (x >= 0) & (x <= old.length)
    w = np.interp(x, np.concatenate([[0.0], old.s, [old.length]]), np.concatenate([[0.0], old.w, [0.0]]))
    w = np.where(inside, w, 0.0)
    p = np.interp(x, old.s, old.p)
    t0 = np.where(inside, np.interp(x, old.s, old.t0), np.nan)
    frac = np.zeros(len(s))
    if a_first > 0:
        frac = np.where(x < 0, np.clip(-x / a_first, 0.0, 1.0), frac)
    if a_last > 0:
        frac = np.where(x > old.length, np.clip((x - old.length) / a_last, 0.0, 1.0), frac)
    return w, p, t0, frac


def _flow_step(current, crack, options, ends, advance, history, guess, injection, schedule, fluid) -> dict:
    """One step on the geometry `current` whose tips advanced by `advance` (steps 1-3 of the module
    docstring); raises SolveError or StepError. Where the moving tips differ from the last step's
    (a tip arrested or started), the step is backward Euler in time: the last step's fluxes belong
    to another motion, and the theta rule would carry them on as an oscillation."""
    K_Ic, E_prime, mu, C_L = fluid
    pipe = Pipeline()
    cc = crack_compliance(pipe, current, crack, options)
    N = len(cc.h)
    bounds = np.concatenate([[0.0], np.cumsum(cc.h)])
    if history is None:
        s_inj = injection_arclength(current.cracks[crack].points, injection)
        # step 0: the crack taken as grown from the injection point
        advance.update({"first": s_inj if "first" in ends else 0.0, "last": bounds[-1] - s_inj if "last" in ends else 0.0})
        w_old, p_old, t0_old = np.zeros(N), None, np.full(N, np.nan)
        frac = np.where(cc.s < s_inj, (s_inj - cc.s) / max(advance["first"], 1e-300),
                        (cc.s - s_inj) / max(advance["last"], 1e-300))
        # the tip passed distance d at t (d / a)^(1 / GROWTH_EXPONENT) (KGD's vertices: l ~ t^(2/3));
        # a linear arrival would date the leak-off near the tips too late, and its rate at the
        # first step's end would exceed the injection (estimated: 1.1 Q0 at C_L = 3e-5)
        frac = np.clip(frac, 0.0, 1.0) ** (1.0 / GROWTH_EXPONENT)
        t_old, previous, start = 0.0, None, None
    else:
        s_inj = history.s_inj + advance.get("first", 0.0)
        w_old, p_old, t0_old, frac = carried_over(history, cc.s, advance)
        t_old = history.t
        previous = [history.last.get(e) for e in ends]
        start = p_old
        if any((advance.get(e, 0.0) > 0) != (history.last.get(e, (0.0,))[0] > 0) for e in ends):
            p_old = None  # backward Euler (flow.solve_step without the old fluxes)
    inj = int(np.clip(np.searchsorted(bounds, s_inj) - 1, 0, N - 1))
    tips = [(0 if e == "first" else N - 1, advance[e]) for e in ends]
    scale = dict(tip_calibration(cc.C, cc.h, i, cc.K_unit.get(e, 0.0), E_prime) for (i, _), e in zip(tips, ends))
    cells = Cells(s=cc.s, h=cc.h, C=cc.C, w_is=cc.w_is, tips=tips, inj=inj, scale=scale)
    state = solve_step(cells, w_old, t_old, t0_old, frac, schedule, K_Ic, E_prime, mu, C_L, start, guess, previous, p_old)
    return {"pipe": pipe, "cc": cc, "bounds": bounds, "s_inj": s_inj, "inj": inj, "cells": cells, "state": state}


def fed(step: dict, end: str) -> bool:
    """Whether the fluid flows towards the tip at `end` past the cell where its asymptote is
    imposed (the pressure does not rise towards the tip there, to FED_RTOL). A tip driven into a band of higher
    in-situ stress is not: the fixed increment forces it open, the pressure rises towards it
    and the fluid would flow back from it."""
    p, n = step["state"].p, len(step["state"].p)
    if n < 6:
        return True
    j, inner = (1, 2) if end == "first" else (n - 2, n - 3)
    return bool(p[j] - p[inner] <= FED_RTOL * float(np.max(np.abs(p))))


def apparent_K(step: dict, end: str, E_prime: float) -> float:
    """The stress intensity the opening next to the tip at `end` shows (calibrated, `tip_calibration`):
    its ratio to the K field's mean opening there per unit K_I."""
    cells, w = step["cells"], step["state"].w
    n = len(cells.h)
    j, x0 = asymptote_cell(0 if end == "first" else n - 1, n, cells.h)
    unit = tip_cell_mean(cells.h[j], 0.0, 1.0, E_prime, 0.0, x0)
    return float(w[j] / cells.scale.get(j, 1.0) / unit) if unit > 0 else 0.0


def viscous_run(scene, schedule, K_Ic: float, da: float, steps: int, t_end, crack: int, injection, progress,
                options: SolveOptions, result, K_m: float, mu: float, C_L: float):
    """The viscous loop (module docstring) into `result`; returns it."""
    mat = scene.material
    E_prime = effective_modulus(mat.E, mat.nu, mat.plane)
    fluid = (K_Ic, E_prime, mu, C_L)
    region = body_region(scene)
    current = scene
    ends = [lab.split(",")[1] for lab in tip_labels(scene) if lab.startswith(f"{crack},")]
    history: FluidHistory | None = None
    stopped, advance, guess = "", {}, None
    before, before_tips = None, None  # the geometry before the last growth and the tips that grew it
    for n in range(steps + 1):
        t_cpu = time.process_time()
        try:
            step = _flow_step(current, crack, options, ends, advance, history, guess, injection, schedule, fluid)
            moving = [e for e in ends if advance[e] > 0]
            unfed = [e for e in moving if not fed(step, e)] if history is not None else []
            if unfed and len(unfed) < len(moving):  # those tips stay: the step again without their growth
                before_tips = [dict(t, advanced=t["advanced"] and t["end"] not in unfed) for t in before_tips]
                current, stopped = grow_tips(before, region, crack, before_tips, da)
                if stopped:
                    break
                advance = {e: 0.0 if e in unfed else advance[e] for e in ends}
                step = _flow_step(current, crack, options, ends, advance, history, guess, injection, schedule, fluid)
        except SolveError as exc:
            stopped = f"solve: step {n}: {exc}"
            break
        except StepError as exc:
            stopped = f"flow: step {n}: {exc}"
            break
        cc, state, bounds = step["cc"], step["state"], step["bounds"]
        guess = state.dt
        # the mixed solve with the fluid's pressure on the faces (contact): the tips' K, the KKT check
        table = pressure_table(bounds, state.p)
        loaded = current.with_(cracks=[dataclasses.replace(c, pressure=table) if k == crack else c
                                       for k, c in enumerate(current.cracks)])
        try:
            sol = step["pipe"].run(loaded, options, crack_mesh=cc.crack_mesh)
        except SolveError as exc:
            stopped = f"solve: step {n}: {exc}"
            break
        # the tips that grow after the step: the moving ones, and an arrested one whose opening shows K_Ic
        K_app = {e: apparent_K(step, e, E_prime) for e in ends}
        grows = {e: advance[e] > 0 or K_app[e] >= (1.0 - ADVANCE_RTOL) * K_Ic for e in ends}
        if ends and not any(grows.values()):
            grows[max(ends, key=K_app.get)] = True
        row, frame = viscous_record(n, current, sol, crack, cc, state, step["s_inj"], step["inj"], K_m,
                                    time.process_time() - t_cpu, grows)
        result.add(row, frame, current)
        if progress is not None:
            progress(n, result)
        history = FluidHistory(s=cc.s, length=float(bounds[-1]), w=state.w, p=state.p, t0=state.t0, t=state.t,
                               s_inj=step["s_inj"], last={e: (advance[e], state.dt) for e in ends})
        if t_end is not None and state.t >= t_end:
            stopped = f"time: t = {state.t:.6g} reached the end time {t_end:.6g} at step {n}"
            break
        if n == steps:
            stopped = f"steps: {steps} of {steps} steps done"
            break
        before, before_tips = current, row["tips"]
        current, stopped = grow_tips(current, region, crack, row["tips"], da)
        if stopped:
            break
        advance = {e: da if grows[e] else 0.0 for e in ends}
    result.stopped = stopped
    result.final = current
    return result


def viscous_record(n, scene, sol, crack, cc, state, s_inj, inj, K_m, elapsed, grows) -> tuple[dict, dict]:
    """The step's JSON row and its frame (the opening the fluid holds); `grows`: per tip end,
    whether it advances after the step."""
    w0 = float(np.interp(s_inj, cc.s, state.w))
    tips = []
    for v in tip_values(sol):
        if v["crack"] != crack:
            continue
        K_I, K_II = v["K_I"], v["K_II"]
        k1 = effective_K_I(K_I, v["closed"])
        kink_II = 0.0 if abs(K_II) <= KINK_NOISE_RTOL * abs(mts_keq(k1, K_II)) else K_II
        tips.append({"crack": crack, "end": v["end"], "x": v["x"], "y": v["y"], "K_I": K_I, "K_II": K_II,
                     "kink_deg": math.degrees(mts_angle(k1, kink_II)) + 0.0, "advanced": bool(grows.get(v["end"], False))})
    prof = sol.profiles[crack]
    row = {"step": n, "time": state.t, "half_length": 0.5 * scene.cracks[crack].length,
           "pressure": float(state.p[inj]), "opening_at_injection": w0, "volume": float(np.sum(cc.h * state.w)),
           "ndof": int(sol.ndof["total"]), "time_s": float(elapsed), "kkt": float(max(sol.kkt.values(), default=0.0)),
           "solves": 3, "K_m": K_m, "efficiency": state.efficiency,
           "profile": {"s": cc.s.tolist(), "opening": state.w.tolist(), "pressure": state.p.tolist()},
           "tips": tips, "mixed_opening_gap": float(np.max(np.abs(prof.normal_jump[np.argsort(sol.crack_mesh.cracks[crack].s_mid)]
                                                                   - state.w)) / max(float(np.max(state.w)), 1e-300))}
    frame = {"points": [list(p) for p in scene.cracks[crack].points], "x": cc.x.tolist(), "y": cc.y.tolist(),
             "normal": sol.crack_mesh.cracks[crack].normal[np.argsort(sol.crack_mesh.cracks[crack].s_mid)].tolist(),
             "opening": state.w.tolist()}
    return row, frame
