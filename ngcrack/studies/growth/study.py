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
import inspect
import math
import os
import pickle
import time
from pathlib import Path

from ...core.errors import InputError
from ...core.fields import SceneError

#: the columns of a growth study's table, after the parameter's
STUDY_COLUMNS = ("steps", "final_length", "lambda_first", "lambda_last", "lambda_max", "cycles", "stopped", "time_s",
                 "ndof")
#: the columns of STUDY_COLUMNS holding whole numbers and text; the others hold numbers (NaN: an empty CSV cell)
_INT_COLUMNS, _TEXT_COLUMNS = ("steps", "ndof"), ("stopped",)


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
    from .checks import check_corrector
    from .loop import check_grow_call

    if "frames" in options:
        raise InputError(f"frames = {options['frames']!r}: a growth study keeps no frames (its rows are the paths' "
                         f"summaries); leave it out")
    opts = dict(options)
    paris, R, progress = opts.pop("paris", None), opts.pop("R", 0.0), opts.pop("progress", None)
    if getattr(scene, "dimension", 2) == 3:
        from .fronts3d import GROW_TOGETHER_RTOL
        from .loop3d import check_solid_grow, planar_options

        planar = planar_options(criterion, opts.pop("r_c", None), opts.pop("at_hole", "stop"), opts.pop("estimate", False))
        together = opts.pop("together", GROW_TOGETHER_RTOL)
        check_corrector(opts.pop("corrector", False), scene)
        check_solid_grow(scene, da, steps, K_Ic, paris, R, together, progress, opts, planar)
        return
    from .loop import GROW_TOGETHER_RTOL

    if "corrector" in opts:
        check_corrector(opts["corrector"], scene)
    check_grow_call(scene, da, steps, K_Ic, criterion, opts.pop("together", GROW_TOGETHER_RTOL), progress,
                    opts.pop("r_c", None), paris, R, opts.pop("at_hole", "stop"), opts, opts.pop("estimate", False))


def _scene_for(scene, parameter: str, value):
    if _is_function(scene):
        try:
            made = scene() if parameter == "K_Ic" else scene(**{parameter: value})
        except (InputError, SceneError):
            raise
        except Exception as exc:  # the user's function: its failure reported with the value
            raise InputError(f"scene: the scene function failed at {parameter} = {value!r} ({type(exc).__name__}: "
                             f"{exc})") from None
        return made
    return scene if parameter == "K_Ic" else scene.with_(**{parameter: value})


def _is_function(scene) -> bool:
    return callable(scene) and not hasattr(scene, "with_")


def _check_parameter(scene, parameter: str) -> None:
    """A scene function's parameter must be one of its keywords (K_Ic aside)."""
    if parameter == "K_Ic" or not _is_function(scene):
        return
    try:
        params = inspect.signature(scene).parameters
    except (TypeError, ValueError):  # no signature to read: the call itself is the check
        return
    if any(p.kind == p.VAR_KEYWORD for p in params.values()) or parameter in params:
        return
    names = [n for n, p in params.items() if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]
    raise InputError(f"parameter = {parameter!r}: not a keyword of the scene function; allowed: "
                     f"{', '.join(names + ['K_Ic'])}")


def _check_picklable(scene, parameter: str, value) -> None:
    """A path run in a worker process is sent there pickled: a scene that cannot be (a lambda or a local function as
    a load, solid.loads) is refused before any run."""
    try:
        pickle.dumps(scene)
    except Exception as exc:  # pickle raises several types (PicklingError, AttributeError, TypeError)
        raise InputError(f"{parameter} = {value!r}: the scene cannot be sent to a worker process ({type(exc).__name__}: "
                         f"{exc}); give its callables as module-level functions, or jobs=1") from None


