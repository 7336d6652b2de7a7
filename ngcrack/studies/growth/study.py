"""Studies of growth: one growth path per parameter value, run through the sweep's executors.

    table = grow_study(scene, "friction", [0.0, 0.2, 0.4], da=0.1, steps=20, K_Ic=1.0,
                       jobs=2, out="wings.csv")

`parameter` is a scene field that `Scene.with_` sets ("friction", "nu", "E"), "K_Ic", or,
with `scene` a function returning a Scene (a scene function such as
nc.scenes.inclined_crack), any of its keywords ("angle", "half_length", ...). Each path
runs `grow` in this process, in worker processes (jobs > 1) or on a Dask cluster
(dask = an address or a Client), like a sweep's runs. One row per path (STUDY_COLUMNS): the
value, the steps taken, the final crack size (all cracks: their lengths in 2D, their equivalent radii
sqrt(area / pi) in 3D), the first, last and largest load factor, the cycles at the end (fatigue runs,
paris=(C, m); NaN otherwise), the stop reason, the run time and the unknowns of the last solve. A 3D scene
grows its fronts in their planes (loop3d.py): its parameter is a scene field (E, nu, friction, pressure),
K_Ic, or a keyword of its scene function, and the 2D-only options (criterion, r_c, at_hole) are refused
by name before any run. With `out`
(a CSV file) each finished path is written as one complete line at once, and a rerun
skips the values already in the file (resumable like a sweep).
"""

from __future__ import annotations

import csv
import math
import time
from pathlib import Path

from ...core.errors import InputError

#: the columns of a growth study's table, after the parameter's
STUDY_COLUMNS = ("steps", "final_length", "lambda_first", "lambda_last", "lambda_max", "cycles", "stopped", "time_s",
                 "ndof")


def _run_path(scene, da, steps, K_Ic, criterion, options) -> dict:
    """One growth path (runs in a worker): its row without the parameter."""
    from .loop import grow

    t0 = time.perf_counter()
    res = grow(scene, da, steps, K_Ic=K_Ic, criterion=criterion, frames=False, **options)
    lam = [s["load_factor"] for s in res.steps if s["load_factor"] is not None]
    final = res.final_scene
    if getattr(final, "dimension", 2) == 3:  # the cracks' equivalent radii
        size = sum(math.sqrt(float(c.area) / math.pi) for c in final.cracks)
    else:
        size = sum(c.length for c in final.cracks)
    return {"steps": len(res.steps) - 1, "final_length": float(size),
            "lambda_first": lam[0] if lam else math.nan, "lambda_last": lam[-1] if lam else math.nan,
            "lambda_max": max(lam) if lam else math.nan, "cycles": float(res.steps[-1].get("cycles", math.nan)),
            "stopped": res.stopped, "time_s": time.perf_counter() - t0, "ndof": res.steps[-1]["ndof"]}


def _check_case(scene, da, steps, K_Ic, criterion, options: dict) -> None:
    """grow's own checks of one path, before any run: the 3D loop's for a 3D scene, the 2D loop's otherwise."""
    from .loop import GROW_TOGETHER_RTOL, check_grow_call

    opts = dict(options)
    paris, R = opts.pop("paris", None), opts.pop("R", 0.0)
    if getattr(scene, "dimension", 2) == 3:
        from .loop3d import check_solid_grow, planar_options

        planar = planar_options(criterion, opts.pop("r_c", None), opts.pop("at_hole", "stop"), opts.pop("estimate", False))
        together = opts.pop("together", GROW_TOGETHER_RTOL)
        corrector = opts.pop("corrector", False)
        if not isinstance(corrector, bool):
            raise InputError(f"corrector = {corrector!r}: must be True (Heun's step of surface cracks) or False")
        check_solid_grow(scene, da, steps, K_Ic, paris, R, together, None, opts, planar)
        return
    check_grow_call(scene, da, steps, K_Ic, criterion, opts.pop("together", GROW_TOGETHER_RTOL), None,
                    opts.pop("r_c", None), paris, R, opts.pop("at_hole", "stop"), opts, opts.pop("estimate", False))


def _scene_for(scene, parameter: str, value):
    if callable(scene) and not hasattr(scene, "with_"):
        return scene(**{parameter: value})
    if parameter == "K_Ic":
        return scene
    return scene.with_(**{parameter: value})


def _done(path: Path | None, parameter: str) -> dict:
    """The rows already in the study's CSV file, by their value's text."""
    if path is None or not path.exists():
        return {}
    with open(path, newline="") as fh:
        return {row[parameter]: row for row in csv.DictReader(fh)}


def grow_study(scene, parameter: str, values, da: float, steps: int, K_Ic: float | None = None,
               criterion: str = "pls", *, jobs: int = 1, dask=None, out=None, **solve_options):
    """Grow one path per value of `parameter`; a pandas DataFrame, one row per path (module docstring)."""
    import pandas as pd

    from ngcrack.studies.sweeps.executors import _executor

    if not isinstance(parameter, str) or not parameter:
        raise InputError(f"parameter = {parameter!r}: must be a scene field (friction, nu, E), K_Ic, or a keyword "
                          f"of the scene function")
    if isinstance(scene, str):  # a built-in scene's name
        from ngcrack.core.solve import as_scene

        scene = as_scene(scene)
    values = list(values)
    if not values:
        raise InputError("values: give at least one value of the parameter")
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise InputError(f"jobs = {jobs!r}: must be a whole number >= 1")
    path = Path(out) if out is not None else None
    if path is not None and not path.parent.exists():
        raise InputError(f"out = {str(out)!r}: the directory {str(path.parent)!r} does not exist")
    cases = []
    for v in values:  # every case checked before any run
        sc = _scene_for(scene, parameter, v)
        k = v if parameter == "K_Ic" else K_Ic
        _check_case(sc, da, steps, k, criterion, solve_options)
        cases.append((v, sc, k))
    done = _done(path, parameter)
    todo = [c for c in cases if str(c[0]) not in done]
    rows = {str(v): dict(row, **{parameter: v}) for v, row in
            ((v, done[str(v)]) for v, _, _ in cases if str(v) in done)}
    header = not (path is not None and path.exists())
    ex = _executor(jobs, dask)
    try:
        pending = {ex.submit(_run_path, sc, da, steps, k, criterion, dict(solve_options)): v for v, sc, k in todo}
        while pending:
            finished, _ = ex.wait(list(pending))
            for fut in finished:
                v = pending.pop(fut)
                row = {parameter: v, **fut.result()}
                rows[str(v)] = row
                if path is not None:
                    with open(path, "a", newline="") as fh:  # one complete line per finished path
                        writer = csv.DictWriter(fh, fieldnames=[parameter, *STUDY_COLUMNS])
                        if header:
                            writer.writeheader()
                            header = False
                        writer.writerow(row)
    finally:
        ex.close(cancel=True)
    table = pd.DataFrame([rows[str(v)] for v, _, _ in cases], columns=[parameter, *STUDY_COLUMNS])
    for col in ("steps", "ndof"):
        table[col] = table[col].astype(int)
    for col in ("final_length", "lambda_first", "lambda_last", "lambda_max", "cycles", "time_s"):
        table[col] = table[col].astype(float)
    return table
