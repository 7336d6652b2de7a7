"""Several fluid-driven cracks fed from one injection: the stress shadow decides which grows.

A wellbore feeds several cracks of the scene (say parallel ones, perforation clusters along a
horizontal well) at one total rate Q0 (or a schedule). The fluid is inviscid and the wellbore
and perforations offer no friction, so the pressure is the same in every crack: the rate splits
between them by the cracks' own compliance, each taking the volume its opening holds at that
pressure. The cracks load one another through the rock (the stress shadow: an open crack
compresses its neighbours across their planes), which the one mixed solve of the whole body
with all the cracks holds exactly.

Each step, on the current cracks (meshed afresh):

1. the pressure at propagation: the smallest common p at which a tip of any of the cracks
   reaches K_eq = K_Ic (`loop.propagation` with the list of cracks: one solve scaled without
   other loads, a regula falsi with an in-situ stress);
2. the volume of each crack and their sum, the time at which the schedule has injected the sum,
   each crack's share of the step's fluid;
3. per tip, the existing rule: the tips within ADVANCE_RTOL of K_Ic advance by da along their
   MTS kink, the others stay (`loop.grow_tips`, crack by crack). Three equal parallel cracks at
   a small spacing: the outer ones, shielded on one side only, reach K_Ic first; the middle one
   is held below it and stays, while the outer ones take the fluid.

At a spacing large against the cracks' length every crack grows alike, each as a single KGD
fracture fed at Q0 / n (the K-vertex at that rate).
"""

from __future__ import annotations

import math
import time

import numpy as np

from ...core.errors import InputError
from ...core.options import SolveOptions
from ...core.pipeline import Pipeline, SolveError
from ..growth.paths import body_region
from ..volume import with_pressure
from .loop import check_hydrofrac_options, grow_tips, has_other_loads, propagation, step_record, step_stop

#: the keys of a step's "fractures" entries (one per fluid-driven crack)
FRACTURE_KEYS = ("crack", "half_length", "volume", "opening_at_injection", "share", "advancing")


def crack_list(crack) -> list[int] | None:
    """The crack indices when `crack` names several (a list or tuple of two or more), else None."""
    if isinstance(crack, (list, tuple)) and len(crack) >= 2:
        return list(crack)
    return None


def check_multi_options(scene, rate, K_Ic, da, steps, cracks, injection, solve_options, progress, viscous: bool) -> None:
    """Refuse bad input for several fluid-driven cracks by name, before any work."""
    if viscous:
        raise InputError(f"crack = {cracks!r}: several fluid-driven cracks take the inviscid fluid only (one pressure in "
                         "all of them); leave out the viscosity or give inviscid=True (--inviscid)")
    if injection is not None:
        raise InputError(f"injection = {injection!r}: with several fluid-driven cracks each is fed at its centre; "
                         "leave out injection")
    n = len(scene.cracks)
    if any(isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 0 <= k < n for k in cracks) \
            or len(set(int(k) for k in cracks)) != len(cracks):
        raise InputError(f"crack = {cracks!r}: must be distinct crack indices 0..{n - 1}")
    for k in cracks:
        check_hydrofrac_options(scene, rate, K_Ic, da, steps, int(k), None, solve_options, progress)


def multi_record(n, scene, sol, cracks, pressure, factor, schedule, solves, elapsed, K_Ic, K_m, previous):
    """The step's JSON row (the single crack's keys, `half_length` and `opening_at_injection` of the
    largest crack, `volume` the sum, `tips` of every crack, `profile` of the first, and per crack
    `fractures`) and its frame (every crack's). `previous`: the last step's row or None."""
    rows, frames = zip(*(step_record(n, scene, sol, k, pressure, factor, schedule, None, solves, elapsed, K_Ic, K_m)
                         for k in cracks))
    volume = sum(r["volume"] for r in rows)
    last = {f["crack"]: f["volume"] for f in previous["fractures"]} if previous else {k: 0.0 for k in cracks}
    added = volume - (previous["volume"] if previous else 0.0)
    fractures = [{"crack": k, "half_length": r["half_length"], "volume": r["volume"],
                  "opening_at_injection": r["opening_at_injection"],
                  "share": (r["volume"] - last[k]) / added if added > 0 else math.nan,
                  "advancing": any(t["advanced"] for t in r["tips"])} for k, r in zip(cracks, rows)]
    lead = max(rows, key=lambda r: r["half_length"])
    row = dict(rows[0], time=schedule.time_of(volume), half_length=lead["half_length"], volume=volume,
               opening_at_injection=max(r["opening_at_injection"] for r in rows),
               tips=[t for r in rows for t in r["tips"]], fractures=fractures)
    frame = dict(frames[0], all=list(frames))
    return row, frame


def multi_run(scene, schedule, K_Ic: float, da: float, steps: int, t_end, cracks: list, progress,
              options: SolveOptions, result, K_m):
    """The loop of several cracks at one pressure (module docstring) into `result`; returns it."""
    region = body_region(scene)
    in_situ = has_other_loads(scene, cracks)
    current = with_pressure(scene, cracks, 0.0)
    stopped = ""
    for n in range(steps + 1):
        t0 = time.process_time()
        pipe = Pipeline()
        try:
            sol, p, factor, solves = propagation(current, cracks, K_Ic, pipe, options, in_situ)
        except SolveError as exc:
            stopped = f"solve: step {n}: {exc}"
            break
        row, frame = multi_record(n, current, sol, cracks, p, factor, schedule, solves, time.process_time() - t0, K_Ic,
                                  K_m, result.steps[-1] if result.steps else None)
        stopped = step_stop(n, row, result, frame, current, progress, t_end, steps)
        if stopped:
            break
        for k in cracks:
            current, stopped = grow_tips(current, region, k, [t for t in row["tips"] if t["crack"] == k], da)
            if stopped:
                break
        if stopped:
            break
    result.stopped = stopped
    result.final = current
    return result
