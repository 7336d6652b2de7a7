"""`hydrofrac(scene, rate, K_Ic, da, steps, ...)`: the checks, the regime, and the loop that applies.

With `viscosity` (mu > 0) the fluid is viscous (`viscous.py`: lubrication along the crack,
the tip asymptotes, leak-off); without it, or with `inviscid=True`, the fluid's pressure is
uniform (`loop.py`, the toughness-dominated limit). K_m, the dimensionless toughness, is
recorded whenever the viscosity is known, and a toughness-only run where K_m < 4 (viscosity
matters) warns in one line.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ...core.errors import InputError
from ...core.fields import is_number
from ...core.options import SolveOptions
from ...planar.tips import effective_modulus
from .flow import K_M_TOUGHNESS, Schedule, k_m
from .loop import MAX_STEPS, check_hydrofrac_options

#: da, where only the end time is given: this fraction of the crack's initial half-length
DEFAULT_DA_FRACTION = 0.1
#: the most rows of an injection schedule
MAX_SCHEDULE_ROWS = 10000


class RegimeWarning(UserWarning):
    """The toughness-only model used where K_m says viscosity matters."""


def check_schedule(schedule, fld: str = "schedule") -> Schedule:
    """A Schedule from rows [t, rate] (t from 0, increasing; rates >= 0, the first > 0), refused by name."""
    if isinstance(schedule, Schedule):
        schedule = np.column_stack([schedule.time, schedule.rate]).tolist()
    try:
        rows = [(float(t), float(q)) for t, q in schedule]
    except (TypeError, ValueError):
        raise InputError(f"{fld} = {schedule!r:.80}: must be rows [t, rate] of two numbers") from None
    if not 1 <= len(rows) <= MAX_SCHEDULE_ROWS:
        raise InputError(f"{fld}: {len(rows)} rows; give 1 to {MAX_SCHEDULE_ROWS} rows [t, rate]")
    for i, (t, q) in enumerate(rows):
        if not (math.isfinite(t) and math.isfinite(q)) or q < 0:
            raise InputError(f"{fld}[{i}] = [{t:g}, {q:g}]: t and the rate must be finite, the rate >= 0 (0: shut-in)")
        if i == 0 and t != 0.0:
            raise InputError(f"{fld}[0]: t = {t:g}; the schedule starts at t = 0")
        if i > 0 and t <= rows[i - 1][0]:
            raise InputError(f"{fld}[{i}]: t = {t:g} is not after the previous row's {rows[i - 1][0]:g}")
    if rows[0][1] <= 0:
        raise InputError(f"{fld}[0]: the first rate must be > 0 (the injection opens the crack)")
    return Schedule(np.array([r[0] for r in rows]), np.array([r[1] for r in rows]))


def read_schedule(path) -> list:
    """Rows [t, rate] of a text file: two numbers a line (spaces or a comma), '#' comments."""
    rows = []
    try:
        lines = open(path).read().splitlines()
    except OSError as exc:
        raise InputError(f"--schedule {path}: cannot be read ({exc.strerror})") from None
    for i, line in enumerate(lines, 1):
        text = line.split("#", 1)[0].replace(",", " ").split()
        if not text:
            continue
        if len(text) != 2:
            raise InputError(f"--schedule {path}: line {i}: {line.strip()!r} is not two numbers 't rate'")
        try:
            rows.append([float(text[0]), float(text[1])])
        except ValueError:
            raise InputError(f"--schedule {path}: line {i}: {line.strip()!r} is not two numbers 't rate'") from None
    return rows


def check_fluid_options(scene, rate, steps, end_time, viscosity, leakoff, schedule, inviscid, options) -> tuple:
    """(Schedule, steps) after refusing bad fluid options by name (before any work). A 3D scene's radial
    fracture takes leak-off with either model; its viscous model needs the 3D mixed element (tdnns)."""
    from .elastic import ELEMENTS

    if schedule is not None and rate is not None:
        raise InputError("rate and schedule: give one of them (a constant rate, or a schedule of rates)")
    if schedule is None and rate is None:
        raise InputError("rate: required (the injection rate Q0), or give a schedule")
    if end_time is not None and not (is_number(end_time) and math.isfinite(end_time) and end_time > 0):
        raise InputError(f"time = {end_time!r}: must be a finite number > 0 (the end time of the run)")
    if steps is None and end_time is None:
        raise InputError("steps: required, or give the end time (time)")
    if viscosity is not None and not (is_number(viscosity) and math.isfinite(viscosity) and viscosity > 0):
        raise InputError(f"viscosity = {viscosity!r}: must be a finite number > 0 (Pa s), or None for an inviscid fluid")
    if not (is_number(leakoff) and math.isfinite(leakoff) and leakoff >= 0):
        raise InputError(f"leakoff = {leakoff!r}: must be a finite number >= 0 (Carter's coefficient C_L)")
    if not isinstance(inviscid, bool):
        raise InputError(f"inviscid = {inviscid!r}: must be True or False")
    radial = getattr(scene, "dimension", 2) == 3
    viscous = viscosity is not None and not inviscid and not radial
    if leakoff > 0 and not viscous and not radial:
        raise InputError(f"leakoff = {leakoff!r}: leak-off is modelled with the viscous fluid only; give a viscosity")
    element = options.element
    if viscous and element not in ELEMENTS:
        raise InputError(f"element = {element!r}: the viscous fluid needs one of {', '.join(ELEMENTS)} "
                         "(one mean normal jump per crack edge)")
    if radial and viscosity is not None and not inviscid and element != "tdnns":
        raise InputError(f"element = {element!r}: the viscous radial fracture needs 'tdnns' (its crack unknowns, the "
                         "normal jump, are what a crack-face pressure loads)")
    sched = check_schedule(schedule) if schedule is not None else None
    if sched is None:
        if not (is_number(rate) and math.isfinite(rate) and rate > 0):
            raise InputError(f"rate = {rate!r}: must be a finite number > 0 (the injection rate Q0, an area per unit "
                             "time per unit thickness)")
        sched = Schedule.constant(float(rate))
    return sched, MAX_STEPS if steps is None else steps


def default_da(scene, crack):
    """da where only the end time is given: DEFAULT_DA_FRACTION of the crack's initial half-length (3D: of the
    disc's radius); None where the crack index is not one (refused by the checks)."""
    from .multi import crack_list

    several = crack_list(crack)
    if several is not None:  # several fluid-driven cracks: of the first
        crack = several[0]
    if isinstance(crack, bool) or not isinstance(crack, int) or not 0 <= crack < len(scene.cracks):
        return None
    c = scene.cracks[crack]
    return DEFAULT_DA_FRACTION * (c.radius if getattr(scene, "dimension", 2) == 3 else 0.5 * c.length)


