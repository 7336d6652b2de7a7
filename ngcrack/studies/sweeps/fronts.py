"""The sweep of a 3D scene: every (element, front_h, nu, friction) solved, with K along the fronts against the finest run.

A 3D body's mesh size of interest is the front's, `front_h`: the sweep varies it (with the crack
size graded from it as `nc.solve` does when crack_h is not given) and measures, per run, the
unknowns, the seconds and the peak memory, the KKT residuals and the fracture parameters along
every front. The finest front_h of each (element, nu, friction) is the reference: `err_K_I` is the
largest difference of K_I along the fronts from the reference's (interpolated in the front's
parameter: the angle of a disc or an ellipse, the arc length of a polygon), `err_K` the largest of
any mode's (K_I, K_II, K_III), both over the reference's largest |K| of any mode; NaN on the
reference's own row. `nc.sweep` and `ngcrack sweep` send a 3D scene here.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Iterable

import numpy as np

from ...core.errors import InputError
from .cases import _memory_mb, _release_memory, _reset_peak_memory

#: the columns of a 3D sweep's rows, in order
FRONT_COLUMNS = ("scene", "element", "order", "front_h", "nu", "friction", "ndof_total", "ndof_global", "ndof_contact",
                 "time_mesh", "time_assemble", "time_linear", "time_contact", "time_fronts", "time_total", "time_cpu",
                 "memory_peak_mb", "kkt_max_penetration", "kkt_complementarity", "K_I_min", "K_I_max", "K_I_mean",
                 "err_K_I", "err_K", "reference")
#: the sweep arguments of a 2D scene that a 3D one does not take, with what it takes instead
PLANAR_SWEEP_ONLY = {"maxh": "front_h", "adapt": "", "adapt_maxh": "", "reference_maxh": "", "reference_element": "",
                     "vtk": "", "dask": "", "max_dof": ""}


def sweep_fronts(scene, elements: Iterable[str] | str = ("tdnns",), front_h: Iterable[float] | float = (0.3, 0.2),
                 nu: Iterable[float] | float | None = None, *, friction: Iterable[float] | float | None = None,
                 out=None, solve_options: dict | None = None, progress: bool = False):
    """Run every (element, front_h, nu, friction) of a 3D `scene`; one row per run as a pandas DataFrame
    (FRONT_COLUMNS), ordered by element, nu, friction and decreasing front_h (module docstring). `out`:
    a CSV file written whole at the end (temporary name, then moved into place)."""
    import pandas as pd

    from ...core.options import SolveOptions

    elements = [elements] if isinstance(elements, str) else list(elements)
    sizes = _values(front_h, "front_h")
    nus = _values(nu, "nu", allow_zero=True) if nu is not None else [scene.material.nu]
    mus = _values(friction, "friction", allow_zero=True) if friction is not None else [None]
    options = dict(solve_options or {})
    for key in ("front_h", "element"):
        if key in options:
            raise InputError(f"solve_options.{key}: the sweep's own axis; give it as {key.replace('element', 'elements')}=[...]")
    elements = list(dict.fromkeys(elements))
    if not elements:
        raise InputError("elements: give at least one element family")
    for element in elements:  # every run's options, checked by the body before anything is solved
        for v, m in itertools.product(nus, mus):
            s = scene.with_(nu=v) if m is None else scene.with_(nu=v, friction=m)
            try:
                run_options = SolveOptions.of(element=element, front_h=sizes[0], **options)
            except TypeError as exc:  # an unknown option: refused by name, as a 2D sweep's
                raise InputError(f"solve_options: {exc}") from None
            run_options.check_for(s)
    if out is not None:
        from ...shell.files import check_output

        out = check_output(out, "out", ".csv")
    rows = []
    for element, v, m in itertools.product(elements, nus, mus):
        s = scene.with_(nu=v) if m is None else scene.with_(nu=v, friction=m)
        runs = [(h, _run(s, element, h, options)) for h in sorted(sizes, reverse=True)]
        reference = runs[-1][1]
        for h, (row, sol) in runs:
            errors = (math.nan, math.nan) if sol is reference[1] else _k_errors(sol, reference[1])
            row["err_K_I"], row["err_K"] = errors
            row["reference"] = sol is reference[1]
            rows.append(row)
            if progress:
                print(f"sweep {scene.name}: {element} front_h {h:g} nu {v:g}: err_K_I {row['err_K_I']:.3g}, "
                      f"{row['time_total']:.1f} s", flush=True)
    df = pd.DataFrame(rows, columns=list(FRONT_COLUMNS))
    if out is not None:
        from ...shell.files import Staged

        with Staged() as staged:
            staged.write(out, lambda tmp: df.to_csv(tmp, index=False))
    return df


def _values(given, name: str, allow_zero: bool = False) -> list[float]:
    if isinstance(given, (int, float)) and not isinstance(given, bool):
        vals = [given]
    elif isinstance(given, (str, bytes)) or not hasattr(given, "__iter__"):
        raise InputError(f"{name} = {given!r}: must be a number or a list of numbers")
    else:
        vals = list(given)
    if not vals:
        raise InputError(f"{name}: give at least one value")
    for v in vals:
        ok = isinstance(v, (int, float, np.floating, np.integer)) and not isinstance(v, bool) and math.isfinite(v)
        if not ok or v < 0 or (v == 0 and not allow_zero):
            raise InputError(f"{name} = {v!r}: must be finite numbers {'>= 0' if allow_zero else '> 0'}")
    return list(dict.fromkeys(float(v) for v in vals))  # a value given twice is run once (as a 2D sweep's)


def _run(scene, element: str, h: float, options: dict) -> tuple[dict, object]:
    from ...core.solve import solve

    _release_memory()
    _reset_peak_memory()
    cpu0 = time.process_time()
    sol = solve(scene, element=element, front_h=h, **options)
    cpu = time.process_time() - cpu0
    _, peak = _memory_mb()
    t, n = sol.timings, sol.ndof
    K = np.concatenate([np.asarray(f.K_I) for f in sol.fronts]) if sol.fronts else np.full(1, math.nan)
    row = {"scene": scene.name, "element": element, "order": int(sol.disc.order), "front_h": h,
           "nu": float(scene.material.nu), "friction": max((float(c.friction) for c in scene.cracks), default=0.0),
           "ndof_total": n["total"], "ndof_global": n["global"], "ndof_contact": n["contact"],
           **{f"time_{k}": float(t.get(k, 0.0)) for k in ("mesh", "assemble", "linear", "contact", "fronts", "total")},
           "time_cpu": cpu, "memory_peak_mb": peak, "kkt_max_penetration": sol.kkt["max_penetration"],
           "kkt_complementarity": sol.kkt["complementarity"], "K_I_min": float(np.min(K)), "K_I_max": float(np.max(K)),
           "K_I_mean": float(np.mean(K))}
    return row, sol


def _k_errors(sol, reference) -> tuple[float, float]:
    """(err_K_I, err_K): the largest |K - K_ref| along the fronts, of K_I and of any mode, over the reference's
    largest |K| of any mode (module docstring)."""
    worst, scale = np.zeros(3), 0.0
    for f, r in zip(sol.fronts, reference.fronts):
        order = np.argsort(r.angle)
        closed = reference.scene.cracks[r.crack].shape in ("disc", "ellipse")  # the angle goes round
        for k, mode in enumerate(("K_I", "K_II", "K_III")):
            ref = np.interp(f.angle, np.asarray(r.angle)[order], np.asarray(getattr(r, mode))[order],
                            period=2 * np.pi if closed else None)
            worst[k] = max(worst[k], float(np.max(np.abs(np.asarray(getattr(f, mode)) - ref))))
            scale = max(scale, float(np.max(np.abs(getattr(r, mode)))))
    return (float(worst[0] / scale), float(worst.max() / scale)) if scale > 0 else (math.nan, math.nan)