def _done(path: Path | None, parameter: str) -> dict:
    """The rows already in the study's CSV file, by their value's text, their cells typed; a file that is not this
    study's (other columns, a cell of the wrong type) is refused naming it, before any run."""
    if path is None or not path.exists() or path.stat().st_size == 0:
        return {}
    columns = [parameter, *STUDY_COLUMNS]
    try:  # a file that is not text, or not CSV, is refused like one of other columns
        with open(path, newline="", encoding="utf-8") as fh:
            reader = csv.DictReader(fh)
            if reader.fieldnames != columns:
                raise InputError(f"out = {str(path)!r}: its columns ({', '.join(reader.fieldnames or [])}) are not this "
                                 f"study's ({', '.join(columns)}); give another file or move this one away")
            rows = {}
            for i, row in enumerate(reader, start=2):
                for col in STUDY_COLUMNS:
                    if col in _TEXT_COLUMNS:
                        continue
                    try:
                        row[col] = int(row[col]) if col in _INT_COLUMNS else (float(row[col]) if row[col] else math.nan)
                    except (TypeError, ValueError):
                        raise InputError(f"out = {str(path)!r}: line {i}, column {col} = {row[col]!r} is not "
                                         f"{'a whole number' if col in _INT_COLUMNS else 'a number'}; give another "
                                         f"file or mend this one") from None
                rows[row[parameter]] = row
    except (UnicodeDecodeError, csv.Error) as exc:
        raise InputError(f"out = {str(path)!r}: is not a CSV file of this study ({type(exc).__name__}: {exc}); give "
                         f"another file or move this one away") from None
    return rows


def grow_study(scene, parameter: str, values, da: float, steps: int, K_Ic: float | None = None,
               criterion: str = "pls", *, jobs: int = 1, dask=None, out=None, **solve_options):
    """Grow one path per value of `parameter`; a pandas DataFrame, one row per path (module docstring)."""
    import pandas as pd

    from ngcrack.studies.sweeps.executors import _executor, check_dask
    from ngcrack.studies.sweeps.results import csv_line

    if not isinstance(parameter, str) or not parameter:
        raise InputError(f"parameter = {parameter!r}: must be a scene field (friction, nu, E), K_Ic, or a keyword "
                          f"of the scene function")
    if isinstance(scene, str):  # a built-in scene's name
        from ngcrack.core.solve import as_scene

        scene = as_scene(scene)
    if not (hasattr(scene, "with_") or callable(scene)):
        raise InputError(f"scene = {scene!r}: must be a Scene, the name of a built-in scene or a function returning "
                         f"a Scene")
    _check_parameter(scene, parameter)
    if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
        raise InputError(f"values = {values!r}: must be a list of the parameter's values")
    values = list(values)
    if not values:
        raise InputError("values: give at least one value of the parameter")
    seen: set[str] = set()
    for v in values:  # a path's key is its value's text (the CSV's cell): two values of one text would be one path
        if str(v) in seen:
            raise InputError(f"values: {v!r} is given twice; give each value of {parameter} once")
        seen.add(str(v))
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise InputError(f"jobs = {jobs!r}: must be a whole number >= 1")
    check_dask(dask)
    if out is not None and not isinstance(out, (str, os.PathLike)):
        raise InputError(f"out = {out!r}: must be None or the path of a CSV file")
    path = Path(out) if out is not None else None
    if path is not None and not path.parent.exists():
        raise InputError(f"out = {str(out)!r}: the directory {str(path.parent)!r} does not exist")
    if path is not None and path.is_dir():
        raise InputError(f"out = {str(out)!r}: is a directory; give the path of a CSV file")
    if path is not None and not os.access(path if path.exists() else path.parent, os.W_OK):
        raise InputError(f"out = {str(out)!r}: cannot be written (no permission); give a path of a CSV file you can write")
    cases = []
    for v in values:  # every case checked before any run
        sc = _scene_for(scene, parameter, v)
        k = v if parameter == "K_Ic" else K_Ic
        _check_case(sc, da, steps, k, criterion, solve_options)
        if jobs > 1 or dask is not None:
            _check_picklable(sc, parameter, v)
        cases.append((v, sc, k))
    done = _done(path, parameter)
    todo = [c for c in cases if str(c[0]) not in done]
    rows = {str(v): dict(row, **{parameter: v}) for v, row in
            ((v, done[str(v)]) for v, _, _ in cases if str(v) in done)}
    header = not (path is not None and path.exists() and path.stat().st_size > 0)
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
                    columns = [parameter, *STUDY_COLUMNS]
                    with open(path, "a", newline="") as fh:  # one complete line per finished path
                        fh.write((",".join(columns) + "\n" if header else "") + csv_line(row, columns))  # NaN: an empty cell
                        header = False
    finally:
        ex.close(cancel=True)
    table = pd.DataFrame([rows[str(v)] for v, _, _ in cases], columns=[parameter, *STUDY_COLUMNS])
    for col in ("steps", "ndof"):
        table[col] = table[col].astype(int)
    for col in ("final_length", "lambda_first", "lambda_last", "lambda_max", "cycles", "time_s"):
        table[col] = table[col].astype(float)
    return table