def check_run(scene, rate, K_Ic, da, steps, end_time, viscosity, leakoff, schedule, inviscid, crack, injection,
              solve_options, progress=None) -> tuple:
    """(Schedule, steps, SolveOptions) after refusing every bad input by name, before any meshing (2D and 3D)."""
    options = SolveOptions.of(**{k: v for k, v in solve_options.items() if k not in ("warm_start", "crack_mesh", "loads")})
    sched, n_steps = check_fluid_options(scene, rate, steps, end_time, viscosity, leakoff, schedule, inviscid, options)
    from .multi import check_multi_options, crack_list

    several = crack_list(crack)
    if several is not None and getattr(scene, "dimension", 2) == 2:
        check_multi_options(scene, sched.largest_rate, K_Ic, da, n_steps, several, injection, solve_options, progress,
                            viscous=viscosity is not None and not inviscid)
    elif getattr(scene, "dimension", 2) == 3:
        from .radial import check_radial_options

        check_radial_options(scene, sched.largest_rate, K_Ic, da, n_steps, crack, injection, solve_options, progress)
    else:
        check_hydrofrac_options(scene, sched.largest_rate, K_Ic, da, n_steps, crack, injection, solve_options, progress)
    options.check_for(scene)
    return sched, n_steps, options


def hydrofrac(scene, rate=None, K_Ic=None, da=None, steps=None, *, time=None, viscosity=None, leakoff=0.0,
              schedule=None, inviscid=False, crack: int | list = 0, injection=None, progress=None, **solve_options):
    """Grow a fluid-driven crack of `scene` (the scene's loads are the in-situ stress).

    rate: Q0, the injected area per unit time (per unit thickness), or `schedule`: rows
    [t, rate] (from t = 0; a rate holds until the next row, 0 is a shut-in); K_Ic: the
    toughness; da: the growth of each tip per step (with `time` alone: DEFAULT_DA_FRACTION of
    the crack's initial half-length); steps (at most MAX_STEPS) and/or time:
    the run ends after `steps` steps or at the first step at or past `time`. viscosity: mu
    (Pa s) of a Newtonian fluid (None: inviscid, uniform pressure); leakoff: Carter's C_L
    (viscous fluid only); inviscid: the uniform-pressure model even where a viscosity is given
    (then K_m is recorded, and a warning given where K_m < 4). crack: the index of the
    fluid-driven crack; injection: the injection point [x, y] on it (its centre by default); a list
    of two or more indices: several cracks fed from one injection at one pressure, each at its
    centre (`multi.py`, the inviscid fluid).
    progress: called as progress(step, result_so_far) after every step. The other keywords go
    to every solve (element, order, maxh, tip_h, crack_h, grading, crack_model, ...).
    A 3D scene gives a radial fracture: a disc crack fed at its centre, da the growth of the
    radius, no injection point; with a viscosity the viscous model (`radial_viscous.py`:
    axisymmetric lubrication on rings, the compliance from the 3D solve), else (or with
    inviscid) the toughness-only one (`radial.py`; with a viscosity K_m per step and the warning
    where it is below K_RADIAL_TOUGHNESS); leak-off with either.
    Returns a HydrofracResult.
    """
    from ...core.solve import as_scene
    from .loop import toughness_run
    from .result import HydrofracResult
    from .viscous import viscous_run

    scene = as_scene(scene)
    if da is None:
        if time is None:
            raise InputError("da: required (the growth of each tip per step), unless the end time (time) is given")
        da = default_da(scene, crack)
    sched, n_steps, options = check_run(scene, rate, K_Ic, da, steps, time, viscosity, leakoff, schedule, inviscid,
                                        crack, injection, solve_options, progress)
    if scene.dimension == 3:
        return _radial(scene, sched, float(K_Ic), float(da), n_steps, time, int(crack), progress, options, viscosity,
                       float(leakoff), inviscid)
    from .multi import crack_list, multi_run

    several = crack_list(crack)
    mat = scene.material
    E_prime = effective_modulus(mat.E, mat.nu, mat.plane)
    K_Ic, da, crack = float(K_Ic), float(da), [int(k) for k in several] if several else int(crack)
    km = None if viscosity is None else k_m(K_Ic, E_prime, float(viscosity), sched.largest_rate)
    viscous = viscosity is not None and not inviscid
    result = HydrofracResult(scene=scene, element=options.element, rate=sched.largest_rate, K_Ic=K_Ic, da=da,
                             viscosity=viscosity, leakoff=float(leakoff), K_m=km,
                             model="viscous" if viscous else "toughness", schedule=sched)
    if km is not None and not viscous and km < K_M_TOUGHNESS:
        warnings.warn(f"K_m = {km:.3g} < {K_M_TOUGHNESS:g}: viscosity matters here, and the toughness-only model "
                      "(uniform pressure) overestimates the length; leave out inviscid for the viscous model",
                      RegimeWarning, stacklevel=2)
    if several:
        return multi_run(scene, sched, K_Ic, da, n_steps, time, crack, progress, options, result, km)
    if viscous:
        return viscous_run(scene, sched, K_Ic, da, n_steps, time, crack, injection, progress, options, result, km,
                           float(viscosity), float(leakoff))
    return toughness_run(scene, sched, K_Ic, da, n_steps, time, crack, injection, progress, options, result, km)


def _radial(scene, sched, K_Ic, da, n_steps, end_time, crack, progress, options, viscosity, leakoff, inviscid=False):
    """The radial fracture of a 3D scene: viscous (`radial_viscous.py`) with a viscosity, else toughness-only
    (`radial.py`; K_m per step where the viscosity is known)."""
    from .radial import K_RADIAL_TOUGHNESS, radial_run
    from .result import HydrofracResult

    viscous = viscosity is not None and not inviscid
    result = HydrofracResult(scene=scene, element=options.element, rate=sched.largest_rate, K_Ic=K_Ic, da=da,
                             viscosity=viscosity, leakoff=leakoff, K_m=None, model="viscous" if viscous else "toughness",
                             schedule=sched)
    if viscous:
        from .radial_viscous import viscous_radial_run

        viscous_radial_run(scene, sched, K_Ic, da, n_steps, end_time, crack, progress, options, result, float(viscosity),
                           leakoff)
        if result.steps:
            result.K_m = result.steps[0]["K_m"]
        return result

    def warn(km, t):
        warnings.warn(f"K_m = {km:.3g} < {K_RADIAL_TOUGHNESS:g} at t = {t:.4g} (radial): viscosity matters here, and "
                      "the toughness-only model (uniform pressure) overestimates the radius; leave out inviscid for the "
                      "viscous model", RegimeWarning, stacklevel=3)

    radial_run(scene, sched, K_Ic, da, n_steps, end_time, crack, progress, options, result,
               None if viscosity is None else float(viscosity), leakoff, warn)
    if result.steps and viscosity is not None:
        result.K_m = result.steps[0]["K_m"]  # the smallest: the radial K_m grows as t^(1/9)
    return result
